/* The reduced-model table on disk (planner/ea_simulate.h, ea_rom_table_cached): built once per
 * arm, tip mass, box, grid and model settings, then loaded. A cache file holds a text key that
 * names every input in exact hexadecimal floating point, the file format, the meaning of the
 * values (EA_ROM_TABLE_VERSION) and the library version, then the grid values, then a CRC-32
 * of all that. A file whose key differs, whose checksum or size does not match, or that is not
 * a regular file is not used: the table is rebuilt and info->message says why. Written
 * atomically; opened without blocking (a FIFO at the path would block a plain open). */
#include "ea_simulate.h"
#include "ea_util.h"
#include "ea_version.h"

#include <errno.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

/* The file format: magic, u64 key length, key, u64 value count, the values (native doubles),
 * u32 CRC-32 (ea_crc32, as zlib's crc32) of every byte before it. */
#define EA__ROM_FORMAT 2
#define EA__ROM_MAGIC "elasticarm-rom-table 2\n"
#define EA__ROM_MAGIC_ANY "elasticarm-rom-table "

/* Every input of a table, exactly. */
static void ea__rom_key(const ea_arm_t *a, double tip_mass, const ea_rom_settings_t *s,
                        const double box[4], int nL, int na, char *key, size_t len) {
  snprintf(key, len,
           "format %d; values %d; elasticarm %s; arm %a %a %a %a %a %a %a %a %a %a %a %a; "
           "tip_mass %a; modes %d elements %d steps %a %a; box %a %a %a %a; grid %d %d",
           EA__ROM_FORMAT, EA_ROM_TABLE_VERSION, EA_VERSION_STRING, a->rho, a->m_hand, a->length,
           a->EI, a->x_c, a->y_c, a->g, a->EA, a->GA_s, a->EA_cable, a->I_zz, a->I_hand, tip_mass,
           s->modes, s->elements, s->step_length, s->step_angle, box[0], box[1], box[2], box[3], nL,
           na);
}

/* FNV-1a of the key: the file name. */
static unsigned long long ea__rom_hash(const char *key) {
  unsigned long long h = 1469598103934665603ULL;
  for (const unsigned char *p = (const unsigned char *)key; *p; ++p) {
    h ^= *p;
    h *= 1099511628211ULL;
  }
  return h;
}

const char *ea_rom_cache_dir(char *buf, size_t len) {
  const char *e = getenv("EA_CACHE_DIR");
  if (e) {
    if (!*e || !strcmp(e, "off")) return NULL;
    snprintf(buf, len, "%s", e);
    return buf;
  }
  const char *x = getenv("XDG_CACHE_HOME"), *h = getenv("HOME");
  if (x && *x)
    snprintf(buf, len, "%s/elasticarm", x);
  else if (h && *h)
    snprintf(buf, len, "%s/.cache/elasticarm", h);
  else
    return NULL;
  return buf;
}

/* Why the file at path cannot be used, in why (EA_OK: the table, in *out). EA_ERR_IO with
 * *missing = 1: there is no file (nothing to say). */
static ea_status_t ea__rom_load(const char *path, const char *key, int modes, int nL, int na,
                                const double box[4], ea_rom_table_t **out, int *missing, char *why,
                                size_t wlen) {
  *missing = 0;
  char *buf = NULL;
  size_t len = 0;
  ea_error_t e = {0};
  errno = 0;
  struct stat sb;
  if (stat(path, &sb) != 0 && (errno == ENOENT || errno == ENOTDIR)) {
    *missing = 1;
    return EA_ERR_IO;
  }
  ea_status_t st = ea__file_read_regular(path, NULL, &buf, &len, &e);
  if (st) {
    snprintf(why, wlen, "%s", e.msg);
    return st;
  }
  st = EA_ERR_PARSE;
  const size_t ml = strlen(EA__ROM_MAGIC), count = (size_t)(10 * modes + 2) * nL * na;
  const size_t klen = strlen(key), want = ml + 8 + klen + 8 + count * sizeof(double) + 4;
  uint64_t fk = 0, fc = 0;
  uint32_t crc = 0, stored = 0;
  if (len >= ml && memcmp(buf, EA__ROM_MAGIC_ANY, strlen(EA__ROM_MAGIC_ANY)) == 0 &&
      memcmp(buf, EA__ROM_MAGIC, ml) != 0) {
    snprintf(why, wlen, "%s: another cache format ('%.*s'): not used", path,
             (int)strcspn(buf, "\n") < 40 ? (int)strcspn(buf, "\n") : 40, buf);
    goto done;
  }
  if (len < ml + 8 || memcmp(buf, EA__ROM_MAGIC, ml) != 0) {
    snprintf(why, wlen, "%s: not a reduced-model cache file: not used", path);
    goto done;
  }
  memcpy(&fk, buf + ml, 8);
  if (fk != klen || len < ml + 8 + klen + 8 || memcmp(buf + ml + 8, key, klen) != 0) {
    /* another table whose key has the same 64-bit hash, or a damaged key */
    snprintf(why, wlen, "%s: holds another table (its key differs): not used", path);
    goto done;
  }
  memcpy(&fc, buf + ml + 8 + klen, 8);
  if (fc != count || len != want) {
    snprintf(why, wlen, "%s: damaged (%zu bytes, %zu expected for %zu values): not used", path, len,
             want, count);
    goto done;
  }
  memcpy(&stored, buf + len - 4, 4);
  crc = ea_crc32(0, buf, len - 4);
  if (crc != stored) {
    snprintf(why, wlen, "%s: damaged (CRC-32 %08lx, the file says %08lx): not used", path,
             (unsigned long)crc, (unsigned long)stored);
    goto done;
  }
  {
    double *vals = malloc(sizeof(double) * count);
    if (!vals) {
      st = EA_ERR_NOMEM;
      snprintf(why, wlen, "%s: out of memory", path);
      goto done;
    }
    memcpy(vals, buf + ml + 8 + klen + 8, sizeof(double) * count);
    st = ea_rom_table_from_values(modes, nL, na, box, vals, out, &e);
    free(vals);
    if (st) snprintf(why, wlen, "%.800s: %.500s: not used", path, e.msg);
  }
done:
  free(buf);
  return st;
}

static ea_status_t ea__rom_save(const char *path, const char *key, const ea_rom_table_t *tb,
                                ea_error_t *err) {
  /* a FIFO, directory or device at the path is someone else's: left alone */
  struct stat sb;
  if (lstat(path, &sb) == 0 && !S_ISREG(sb.st_mode))
    return ea_error_set(err, EA_ERR_IO, "%s: not a regular file: left alone", path);
  ea_afile_t f = {0};
  ea_status_t st = ea_mkdir_parents(path, err);
  if (!st) st = ea_afile_open(&f, path, err);
  if (st) return st;
  size_t count = 0;
  const double *v = ea_rom_table_values(tb, &count);
  const uint64_t klen = strlen(key), cnt = count;
  const size_t ml = strlen(EA__ROM_MAGIC);
  uint32_t crc = ea_crc32(0, EA__ROM_MAGIC, ml);
  crc = ea_crc32(crc, &klen, sizeof klen);
  crc = ea_crc32(crc, key, (size_t)klen);
  crc = ea_crc32(crc, &cnt, sizeof cnt);
  crc = ea_crc32(crc, v, sizeof(double) * count);
  int ok = fwrite(EA__ROM_MAGIC, 1, ml, f.fp) == ml && fwrite(&klen, sizeof klen, 1, f.fp) == 1 &&
           fwrite(key, 1, (size_t)klen, f.fp) == klen && fwrite(&cnt, sizeof cnt, 1, f.fp) == 1 &&
           fwrite(v, sizeof(double), count, f.fp) == count &&
           fwrite(&crc, sizeof crc, 1, f.fp) == 1;
  if (!ok) {
    ea_afile_abort(&f);
    return ea_error_set(err, EA_ERR_IO, "%s: write failed", path);
  }
  return ea_afile_commit(&f, err);
}

ea_status_t ea_rom_table_cached(const ea_arm_t *arm, double tip_mass, const ea_rom_settings_t *s,
                                const double box[4], int nL, int na, const char *cache_dir,
                                ea_rom_table_t **out, ea_rom_cache_info_t *info, ea_error_t *err) {
  ea_rom_cache_info_t loc;
  if (!info) info = &loc;
  memset(info, 0, sizeof *info);
  if (!arm || !s || !box || !out) return ea_error_set(err, EA_ERR_ARG, "reduced model: NULL");
  *out = NULL;
  char key[1024], path[1200];
  ea__rom_key(arm, tip_mass, s, box, nL, na, key, sizeof key);
  char why[1400] = "";
  if (cache_dir && *cache_dir) {
    snprintf(path, sizeof path, "%s/rom-%016llx.bin", cache_dir, ea__rom_hash(key));
    snprintf(info->path, sizeof info->path, "%s", path);
    int missing = 0;
    if (ea__rom_load(path, key, s->modes, nL, na, box, out, &missing, why, sizeof why) == EA_OK) {
      info->loaded = 1;
      return EA_OK;
    }
    info->rejected = !missing;
  }
  ea_rom_t *r = NULL;
  ea_status_t st = ea_rom_alloc(arm, tip_mass, s, &r, err);
  if (!st) st = ea_rom_table_build(r, box, nL, na, out, err);
  ea_rom_free(r);
  if (st) return st;
  info->built = 1;
  if (cache_dir && *cache_dir) {
    ea_error_t e2 = {0};
    if (ea__rom_save(path, key, *out, &e2) == EA_OK)
      info->saved = 1;
    else
      info->save_failed = 1;
    if (info->rejected && info->saved)
      snprintf(info->message, sizeof info->message, "%.1400s; rebuilt and saved", why);
    else if (info->rejected)
      snprintf(info->message, sizeof info->message, "%.1400s; rebuilt, not saved: %.512s", why,
               e2.msg);
    else if (info->save_failed)
      snprintf(info->message, sizeof info->message, "built, not saved: %.512s", e2.msg);
  }
  return EA_OK;
}
