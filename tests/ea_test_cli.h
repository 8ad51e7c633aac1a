/* Running the CLI from a test: the binary from $EA_BINARY (set by CTest),
 * its combined stdout and stderr in out, and simple JSON look-ups. */
#ifndef EA_TEST_CLI_H
#define EA_TEST_CLI_H

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>

static char out[1 << 18];
static const char *bin;

/* bin from $EA_BINARY and the arm file under $EA_SOURCE_DIR (both set by
 * CTest); returns 0, or 1 with a message when run outside CTest. */
static inline int cli_setup(char *arm_path, size_t len) {
  bin = getenv("EA_BINARY");
  const char *src = getenv("EA_SOURCE_DIR");
  if (!bin || !src) {
    printf("EA_BINARY / EA_SOURCE_DIR not set (run through ctest)\n");
    return 1;
  }
  snprintf(arm_path, len, "%s/data/elasticarm.yaml", src);
  return 0;
}

/* Run "bin args" through the shell; returns the exit code (-1 if killed). */
static inline int run(const char *args) {
  char cmd[4096];
  snprintf(cmd, sizeof cmd, "%s %s 2>&1", bin, args);
  FILE *p = popen(cmd, "r");
  if (!p) return -1;
  size_t n = fread(out, 1, sizeof out - 1, p);
  out[n] = '\0';
  int rc = pclose(p);
  return WIFEXITED(rc) ? WEXITSTATUS(rc) : -1;
}

/* The number after "key": in out (NaN if absent). */
static inline double json_num(const char *key) {
  char k[128];
  snprintf(k, sizeof k, "\"%s\": ", key);
  const char *p = strstr(out, k);
  return p ? strtod(p + strlen(k), NULL) : NAN;
}

/* The i-th number of the JSON list "key": [a,b,c] in out. */
static inline double json_list(const char *key, int i) {
  char k[128];
  snprintf(k, sizeof k, "\"%s\": [", key);
  const char *p = strstr(out, k);
  if (!p) return NAN;
  p += strlen(k);
  for (int j = 0; j < i; ++j) {
    p = strchr(p, ',');
    if (!p) return NAN;
    ++p;
  }
  char *end;
  double v = strtod(p, &end);
  return end == p ? NAN : v;
}

#endif
