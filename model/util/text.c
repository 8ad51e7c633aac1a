/* Text helpers of the utility layer (ea_util.h): a growable string buffer,
 * CSV quoting, file name extensions. */
#include "ea_util.h"

#include <stdarg.h>
#include <stdlib.h>
#include <string.h>

void ea__sbuf_put(ea__sbuf_t *b, const char *text, size_t len) {
  if (b->oom) return;
  if (b->len + len + 1 > b->cap) {
    size_t cap = b->cap ? b->cap : 256;
    while (cap < b->len + len + 1)
      cap *= 2;
    char *s = realloc(b->s, cap);
    if (!s) {
      b->oom = 1;
      return;
    }
    b->s = s;
    b->cap = cap;
  }
  memcpy(b->s + b->len, text, len);
  b->len += len;
  b->s[b->len] = '\0';
}

void ea__sbuf_printf(ea__sbuf_t *b, const char *fmt, ...) {
  char tmp[1024];
  va_list ap;
  va_start(ap, fmt);
  int n = vsnprintf(tmp, sizeof tmp, fmt, ap);
  va_end(ap);
  if (n < 0) return;
  if ((size_t)n < sizeof tmp) {
    ea__sbuf_put(b, tmp, (size_t)n);
    return;
  }
  char *big = malloc((size_t)n + 1);
  if (!big) {
    b->oom = 1;
    return;
  }
  va_start(ap, fmt);
  vsnprintf(big, (size_t)n + 1, fmt, ap);
  va_end(ap);
  ea__sbuf_put(b, big, (size_t)n);
  free(big);
}

void ea__sbuf_free(ea__sbuf_t *b) {
  free(b->s);
  memset(b, 0, sizeof *b);
}

/* The character c as it appears inside a quoted CSV field: '"' doubled, line
 * breaks as spaces (a row stays one line), others as they are. */
static const char *ea__csv_char(const char *c, size_t *len) {
  *len = 1;
  if (*c == '"') {
    *len = 2;
    return "\"\"";
  }
  if (*c == '\n' || *c == '\r') return " ";
  return c;
}

void ea__sbuf_csv_quote(ea__sbuf_t *b, const char *text) {
  ea__sbuf_put(b, "\"", 1);
  for (const char *c = text ? text : ""; *c; ++c) {
    size_t n;
    const char *s = ea__csv_char(c, &n);
    ea__sbuf_put(b, s, n);
  }
  ea__sbuf_put(b, "\"", 1);
}

void ea__csv_quote(FILE *fp, const char *text) {
  fputc('"', fp);
  for (const char *c = text ? text : ""; *c; ++c) {
    size_t n;
    const char *s = ea__csv_char(c, &n);
    fwrite(s, 1, n, fp);
  }
  fputc('"', fp);
}

void ea__replace_ext(const char *in, const char *ext, char *out, size_t len) {
  const char *dot = strrchr(in, '.'), *slash = strrchr(in, '/');
  const size_t stem = (dot && (!slash || dot > slash)) ? (size_t)(dot - in) : strlen(in);
  snprintf(out, len, "%.*s%s", (int)stem, in, ext);
}
