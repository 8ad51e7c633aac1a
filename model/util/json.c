/* A minimal JSON emitter: enough for summaries; strings are escaped. */
#include "ea_util.h"

#include <math.h>

void ea_json_init(ea_json_t *j, FILE *fp, int pretty) {
  j->fp = fp;
  j->depth = 0;
  j->first[0] = 1;
  j->pretty = pretty;
}

static void ea__jstr(FILE *fp, const char *s) {
  fputc('"', fp);
  for (; s && *s; ++s) {
    const unsigned char c = (unsigned char)*s;
    if (c == '"' || c == '\\')
      fprintf(fp, "\\%c", c);
    else if (c == '\n')
      fputs("\\n", fp);
    else if (c == '\t')
      fputs("\\t", fp);
    else if (c < 0x20)
      fprintf(fp, "\\u%04x", c);
    else
      fputc(c, fp);
  }
  fputc('"', fp);
}

static void ea__jsep(ea_json_t *j, const char *key) {
  if (!j->first[j->depth]) fputc(',', j->fp);
  j->first[j->depth] = 0;
  if (j->pretty && j->depth > 0) {
    fputc('\n', j->fp);
    for (int i = 0; i < j->depth; ++i)
      fputs("  ", j->fp);
  }
  if (key) {
    ea__jstr(j->fp, key);
    fputs(j->pretty ? ": " : ":", j->fp);
  }
}

static void ea__jopen(ea_json_t *j, const char *key, char c) {
  ea__jsep(j, key);
  fputc(c, j->fp);
  if (j->depth < 31) ++j->depth;
  j->first[j->depth] = 1;
}

static void ea__jclose(ea_json_t *j, char c) {
  const int empty = j->first[j->depth];
  if (j->depth > 0) --j->depth;
  if (j->pretty && !empty) {
    fputc('\n', j->fp);
    for (int i = 0; i < j->depth; ++i)
      fputs("  ", j->fp);
  }
  fputc(c, j->fp);
}

void ea_json_obj_begin(ea_json_t *j, const char *key) {
  ea__jopen(j, key, '{');
}
void ea_json_obj_end(ea_json_t *j) {
  ea__jclose(j, '}');
}
void ea_json_arr_begin(ea_json_t *j, const char *key) {
  ea__jopen(j, key, '[');
}
void ea_json_arr_end(ea_json_t *j) {
  ea__jclose(j, ']');
}

static void ea__jnum(FILE *fp, double v) {
  if (isfinite(v))
    fprintf(fp, "%.17g", v);
  else
    fputs("null", fp);
}

void ea_json_num(ea_json_t *j, const char *key, double v) {
  ea__jsep(j, key);
  ea__jnum(j->fp, v);
}
void ea_json_int(ea_json_t *j, const char *key, long v) {
  ea__jsep(j, key);
  fprintf(j->fp, "%ld", v);
}
void ea_json_bool(ea_json_t *j, const char *key, int v) {
  ea__jsep(j, key);
  fputs(v ? "true" : "false", j->fp);
}
void ea_json_str(ea_json_t *j, const char *key, const char *v) {
  ea__jsep(j, key);
  ea__jstr(j->fp, v);
}
void ea_json_null(ea_json_t *j, const char *key) {
  ea__jsep(j, key);
  fputs("null", j->fp);
}
void ea_json_vec(ea_json_t *j, const char *key, const double *v, int n) {
  ea__jsep(j, key);
  fputc('[', j->fp);
  for (int i = 0; i < n; ++i) {
    if (i) fputc(',', j->fp);
    ea__jnum(j->fp, v[i]);
  }
  fputc(']', j->fp);
}
void ea_json_end(ea_json_t *j) {
  fputc('\n', j->fp);
}
