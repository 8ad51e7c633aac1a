/* Arm files: the shipped file holds the paper's Tables 1 and 2; every kind
 * of bad input gives a clear error naming file:line:column and the key. */
#include "ea_problems.h"
#include "ea_test.h"

#include <stdint.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

static char *slurp(const char *path, size_t *len) {
  FILE *f = fopen(path, "rb");
  if (!f) return NULL;
  fseek(f, 0, SEEK_END);
  long n = ftell(f);
  fseek(f, 0, SEEK_SET);
  char *b = malloc((size_t)n + 1);
  if (b && fread(b, 1, (size_t)n, f) != (size_t)n) {
    free(b);
    b = NULL;
  }
  if (b) b[n] = '\0';
  fclose(f);
  *len = (size_t)n;
  return b;
}

/* Replace the first occurrence of from by to in text (new string). */
static char *subst(const char *text, const char *from, const char *to) {
  const char *p = strstr(text, from);
  if (!p) return NULL;
  size_t n = strlen(text) - strlen(from) + strlen(to);
  char *o = malloc(n + 1);
  size_t a = (size_t)(p - text);
  memcpy(o, text, a);
  memcpy(o + a, to, strlen(to));
  strcpy(o + a + strlen(to), p + strlen(from));
  return o;
}

static void expect_error(const char *good, const char *from, const char *to, const char *want1,
                         const char *want2, const char *what) {
  char *bad = subst(good, from, to);
  if (!bad) {
    ea_test_true(0, what);
    printf("  (test setup: '%s' not found)\n", from);
    return;
  }
  ea_arm_t arm;
  ea_error_t err = {0};
  ea_status_t st = ea_arm_load_string("arm.yaml", bad, strlen(bad), &arm, &err);
  const int ok = st != EA_OK && strstr(err.msg, "arm.yaml:") && strstr(err.msg, want1) &&
                 (!want2 || strstr(err.msg, want2));
  ea_test_true(ok, what);
  printf("  -> %s\n", err.msg);
  free(bad);
}

/* FNV-1a, 64 bit (Fowler, Noll, Vo; offset basis 14695981039346656037, prime 1099511628211),
 * over bytes, for the reference below. */
static uint64_t fnv1a(uint64_t h, const unsigned char *b, size_t n) {
  for (size_t i = 0; i < n; ++i) {
    h ^= b[i];
    h *= 1099511628211u;
  }
  return h;
}

/* ea_arm_hash: the documented byte sequence (ea_arm.h: each parameter's IEEE-754 bits, least
 * significant byte first) through FNV-1a, checked on the published test vector "a"; a
 * reformatted arm file (comments, number spelling) has the same hash, a gear ratio of 2
 * another. */
static void test_arm_hash(const char *good) {
  ea_test_true(fnv1a(14695981039346656037u, (const unsigned char *)"a", 1) == 0xaf63dc4c8601ec8cu,
               "FNV-1a 64 of \"a\" = af63dc4c8601ec8c (the published test vector)");
  ea_arm_t arm;
  if (ea_arm_load_string("arm.yaml", good, strlen(good), &arm, NULL)) {
    ea_test_true(0, "arm loads");
    return;
  }
  const double f[] = {arm.rho, arm.m_hand, arm.length, arm.EI,       arm.x_c,  arm.y_c,
                      arm.g,   arm.EA,     arm.GA_s,   arm.EA_cable, arm.I_zz, arm.I_hand};
  double v[64];
  size_t n = 0;
  for (size_t i = 0; i < sizeof f / sizeof *f; ++i)
    v[n++] = f[i];
  memcpy(v + n, &arm.act, sizeof arm.act);
  n += sizeof arm.act / sizeof(double);
  v[n++] = arm.n_damping;
  for (int i = 0; i < arm.n_damping; ++i)
    v[n++] = arm.damping_ratio[i];
  uint64_t h = 14695981039346656037u;
  for (size_t i = 0; i < n; ++i) {
    uint64_t bits;
    memcpy(&bits, &v[i], sizeof bits);
    unsigned char b[8];
    for (int k = 0; k < 8; ++k)
      b[k] = (unsigned char)(bits >> (8 * k));
    h = fnv1a(h, b, 8);
  }
  printf("  ea_arm_hash %016llx, reference %016llx (%zu values)\n",
         (unsigned long long)ea_arm_hash(&arm), (unsigned long long)h, n);
  ea_test_true(ea_arm_hash(&arm) == h, "ea_arm_hash = FNV-1a of the documented bytes");
  char *t1 = subst(good, "  EI_Nm2:", "  # a comment\n  EI_Nm2:");
  char *t2 = t1 ? subst(t1, "0.705", "7.050e-1") : NULL;
  char *t3 = subst(good, "gear_ratio: 1.0\n", "gear_ratio: 2\n");
  ea_arm_t a2, a3;
  const int ok = t2 && t3 && !ea_arm_load_string("arm.yaml", t2, strlen(t2), &a2, NULL) &&
                 !ea_arm_load_string("arm.yaml", t3, strlen(t3), &a3, NULL);
  ea_test_true(ok && ea_arm_hash(&a2) == ea_arm_hash(&arm),
               "a comment and 7.050e-1 for 0.705: the same hash");
  ea_test_true(ok && ea_arm_hash(&a3) != ea_arm_hash(&arm), "gear ratio 2: another hash");
  free(t1);
  free(t2);
  free(t3);
}

int main(void) {
  const char *src = getenv("EA_SOURCE_DIR");
  char path[1024];
  snprintf(path, sizeof path, "%s/data/elasticarm.yaml", src ? src : ".");
  size_t len = 0;
  char *good = slurp(path, &len);
  ea_test_true(good != NULL, "data/elasticarm.yaml readable");
  if (!good) return ea_test_summary("test_arm_file");

  ea_arm_t arm;
  ea_error_t err = {0};
  ea_test_true(ea_arm_load(path, &arm, &err) == EA_OK, "data/elasticarm.yaml loads");
  /* Paper, Table 1 and Table 2 */
  ea_test_rel(arm.rho, 0.501, 0, "Table 1 rho");
  ea_test_rel(arm.m_hand, 0.230, 0, "Table 1 m_h");
  ea_test_rel(arm.length, 0.914, 0, "Table 1 L");
  ea_test_rel(arm.EI, 0.705, 0, "Table 1 EI");
  ea_test_rel(arm.x_c, 0.098, 0, "Table 1 x_c");
  ea_test_rel(arm.y_c, -0.006, 0, "Table 1 y_c");
  ea_test_rel(arm.EA, 1.28e8, 0, "Table 2 EA");
  ea_test_rel(arm.GA_s, 3.28e6, 0, "Table 2 beta GA");
  ea_test_rel(arm.EA_cable, 1.02e5, 0, "Table 2 EA_c");
  ea_test_rel(arm.I_zz, 2.68e-8, 0, "Table 2 I_zz");
  ea_test_rel(arm.I_hand, 4.00e-4, 0, "Table 2 I_L");
  ea_test_rel(arm.g, 9.81, 0, "g");

  expect_error(good, "  EI_Nm2: 0.705              # Table 1: flexural rigidity\n", "",
               "missing required key 'EI_Nm2'", NULL, "missing key");
  expect_error(good, "EI_Nm2: 0.705", "EI_Nm2: -0.705", "EI_Nm2", "below", "negative stiffness");
  expect_error(good, "rho_kg_per_m: 0.501", "rho_kg_per_m: nan", "rho_kg_per_m", "not finite",
               "NaN value");
  expect_error(good, "rho_kg_per_m: 0.501", "rho_kg_per_m: .nan", "rho_kg_per_m", "not a number",
               "YAML .nan value");
  expect_error(good, "length_m: 0.914", "length_m: [1, 2]", "length_m", "must be a number",
               "wrong type (sequence for a number)");
  expect_error(good, "length_m: 0.914", "length_m: long", "length_m", "not a number",
               "wrong type (word for a number)");
  expect_error(good, "  length_m: 0.914", "  lenght_m: 0.914", "unknown key 'lenght_m'", NULL,
               "misspelt key");
  expect_error(good, "hand:\n", "hand: [\n", "syntax error", NULL, "YAML syntax error");
  expect_error(good, "  max_N: 60.0", "  max_N: 0.01", "actuators.tension",
               "min_N = 0.05 must be below max_N = 0.01",
               "contradictory limits (tension max below min)");
  expect_error(good, "    radius_m: 0.015", "    radius_m: 0.015\n    radius_m: 0.02",
               "duplicate key 'radius_m'", NULL, "duplicate key");
  /* physical ranges of the actuator values (issue 31: radius_m 1e308 streamed spool positions
   * near 1e-309 rad; a negative cable length at motor position 0 was taken) */
  expect_error(good, "radius_m: 0.015", "radius_m: 1e308", "radius_m", "above the bound 1",
               "spool radius 1e308 m refused");
  expect_error(good, "zero_length_m: 0.254", "zero_length_m: -1", "zero_length_m",
               "below the bound 0", "negative cable length at spool position 0 refused");
  expect_error(good, "gear_ratio: 1.0", "gear_ratio: 1e9", "gear_ratio", "above the bound",
               "gear ratio 1e9 refused");
  expect_error(good, "    angle_max_rad: 3.6651914292", "    angle_max_rad: 100", "angle_max_rad",
               "above the bound", "shoulder angle beyond a turn refused");
  expect_error(good, "torque_max_Nm: 4.0", "torque_max_Nm: 1e30", "torque_max_Nm",
               "above the bound", "shoulder torque 1e30 N m refused");
  /* no configuration has a cable longer than L + |root| = 0.914 + 0.0982 m */
  expect_error(good, "cable_length_min_m: 0.254", "cable_length_min_m: 1.1",
               "cable_length_min_m = 1.1", "no static solution exists",
               "shortest cable beyond the tip's reach: an error");
  {
    /* the position of the value of the first 'key: value' in text: "arm.yaml:L:C:" */
    char want[64], warn[700];
    char *stiff = subst(good, "EI_Nm2: 0.705", "EI_Nm2: 705  ");
    int line = 1;
    const char *q = stiff, *at = stiff ? strstr(stiff, "EI_Nm2: 705") : NULL;
    for (const char *c = stiff; at && c < at; ++c)
      if (*c == '\n') ++line, q = c + 1;
    snprintf(want, sizeof want, "arm.yaml:%d:%d:", line, at ? (int)(at - q) + 9 : 0);
    ea_arm_t a;
    ea_status_t st =
        ea_arm_load_string_warn("arm.yaml", stiff, strlen(stiff), &a, warn, sizeof warn, &err);
    /* rho g L^3 / EI = 0.501 * 9.81 * 0.914^3 / 705 */
    char g[32];
    snprintf(g, sizeof g, "%.3g", 0.501 * 9.81 * pow(0.914, 3) / 705);
    ea_test_true(st == EA_OK && strstr(warn, want) && strstr(warn, "EI_Nm2 = 705") &&
                     strstr(warn, g) && strstr(warn, "too large"),
                 "EI_Nm2 705 (1000x): loads, with a warning at its line:column naming EI and "
                 "rho g L^3 / EI");
    printf("  want %s, %s in: %s\n", want, g, warn);
    free(stiff);
    ea_test_true(ea_arm_load_warn(path, &a, warn, sizeof warn, &err) == EA_OK && !warn[0],
                 "the paper's arm: no warning");
    char *weak = subst(good, "max_N: 60.0", "max_N: 0.5 ");
    st = ea_arm_load_string_warn("arm.yaml", weak, strlen(weak), &a, warn, sizeof warn, &err);
    ea_test_true(st == EA_OK && strstr(warn, "max_N = 0.5") && strstr(warn, "too low"),
                 "tension max 0.5 N: the cable cannot bend the beam, max_N named");
    printf("  -> %s\n", warn);
    free(weak);
  }
  /* optional measured modal damping ratios */
  ea_test_true(arm.n_damping == 0, "no damping key: undamped");
  {
    char *d = subst(good, "gravity_m_per_s2: 9.81",
                    "gravity_m_per_s2: 9.81\n"
                    "damping:\n  modal_ratios: [0.02, 0.015]");
    ea_arm_t ad;
    ea_test_true(d && ea_arm_load_string("arm.yaml", d, strlen(d), &ad, &err) == EA_OK &&
                     ad.n_damping == 2 && ad.damping_ratio[0] == 0.02 &&
                     ad.damping_ratio[1] == 0.015,
                 "damping.modal_ratios: two measured ratios");
    free(d);
  }
  char dpos[64]; /* the value 1.5: two lines below the gravity key, column 24 */
  {
    int gl = 1;
    for (const char *c = good; *c && c < strstr(good, "gravity_m_per_s2"); ++c)
      gl += *c == '\n';
    snprintf(dpos, sizeof dpos, "arm.yaml:%d:24:", gl + 2);
  }
  expect_error(good, "gravity_m_per_s2: 9.81",
               "gravity_m_per_s2: 9.81\ndamping:\n  modal_ratios: [0.02, 1.5]", dpos,
               "damping.modal_ratios[1] = 1.5: must be in [0, 1)",
               "damping ratio above critical, at the value's line:column");
  expect_error(good, "gravity_m_per_s2: 9.81",
               "gravity_m_per_s2: 9.81\ndamping:\n  modal_ratios: [0.1, 0.1, 0.1, 0.1, 0.1, "
               "0.1, 0.1]",
               "modal_ratios", "1 to 6 numbers, not 7", "more damping ratios than modes kept");
  expect_error(good, "gravity_m_per_s2: 9.81", "gravity_m_per_s2: 9.81\ndamping:\n  zeta: [0.02]",
               "unknown key 'zeta'", NULL, "damping: unknown key");
  {
    const char *seq = "- 1\n- 2\n";
    ea_status_t st = ea_arm_load_string("arm.yaml", seq, strlen(seq), &arm, &err);
    ea_test_true(st != EA_OK && strstr(err.msg, "arm.yaml:1:1: the top level must be a mapping"),
                 "top level not a mapping");
    printf("  -> %s\n", err.msg);
  }

  /* The position points at the offending value. */
  char *bad = subst(good, "EI_Nm2: 0.705", "EI_Nm2: -1");
  ea_arm_load_string("arm.yaml", bad, strlen(bad), &arm, &err);
  int line = 0;
  const char *q = bad;
  for (const char *s = bad; *s && s < strstr(bad, "EI_Nm2: -1"); ++s)
    if (*s == '\n') ++line, q = s + 1;
  char want[64];
  snprintf(want, sizeof want, "arm.yaml:%d:%d:", line + 1, (int)(strstr(bad, "-1") - q) + 1);
  ea_test_true(strstr(err.msg, want) != NULL, "error position is the value's line:column");
  printf("  want %s in: %s\n", want, err.msg);
  free(bad);

  ea_test_true(ea_arm_load("/nonexistent/arm.yaml", &arm, &err) == EA_ERR_IO &&
                   strstr(err.msg, "/nonexistent/arm.yaml"),
               "missing file: EA_ERR_IO naming the file");

  /* A FIFO or a directory is refused at once, naming the path (without the
   * check the FIFO open blocks forever: the alarm makes that a failure). */
  char dir[] = "/tmp/ea_test_arm_XXXXXX";
  if (mkdtemp(dir)) {
    char fifo[64], deep[64], buf[1024];
    snprintf(fifo, sizeof fifo, "%s/arm.fifo", dir);
    ea_test_true(mkfifo(fifo, 0600) == 0, "mkfifo");
    alarm(20);
    ea_status_t st = ea_arm_load(fifo, &arm, &err);
    alarm(0);
    snprintf(buf, sizeof buf, "FIFO -> %s: %s", ea_status_name(st), err.msg);
    ea_test_true(st == EA_ERR_IO && strstr(err.msg, fifo) &&
                     strstr(err.msg, "is a FIFO (named pipe), not a regular file"),
                 buf);
    st = ea_arm_load(dir, &arm, &err);
    snprintf(buf, sizeof buf, "directory -> %s: %s", ea_status_name(st), err.msg);
    ea_test_true(st == EA_ERR_IO && strstr(err.msg, dir) &&
                     strstr(err.msg, "is a directory, not a regular file"),
                 buf);
    /* nesting beyond the cap in a file: refused at the 65th level */
    snprintf(deep, sizeof deep, "%s/deep.yaml", dir);
    FILE *f = fopen(deep, "w");
    if (f) {
      fputs("beam: ", f);
      for (int i = 0; i < 1000; ++i)
        fputs("{a: ", f);
      fputs("1", f);
      for (int i = 0; i < 1000; ++i)
        fputc('}', f);
      fputc('\n', f);
      fclose(f);
    }
    st = ea_arm_load(deep, &arm, &err);
    snprintf(buf, sizeof buf, "1000 levels -> %s: %s", ea_status_name(st), err.msg);
    /* level 65 is the 64th '{a: ' (column 7 + 4 * 63) */
    ea_test_true(st == EA_ERR_PARSE && strstr(err.msg, "deep.yaml:1:259: ") &&
                     strstr(err.msg, "limit of 64 levels"),
                 buf);
    unlink(deep);
    unlink(fifo);
    rmdir(dir);
  } else {
    ea_test_true(0, "mkdtemp");
  }

  /* The error context is written only on failure (ea_status.h): a call that
   * succeeds leaves the caller's message alone. */
  {
    ea_error_t keep;
    memset(&keep, 0, sizeof keep);
    keep.status = EA_ERR_NOTIMPL;
    snprintf(keep.msg, sizeof keep.msg, "sentinel");
    ea_error_t e = keep;
    ea_arm_t a;
    ea_shooter_t *sh = NULL;
    ea_fe_model_t *fe = NULL;
    ea_statics_solution_t sol;
    ea_statics_problem_t pr = ea_statics_problem_cable(0.45, -0.4);
    int ok = ea_arm_load(path, &a, &e) == EA_OK && ea_arm_validate(&a, &e) == EA_OK &&
             ea_shooter_alloc(&a, NULL, &sh, &e) == EA_OK &&
             ea_statics_solve(sh, &pr, NULL, NULL, &sol, &e) == EA_OK &&
             ea_fe_model_alloc(&a, NULL, &fe, &e) == EA_OK;
    ea_test_true(ok && e.status == keep.status && !strcmp(e.msg, "sentinel"),
                 "successful calls leave the error context as it was");
    ea_fe_model_free(fe);
    ea_shooter_free(sh);
    a.EI = -1.0;
    ea_test_true(ea_arm_validate(&a, &e) == EA_ERR_INPUT && e.status == EA_ERR_INPUT &&
                     strcmp(e.msg, "sentinel"),
                 "a failed call writes its status and message");
  }
  test_arm_hash(good);
  free(good);
  return ea_test_summary("test_arm_file");
}
