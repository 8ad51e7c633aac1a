/* Measurement records (docs/calibration.md): plain CSV with '# key: value' header lines,
 * one header row of column names, data rows. Every error names file:line:column, the
 * column and the value. */
#include "ea_calib.h"
#include "ea_util.h"

#include <ctype.h>
#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>

static const char *const ea__ch_col[EA_CALIB_NCH] = {
    "theta0_rad", "shoulder_torque_Nm", "tension_N", "tip_x_m", "tip_y_m", "cable_angle_rad"};
static const char *const ea__ch_unit[EA_CALIB_NCH] = {"rad", "N m", "N", "m", "m", "rad"};

const char *ea_calib_channel_column(int ch) {
  return (ch >= 0 && ch < EA_CALIB_NCH) ? ea__ch_col[ch] : "unknown";
}
const char *ea_calib_channel_unit(int ch) {
  return (ch >= 0 && ch < EA_CALIB_NCH) ? ea__ch_unit[ch] : "";
}

void ea_calib_record_free(ea_calib_record_t *rec) {
  if (!rec) return;
  free(rec->line);
  free(rec->cable_length);
  free(rec->payload);
  free(rec->t);
  for (int c = 0; c < EA_CALIB_NCH; ++c)
    free(rec->ch[c]);
  memset(rec, 0, sizeof *rec);
}

/* Column roles beyond the channels. */
enum { EA__COL_CABLE_LENGTH = EA_CALIB_NCH, EA__COL_PAYLOAD, EA__COL_T, EA__NCOL };

static int ea__col_role(const char *name, size_t n) {
  for (int c = 0; c < EA_CALIB_NCH; ++c)
    if (strlen(ea__ch_col[c]) == n && !strncmp(name, ea__ch_col[c], n)) return c;
  if (n == 14 && !strncmp(name, "cable_length_m", n)) return EA__COL_CABLE_LENGTH;
  if (n == 10 && !strncmp(name, "payload_kg", n)) return EA__COL_PAYLOAD;
  if (n == 3 && !strncmp(name, "t_s", n)) return EA__COL_T;
  return -1;
}

/* Strict number: the whole field (surrounding blanks allowed) a finite double. */
static int ea__num(const char *s, size_t n, double *out) {
  char buf[128];
  while (n && isspace((unsigned char)*s))
    ++s, --n;
  while (n && isspace((unsigned char)s[n - 1]))
    --n;
  if (!n || n >= sizeof buf) return 0;
  memcpy(buf, s, n);
  buf[n] = '\0';
  char *end;
  errno = 0;
  const double v = strtod(buf, &end);
  if (end != buf + n || errno == ERANGE || !isfinite(v)) return 0;
  *out = v;
  return 1;
}

/* A field's text for a message: at most 40 characters, no line break. */
static void ea__field_text(const char *s, size_t n, char *buf, size_t len) {
  if (n > 40) n = 40;
  size_t k = 0;
  for (size_t i = 0; i < n && k + 1 < len; ++i)
    buf[k++] = (s[i] == '\r' || s[i] == '\n') ? ' ' : s[i];
  buf[k] = '\0';
}

typedef struct {
  const char *name;
  int line;
  ea_error_t *err;
} ea__rd_t;

#define EA__ERR(rd, line, col, st, ...) ea__rerr(rd, line, col, st, __VA_ARGS__)

static ea_status_t ea__rerr(ea__rd_t *rd, int line, int col, ea_status_t st, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 5, 6)))
#endif
    ;
static ea_status_t ea__rerr(ea__rd_t *rd, int line, int col, ea_status_t st, const char *fmt, ...) {
  char msg[400];
  va_list ap;
  va_start(ap, fmt);
  vsnprintf(msg, sizeof msg, fmt, ap);
  va_end(ap);
  return ea_error_set(rd->err, st, "%s:%d:%d: %s", rd->name, line, col, msg);
}

/* Header value "# key: value" of a noise key etc.: a positive finite number. */
static ea_status_t ea__hdr_num(ea__rd_t *rd, int line, int col, const char *key, const char *v,
                               size_t n, double lo, int lo_open, double *out) {
  char t[64];
  ea__field_text(v, n, t, sizeof t);
  double x;
  if (!ea__num(v, n, &x))
    return EA__ERR(rd, line, col, EA_ERR_INPUT, "header '%s': '%s' is not a finite number", key, t);
  if (lo_open ? !(x > lo) : !(x >= lo))
    return EA__ERR(rd, line, col, EA_ERR_INPUT, "header '%s' = %s: must be %s %g", key, t,
                   lo_open ? ">" : ">=", lo);
  *out = x;
  return EA_OK;
}

static const struct {
  const char *key;
  int ch;
} ea__noise_keys[] = {{"noise_theta0_rad", EA_CALIB_CH_THETA0},
                      {"noise_torque_Nm", EA_CALIB_CH_TORQUE},
                      {"noise_tension_N", EA_CALIB_CH_TENSION},
                      {"noise_tip_m", EA_CALIB_CH_TIP_X},
                      {"noise_cable_angle_rad", EA_CALIB_CH_CABLE_ANGLE}};

ea_status_t ea_calib_record_parse(const char *name, const char *text, size_t len,
                                  ea_calib_record_t *rec, ea_error_t *err) {
  if (!rec) return ea_error_set(err, EA_ERR_ARG, "ea_calib_record_parse: NULL record");
  memset(rec, 0, sizeof *rec);
  if (!text || !name) return ea_error_set(err, EA_ERR_ARG, "ea_calib_record_parse: NULL argument");
  snprintf(rec->path, sizeof rec->path, "%s", name);
  for (int c = 0; c < EA_CALIB_NCH; ++c)
    rec->noise[c] = NAN;
  rec->hold_cable_length = rec->hold_theta0 = NAN;
  ea__rd_t rd = {name, 0, err};
  ea_status_t st = EA_OK;
  int kind = -1, have_header_row = 0, ncol = 0, cap = 0;
  int role[64];
  int col_pos[64];
  double hold_payload = NAN;
  int payload_line = 0;
  double *cols[EA__NCOL] = {0};
  const char *p = text, *end = text + len;
  int line = 0;
  while (p < end) {
    const char *nl = memchr(p, '\n', (size_t)(end - p));
    const char *le = nl ? nl : end;
    ++line;
    size_t n = (size_t)(le - p);
    if (n && p[n - 1] == '\r') --n;
    const char *s = p;
    p = nl ? nl + 1 : end;
    if (line == 1) {
      if (!(n >= 21 && !strncmp(s, "# elasticarm-record 1", 21) &&
            (n == 21 || isspace((unsigned char)s[21])))) {
        char t[64];
        ea__field_text(s, n, t, sizeof t);
        st = EA__ERR(&rd, 1, 1, EA_ERR_PARSE,
                     "not a measurement record: the first line must be '# elasticarm-record 1' "
                     "(found '%s')",
                     t);
        goto fail;
      }
      continue;
    }
    if (n && s[0] == '#') {
      if (have_header_row) {
        st = EA__ERR(&rd, line, 1, EA_ERR_PARSE,
                     "a '#' line after the header row (comments come only before it)");
        goto fail;
      }
      const char *k = s + 1;
      while (k < s + n && *k == ' ')
        ++k;
      const char *colon = memchr(k, ':', (size_t)(s + n - k));
      if (!colon) continue; /* a comment */
      const size_t kl = (size_t)(colon - k);
      const char *v = colon + 1;
      while (v < s + n && *v == ' ')
        ++v;
      const size_t vl = (size_t)(s + n - v);
      const int vcol = (int)(v - s) + 1;
      char key[64];
      ea__field_text(k, kl, key, sizeof key);
      if (!strcmp(key, "kind")) {
        char t[64];
        ea__field_text(v, vl, t, sizeof t);
        while (strlen(t) && isspace((unsigned char)t[strlen(t) - 1]))
          t[strlen(t) - 1] = '\0';
        if (!strcmp(t, "static"))
          kind = EA_CALIB_STATIC;
        else if (!strcmp(t, "ringdown"))
          kind = EA_CALIB_RINGDOWN;
        else {
          st = EA__ERR(&rd, line, vcol, EA_ERR_INPUT,
                       "header 'kind': '%s' is neither 'static' nor 'ringdown'", t);
          goto fail;
        }
      } else if (!strcmp(key, "arm_file")) {
        snprintf(rec->arm_file, sizeof rec->arm_file, "%.*s", (int)vl, v);
      } else if (!strcmp(key, "source")) {
        snprintf(rec->source, sizeof rec->source, "%.*s", (int)vl, v);
      } else if (!strcmp(key, "payload_kg") && vl == 7 && !strncmp(v, "unknown", 7)) {
        rec->payload_unknown = 1; /* the fit estimates it (one unknown payload) */
        payload_line = line;
      } else if (!strcmp(key, "payload_kg")) {
        if ((st = ea__hdr_num(&rd, line, vcol, key, v, vl, 0.0, 0, &hold_payload))) goto fail;
        payload_line = line;
      } else if (!strcmp(key, "cable_length_m")) {
        if ((st = ea__hdr_num(&rd, line, vcol, key, v, vl, 0.0, 1, &rec->hold_cable_length)))
          goto fail;
      } else if (!strcmp(key, "theta0_rad")) {
        if ((st = ea__hdr_num(&rd, line, vcol, key, v, vl, -INFINITY, 0, &rec->hold_theta0)))
          goto fail;
      } else if (!strncmp(key, "noise_", 6)) {
        size_t i = 0;
        for (; i < sizeof ea__noise_keys / sizeof *ea__noise_keys; ++i)
          if (!strcmp(key, ea__noise_keys[i].key)) break;
        if (i == sizeof ea__noise_keys / sizeof *ea__noise_keys) {
          st = EA__ERR(&rd, line, 3, EA_ERR_INPUT,
                       "unknown noise header '%s' (known: noise_theta0_rad, noise_torque_Nm, "
                       "noise_tension_N, noise_tip_m, noise_cable_angle_rad)",
                       key);
          goto fail;
        }
        double x;
        if ((st = ea__hdr_num(&rd, line, vcol, key, v, vl, 0.0, 1, &x))) goto fail;
        rec->noise[ea__noise_keys[i].ch] = x;
        if (ea__noise_keys[i].ch == EA_CALIB_CH_TIP_X) rec->noise[EA_CALIB_CH_TIP_Y] = x;
      } /* other keys: informative, ignored */
      continue;
    }
    if (!have_header_row) {
      if (n == 0) continue;
      if (kind < 0) {
        st = EA__ERR(&rd, line, 1, EA_ERR_INPUT,
                     "no '# kind: static' or '# kind: ringdown' header before the column names");
        goto fail;
      }
      have_header_row = 1;
      /* the column names */
      const char *f = s;
      while (f <= s + n) {
        const char *c = memchr(f, ',', (size_t)(s + n - f));
        const char *fe = c ? c : s + n;
        const int fcol = (int)(f - s) + 1;
        const char *a = f, *b = fe;
        while (a < b && isspace((unsigned char)*a))
          ++a;
        while (b > a && isspace((unsigned char)b[-1]))
          --b;
        char t[64];
        ea__field_text(a, (size_t)(b - a), t, sizeof t);
        if (ncol >= 64) {
          st = EA__ERR(&rd, line, fcol, EA_ERR_INPUT, "more than 64 columns");
          goto fail;
        }
        const int r = ea__col_role(a, (size_t)(b - a));
        const int ok =
            r >= 0 && (kind == EA_CALIB_STATIC
                           ? r != EA__COL_T
                           : (r == EA__COL_T || (r < EA_CALIB_NCH && r != EA_CALIB_CH_THETA0)));
        if (!ok) {
          st = EA__ERR(
              &rd, line, fcol, EA_ERR_INPUT, "column %d: '%s' is not a column of a %s record (%s)",
              ncol + 1, t, kind == EA_CALIB_STATIC ? "static" : "ring-down",
              kind == EA_CALIB_STATIC
                  ? "cable_length_m, cable_angle_rad, theta0_rad, payload_kg, "
                    "shoulder_torque_Nm, tension_N, tip_x_m, tip_y_m"
                  : "t_s, shoulder_torque_Nm, tension_N, tip_x_m, tip_y_m, cable_angle_rad");
          goto fail;
        }
        for (int j = 0; j < ncol; ++j)
          if (role[j] == r) {
            st = EA__ERR(&rd, line, fcol, EA_ERR_INPUT, "column %d: '%s' appears twice", ncol + 1,
                         t);
            goto fail;
          }
        role[ncol] = r;
        col_pos[ncol] = fcol;
        ++ncol;
        if (!c) break;
        f = c + 1;
      }
      int seen[EA__NCOL] = {0};
      for (int j = 0; j < ncol; ++j)
        seen[role[j]] = 1;
      const char *missing = NULL;
      if (kind == EA_CALIB_STATIC) {
        if (!seen[EA__COL_CABLE_LENGTH])
          missing = "cable_length_m";
        else if (!seen[EA_CALIB_CH_THETA0])
          missing = "theta0_rad";
      } else {
        if (!seen[EA__COL_T]) missing = "t_s";
        int any = 0;
        for (int c = 0; c < EA_CALIB_NCH; ++c)
          any |= seen[c];
        if (!missing && !any)
          missing = "a measured column (shoulder_torque_Nm, tension_N, tip_x_m, tip_y_m or "
                    "cable_angle_rad)";
      }
      if (missing) {
        st = EA__ERR(&rd, line, 1, EA_ERR_INPUT, "the %s record has no column %s",
                     kind == EA_CALIB_STATIC ? "static" : "ring-down", missing);
        goto fail;
      }
      continue;
    }
    if (n == 0) { /* a blank line: only at the end */
      const char *q = p;
      while (q < end && (*q == '\n' || *q == '\r' || *q == ' '))
        ++q;
      if (q == end) break;
      st = EA__ERR(&rd, line, 1, EA_ERR_PARSE, "empty line between data rows");
      goto fail;
    }
    /* a data row */
    if (rec->rows == cap) {
      cap = cap ? 2 * cap : 64;
      for (int r = 0; r < EA__NCOL; ++r) {
        double *q = realloc(cols[r], (size_t)cap * sizeof *q);
        if (!q) {
          st = ea_error_set(err, EA_ERR_NOMEM, "%s: out of memory at line %d", name, line);
          goto fail;
        }
        cols[r] = q;
      }
      int *ql = realloc(rec->line, (size_t)cap * sizeof *ql);
      if (!ql) {
        st = ea_error_set(err, EA_ERR_NOMEM, "%s: out of memory at line %d", name, line);
        goto fail;
      }
      rec->line = ql;
    }
    const char *f = s;
    int j = 0;
    for (;;) {
      const char *c = memchr(f, ',', (size_t)(s + n - f));
      const char *fe = c ? c : s + n;
      const int fcol = (int)(f - s) + 1;
      if (j >= ncol) {
        st = EA__ERR(&rd, line, fcol, EA_ERR_PARSE, "more fields than the %d columns of the header",
                     ncol);
        goto fail;
      }
      double x;
      if (!ea__num(f, (size_t)(fe - f), &x)) {
        char t[64];
        ea__field_text(f, (size_t)(fe - f), t, sizeof t);
        const char *cn = role[j] < EA_CALIB_NCH            ? ea__ch_col[role[j]]
                         : role[j] == EA__COL_CABLE_LENGTH ? "cable_length_m"
                         : role[j] == EA__COL_PAYLOAD      ? "payload_kg"
                                                           : "t_s";
        st = EA__ERR(&rd, line, fcol, EA_ERR_INPUT, "column %d (%s): '%s' is not a finite number",
                     j + 1, cn, t);
        goto fail;
      }
      if ((role[j] == EA__COL_CABLE_LENGTH && !(x > 0)) || (role[j] == EA__COL_PAYLOAD && x < 0)) {
        st = EA__ERR(&rd, line, fcol, EA_ERR_INPUT, "column %d (%s): %.17g must be %s", j + 1,
                     role[j] == EA__COL_PAYLOAD ? "payload_kg" : "cable_length_m", x,
                     role[j] == EA__COL_PAYLOAD ? ">= 0" : "> 0");
        goto fail;
      }
      cols[role[j]][rec->rows] = x;
      ++j;
      if (!c) break;
      f = c + 1;
    }
    if (j < ncol) {
      st = EA__ERR(&rd, line, (int)n + 1, EA_ERR_PARSE,
                   "%d fields, the header has %d columns (column %d, %s, is missing)", j, ncol,
                   j + 1,
                   role[j] < EA_CALIB_NCH            ? ea__ch_col[role[j]]
                   : role[j] == EA__COL_CABLE_LENGTH ? "cable_length_m"
                   : role[j] == EA__COL_PAYLOAD      ? "payload_kg"
                                                     : "t_s");
      goto fail;
    }
    rec->line[rec->rows] = line;
    /* time: strictly increasing */
    if (kind == EA_CALIB_RINGDOWN && rec->rows > 0 &&
        !(cols[EA__COL_T][rec->rows] > cols[EA__COL_T][rec->rows - 1])) {
      int tc = 1;
      for (int q = 0; q < ncol; ++q)
        if (role[q] == EA__COL_T) tc = col_pos[q];
      st = EA__ERR(&rd, line, tc, EA_ERR_INPUT,
                   "column t_s: %.17g does not increase (previous row %.17g)",
                   cols[EA__COL_T][rec->rows], cols[EA__COL_T][rec->rows - 1]);
      goto fail;
    }
    ++rec->rows;
  }
  if (line == 0) {
    st = ea_error_set(err, EA_ERR_PARSE, "%s:1:1: empty file: not a measurement record", name);
    goto fail;
  }
  if (kind < 0) {
    st = EA__ERR(&rd, line, 1, EA_ERR_INPUT, "no '# kind: static' or '# kind: ringdown' header");
    goto fail;
  }
  if (!have_header_row) {
    st = EA__ERR(&rd, line, 1, EA_ERR_INPUT, "no header row of column names");
    goto fail;
  }
  rec->kind = (ea_calib_kind_t)kind;
  const int min_rows = kind == EA_CALIB_STATIC ? 1 : 16;
  if (rec->rows < min_rows) {
    st = EA__ERR(&rd, line, 1, EA_ERR_INPUT, "%d data rows: a %s record needs at least %d",
                 rec->rows, kind == EA_CALIB_STATIC ? "static" : "ring-down", min_rows);
    goto fail;
  }
  int seen[EA__NCOL] = {0};
  for (int j = 0; j < ncol; ++j)
    seen[role[j]] = 1;
  for (int c = 0; c < EA_CALIB_NCH; ++c) {
    rec->has[c] = seen[c];
    if (seen[c]) {
      rec->ch[c] = cols[c];
      cols[c] = NULL;
    }
  }
  rec->payload_kg = isfinite(hold_payload) ? hold_payload : 0.0;
  if (kind == EA_CALIB_STATIC) {
    rec->cable_length = cols[EA__COL_CABLE_LENGTH];
    cols[EA__COL_CABLE_LENGTH] = NULL;
    if (seen[EA__COL_PAYLOAD]) {
      rec->payload = cols[EA__COL_PAYLOAD];
      cols[EA__COL_PAYLOAD] = NULL;
    } else {
      rec->payload = cols[EA__COL_PAYLOAD]; /* allocated: fill with the header's value */
      cols[EA__COL_PAYLOAD] = NULL;
      for (int i = 0; i < rec->rows; ++i)
        rec->payload[i] = rec->payload_kg;
    }
  } else {
    if (!isfinite(rec->hold_cable_length) || !isfinite(rec->hold_theta0)) {
      st = EA__ERR(&rd, 2, 1, EA_ERR_INPUT,
                   "a ring-down record needs the headers "
                   "'# cable_length_m:' and '# theta0_rad:' (the hold)");
      goto fail;
    }
    (void)payload_line;
    rec->t = cols[EA__COL_T];
    cols[EA__COL_T] = NULL;
    const int nr = rec->rows;
    rec->dt = (rec->t[nr - 1] - rec->t[0]) / (nr - 1);
    int tc = 1;
    for (int q = 0; q < ncol; ++q)
      if (role[q] == EA__COL_T) tc = col_pos[q];
    for (int i = 1; i < nr; ++i) {
      const double d = rec->t[i] - rec->t[i - 1];
      if (fabs(d - rec->dt) > 0.01 * rec->dt) {
        st = EA__ERR(&rd, rec->line[i], tc, EA_ERR_INPUT,
                     "column t_s: %.17g is %.6g s after the previous row, the record's mean "
                     "interval is %.6g s: a ring-down is sampled at a constant rate",
                     rec->t[i], d, rec->dt);
        goto fail;
      }
    }
  }
  for (int r = 0; r < EA__NCOL; ++r)
    free(cols[r]);
  return EA_OK;
fail:
  for (int r = 0; r < EA__NCOL; ++r)
    free(cols[r]);
  ea_calib_record_free(rec);
  return st;
}

ea_status_t ea_calib_record_read(const char *path, ea_calib_record_t *rec, ea_error_t *err) {
  if (!path || !rec) return ea_error_set(err, EA_ERR_ARG, "ea_calib_record_read: NULL argument");
  memset(rec, 0, sizeof *rec);
  char *buf = NULL;
  size_t len = 0;
  ea_status_t st = ea__file_read_regular(path, NULL, &buf, &len, err);
  if (st) return st;
  st = ea_calib_record_parse(path, buf, len, rec, err);
  free(buf);
  return st;
}
