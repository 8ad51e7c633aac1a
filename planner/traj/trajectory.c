/* Trajectory files, format version 1 (docs/trajectory-format.md). */
#include "ea_statics.h"
#include "ea_traj.h"
#include "ea_util.h"

#include <errno.h>
#include <inttypes.h>
#include <limits.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#define EA__TRAJ_NAME(name, header) header,
static const char *const ea__traj_names[EA_TRAJ_NCOL] = {EA_TRAJ_COLUMNS(EA__TRAJ_NAME)};
#undef EA__TRAJ_NAME

const char *ea_traj_column_name(int c) {
  return (c >= 0 && c < EA_TRAJ_NCOL) ? ea__traj_names[c] : "?";
}

ea_status_t ea_traj_alloc(ea_traj_t *tr, int n) {
  if (n < 0) return EA_ERR_ARG;
  free(tr->data);
  tr->data = n ? calloc((size_t)n * EA_TRAJ_NCOL, sizeof *tr->data) : NULL;
  tr->n = (n && !tr->data) ? 0 : n;
  return (n && !tr->data) ? EA_ERR_NOMEM : EA_OK;
}

void ea_traj_free(ea_traj_t *tr) {
  if (!tr) return;
  free(tr->data);
  tr->data = NULL;
  tr->n = 0;
}

void ea_traj_set_statics(ea_traj_t *tr, int i, const double p[4], const double xL[4], double EI) {
  const double b = EA_TRAJ_AT(tr, i, EA_TRAJ_base_angle);
  EA_TRAJ_AT(tr, i, EA_TRAJ_tension) = p[EA_P_TENSION];
  EA_TRAJ_AT(tr, i, EA_TRAJ_theta0) = p[EA_P_THETA0];
  EA_TRAJ_AT(tr, i, EA_TRAJ_kappa0) = p[EA_P_KAPPA0];
  EA_TRAJ_AT(tr, i, EA_TRAJ_shoulder_torque) = EI * p[EA_P_KAPPA0];
  EA_TRAJ_AT(tr, i, EA_TRAJ_tip_x) = xL[EA_X_X] * cos(b);
  EA_TRAJ_AT(tr, i, EA_TRAJ_tip_y) = xL[EA_X_X] * sin(b);
  EA_TRAJ_AT(tr, i, EA_TRAJ_tip_z) = xL[EA_X_Y];
}

ea_status_t ea_traj_write(const ea_traj_t *tr, const char *path, ea_error_t *err) {
  ea_afile_t f;
  ea_status_t st = ea_afile_open(&f, path, err);
  if (st) return st;
  /* the arm file by its absolute path: a relative one would be read against whatever folder
   * the reader runs in (and is taken relative to the trajectory's folder, ea_traj_read) */
  char abs[PATH_MAX];
  const char *arm_file = tr->arm_file[0] && realpath(tr->arm_file, abs) ? abs : tr->arm_file;
  fprintf(f.fp, "# elasticarm-trajectory %d\n", EA_TRAJ_FORMAT_VERSION);
  if (tr->run_id[0]) fprintf(f.fp, "# run_id: %s\n", tr->run_id);
  fprintf(f.fp, "# arm_file: %s\n", arm_file);
  if (tr->has_arm_hash) fprintf(f.fp, "# arm_hash: %016" PRIx64 "\n", tr->arm_hash);
  fprintf(f.fp, "# task: %s\n", tr->task);
  fprintf(f.fp, "# status: %s\n", tr->status);
  fprintf(f.fp, "# payload_kg: %.17g\n", tr->payload_kg);
  fprintf(f.fp, "# tip_mass_kg: %.17g\n", tr->tip_mass_kg);
  for (int c = 0; c < EA_TRAJ_NCOL; ++c)
    fprintf(f.fp, c ? ",%s" : "%s", ea__traj_names[c]);
  fputc('\n', f.fp);
  for (int i = 0; i < tr->n; ++i) {
    for (int c = 0; c < EA_TRAJ_NCOL; ++c)
      fprintf(f.fp, c ? ",%.17g" : "%.17g", EA_TRAJ_AT(tr, i, c));
    fputc('\n', f.fp);
  }
  return ea_afile_commit(&f, err);
}

/* A '#' metadata line; the masses must be finite numbers >= 0 (they set
 * the tip load of a replayed or simulated plan). */
static ea_status_t ea__meta(ea_traj_t *tr, const char *line, const char *path, long lineno,
                            ea_error_t *err) {
  const char *v;
#define EA__META_STR(key, field)                                                                   \
  if (!strncmp(line, "# " key ": ", strlen("# " key ": "))) {                                      \
    v = line + strlen("# " key ": ");                                                              \
    snprintf(tr->field, sizeof tr->field, "%.*s", (int)strcspn(v, "\r\n"), v);                     \
    return EA_OK;                                                                                  \
  }
  EA__META_STR("arm_file", arm_file)
  EA__META_STR("task", task)
  EA__META_STR("status", status)
  EA__META_STR("run_id", run_id)
#undef EA__META_STR
  static const char hk[] = "# arm_hash: ";
  if (!strncmp(line, hk, sizeof hk - 1)) {
    v = line + sizeof hk - 1;
    const size_t nh = strspn(v, "0123456789abcdefABCDEF");
    if (nh != 16 || v[16 + strspn(v + 16, " \t\r\n")] != '\0')
      return ea_error_set(err, EA_ERR_INPUT,
                          "%s:%ld:%zu: 'arm_hash': '%.*s' is not 16 hexadecimal digits", path,
                          lineno, sizeof hk, (int)strcspn(v, "\r\n"), v);
    tr->arm_hash = (uint64_t)strtoull(v, NULL, 16);
    tr->has_arm_hash = 1;
    return EA_OK;
  }
  static const char *const keys[] = {"# payload_kg: ", "# tip_mass_kg: "};
  double *dst[] = {&tr->payload_kg, &tr->tip_mass_kg};
  for (int k = 0; k < 2; ++k) {
    const size_t kl = strlen(keys[k]);
    if (strncmp(line, keys[k], kl)) continue;
    char *end;
    errno = 0;
    const double x = strtod(line + kl, &end);
    if (end == line + kl || errno == ERANGE || !isfinite(x) || x < 0 ||
        end[strspn(end, " \t\r\n")] != '\0')
      return ea_error_set(err, EA_ERR_INPUT, "%s:%ld:%zu: '%.*s': '%.*s' is not a finite mass >= 0",
                          path, lineno, kl + 1, (int)kl - 4, keys[k] + 2,
                          (int)strcspn(line + kl, "\r\n"), line + kl);
    *dst[k] = x;
  }
  return EA_OK;
}

/* A relative '# arm_file:' names a file beside the trajectory: the trajectory's folder
 * prefixed, so the arm does not depend on the folder the reader runs in. */
static ea_status_t ea__arm_file_beside(ea_traj_t *tr, const char *path, ea_error_t *err) {
  const char *slash = strrchr(path, '/');
  if (!tr->arm_file[0] || tr->arm_file[0] == '/' || !slash) return EA_OK;
  char rel[sizeof tr->arm_file];
  memcpy(rel, tr->arm_file, sizeof rel);
  const int n =
      snprintf(tr->arm_file, sizeof tr->arm_file, "%.*s/%s", (int)(slash - path), path, rel);
  if (n < 0 || (size_t)n >= sizeof tr->arm_file)
    return ea_error_set(err, EA_ERR_INPUT,
                        "%s: 'arm_file': '%s' relative to the trajectory's folder is longer "
                        "than %zu bytes",
                        path, rel, sizeof tr->arm_file - 1);
  return EA_OK;
}

ea_status_t ea_traj_read(ea_traj_t *tr, const char *path, ea_error_t *err) {
  if (!tr || !path) return ea_error_set(err, EA_ERR_ARG, "ea_traj_read: NULL argument");
  ea_traj_free(tr); /* a reused trajectory: its samples are replaced, not leaked */
  memset(tr, 0, sizeof *tr);
  FILE *fp = NULL;
  ea_status_t st = ea__file_open_regular(path, NULL, &fp, err);
  if (st) return st;
  char *line = NULL;
  size_t cap = 0;
  long lineno = 0;
  int cap_rows = 0, header_seen = 0, version_seen = 0;
  ssize_t got;
  while ((got = getline(&line, &cap, fp)) != -1) {
    ++lineno;
    if (strlen(line) != (size_t)got) {
      st = ea_error_set(err, EA_ERR_INPUT, "%s:%ld:%zu: NUL byte: not a text file", path, lineno,
                        strlen(line) + 1);
      break;
    }
    if (line[0] == '#') {
      static const char magic[] = "# elasticarm-trajectory ";
      if (!strncmp(line, magic, sizeof magic - 1)) {
        char *end;
        errno = 0;
        const long ver = strtol(line + sizeof magic - 1, &end, 10);
        if (end == line + sizeof magic - 1 || errno == ERANGE || ver != EA_TRAJ_FORMAT_VERSION ||
            end[strspn(end, " \t\r\n")] != '\0') {
          st = ea_error_set(err, EA_ERR_INPUT,
                            "%s:%ld:%zu: trajectory format version '%.*s', expected %d", path,
                            lineno, sizeof magic, (int)strcspn(line + sizeof magic - 1, "\r\n"),
                            line + sizeof magic - 1, EA_TRAJ_FORMAT_VERSION);
          break;
        }
        version_seen = 1;
      }
      if ((st = ea__meta(tr, line, path, lineno, err))) break;
      continue;
    }
    if (line[0] == '\n' || line[0] == '\0') continue;
    if (!version_seen) {
      st =
          ea_error_set(err, EA_ERR_INPUT,
                       "%s:%ld:1: not an elasticarm trajectory (no '# elasticarm-trajectory' line)",
                       path, lineno);
      break;
    }
    if (!header_seen) {
      char *save = NULL, *tok = strtok_r(line, ",\r\n", &save);
      int c = 0;
      long col = 1;
      for (; tok; tok = strtok_r(NULL, ",\r\n", &save), ++c) {
        if (c >= EA_TRAJ_NCOL || strcmp(tok, ea__traj_names[c]) != 0) {
          st = ea_error_set(err, EA_ERR_INPUT, "%s:%ld:%ld: column %d is '%s', expected '%s'", path,
                            lineno, col, c + 1, tok,
                            c < EA_TRAJ_NCOL ? ea__traj_names[c] : "(end of line)");
          break;
        }
        col += (long)strlen(tok) + 1;
      }
      if (st) break;
      if (c != EA_TRAJ_NCOL) {
        st = ea_error_set(err, EA_ERR_INPUT, "%s:%ld:%ld: header has %d columns, expected %d", path,
                          lineno, col, c, EA_TRAJ_NCOL);
        break;
      }
      header_seen = 1;
      continue;
    }
    if (tr->n == cap_rows) {
      int nc = cap_rows ? 2 * cap_rows : 256;
      double *nd = realloc(tr->data, (size_t)nc * EA_TRAJ_NCOL * sizeof *nd);
      if (!nd) {
        st = ea_error_set(err, EA_ERR_NOMEM, "out of memory reading %s", path);
        break;
      }
      tr->data = nd;
      cap_rows = nc;
    }
    const char *s = line;
    for (int c = 0; c < EA_TRAJ_NCOL; ++c) {
      char *end;
      errno = 0;
      double v = strtod(s, &end);
      const long col = (long)(s - line) + 1;
      if (end == s || errno == ERANGE || !isfinite(v)) {
        st = ea_error_set(err, EA_ERR_INPUT, "%s:%ld:%ld: column '%s': not a finite number", path,
                          lineno, col, ea__traj_names[c]);
        break;
      }
      if (c + 1 < EA_TRAJ_NCOL && *end != ',') {
        st = ea_error_set(err, EA_ERR_INPUT, "%s:%ld:%ld: expected %d columns", path, lineno,
                          (long)(end - line) + 1, EA_TRAJ_NCOL);
        break;
      }
      if (c + 1 == EA_TRAJ_NCOL && *end && *end != '\n' && *end != '\r') {
        st = ea_error_set(err, EA_ERR_INPUT, "%s:%ld:%ld: extra data after column %d", path, lineno,
                          (long)(end - line) + 1, EA_TRAJ_NCOL);
        break;
      }
      tr->data[(size_t)tr->n * EA_TRAJ_NCOL + c] = v;
      s = end + 1;
    }
    if (st) break;
    if (tr->n > 0 && !(EA_TRAJ_AT(tr, tr->n, EA_TRAJ_t) > EA_TRAJ_AT(tr, tr->n - 1, EA_TRAJ_t))) {
      st = ea_error_set(err, EA_ERR_INPUT, "%s:%ld:1: time %.17g does not increase", path, lineno,
                        EA_TRAJ_AT(tr, tr->n, EA_TRAJ_t));
      break;
    }
    ++tr->n;
  }
  free(line);
  fclose(fp);
  if (!st && !header_seen)
    st = ea_error_set(err, EA_ERR_INPUT, "%s: no header line: not a trajectory file", path);
  if (!st && tr->n < 2)
    st = ea_error_set(err, EA_ERR_INPUT, "%s: a trajectory needs at least 2 samples", path);
  if (!st) st = ea__arm_file_beside(tr, path, err);
  if (st) ea_traj_free(tr);
  return st;
}

/* The simple CSV form of a trajectory (ea_traj.h). */
ea_status_t ea_traj_read_simple(ea_traj_t *tr, const char *path, ea_error_t *err) {
  if (!tr || !path) return ea_error_set(err, EA_ERR_ARG, "ea_traj_read_simple: NULL argument");
  ea_traj_free(tr);
  memset(tr, 0, sizeof *tr);
  FILE *fp = NULL;
  ea_status_t st = ea__file_open_regular(path, NULL, &fp, err);
  if (st) return st;
  char line[4096];
  long lineno = 0;
  int cap = 0, n = 0;
  double *rows = NULL;
  while (fgets(line, sizeof line, fp)) {
    ++lineno;
    line[strcspn(line, "\r\n")] = '\0';
    if (lineno == 1) {
      if (strcmp(line, "t_s,cable_length_m,cable_angle_rad")) {
        st = ea_error_set(err, EA_ERR_PARSE,
                          "%s:1:1: header must be 't_s,cable_length_m,cable_angle_rad' (or a "
                          "trajectory file starting with '# elasticarm-trajectory 1')",
                          path);
        break;
      }
      continue;
    }
    if (!line[0]) continue;
    double v[3];
    const char *s = line;
    for (int c = 0; c < 3; ++c) {
      char *end;
      v[c] = strtod(s, &end);
      const int sep_ok = c < 2 ? *end == ',' : *end == '\0';
      if (end == s || !isfinite(v[c]) || !sep_ok) {
        st = ea_error_set(err, EA_ERR_PARSE, "%s:%ld:%ld: expected a finite number%s", path, lineno,
                          (long)(s - line) + 1, c < 2 ? " followed by ','" : " at the end");
        break;
      }
      s = end + 1;
    }
    if (st) break;
    if (n && !(v[0] > rows[3 * (n - 1)])) {
      st = ea_error_set(err, EA_ERR_INPUT, "%s:%ld:1: time %g does not increase", path, lineno,
                        v[0]);
      break;
    }
    if (!(v[1] > 0)) {
      st = ea_error_set(err, EA_ERR_INPUT, "%s:%ld: cable length %g <= 0", path, lineno, v[1]);
      break;
    }
    if (n == cap) {
      cap = cap ? 2 * cap : 64;
      double *r = realloc(rows, sizeof(double) * 3 * (size_t)cap);
      if (!r) {
        st = ea_error_set(err, EA_ERR_NOMEM, "out of memory");
        break;
      }
      rows = r;
    }
    memcpy(rows + 3 * n++, v, sizeof v);
  }
  fclose(fp);
  if (!st && n < 2)
    st = ea_error_set(err, EA_ERR_INPUT, "%s: needs at least 2 samples, has %d", path, n);
  if (!st && (st = ea_traj_alloc(tr, n))) ea_error_set(err, st, "out of memory");
  if (!st) {
    for (int i = 0; i < n; ++i) {
      EA_TRAJ_AT(tr, i, EA_TRAJ_t) = rows[3 * i];
      EA_TRAJ_AT(tr, i, EA_TRAJ_cable_length) = rows[3 * i + 1];
      EA_TRAJ_AT(tr, i, EA_TRAJ_cable_angle) = rows[3 * i + 2];
    }
    for (int i = 0; i < n; ++i) { /* rates by centred (end: one-sided) differences */
      const int a = i ? i - 1 : 0, b = i < n - 1 ? i + 1 : n - 1;
      const double dt = rows[3 * b] - rows[3 * a];
      EA_TRAJ_AT(tr, i, EA_TRAJ_cable_length_rate) = (rows[3 * b + 1] - rows[3 * a + 1]) / dt;
      EA_TRAJ_AT(tr, i, EA_TRAJ_cable_angle_rate) = (rows[3 * b + 2] - rows[3 * a + 2]) / dt;
    }
    snprintf(tr->status, sizeof tr->status, "simple-csv");
  }
  free(rows);
  return st;
}

ea_status_t ea_traj_read_any(ea_traj_t *tr, const char *path, int *simple, ea_error_t *err) {
  if (!tr || !path) return ea_error_set(err, EA_ERR_ARG, "ea_traj_read_any: NULL argument");
  FILE *fp = NULL;
  ea_status_t st = ea__file_open_regular(path, NULL, &fp, err);
  if (st) return st;
  const int c = fgetc(fp);
  fclose(fp);
  const int s = c != '#' && c != EOF;
  if (simple) *simple = s;
  return s ? ea_traj_read_simple(tr, path, err) : ea_traj_read(tr, path, err);
}
