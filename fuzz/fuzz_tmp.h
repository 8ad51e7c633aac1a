/* Shared by the fuzz targets whose loader reads a path: the input is
 * written to one temporary file per process (under $TMPDIR or /tmp),
 * removed at exit. */
#ifndef EA_FUZZ_TMP_H
#define EA_FUZZ_TMP_H

#include <fcntl.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <unistd.h>

static char ea__fuzz_path[512];

static void ea__fuzz_tmp_remove(void) {
  if (ea__fuzz_path[0]) unlink(ea__fuzz_path);
}

/* Write the bytes to the process's temporary file (name ends in suffix);
 * returns its path. Traps if the file cannot be written: a fuzz run on a
 * full disk must stop, not report false passes. */
static const char *ea__fuzz_tmp_write(const char *suffix, const void *a, size_t na, const void *b,
                                      size_t nb) {
  if (!ea__fuzz_path[0]) {
    const char *dir = getenv("TMPDIR");
    snprintf(ea__fuzz_path, sizeof ea__fuzz_path, "%s/ea_fuzz_%ld%s", dir && dir[0] ? dir : "/tmp",
             (long)getpid(), suffix);
    atexit(ea__fuzz_tmp_remove);
  }
  const int fd = open(ea__fuzz_path, O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0600);
  if (fd < 0) __builtin_trap();
  const void *part[2] = {a, b};
  const size_t len[2] = {na, nb};
  for (int i = 0; i < 2; ++i) {
    const uint8_t *p = part[i];
    size_t n = len[i];
    while (n) {
      const ssize_t w = write(fd, p, n);
      if (w <= 0) __builtin_trap();
      p += w;
      n -= (size_t)w;
    }
  }
  close(fd);
  return ea__fuzz_path;
}

#endif
