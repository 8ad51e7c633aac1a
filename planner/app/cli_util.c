/* Shared CLI helpers: option parsing with clear messages, arm loading. */
#include "cli_impl.h"

#include <ctype.h>
#include <errno.h>
#include <inttypes.h>
#include <fcntl.h>
#include <getopt.h>
#include <limits.h>
#include <math.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdlib.h>
#include <string.h>
#include <sys/file.h>
#include <unistd.h>

int ea__cli_usage_error(const char *cmd, const char *fmt, ...) {
  va_list ap;
  fprintf(stderr, "elasticarm %s: ", cmd);
  va_start(ap, fmt);
  vfprintf(stderr, fmt, ap);
  va_end(ap);
  fprintf(stderr, "\n(see 'elasticarm %s --help')\n", cmd);
  return EA_EXIT_USAGE;
}

int ea__cli_fail(const char *cmd, ea_status_t st, const ea_error_t *err) {
  fprintf(stderr, "elasticarm %s: error: %s\n", cmd,
          (err && err->msg[0]) ? err->msg : ea_strerror(st));
  if (st == EA_ERR_ARG || st == EA_ERR_INPUT || st == EA_ERR_PARSE || st == EA_ERR_IO)
    return EA_EXIT_USAGE;
  return EA_EXIT_FAIL;
}

int ea__cli_oom(const char *cmd, const char *what) {
  fprintf(stderr, "elasticarm %s: error: out of memory (%s)\n", cmd, what);
  return EA_EXIT_FAIL;
}

int ea__cli_double(const char *cmd, const char *flag, const char *text, double lo, double hi,
                   double *out) {
  char *end;
  errno = 0;
  const double v = text ? strtod(text, &end) : NAN;
  if (!text || end == text || *end || errno == ERANGE || !isfinite(v))
    return ea__cli_usage_error(cmd, "%s: '%s' is not a finite number", flag, text ? text : "");
  if (v < lo || v > hi)
    return ea__cli_usage_error(cmd, "%s: value %s is outside [%g, %g]", flag, text, lo, hi);
  *out = v;
  return 0;
}

int ea__cli_int(const char *cmd, const char *flag, const char *text, long lo, long hi, long *out) {
  char *end;
  errno = 0;
  const long v = text ? strtol(text, &end, 10) : 0;
  if (!text || end == text || *end || errno == ERANGE)
    return ea__cli_usage_error(cmd, "%s: '%s' is not an integer", flag, text ? text : "");
  if (v < lo || v > hi)
    return ea__cli_usage_error(cmd, "%s: value %ld is outside [%ld, %ld]", flag, v, lo, hi);
  *out = v;
  return 0;
}

int ea__cli_pair(const char *cmd, const char *flag, const char *text, double out[2]) {
  char *end;
  errno = 0;
  double a = strtod(text, &end);
  if (end == text || *end != ',' || !isfinite(a))
    return ea__cli_usage_error(cmd, "%s: '%s' is not 'X,Y'", flag, text);
  const char *s = end + 1;
  double b = strtod(s, &end);
  if (end == s || *end || !isfinite(b) || errno == ERANGE)
    return ea__cli_usage_error(cmd, "%s: '%s' is not 'X,Y'", flag, text);
  out[0] = a;
  out[1] = b;
  return 0;
}

int ea__cli_list(const char *cmd, const char *flag, const char *text, double **out, int *n) {
  *out = NULL;
  *n = 0;
  double a, st, b;
  char tail;
  if (sscanf(text, "%lf:%lf:%lf%c", &a, &st, &b, &tail) == 3) {
    if (!isfinite(a) || !isfinite(st) || !isfinite(b) || !(st > 0) || b < a || (b - a) / st > 1e6)
      return ea__cli_usage_error(cmd, "%s: '%s' is not a range start:step:stop with step > 0", flag,
                                 text);
    const int m = (int)floor((b - a) / st + 1e-9) + 1;
    double *v = malloc((size_t)m * sizeof *v);
    if (!v) return ea__cli_oom(cmd, flag);
    for (int i = 0; i < m; ++i)
      v[i] = a + i * st;
    *out = v;
    *n = m;
    return 0;
  }
  int m = 1;
  for (const char *c = text; *c; ++c)
    m += (*c == ',');
  double *v = malloc((size_t)m * sizeof *v);
  if (!v) return ea__cli_oom(cmd, flag);
  const char *s = text;
  for (int i = 0; i < m; ++i) {
    char *end;
    v[i] = strtod(s, &end);
    if (end == s || !isfinite(v[i]) || (*end && *end != ',')) {
      free(v);
      return ea__cli_usage_error(cmd, "%s: '%s' is not a list a,b,c or a range start:step:stop",
                                 flag, text);
    }
    s = end + 1;
  }
  *out = v;
  *n = m;
  return 0;
}

int ea__cli_help_asked(int argc, char **argv) {
  for (int i = 1; i < argc; ++i) {
    const size_t n = strlen(argv[i]);
    if (!strcmp(argv[i], "-h") || (n >= 3 && n <= 6 && !strncmp(argv[i], "--help", n))) return 1;
    if (!strcmp(argv[i], "--")) break;
  }
  return 0;
}

void ea__cli_args_init(ea__cli_args_t *g, const char *cmd, int argc, char **argv,
                       const ea__cli_opt_t *opts) {
  memset(g, 0, sizeof *g);
  g->cmd = cmd;
  g->argc = argc;
  g->argv = argv;
  g->opts = opts;
  while (opts[g->nopts].name && g->nopts < EA__CLI_MAX_OPTS)
    ++g->nopts;
  optind = 0; /* glibc: a full restart (another subcommand's parse may have run) */
}

/* A long option's usage error: argv text t ("--name" or "--name=value") did not match. */
static int ea__cli_long_error(const ea__cli_args_t *g, const char *t) {
  const char *eq = strchr(t, '=');
  const size_t n = eq ? (size_t)(eq - t - 2) : strlen(t + 2);
  char list[400] = "";
  int matches = 0, exact = -1;
  size_t u = 0;
  for (int i = 0; i < g->nopts; ++i) {
    if (strncmp(g->opts[i].name, t + 2, n)) continue;
    if (strlen(g->opts[i].name) == n) exact = i;
    ++matches;
    if (u < sizeof list)
      u += (size_t)snprintf(list + u, sizeof list - u, "%s--%s", matches > 1 ? ", " : "",
                            g->opts[i].name);
  }
  if (eq && (exact >= 0 || matches == 1))
    return ea__cli_usage_error(g->cmd, "--%s takes no value ('%s')",
                               g->opts[exact >= 0 ? exact : 0].name, t);
  if (matches > 1)
    return ea__cli_usage_error(g->cmd, "option '%.*s' is ambiguous (%s)", (int)(n + 2), t, list);
  return ea__cli_usage_error(g->cmd, "unknown option '%.*s'", (int)(n + 2), t);
}

int ea__cli_args_next(ea__cli_args_t *g) {
  /* getopt_long's table: every long option its own code (>= 256, or its letter), so that an
   * abbreviation of two options is ambiguous however alike they are */
  struct option lo[EA__CLI_MAX_OPTS + 1];
  char shorts[2 * EA__CLI_MAX_OPTS + 3] = "-:"; /* operands in order; ':' for a missing value */
  size_t ns = 2;
  for (int i = 0; i < g->nopts; ++i) {
    lo[i].name = g->opts[i].name;
    lo[i].has_arg = g->opts[i].value ? required_argument : no_argument;
    lo[i].flag = NULL;
    lo[i].val = g->opts[i].letter ? g->opts[i].letter : 256 + i;
    if (g->opts[i].letter) {
      shorts[ns++] = g->opts[i].letter;
      if (g->opts[i].value) shorts[ns++] = ':';
    }
  }
  memset(&lo[g->nopts], 0, sizeof lo[g->nopts]);
  shorts[ns] = '\0';
  int idx = -1, c = -1;
  g->opt = g->arg = NULL;
  if (!g->rest) {
    opterr = 0;
    idx = -1;
    c = getopt_long(g->argc, g->argv, shorts, lo, &idx);
    g->rest = c == -1;
  }
  if (g->rest) { /* after "--" every argument is an operand */
    if (optind >= g->argc) return 0;
    g->arg = g->argv[optind++];
    return 1;
  }
  if (c == 1) {
    g->arg = optarg;
    return 1;
  }
  const char *t = g->argv[optind - 1 < g->argc ? optind - 1 : g->argc - 1];
  if (c == ':') {
    if (!strncmp(t, "--", 2)) {
      const char *eq = strchr(t, '=');
      return ea__cli_usage_error(g->cmd, "%.*s needs a value", eq ? (int)(eq - t) : (int)strlen(t),
                                 t),
             -1;
    }
    return ea__cli_usage_error(g->cmd, "-%c needs a value", optopt), -1;
  }
  if (c == '?') {
    if (!strncmp(t, "--", 2)) return ea__cli_long_error(g, t), -1;
    return ea__cli_usage_error(g->cmd, "unknown option '-%c'", optopt ? optopt : '?'), -1;
  }
  if (idx >= 0 && idx < g->nopts) { /* a long option (getopt_long sets idx for those only) */
    snprintf(g->buf, sizeof g->buf, "--%s", g->opts[idx].name);
  } else { /* a letter: its option */
    for (int i = 0; i < g->nopts; ++i)
      if (g->opts[i].letter == c) idx = i;
    if (idx < 0) return ea__cli_usage_error(g->cmd, "unknown option '-%c'", c), -1;
    snprintf(g->buf, sizeof g->buf, "-%c", c);
  }
  g->opt = g->buf;
  g->arg = g->opts[idx].value ? optarg : NULL;
  return 1;
}

/* The folder of the running executable (from /proc/self/exe) into buf; 0 if unknown. */
static int ea__exe_dir(char *buf, size_t len) {
  char exe[PATH_MAX];
  const ssize_t n = readlink("/proc/self/exe", exe, sizeof exe - 1);
  if (n <= 0) return 0;
  exe[n] = '\0';
  char *slash = strrchr(exe, '/');
  if (!slash) return 0;
  *slash = '\0';
  return snprintf(buf, len, "%s", exe[0] ? exe : "/") < (int)len;
}

static void ea__find_default_arm(char *path, size_t len, const char **how) {
  const char *e = getenv("EA_ARM_FILE");
  if (e && *e) {
    snprintf(path, len, "%s", e);
    *how = "$EA_ARM_FILE";
    return;
  }
  if (access("data/elasticarm.yaml", R_OK) == 0) {
    snprintf(path, len, "data/elasticarm.yaml");
    *how = "./data/ of the working directory";
    return;
  }
  char dir[PATH_MAX];
  if (ea__exe_dir(dir, sizeof dir)) {
    static const struct {
      const char *rel, *how;
    } near[] = {
        {"/../share/elasticarm/elasticarm.yaml",
         "share/elasticarm/ beside the folder of the executable (installed)"},
        {"/../data/elasticarm.yaml", "data/ beside the folder of the executable (a build tree)"}};
    for (size_t i = 0; i < sizeof near / sizeof *near; ++i) {
      char p[PATH_MAX + 64], real[PATH_MAX];
      if (snprintf(p, sizeof p, "%s%s", dir, near[i].rel) < (int)sizeof p && access(p, R_OK) == 0) {
        snprintf(path, len, "%s", realpath(p, real) ? real : p);
        *how = near[i].how;
        return;
      }
    }
  }
  snprintf(path, len, "%s", EA_INSTALL_DATADIR "/elasticarm/elasticarm.yaml");
  *how = "the install location";
}

static char ea__default_arm_path[PATH_MAX + 64];
static const char *ea__default_arm_how; /* NULL until looked up (once per process) */

const char *ea__cli_default_arm(void) {
  if (!ea__default_arm_how)
    ea__find_default_arm(ea__default_arm_path, sizeof ea__default_arm_path, &ea__default_arm_how);
  return ea__default_arm_path;
}

const char *ea__cli_default_arm_how(void) {
  ea__cli_default_arm();
  return ea__default_arm_how;
}

int ea__cli_load_arm(const char *cmd, const char *path, ea_arm_t *arm) {
  ea_error_t err = {0};
  char warning[700];
  ea_status_t st =
      ea_arm_load_warn(path ? path : ea__cli_default_arm(), arm, warning, sizeof warning, &err);
  if (st) return ea__cli_fail(cmd, st, &err);
  if (warning[0]) fprintf(stderr, "elasticarm %s: warning: %s\n", cmd, warning);
  return 0;
}

double ea__cli_tip_mass(const ea_arm_t *arm, const ea__cli_payload_t *p) {
  double mp = 0.0;
  if (p->given == 1) mp = ea_arm_payload_from_factor(arm, p->value);
  if (p->given == 2) mp = p->value;
  return ea_arm_tip_mass(arm, mp);
}

int ea__cli_check_figure(const char *cmd, const char *path) {
  ea_plot_t *p = NULL;
  ea_error_t err = {0};
  ea_status_t st = ea_plot_open(&p, path, 0, 0, &err);
  if (st) return ea__cli_fail(cmd, st, &err);
  ea_plot_discard(p);
  return 0;
}

int ea__cli_check_output(const char *cmd, const char *path) {
  if (!strcmp(path, "-")) return 0;
  ea_afile_t f;
  ea_error_t err = {0};
  ea_status_t st = ea_afile_open(&f, path, &err);
  if (st) return ea__cli_fail(cmd, st, &err);
  ea_afile_abort(&f);
  return 0;
}

void ea__cli_safe_name(const char *name, const char *fallback, char *buf, size_t len) {
  size_t n = 0;
  for (const char *c = name ? name : ""; *c && n + 1 < len && n < 100; ++c) {
    const unsigned char u = (unsigned char)*c;
    if (n == 0 && (u == '.' || u == '/' || u == ' ')) continue; /* no hidden, absolute names */
    buf[n++] = (isalnum(u) || u == '-' || u == '_' || u == '.' || u == '+') ? (char)u : '_';
  }
  buf[n] = '\0';
  if (!n) snprintf(buf, len, "%s", fallback);
}

/* The first parameter in which two arms differ ("" if none). */
static const char *ea__arm_diff(const ea_arm_t *a, const ea_arm_t *b) {
#define EA__F(f)                                                                                   \
  { #f, offsetof(ea_arm_t, f) }
  static const struct {
    const char *name;
    size_t off;
  } f[] = {EA__F(rho),
           EA__F(m_hand),
           EA__F(length),
           EA__F(EI),
           EA__F(x_c),
           EA__F(y_c),
           EA__F(g),
           EA__F(EA),
           EA__F(GA_s),
           EA__F(EA_cable),
           EA__F(I_zz),
           EA__F(I_hand),
           EA__F(act.spool_radius),
           EA__F(act.spool_gear_ratio),
           EA__F(act.spool_zero_length),
           EA__F(act.cable_length_min),
           EA__F(act.cable_length_max),
           EA__F(act.cable_speed_max),
           EA__F(act.cable_accel_max),
           EA__F(act.tension_max),
           EA__F(act.tension_min),
           EA__F(act.shoulder_torque_max),
           EA__F(act.shoulder_speed_max),
           EA__F(act.shoulder_angle_min),
           EA__F(act.shoulder_angle_max),
           EA__F(act.shoulder_accel_max),
           EA__F(act.base_speed_max),
           EA__F(act.base_accel_max),
           EA__F(act.base_angle_min),
           EA__F(act.base_angle_max)};
#undef EA__F
  for (size_t i = 0; i < sizeof f / sizeof *f; ++i) {
    double x, y;
    memcpy(&x, (const char *)a + f[i].off, sizeof x);
    memcpy(&y, (const char *)b + f[i].off, sizeof y);
    if (x != y) return f[i].name;
  }
  return "";
}

/* "X" for a hash, "(none)" without one. */
static const char *ea__hash_str(int has, uint64_t h, char buf[17]) {
  if (!has) return "(none)";
  snprintf(buf, 17, "%016" PRIx64, h);
  return buf;
}

/* The first parameter in which two arms differ, including the damping ratios. */
static const char *ea__arm_diff_all(const ea_arm_t *a, const ea_arm_t *b) {
  const char *d = ea__arm_diff(a, b);
  return d[0] || ea_arm_equal(a, b) ? d : "damping.modal_ratios";
}

int ea__cli_arm_for_traj(const char *cmd, const char *traj_path, const char *arm_opt,
                         const ea_traj_t *tr, int flags, ea_arm_t *arm, char *used,
                         size_t used_len) {
  const int quiet = flags & EA__ARM_QUIET, strict = flags & EA__ARM_STRICT;
  const char *rec = tr->arm_file[0] ? tr->arm_file : NULL;
  /* the arm file the plan names: its own, else the default the planner used */
  const char *planned = rec ? rec : ea__cli_default_arm();
  char hx[17], hy[17], hz[17];
  const char *X = ea__hash_str(tr->has_arm_hash, tr->arm_hash, hx);
  if (used && used_len) used[0] = '\0';
  ea_arm_t recorded;
  ea_error_t err = {0};
  ea_status_t rst = ea_arm_load(planned, &recorded, &err);
  const uint64_t Y = rst ? 0 : ea_arm_hash(&recorded);
  if (!arm_opt) {
    if (rst && !rec) return ea__cli_fail(cmd, rst, &err);
    if (rst) {
      fprintf(stderr,
              "elasticarm %s: error: %s records the arm file '%s', which cannot be loaded: %s\n"
              "(give the arm it was planned for with --arm FILE)\n",
              cmd, traj_path, planned, err.msg);
      return EA_EXIT_USAGE;
    }
    if (tr->has_arm_hash && Y != tr->arm_hash) {
      fprintf(stderr,
              "elasticarm %s: error: %s was planned for the arm with hash %s ('# arm_hash:'), but "
              "its arm file '%s' now holds an arm with hash %s: refused (the plan's limits and "
              "motor mapping would not hold; give the arm it was planned for with --arm FILE)\n",
              cmd, traj_path, X, planned, ea__hash_str(1, Y, hy));
      return EA_EXIT_USAGE;
    }
    if (rec && !tr->has_arm_hash)
      fprintf(stderr,
              "elasticarm %s: note: %s has no '# arm_hash:' line (written by an older "
              "elasticarm): its arm file '%s' cannot be checked against the plan\n",
              cmd, traj_path, rec);
    if (rec && !quiet)
      fprintf(stderr, "elasticarm %s: using the trajectory's arm file '%s' (arm hash %s)\n", cmd,
              rec, ea__hash_str(1, Y, hy));
    *arm = recorded;
    if (used && used_len) snprintf(used, used_len, "%s", rec ? rec : "");
    return 0;
  }
  ea_arm_t given;
  int rc = ea__cli_load_arm(cmd, arm_opt, &given);
  if (rc) return rc;
  const uint64_t Z = ea_arm_hash(&given);
  /* planned for: the hash when the file has one, else the recorded file's parameters */
  int same;
  if (tr->has_arm_hash)
    same = Z == tr->arm_hash;
  else if (!rst && rec)
    same = ea_arm_equal(&recorded, &given);
  else
    same = -1; /* nothing to compare with */
  /* the first parameter that differs, when the recorded file still holds the planned arm */
  const char *d = same == 0 && !rst && (!tr->has_arm_hash || Y == tr->arm_hash)
                      ? ea__arm_diff_all(&recorded, &given)
                      : "";
  if (same == 0 && strict) {
    fprintf(stderr,
            "elasticarm %s: error: --arm %s (arm hash %s) differs from the arm %s was planned "
            "for (%s '%s', arm hash %s)%s%s: refused (the plan's limits and motor mapping "
            "would not hold)\n",
            cmd, arm_opt, ea__hash_str(1, Z, hz), traj_path,
            tr->has_arm_hash ? "arm file then" : "its arm file", planned,
            tr->has_arm_hash ? X : ea__hash_str(!rst, Y, hy), d[0] ? " in " : "", d);
    return EA_EXIT_USAGE;
  }
  if (same == 0)
    fprintf(stderr,
            "elasticarm %s: note: %s was planned for the arm with hash %s (arm file '%s'); it is "
            "used with --arm %s (arm hash %s)%s%s\n",
            cmd, traj_path, X, planned, arm_opt, ea__hash_str(1, Z, hz),
            d[0] ? ", which differs in " : "", d);
  if (same == -1 && rec)
    fprintf(stderr,
            "elasticarm %s: warning: the trajectory's arm file '%s' cannot be read and %s has no "
            "'# arm_hash:': the arm it was planned for is not compared with --arm %s\n",
            cmd, rec, traj_path, arm_opt);
  if (same == 1 && tr->has_arm_hash && (rst || Y != tr->arm_hash) && !quiet)
    fprintf(stderr,
            "elasticarm %s: note: the trajectory's arm file '%s' %s; --arm %s holds the arm it "
            "was planned for (arm hash %s)\n",
            cmd, planned, rst ? "cannot be loaded" : "has changed since the plan", arm_opt, X);
  *arm = given;
  if (used && used_len) snprintf(used, used_len, "%s", arm_opt);
  return 0;
}

/* The value of '# run_id: ' among the leading '#' lines of a trajectory file ("" if none). */
static void ea__traj_run_id(FILE *fp, char *id, size_t len) {
  char line[1200];
  id[0] = '\0';
  while (fgets(line, sizeof line, fp) && line[0] == '#')
    if (!strncmp(line, "# run_id: ", 10)) {
      snprintf(id, len, "%.*s", (int)strcspn(line + 10, "\r\n"), line + 10);
      return;
    }
}

/* The top-level string "run_id" of a plan summary ("" if none: the key is first at depth 1;
 * a key of that name inside an object or array is not it). */
static void ea__summary_run_id(FILE *fp, char *id, size_t len) {
  id[0] = '\0';
  int depth = 0, c;
  while ((c = getc(fp)) != EOF) {
    if (c == '{' || c == '[') {
      ++depth;
    } else if (c == '}' || c == ']') {
      --depth;
    } else if (c == '"') {
      char key[16];
      size_t n = 0;
      int esc = 0;
      while ((c = getc(fp)) != EOF && (esc || c != '"')) {
        esc = !esc && c == '\\';
        if (n + 1 < sizeof key) key[n++] = (char)c;
      }
      key[n] = '\0';
      if (depth != 1 || strcmp(key, "run_id")) continue;
      while ((c = getc(fp)) == ' ' || c == ':' || c == '\t' || c == '\n')
        ;
      if (c != '"') return;
      n = 0;
      while ((c = getc(fp)) != EOF && c != '"')
        if (n + 1 < len) id[n++] = (char)c;
      id[n] = '\0';
      return;
    }
  }
}

int ea__cli_check_plan_pair(const char *cmd, const char *traj_path) {
  if (!traj_path || !strcmp(traj_path, "-")) return 0;
  char json[1100], lock[1100], tid[128], sid[128] = "";
  ea__replace_ext(traj_path, ".json", json, sizeof json);
  if (!strcmp(json, traj_path)) return 0;
  snprintf(lock, sizeof lock, "%s.lock", traj_path);
  const int lfd = open(lock, O_RDONLY | O_CLOEXEC); /* only when a plan made one */
  if (lfd >= 0)
    while (flock(lfd, LOCK_SH) != 0 && errno == EINTR)
      ;
  int rc = 0;
  FILE *tf = fopen(traj_path, "r");
  if (tf) {
    ea__traj_run_id(tf, tid, sizeof tid);
    fclose(tf);
    FILE *sf = tid[0] ? fopen(json, "r") : NULL;
    if (sf) {
      ea__summary_run_id(sf, sid, sizeof sid);
      fclose(sf);
      if (strcmp(tid, sid)) {
        fprintf(stderr,
                "elasticarm %s: error: %s (run_id %s) and the summary beside it, %s (%s), come "
                "from different plan runs (two runs writing the same outputs, or one killed "
                "between its two renames): run 'elasticarm plan' again, or move %s away\n",
                cmd, traj_path, tid, json, sid[0] ? sid : "no run_id", json);
        rc = EA_EXIT_USAGE;
      }
    }
  }
  if (lfd >= 0) close(lfd);
  return rc;
}

void ea__cli_progress_init(ea__cli_progress_t *p, const char *cmd, int on) {
  memset(p, 0, sizeof *p);
  p->cmd = cmd;
  p->on = on;
  p->tty = isatty(STDERR_FILENO);
  p->t0 = ea__mono_s();
}

double ea__cli_progress_elapsed(const ea__cli_progress_t *p) {
  return ea__mono_s() - p->t0;
}

void ea__cli_progress(ea__cli_progress_t *p, int force, const char *fmt, ...) {
  if (!p || !p->on) return;
  const double now = ea__mono_s();
  if (now - p->t0 < 1.0) return; /* a short job stays silent */
  if (!force && p->last > 0 && now - p->last < (p->tty ? 0.2 : 2.0)) return;
  p->last = now;
  char line[400];
  va_list ap;
  va_start(ap, fmt);
  vsnprintf(line, sizeof line, fmt, ap);
  va_end(ap);
  if (p->tty) {
    fprintf(stderr, "\r\033[Kelasticarm %s: %s", p->cmd, line); /* \033[K: clear the rest */
    p->open = 1;
  } else {
    fprintf(stderr, "elasticarm %s: %s\n", p->cmd, line);
  }
  fflush(stderr);
}

void ea__cli_progress_end(ea__cli_progress_t *p) {
  if (p && p->open) fputc('\n', stderr);
  if (p) p->open = 0;
}

void ea__cli_progress_fe(void *data, double t_s, double t_end_s) {
  ea__cli_progress_t *p = data;
  ea__cli_progress(p, 0, "FE transient: t = %.2f of %.2f s simulated (%.0f %%), %.1f s", t_s,
                   t_end_s, t_end_s > 0 ? 100.0 * t_s / t_end_s : 100.0,
                   ea__cli_progress_elapsed(p));
}
