/* Figures through gnuplot: a script is built in memory (data inline as
 * $blocks), piped to gnuplot, which draws to a temporary file that is
 * renamed onto the target when gnuplot succeeds. All figure code of the
 * project goes through here. */
#include "ea_planner.h"

#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <unistd.h>

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
  p->script = open_memstream(&p->buf, &p->len);
  if (!p->script) {
    free(p);
    return ea_error_set(err, EA_ERR_NOMEM, "out of memory");
  }
  snprintf(p->out, sizeof p->out, "%s", out_path);
  snprintf(p->tmp, sizeof p->tmp, "%s.tmp%ld%s", out_path, (long)getpid(), ext);
  if (width <= 0) width = 900;
  if (height <= 0) height = 650;
  const int pdf = !strcmp(ext, ".pdf");
  if (pdf)
    fprintf(p->script, "set terminal %s size %gin,%gin\n", term, width / 100.0, height / 100.0);
  else
    fprintf(p->script, "set terminal %s size %d,%d\n", term, width, height);
  fprintf(p->script, "set output '%s'\nset grid\nset key box opaque\n", p->tmp);
  *pp = p;
  return EA_OK;
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
  free(p->buf);
  free(p);
}

ea_status_t ea_plot_close(ea_plot_t *p, ea_error_t *err) {
  if (!p) return ea_error_set(err, EA_ERR_ARG, "no figure");
  fputs("unset output\n", p->script);
  fclose(p->script);
  p->script = NULL;
  ea_status_t st = EA_OK;
  FILE *gp = popen("gnuplot 2>/dev/null", "w");
  if (!gp) {
    st = ea_error_set(err, EA_ERR_IO, "%s: cannot run gnuplot (install gnuplot-nox)", p->out);
  } else {
    fwrite(p->buf, 1, p->len, gp);
    int rc = pclose(gp);
    if (rc == -1 || !WIFEXITED(rc) || WEXITSTATUS(rc) != 0)
      st = ea_error_set(err, EA_ERR_IO, "%s: gnuplot failed (exit %d; is gnuplot-nox installed?)",
                        p->out, WIFEXITED(rc) ? WEXITSTATUS(rc) : -1);
    else if (rename(p->tmp, p->out) != 0)
      st = ea_error_set(err, EA_ERR_IO, "%s: cannot write the figure", p->out);
  }
  if (st) unlink(p->tmp);
  free(p->buf);
  free(p);
  return st;
}
