/* Input files of the utility layer (ea_util.h): opened without blocking and
 * refused unless regular, so a FIFO without a writer, a directory or a device
 * gives a message naming the path instead of a hang or a parse error. */
#include "ea_util.h"

#include <errno.h>
#include <fcntl.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

/* A short name for what a non-regular file is, for the error message. */
static const char *ea__file_kind(mode_t m) {
  if (S_ISDIR(m)) return "a directory";
  if (S_ISFIFO(m)) return "a FIFO (named pipe)";
  if (S_ISCHR(m)) return "a character device";
  if (S_ISBLK(m)) return "a block device";
  if (S_ISSOCK(m)) return "a socket";
  return "another kind of file";
}

/* A descriptor of path if it is a regular file (blocking again), its size in *size. */
static ea_status_t ea__file_open_fd(const char *path, const char *name, int *fd_out, size_t *size,
                                    ea_error_t *err) {
  *fd_out = -1;
  if (!name) name = path;
  const int fd = open(path, O_RDONLY | O_NONBLOCK | O_CLOEXEC);
  if (fd < 0) return ea_error_set(err, EA_ERR_IO, "%s: cannot open: %s", name, strerror(errno));
  struct stat sb;
  if (fstat(fd, &sb) != 0) {
    const int e = errno;
    close(fd);
    return ea_error_set(err, EA_ERR_IO, "%s: cannot stat: %s", name, strerror(e));
  }
  if (!S_ISREG(sb.st_mode)) {
    close(fd);
    return ea_error_set(err, EA_ERR_IO, "%s: is %s, not a regular file", name,
                        ea__file_kind(sb.st_mode));
  }
  const int fl = fcntl(fd, F_GETFL);
  if (fl >= 0) fcntl(fd, F_SETFL, fl & ~O_NONBLOCK);
  *fd_out = fd;
  if (size) *size = sb.st_size > 0 ? (size_t)sb.st_size : 0;
  return EA_OK;
}

ea_status_t ea__file_open_regular(const char *path, const char *name, FILE **fp, ea_error_t *err) {
  *fp = NULL;
  if (!name) name = path;
  int fd;
  ea_status_t st = ea__file_open_fd(path, name, &fd, NULL, err);
  if (st) return st;
  if (!(*fp = fdopen(fd, "r"))) {
    const int e = errno;
    close(fd);
    return ea_error_set(err, EA_ERR_IO, "%s: cannot open: %s", name, strerror(e));
  }
  return EA_OK;
}

ea_status_t ea__file_read_regular(const char *path, const char *name, char **buf, size_t *len,
                                  ea_error_t *err) {
  *buf = NULL;
  *len = 0;
  if (!name) name = path;
  int fd;
  size_t size = 0;
  ea_status_t st = ea__file_open_fd(path, name, &fd, &size, err);
  if (st) return st;
  size_t cap = size > 0 ? size + 1 : 4096, n = 0;
  char *b = malloc(cap);
  st = b ? EA_OK : ea_error_set(err, EA_ERR_NOMEM, "%s: out of memory", name);
  while (!st) {
    if (n + 1 >= cap) { /* the file grew since fstat */
      char *nb = cap < ((size_t)-1) / 2 ? realloc(b, 2 * cap) : NULL;
      if (!nb) {
        st = ea_error_set(err, EA_ERR_NOMEM, "%s: out of memory", name);
        break;
      }
      b = nb;
      cap *= 2;
    }
    const ssize_t r = read(fd, b + n, cap - 1 - n);
    if (r < 0 && errno == EINTR) continue;
    if (r < 0) st = ea_error_set(err, EA_ERR_IO, "%s: cannot read: %s", name, strerror(errno));
    if (r <= 0) break;
    n += (size_t)r;
  }
  close(fd);
  if (st) {
    free(b);
    return st;
  }
  b[n] = '\0';
  *buf = b;
  *len = n;
  return EA_OK;
}
