/* Atomic output: temporary beside the target, fsync, rename. Temporaries
 * are named "<target>.tmp<pid>.XXXXXX"; opening a target removes the ones a
 * killed run left behind (ea__afile_clean_stale). */
#include "ea_util.h"

#include <dirent.h>
#include <errno.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

ea_status_t ea_mkdir_parents(const char *path, ea_error_t *err) {
  char buf[1024];
  if (!path || strlen(path) >= sizeof buf) return ea_error_set(err, EA_ERR_ARG, "path too long");
  snprintf(buf, sizeof buf, "%s", path);
  for (char *p = buf + 1; *p; ++p) {
    if (*p != '/') continue;
    *p = '\0';
    if (mkdir(buf, 0777) != 0 && errno != EEXIST) {
      ea_status_t st = ea_error_set(err, EA_ERR_IO, "%s: cannot create directory %s: %s", path, buf,
                                    strerror(errno));
      return st;
    }
    *p = '/';
  }
  return EA_OK;
}

void ea__afile_clean_stale(const char *path) {
  if (!path || !*path || !strcmp(path, "-")) return;
  char dir[1024];
  const char *slash = strrchr(path, '/');
  const char *base = slash ? slash + 1 : path;
  if (!*base || strlen(path) >= sizeof dir) return;
  if (!slash)
    snprintf(dir, sizeof dir, ".");
  else if (slash == path)
    snprintf(dir, sizeof dir, "/");
  else
    snprintf(dir, sizeof dir, "%.*s", (int)(slash - path), path);
  DIR *d = opendir(dir);
  if (!d) return;
  const size_t nb = strlen(base);
  const pid_t self = getpid();
  struct dirent *e;
  while ((e = readdir(d)) != NULL) {
    const char *n = e->d_name;
    if (strncmp(n, base, nb) || strncmp(n + nb, ".tmp", 4)) continue;
    const char *q = n + nb + 4;
    long pid = 0;
    int digits = 0;
    while (*q >= '0' && *q <= '9' && digits < 10) {
      pid = 10 * pid + (*q++ - '0');
      ++digits;
    }
    if (!digits || *q != '.' || pid <= 0 || (pid_t)pid == self) continue;
    if (kill((pid_t)pid, 0) == 0 || errno != ESRCH) continue; /* alive (or not ours to judge) */
    char full[2048];
    snprintf(full, sizeof full, "%s/%s", dir, n);
    struct stat sb;
    if (lstat(full, &sb) == 0 && S_ISREG(sb.st_mode) && sb.st_uid == geteuid()) unlink(full);
  }
  closedir(d);
}

ea_status_t ea_afile_open(ea_afile_t *f, const char *path, ea_error_t *err) {
  memset(f, 0, sizeof *f);
  if (!path || !*path) return ea_error_set(err, EA_ERR_ARG, "empty output path");
  if (strlen(path) + 24 >= sizeof f->tmp)
    return ea_error_set(err, EA_ERR_ARG, "output path too long: %s", path);
  snprintf(f->path, sizeof f->path, "%s", path);
  if (strcmp(path, "-") == 0) {
    f->fp = stdout;
    return EA_OK;
  }
  ea_status_t st = ea_mkdir_parents(path, err);
  if (st) return st;
  ea__afile_clean_stale(path);
  snprintf(f->tmp, sizeof f->tmp, "%s.tmp%ld.XXXXXX", path, (long)getpid());
  int fd = mkstemp(f->tmp);
  if (fd < 0) {
    f->tmp[0] = '\0';
    return ea_error_set(err, EA_ERR_IO, "%s: cannot create a temporary file: %s", path,
                        strerror(errno));
  }
  /* mkstemp makes 0600; give the file the mode a plain fopen would. */
  const mode_t mask = umask(0);
  umask(mask);
  if (fchmod(fd, 0666 & ~mask) != 0) {
    /* not fatal: the file stays private */
  }
  f->fp = fdopen(fd, "w");
  if (!f->fp) {
    close(fd);
    unlink(f->tmp);
    f->tmp[0] = '\0';
    return ea_error_set(err, EA_ERR_IO, "%s: %s", path, strerror(errno));
  }
  return EA_OK;
}

ea_status_t ea_afile_commit(ea_afile_t *f, ea_error_t *err) {
  if (!f->fp) return ea_error_set(err, EA_ERR_ARG, "%s: file is not open", f->path);
  if (f->fp == stdout) {
    fflush(stdout);
    f->fp = NULL;
    return EA_OK;
  }
  int bad = ferror(f->fp) || fflush(f->fp) != 0 || fsync(fileno(f->fp)) != 0;
  int eno = errno;
  if (fclose(f->fp) != 0) bad = 1;
  f->fp = NULL;
  if (bad || rename(f->tmp, f->path) != 0) {
    if (!bad) eno = errno;
    unlink(f->tmp);
    f->tmp[0] = '\0';
    return ea_error_set(err, EA_ERR_IO, "%s: write failed: %s", f->path, strerror(eno));
  }
  f->tmp[0] = '\0';
  return EA_OK;
}

void ea_afile_abort(ea_afile_t *f) {
  if (!f) return;
  if (f->fp && f->fp != stdout) fclose(f->fp);
  f->fp = NULL;
  if (f->tmp[0]) unlink(f->tmp);
  f->tmp[0] = '\0';
}
