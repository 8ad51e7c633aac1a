/* libFuzzer target for the study journal reader and the shard merge
 * (problems/study_run.c: ea_study_run with a checkpoint, ea_study_merge).
 *
 * A fixed 3-case study (below) is loaded once; its journal key line is
 * taken from a run on an empty journal. Each input is then
 *   byte 0: bit 0 = rewrite every "#case ID ..." line with the true byte
 *           count and CRC-32 of the rows before it (so the fuzzer reaches
 *           the per-row checks behind the CRC), bits 1-3 = shard K/N;
 *   rest:   the journal after the key line (and, split at 0x01 bytes, up to
 *           4 shard CSVs for the merge).
 * The run is asked to stop before computing anything, so it only reads the
 * journal (and assembles the CSV when the journal holds every case).
 * Invariants: the journal is always accepted (OK or INTERRUPTED); a second
 * run on the journal the first one truncated drops nothing and skips the
 * same cases; a merge gives an error with a message or the header plus
 * every row exactly once.
 * EA_FUZZ_JOURNAL_SEEDS=DIR: write seed inputs from a real run to DIR and
 * exit (fuzz/corpus/journal was made so). */
#include "ea_problems.h"
#include "fuzz_tmp.h"

#include <signal.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

int LLVMFuzzerInitialize(int *argc, char ***argv);
int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

static const char *const ea__spec = "name: fuzz-journal\n"
                                    "grid:\n"
                                    "  payload_factor: [0, 0.1]\n"
                                    "  EI_Nm2: [0.6, 0.705]\n"
                                    "metrics:\n"
                                    "  workspace: {points: 3}\n";

static ea_study_t g_study;
static char g_key[256];
static size_t g_klen;
static const volatile sig_atomic_t g_stop = 1;

static void ea__check(int cond) {
  if (!cond) __builtin_trap();
}

static ea_status_t ea__run(const char *path, int k, int n, int stop, ea_study_info_t *info,
                           char **csv, size_t *len) {
  ea_study_settings_t set;
  ea_study_settings_default(&set);
  set.threads = 1;
  set.fsync = 0;
  set.shard_k = k;
  set.shard_n = n;
  set.checkpoint = path;
  if (stop) set.stop_request = &g_stop;
  ea_error_t err = {0};
  const ea_status_t st = ea_study_run(&g_study, &set, csv, len, info, &err);
  ea__check(st == EA_OK || err.msg[0] != '\0');
  return st;
}

static size_t ea__file(const char *path, char *buf, size_t cap) {
  FILE *f = fopen(path, "rb");
  ea__check(f != NULL);
  const size_t n = fread(buf, 1, cap, f);
  fclose(f);
  return n;
}

static void ea__seeds(const char *dir) {
  /* the whole journal of a real run; then shard 2 of 2, a torn tail, and
     a journal with one case only */
  static char j[1 << 16];
  const char *path = ea__fuzz_tmp_write(".journal", "", 0, NULL, 0);
  char *csv = NULL;
  size_t len = 0;
  ea_study_info_t info;
  ea__check(ea__run(path, 1, 1, 0, &info, &csv, &len) == EA_OK);
  const size_t n = ea__file(path, j, sizeof j);
  ea__check(n > g_klen && n < sizeof j);
  struct {
    const char *name;
    uint8_t ctl;
    size_t len;
  } out[] = {
      {"full", 0, n - g_klen},
      {"full-fixcrc-shard2of2", 1 | (2 << 1), n - g_klen},
      {"torn", 0, (n - g_klen) * 2 / 3},
      {"one-case", 0,
       (size_t)(strstr(j + g_klen, "#case") - (j + g_klen)) +
           (size_t)(strchr(strstr(j + g_klen, "#case"), '\n') - strstr(j + g_klen, "#case")) + 1}};
  for (size_t i = 0; i < sizeof out / sizeof *out; ++i) {
    char p[1024];
    snprintf(p, sizeof p, "%s/%s", dir, out[i].name);
    FILE *f = fopen(p, "wb");
    ea__check(f != NULL);
    fputc(out[i].ctl, f);
    fwrite(j + g_klen, 1, out[i].len, f);
    fclose(f);
  }
  /* merge seed: the run's CSV as two shards split at 0x01 */
  char p[1024];
  snprintf(p, sizeof p, "%s/merge-2-shards", dir);
  FILE *f = fopen(p, "wb");
  ea__check(f != NULL);
  const char *h_end = strchr(csv, '\n') + 1;
  const char *mid = strstr(csv, "\n1,") + 1;
  fputc(0, f);
  fwrite(csv, 1, (size_t)(mid - csv), f);
  fputc(1, f);
  fwrite(csv, 1, (size_t)(h_end - csv), f);
  fwrite(mid, 1, len - (size_t)(mid - csv), f);
  fclose(f);
  free(csv);
  exit(0);
}

int LLVMFuzzerInitialize(int *argc, char ***argv) {
  (void)argc;
  (void)argv;
  ea_error_t err = {0};
  ea__check(ea_study_load_string("fuzz-journal.yaml", ea__spec, strlen(ea__spec), NULL, &g_study,
                                 &err) == EA_OK);
  const char *path = ea__fuzz_tmp_write(".journal", "", 0, NULL, 0);
  ea_study_info_t info;
  char *csv = NULL;
  ea__check(ea__run(path, 1, 1, 1, &info, &csv, NULL) == EA_ERR_INTERRUPTED);
  g_klen = ea__file(path, g_key, sizeof g_key - 1);
  ea__check(g_klen > 0 && g_key[g_klen - 1] == '\n' && !memchr(g_key, '\n', g_klen - 1));
  const char *dir = getenv("EA_FUZZ_JOURNAL_SEEDS");
  if (dir) ea__seeds(dir);
  return 0;
}

/* Rewrite "#case ID ..." lines with the true count and CRC of the rows
 * before them (CRC-32 as zlib's, as the journal uses). */
static uint32_t ea__crc32(const uint8_t *p, size_t n) {
  uint32_t c = 0xffffffffu;
  for (size_t i = 0; i < n; ++i) {
    c ^= p[i];
    for (int k = 0; k < 8; ++k)
      c = (c >> 1) ^ (0xedb88320u & (0u - (c & 1u)));
  }
  return c ^ 0xffffffffu;
}

static size_t ea__fix_crc(const uint8_t *in, size_t n, uint8_t *out) {
  size_t o = 0, block = 0;
  for (size_t i = 0; i < n;) {
    const uint8_t *nl = memchr(in + i, '\n', n - i);
    const size_t ll = nl ? (size_t)(nl - (in + i)) + 1 : n - i;
    if (nl && ll > 6 && !memcmp(in + i, "#case ", 6)) {
      char idtxt[24];
      const size_t m = ll - 6 < sizeof idtxt - 1 ? ll - 6 : sizeof idtxt - 1;
      memcpy(idtxt, in + i + 6, m);
      idtxt[m] = '\0';
      const long id = strtol(idtxt, NULL, 10);
      o += (size_t)sprintf((char *)out + o, "#case %ld %zu %08x\n", id, o - block,
                           (unsigned)ea__crc32(out + block, o - block));
      block = o;
    } else {
      memcpy(out + o, in + i, ll);
      o += ll;
    }
    i += ll;
  }
  return o;
}

static void ea__merge(const uint8_t *body, size_t n) {
  const char *texts[4];
  size_t lens[4];
  const char *names[4] = {"s1.csv", "s2.csv", "s3.csv", "s4.csv"};
  int k = 0;
  size_t at = 0;
  while (k < 4) {
    const uint8_t *sep = k < 3 ? memchr(body + at, 1, n - at) : NULL;
    const size_t end = sep ? (size_t)(sep - body) : n;
    texts[k] = (const char *)body + at;
    lens[k++] = end - at;
    if (!sep) break;
    at = end + 1;
  }
  char *out = NULL;
  size_t out_len = 0;
  ea_error_t err = {0};
  const ea_status_t st = ea_study_merge(texts, lens, names, k, 0, &out, &out_len, &err);
  if (st != EA_OK) {
    ea__check(err.msg[0] != '\0' && out == NULL);
    return;
  }
  const char *nl = memchr(texts[0], '\n', lens[0]);
  ea__check(nl != NULL);
  const size_t h = (size_t)(nl - texts[0]) + 1;
  size_t want = h;
  for (int i = 0; i < k; ++i)
    want += lens[i] - h;
  ea__check(out_len == want && !memcmp(out, texts[0], h));
  free(out);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
  if (size < 1 || size > (1u << 20)) return 0;
  const uint8_t ctl = data[0];
  const uint8_t *body = data + 1;
  size_t n = size - 1;
  uint8_t *fixed = NULL;
  if (ctl & 1) {
    /* a rewritten "#case" line is at most 6 + 20 + 1 + 20 + 1 + 8 + 1 bytes
       and replaces at least 7 */
    fixed = malloc(n * 8 + 64);
    ea__check(fixed != NULL);
    n = ea__fix_crc(body, n, fixed);
    body = fixed;
  }
  const int shard_n = 1 + ((ctl >> 1) & 3) % 3, shard_k = 1 + ((ctl >> 3) & 3) % shard_n;
  const char *path = ea__fuzz_tmp_write(".journal", g_key, g_klen, body, n);
  ea_study_info_t a, b;
  char *csv = NULL;
  size_t len = 0;
  ea_status_t st = ea__run(path, shard_k, shard_n, 1, &a, &csv, &len);
  ea__check(st == EA_OK || st == EA_ERR_INTERRUPTED);
  ea__check(a.cases_skipped <= a.cases_shard && a.journal_dropped_bytes >= 0 &&
            (size_t)a.journal_dropped_bytes <= n);
  ea__check((st == EA_OK) == (a.cases_skipped == a.cases_shard));
  if (st == EA_OK) ea__check(csv && len > 8 && !strncmp(csv, "case_id,", 8));
  free(csv);
  csv = NULL;
  st = ea__run(path, shard_k, shard_n, 1, &b, &csv, &len);
  ea__check(b.journal_dropped_bytes == 0 && b.cases_skipped == a.cases_skipped);
  free(csv);
  ea__merge(body, n);
  free(fixed);
  return 0;
}
