/* Figures through gnuplot: a script is built in memory (data inline as
 * $blocks) and given to gnuplot as its standard input; gnuplot draws to a
 * temporary file beside the target, created (so the directory is known to
 * be writable) when the figure is opened, and renamed onto the target when
 * gnuplot succeeds. gnuplot's standard output goes to /dev/null (never to
 * ours: a failed 'set output' would make it draw there) and its standard
 * error to a temporary file whose last line goes into the error message.
 * All figure code of the project goes through here. */
#include "ea_util.h"
#include "figure_impl.h"

#include <errno.h>
#include <math.h>
#include <fcntl.h>
#include <spawn.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

extern char **environ;

struct ea_plot {
  char *buf;
  size_t len;
  FILE *script; /* open_memstream */
  char out[1024];
  char tmp[1100];
};

ea_status_t ea_plot_open(ea_plot_t **pp, const char *out_path, int width, int height,
                         ea_error_t *err) {
  *pp = NULL;
  if (!out_path || strlen(out_path) >= 1024)
    return ea_error_set(err, EA_ERR_ARG, "figure path missing or too long");
  const char *ext = strrchr(out_path, '.');
  const char *term = NULL;
  if (ext && !strcmp(ext, ".svg"))
    term = "svg dynamic enhanced font 'Sans,12' background rgb 'white'";
  else if (ext && !strcmp(ext, ".png"))
    term = "pngcairo enhanced font 'Sans,11'";
  else if (ext && !strcmp(ext, ".pdf"))
    term = "pdfcairo enhanced font 'Sans,10'";
  else
    return ea_error_set(err, EA_ERR_ARG, "%s: figure must end in .svg, .png or .pdf", out_path);
  ea_status_t st = ea_mkdir_parents(out_path, err);
  if (st) return st;
  ea_plot_t *p = calloc(1, sizeof *p);
  if (!p) return ea_error_set(err, EA_ERR_NOMEM, "out of memory");
  snprintf(p->out, sizeof p->out, "%s", out_path);
  /* The temporary now: proves the directory writable before any work. */
  ea__afile_clean_stale(out_path);
  snprintf(p->tmp, sizeof p->tmp, "%s.tmp%ld.XXXXXX%s", out_path, (long)getpid(), ext);
  const int fd = mkstemps(p->tmp, (int)strlen(ext));
  if (fd < 0) {
    const int eno = errno;
    free(p);
    return ea_error_set(err, EA_ERR_IO, "%s: cannot write the figure there: %s", out_path,
                        strerror(eno));
  }
  const mode_t mask = umask(0);
  umask(mask);
  if (fchmod(fd, 0666 & ~mask) != 0) {
    /* not fatal: the figure stays private */
  }
  close(fd);
  p->script = open_memstream(&p->buf, &p->len);
  if (!p->script) {
    unlink(p->tmp);
    free(p);
    return ea_error_set(err, EA_ERR_NOMEM, "out of memory");
  }
  if (width <= 0) width = 900;
  if (height <= 0) height = 650;
  const int pdf = !strcmp(ext, ".pdf");
  if (pdf)
    fprintf(p->script, "set terminal %s size %gin,%gin\n", term, width / 100.0, height / 100.0);
  else
    fprintf(p->script, "set terminal %s size %d,%d\n", term, width, height);
  char q[2 * sizeof p->tmp + 3];
  fprintf(p->script, "set output %s\nset grid\nset key box opaque\n",
          ea_plot_quote(p->tmp, q, sizeof q));
  *pp = p;
  return EA_OK;
}

const char *ea_plot_quote(const char *text, char *buf, size_t len) {
  size_t o = 0;
  if (len < 3) {
    if (len) buf[0] = '\0';
    return buf;
  }
  buf[o++] = '\'';
  for (const char *c = text ? text : ""; *c && o + 3 < len; ++c) {
    if (*c == '\'') {
      if (o + 4 >= len) break;
      buf[o++] = '\'';
      buf[o++] = '\'';
    } else {
      buf[o++] = (*c == '\n' || *c == '\r') ? ' ' : *c;
    }
  }
  buf[o++] = '\'';
  buf[o] = '\0';
  return buf;
}

void ea_plot_cmd(ea_plot_t *p, const char *fmt, ...) {
  va_list ap;
  va_start(ap, fmt);
  vfprintf(p->script, fmt, ap);
  va_end(ap);
  fputc('\n', p->script);
}

void ea_plot_data_begin(ea_plot_t *p, const char *name) {
  fprintf(p->script, "$%s << EOD\n", name);
}

void ea_plot_data_row(ea_plot_t *p, int n, const double *v) {
  for (int i = 0; i < n; ++i)
    if (v[i] != v[i]) {
      fputc('\n', p->script);
      return;
    }
  for (int i = 0; i < n; ++i)
    fprintf(p->script, i ? " %.9g" : "%.9g", v[i]);
  fputc('\n', p->script);
}

void ea_plot_data_end(ea_plot_t *p) {
  fputs("EOD\n", p->script);
}

void ea_plot_discard(ea_plot_t *p) {
  if (!p) return;
  if (p->script) fclose(p->script);
  unlink(p->tmp);
  free(p->buf);
  free(p);
}

/* The last non-blank line of fp (gnuplot's error), trimmed, into buf. */
static void ea__last_line(FILE *fp, char *buf, size_t len) {
  buf[0] = '\0';
  if (!fp || fseek(fp, 0, SEEK_SET) != 0) return;
  char line[512];
  while (fgets(line, sizeof line, fp)) {
    size_t n = strlen(line);
    while (n && (line[n - 1] == '\n' || line[n - 1] == '\r' || line[n - 1] == ' '))
      line[--n] = '\0';
    const char *s = line;
    while (*s == ' ' || *s == '\t' || *s == '^')
      ++s;
    if (*s) snprintf(buf, len, "%s", s);
  }
}

/* Run gnuplot: stdin = script, stdout = /dev/null, stderr = errf. Returns
 * the wait status, or -1 (errno set) if it could not be started. */
static int ea__run_gnuplot(FILE *script, FILE *errf) {
  posix_spawn_file_actions_t fa;
  if (posix_spawn_file_actions_init(&fa) != 0) return -1;
  int rc = posix_spawn_file_actions_adddup2(&fa, fileno(script), STDIN_FILENO);
  if (!rc) rc = posix_spawn_file_actions_addopen(&fa, STDOUT_FILENO, "/dev/null", O_WRONLY, 0);
  if (!rc) rc = posix_spawn_file_actions_adddup2(&fa, fileno(errf), STDERR_FILENO);
  pid_t pid = -1;
  char *argv[] = {(char *)"gnuplot", NULL};
  if (!rc) rc = posix_spawnp(&pid, "gnuplot", &fa, NULL, argv, environ);
  posix_spawn_file_actions_destroy(&fa);
  if (rc) {
    errno = rc;
    return -1;
  }
  int status = 0;
  while (waitpid(pid, &status, 0) < 0)
    if (errno != EINTR) return -1;
  return status;
}

ea_status_t ea_plot_close(ea_plot_t *p, ea_error_t *err) {
  if (!p) return ea_error_set(err, EA_ERR_ARG, "no figure");
  fputs("unset output\n", p->script);
  fclose(p->script);
  p->script = NULL;
  ea_status_t st = EA_OK;
  FILE *script = tmpfile(), *errf = tmpfile();
  if (!script || !errf || fwrite(p->buf, 1, p->len, script) != p->len || fflush(script) != 0 ||
      fseek(script, 0, SEEK_SET) != 0) {
    st = ea_error_set(err, EA_ERR_IO, "%s: cannot make the gnuplot script: %s", p->out,
                      strerror(errno));
  } else {
    const int rc = ea__run_gnuplot(script, errf);
    char msg[400];
    ea__last_line(errf, msg, sizeof msg);
    struct stat sb;
    if (rc == -1 || (WIFEXITED(rc) && WEXITSTATUS(rc) == 127))
      st = ea_error_set(err, EA_ERR_IO, "%s: cannot run gnuplot (install gnuplot-nox)", p->out);
    else if (!WIFEXITED(rc) || WEXITSTATUS(rc) != 0)
      st = ea_error_set(err, EA_ERR_IO, "%s: gnuplot failed (exit %d)%s%s", p->out,
                        WIFEXITED(rc) ? WEXITSTATUS(rc) : -1, msg[0] ? ": " : "", msg);
    else if (stat(p->tmp, &sb) != 0 || sb.st_size == 0)
      st = ea_error_set(err, EA_ERR_IO, "%s: gnuplot wrote nothing%s%s", p->out, msg[0] ? ": " : "",
                        msg);
    else if (rename(p->tmp, p->out) != 0)
      st = ea_error_set(err, EA_ERR_IO, "%s: cannot write the figure: %s", p->out, strerror(errno));
  }
  if (script) fclose(script);
  if (errf) fclose(errf);
  if (st) unlink(p->tmp);
  free(p->buf);
  free(p);
  return st;
}

const char *ea_plot_enh(const char *text, char *buf, size_t len) {
  size_t o = 0;
  if (!len) return buf;
  for (const char *c = text ? text : ""; *c && o + 3 < len; ++c) {
    if (*c == '\n' || *c == '\r') {
      buf[o++] = ' ';
      continue;
    }
    if (strchr("_^{}@&~", *c)) buf[o++] = '\\'; /* a literal in enhanced text */
    if (*c == '\'') buf[o++] = '\'';            /* '' inside a single-quoted string */
    buf[o++] = *c;
  }
  buf[o] = '\0';
  return buf;
}

void ea_plot_palette_viridis(ea_plot_t *p) {
  /* matplotlib's viridis at 0, 1/8, ..., 1 */
  ea_plot_cmd(p, "set palette defined (0 '#440154', 1 '#472c7a', 2 '#3b518b', 3 '#2c718e', "
                 "4 '#21908d', 5 '#27ad81', 6 '#5cc863', 7 '#aadc32', 8 '#fde725')  # viridis");
}

const char *ea_plot_colour(int i) {
  static const char *const c[EA_PLOT_NCOLOURS] = {"#0072b2", "#d55e00", "#009e73", "#cc79a7",
                                                  "#e69f00", "#56b4e9", "#000000", "#882255"};
  return c[((i % EA_PLOT_NCOLOURS) + EA_PLOT_NCOLOURS) % EA_PLOT_NCOLOURS];
}

const char *ea_plot_style(int i, int points, char *buf, size_t len) {
  static const int pt[] = {7, 5, 9, 11, 13}; /* filled circle, square, triangles, diamond */
  const int k = i / EA_PLOT_NCOLOURS;
  if (points)
    snprintf(buf, len, "lc rgb '%s' dt %d pt %d", ea_plot_colour(i), 1 + k % 5, pt[k % 5]);
  else
    snprintf(buf, len, "lc rgb '%s' dt %d", ea_plot_colour(i), 1 + k % 5);
  return buf;
}

void ea_plot_beam(ea_plot_t *p, ea_shooter_t *sh, const double params[EA_NP], int n) {
  double xs[101], ys[101];
  if (n > 101) n = 101;
  if (ea_shoot_shape(sh, params, n, NULL, NULL, NULL, xs, ys) != EA_OK) return;
  for (int i = 0; i < n; ++i)
    ea_plot_data_row(p, 2, (double[]){xs[i], ys[i]});
  const double nan = NAN;
  ea_plot_data_row(p, 1, &nan);
}

int ea_plot_region(ea_plot_t *p, const char *name, const ea_arm_t *arm,
                   const ea_config_point_t *outer, int n, double inner_length) {
  int first = -1, last = -1;
  for (int k = 0; k < n; ++k)
    if (outer[k].status == EA_OK) {
      if (first < 0) first = k;
      last = k;
    }
  if (first < 0) return 0;
  int rows = 0;
  ea_plot_data_begin(p, name);
  for (int k = first; k <= last; ++k)
    if (outer[k].status == EA_OK) {
      ea_plot_data_row(p, 2, (double[]){outer[k].x, outer[k].y});
      ++rows;
    }
  /* the inner edge from the last solved angle back to the first: the cable at
   * inner_length, a straight line from the root (the sides lie along it) */
  for (int k = last; k >= first; --k) {
    if (outer[k].status != EA_OK) continue;
    const double a = outer[k].alpha;
    ea_plot_data_row(
        p, 2, (double[]){arm->x_c + inner_length * cos(a), arm->y_c + inner_length * sin(a)});
    ++rows;
  }
  ea_plot_data_row(p, 2, (double[]){outer[first].x, outer[first].y});
  ea_plot_data_end(p);
  return rows + 1;
}
