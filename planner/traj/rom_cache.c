/* The reduced-model table on disk (planner/ea_simulate.h, ea_rom_table_cached): built once per
 * arm, tip mass, box, grid and model settings, then loaded. A cache file holds a text key that
 * names every input in exact hexadecimal floating point, and the grid values; a file whose key
 * differs (another arm, payload, box, ...) or that is damaged is ignored and rebuilt, never
 * used. Written atomically. */
#include "ea_simulate.h"
#include "ea_util.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#define EA__ROM_MAGIC "elasticarm-rom-table 1\n"

/* Every input of a table, exactly. */
static void ea__rom_key(const ea_arm_t *a, double tip_mass, const ea_rom_settings_t *s,
                        const double box[4], int nL, int na, char *key, size_t len) {
  snprintf(key, len,
           "arm %a %a %a %a %a %a %a %a %a %a %a %a; tip_mass %a; modes %d elements %d steps "
           "%a %a; box %a %a %a %a; grid %d %d",
           a->rho, a->m_hand, a->length, a->EI, a->x_c, a->y_c, a->g, a->EA, a->GA_s, a->EA_cable,
           a->I_zz, a->I_hand, tip_mass, s->modes, s->elements, s->step_length, s->step_angle,
           box[0], box[1], box[2], box[3], nL, na);
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

static ea_status_t ea__rom_load(const char *path, const char *key, int modes, int nL, int na,
                                const double box[4], ea_rom_table_t **out) {
  FILE *fp = fopen(path, "rb");
  if (!fp) return EA_ERR_IO;
  ea_status_t st = EA_ERR_PARSE;
  char magic[sizeof EA__ROM_MAGIC];
  size_t klen = 0, count = 0;
  char *fkey = NULL;
  double *vals = NULL;
  if (fread(magic, 1, sizeof magic - 1, fp) != sizeof magic - 1) goto done;
  magic[sizeof magic - 1] = '\0';
  if (strcmp(magic, EA__ROM_MAGIC)) goto done;
  if (fread(&klen, sizeof klen, 1, fp) != 1 || klen != strlen(key)) goto done;
  fkey = malloc(klen + 1);
  if (!fkey || fread(fkey, 1, klen, fp) != klen) goto done;
  fkey[klen] = '\0';
  if (strcmp(fkey, key)) goto done;
  if (fread(&count, sizeof count, 1, fp) != 1 ||
      count != (size_t)(10 * modes + 2) * (size_t)nL * (size_t)na)
    goto done;
  vals = malloc(sizeof(double) * count);
  if (!vals || fread(vals, sizeof(double), count, fp) != count || fgetc(fp) != EOF) goto done;
  st = ea_rom_table_from_values(modes, nL, na, box, vals, out, NULL);
done:
  fclose(fp);
  free(fkey);
  free(vals);
  return st;
}

static ea_status_t ea__rom_save(const char *path, const char *key, const ea_rom_table_t *tb,
                                ea_error_t *err) {
  ea_afile_t f = {0};
  ea_status_t st = ea_mkdir_parents(path, err);
  if (!st) st = ea_afile_open(&f, path, err);
  if (st) return st;
  size_t count = 0;
  const double *v = ea_rom_table_values(tb, &count);
  const size_t klen = strlen(key);
  int ok = fwrite(EA__ROM_MAGIC, 1, strlen(EA__ROM_MAGIC), f.fp) == strlen(EA__ROM_MAGIC) &&
           fwrite(&klen, sizeof klen, 1, f.fp) == 1 && fwrite(key, 1, klen, f.fp) == klen &&
           fwrite(&count, sizeof count, 1, f.fp) == 1 &&
           fwrite(v, sizeof(double), count, f.fp) == count;
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
  if (cache_dir && *cache_dir) {
    snprintf(path, sizeof path, "%s/rom-%016llx.bin", cache_dir, ea__rom_hash(key));
    snprintf(info->path, sizeof info->path, "%s", path);
    if (ea__rom_load(path, key, s->modes, nL, na, box, out) == EA_OK) {
      info->loaded = 1;
      return EA_OK;
    }
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
      snprintf(info->message, sizeof info->message, "not cached: %s", e2.msg);
  }
  return EA_OK;
}
