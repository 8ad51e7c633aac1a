/* Running a study: worker threads, or forked worker processes for studies
 * that plan, over the shard's cases, a checkpoint journal for resume, rows
 * assembled in case order; merging shard CSVs.
 *
 * Journal (docs/studies.md): a header line naming the study's key (CRC-32
 * of its canonical description), then one block per finished case: the
 * case's CSV rows followed by "#case ID BYTES CRC32\n" over those rows.
 * Each block is written with one write(), fsync'd at most every settings'
 * fsync_interval_s (set->fsync), so after a crash
 * (kill -9, power loss) the file holds complete blocks and at most one
 * torn tail, which a resume detects (length or CRC) and truncates. */
#include "study_impl.h"

#include <errno.h>
#include <fcntl.h>
#include <poll.h>
#include <pthread.h>
#include <signal.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>
#ifdef __linux__
#include <sys/prctl.h>
#endif

#define EA__JOURNAL_MAGIC "#elasticarm-study-journal 2"

void ea_study_settings_default(ea_study_settings_t *set) {
  memset(set, 0, sizeof *set);
  set->threads = 0;
  set->shard_k = 1;
  set->shard_n = 1;
  set->fsync = 1;
  set->fsync_interval_s = 0.2;
}

typedef struct {
  const ea_study_t *s;
  const ea_study_settings_t *set;
  long n_shard; /* cases of the shard: case = shard_k - 1 + j * shard_n */
  long *todo;   /* local indices j still to compute */
  long n_todo, next, started;
  long *requeue; /* cases handed to a worker process that never got them */
  long n_requeue;
  char **rows; /* rows[j] (malloc'd) once case j is done */
  size_t *rows_len;
  int fd; /* journal or -1 */
  pthread_mutex_t mu;
  int stop;
  ea_status_t fail;
  char failmsg[400];
  long computed, done_total, workers_lost;
  double last_sync; /* time of the last journal fsync */
  int dirty;        /* journal written since the last fsync */
  char ident[160];  /* "study,study_key" of every row */
} ea__run_t;

static long ea__case_of(const ea__run_t *r, long j) {
  return (long)(r->set->shard_k - 1) + j * r->set->shard_n;
}

static int ea__write_all(int fd, const char *p, size_t n) {
  while (n) {
    ssize_t w = write(fd, p, n);
    if (w < 0) {
      if (errno == EINTR) continue;
      return -1;
    }
    p += w;
    n -= (size_t)w;
  }
  return 0;
}

/* Rows whose status field (n_axes + 6, 0-based) is not "ok"; the fields before
   the message hold no commas or quotes. */
static int ea__rows_failed(const ea_study_t *s, const char *rows) {
  int bad = 0;
  for (const char *p = rows; p && *p;) {
    const char *e = strchr(p, '\n');
    if (!e) break;
    const char *f = p;
    for (int k = 0; k < s->n_axes + 6 && f < e; ++k) {
      const char *c = memchr(f, ',', (size_t)(e - f));
      f = c ? c + 1 : e;
    }
    bad += strncmp(f, "ok,", 3) != 0;
    p = e + 1;
  }
  return bad;
}

static void ea__set_fail(ea__run_t *r, ea_status_t st, const char *fmt, ...) {
  if (r->fail) return;
  r->fail = st;
  va_list ap;
  va_start(ap, fmt);
  vsnprintf(r->failmsg, sizeof r->failmsg, fmt, ap);
  va_end(ap);
}

/* The next case to compute (local index), or -1: none left, or stop (requested,
 * failed, the stop_after hook). Caller holds r->mu (threads) or is the only
 * thread (processes). */
static long ea__next_case(ea__run_t *r) {
  const int more = r->n_requeue > 0 || r->next < r->n_todo;
  const int halt = r->stop || r->fail || !more || (r->set->stop_request && *r->set->stop_request) ||
                   (r->set->stop_after > 0 && r->started >= r->set->stop_after);
  if (halt) {
    if (more) r->stop = 1;
    return -1;
  }
  ++r->started;
  return r->n_requeue > 0 ? r->requeue[--r->n_requeue] : r->todo[r->next++];
}

/* Case j's rows computed: b holds them (rows_len bytes) and the journal trailer. Append
 * the block to the journal, keep the rows. Caller holds r->mu or is the only thread. */
static void ea__commit(ea__run_t *r, long j, ea__sbuf_t *b, size_t rows_len) {
  int io = 0;
  if (r->fd >= 0) {
    io = ea__write_all(r->fd, b->s, b->len);
    r->dirty = 1;
    if (!io && r->set->fsync) {
      const double t = ea__mono_s();
      if (t - r->last_sync >= r->set->fsync_interval_s) {
        io = fsync(r->fd);
        r->last_sync = t;
        r->dirty = 0;
      }
    }
  }
  if (io) {
    ea__set_fail(r, EA_ERR_IO, "checkpoint journal %s: %s", r->set->checkpoint, strerror(errno));
    return;
  }
  b->s[rows_len] = '\0'; /* keep the rows, drop the trailer */
  r->rows[j] = b->s;
  r->rows_len[j] = rows_len;
  b->s = NULL;
  b->len = b->cap = 0;
  ++r->computed;
  ++r->done_total;
  if (r->set->progress)
    r->set->progress(r->set->progress_data, ea__case_of(r, j), r->done_total, r->n_shard,
                     ea__rows_failed(r->s, r->rows[j]));
}

/* The journal trailer of the rows in b (appended); -1 when out of memory. */
static int ea__trailer(ea__sbuf_t *b, long c) {
  if (b->oom) return -1;
  char trailer[96];
  snprintf(trailer, sizeof trailer, "#case %ld %zu %08x\n", c, b->len,
           (unsigned)ea_crc32(0, b->s, b->len));
  ea__sbuf_put(b, trailer, strlen(trailer));
  return b->oom ? -1 : 0;
}

static void *ea__worker(void *arg) {
  ea__run_t *r = arg;
  for (;;) {
    pthread_mutex_lock(&r->mu);
    const long j = ea__next_case(r);
    pthread_mutex_unlock(&r->mu);
    if (j < 0) break;
    const long c = ea__case_of(r, j);
    ea__sbuf_t b = {0};
    const int failed = ea__study_case_eval(r->s, c, r->set, r->ident, &b);
    const size_t rows_len = b.len;
    const int oom = failed < 0 || ea__trailer(&b, c);
    pthread_mutex_lock(&r->mu);
    if (oom)
      ea__set_fail(r, EA_ERR_NOMEM, "case %ld: out of memory", c);
    else
      ea__commit(r, j, &b, rows_len);
    pthread_mutex_unlock(&r->mu);
    ea__sbuf_free(&b);
  }
  return NULL;
}

/* ---- worker processes -------------------------------------------------------------
 * Each worker is forked with one end of a socketpair. The parent sends a case's local
 * index as a text line; the worker computes the case and sends back its journal block
 * (rows + "#case ID BYTES CRC32\n"), or "#fail STATUS MESSAGE\n". The parent alone
 * writes the journal and keeps the rows, exactly as the threads do, so the CSV is the
 * same bytes. A worker reads until its socket is shut for writing, then exits. */

typedef struct {
  pid_t pid; /* 0: slot unused */
  int fd;    /* parent's end; -1 once closed */
  long j;    /* case in flight (local index), -1 = idle */
  int shut;  /* no more cases will be sent */
  ea__sbuf_t in;
} ea__proc_t;

/* The worker process: cases from fd until EOF; never returns. */
static void ea__child_main(ea__run_t *r, int fd, pid_t parent) {
  struct sigaction sa;
  memset(&sa, 0, sizeof sa);
  sa.sa_handler = SIG_IGN;
  sigemptyset(&sa.sa_mask);
  sigaction(SIGINT, &sa, NULL); /* the parent's stop_request decides */
  sigaction(SIGTERM, &sa, NULL);
  sigaction(SIGPIPE, &sa, NULL); /* a closed socket is EPIPE, then exit */
#ifdef __linux__
  prctl(PR_SET_PDEATHSIG, SIGKILL); /* die with the parent (a second Ctrl-C) */
  if (getppid() != parent) _exit(3);
#else
  (void)parent;
#endif
  char line[64];
  size_t have = 0;
  for (;;) {
    char *nl = memchr(line, '\n', have);
    if (!nl) {
      if (have >= sizeof line - 1) _exit(4); /* not a command */
      const ssize_t n = read(fd, line + have, sizeof line - 1 - have);
      if (n < 0 && errno == EINTR) continue;
      if (n <= 0) _exit(0); /* no more cases */
      have += (size_t)n;
      continue;
    }
    *nl = '\0';
    char *end = NULL;
    const long j = strtol(line, &end, 10);
    if (end == line || *end || j < 0 || j >= r->n_shard) _exit(4);
    const size_t used = (size_t)(nl - line) + 1;
    memmove(line, nl + 1, have - used);
    have -= used;
    const long c = ea__case_of(r, j);
    ea__sbuf_t b = {0};
    const int failed = ea__study_case_eval(r->s, c, r->set, r->ident, &b);
    if (failed < 0 || ea__trailer(&b, c)) {
      char msg[128];
      const int w =
          snprintf(msg, sizeof msg, "#fail %d case %ld: out of memory\n", EA_ERR_NOMEM, c);
      if (ea__write_all(fd, msg, (size_t)w)) _exit(2);
    } else if (ea__write_all(fd, b.s, b.len)) {
      _exit(2); /* the parent is gone */
    }
    ea__sbuf_free(&b);
  }
}

/* Fork worker all[i] (of n slots); 0 or -1 (errno set). */
static int ea__spawn(ea__run_t *r, ea__proc_t *all, int n, int i) {
  ea__proc_t *w = &all[i];
  int sv[2];
  if (socketpair(AF_UNIX, SOCK_STREAM, 0, sv)) return -1;
  const pid_t parent = getpid();
  fflush(NULL); /* nothing buffered is written twice */
  const pid_t pid = fork();
  if (pid < 0) {
    const int e = errno;
    close(sv[0]);
    close(sv[1]);
    errno = e;
    return -1;
  }
  if (pid == 0) {
    /* the child keeps only its own end: a worker holding the parent's end of another
       worker's socket would keep that worker from seeing its EOF */
    close(sv[0]);
    for (int k = 0; k < n; ++k)
      if (k != i && all[k].fd >= 0) close(all[k].fd);
    if (r->fd >= 0) close(r->fd);
    ea__child_main(r, sv[1], parent);
  }
  close(sv[1]);
  w->pid = pid;
  w->fd = sv[0];
  w->j = -1;
  w->shut = 0;
  w->in.len = 0;
  return 0;
}

/* Hand worker w its next case, or shut its socket for writing (it then exits). */
static void ea__dispatch(ea__run_t *r, ea__proc_t *w) {
  const long j = w->shut ? -1 : ea__next_case(r);
  if (j < 0) {
    if (!w->shut) shutdown(w->fd, SHUT_WR);
    w->shut = 1;
    return;
  }
  char cmd[32];
  const int n = snprintf(cmd, sizeof cmd, "%ld\n", j);
  if (send(w->fd, cmd, (size_t)n, MSG_NOSIGNAL) != n) {
    /* the worker is gone before it got the case: another one takes it; its EOF follows */
    r->requeue[r->n_requeue++] = j;
    --r->started;
    w->shut = 1;
    return;
  }
  w->j = j;
}

/* A complete frame from worker w, if its input holds one: 1 taken, 0 not yet. */
static int ea__take_frame(ea__run_t *r, ea__proc_t *w) {
  const char *t = w->in.s;
  const size_t len = w->in.len;
  size_t at = 0; /* start of the first line that begins with '#' */
  while (at < len && t[at] != '#') {
    const char *nl = memchr(t + at, '\n', len - at);
    if (!nl) return 0;
    at = (size_t)(nl - t) + 1;
  }
  const char *nl = at < len ? memchr(t + at, '\n', len - at) : NULL;
  if (!nl) return 0;
  const size_t frame = (size_t)(nl - t) + 1;
  char line[512];
  snprintf(line, sizeof line, "%.*s", (int)(frame - at - 1), t + at);
  const long c = w->j >= 0 ? ea__case_of(r, w->j) : -1;
  int status = 0;
  long id;
  size_t bytes;
  unsigned crc;
  char tail;
  if (!strncmp(line, "#fail ", 6) && sscanf(line + 6, "%d", &status) == 1) {
    const char *msg = strchr(line + 6, ' ');
    ea__set_fail(r, (ea_status_t)status, "worker process %ld: %s", (long)w->pid,
                 msg ? msg + 1 : "failed");
  } else if (w->j < 0 || sscanf(line, "#case %ld %zu %8x%c", &id, &bytes, &crc, &tail) != 3 ||
             id != c || bytes != at || ea_crc32(0, t, at) != (uint32_t)crc) {
    ea__set_fail(r, EA_ERR_PROTOCOL,
                 "worker process %ld sent a malformed block for case %ld: '%.80s'", (long)w->pid, c,
                 line);
  } else {
    ea__sbuf_t b = {0};
    ea__sbuf_put(&b, t, frame);
    if (b.oom)
      ea__set_fail(r, EA_ERR_NOMEM, "case %ld: out of memory", c);
    else
      ea__commit(r, w->j, &b, at);
    ea__sbuf_free(&b);
  }
  w->j = -1;
  memmove(w->in.s, t + frame, len - frame);
  w->in.len = len - frame;
  return 1;
}

/* Worker w's socket reached EOF: wait for it; a case it was computing gets its failed
 * row. Returns 1 when it died with a case in flight. */
static int ea__reap(ea__run_t *r, ea__proc_t *w) {
  close(w->fd);
  w->fd = -1;
  int status = 0;
  while (waitpid(w->pid, &status, 0) < 0 && errno == EINTR) {
  }
  const pid_t pid = w->pid;
  w->pid = 0;
  ea__sbuf_free(&w->in);
  if (w->j < 0) return 0;
  const long j = w->j, c = ea__case_of(r, j);
  w->j = -1;
  char msg[300];
  if (WIFSIGNALED(status))
    snprintf(msg, sizeof msg,
             "the worker process computing this case was killed by signal %d (%s); its rows are "
             "lost: rerun the study (with --restart while its journal remains) to recompute it",
             WTERMSIG(status), strsignal(WTERMSIG(status)));
  else
    snprintf(msg, sizeof msg,
             "the worker process computing this case exited with status %d before sending its "
             "rows; they are lost: rerun the study (with --restart while its journal remains) to "
             "recompute it",
             WIFEXITED(status) ? WEXITSTATUS(status) : -1);
  (void)pid;
  ++r->workers_lost;
  ea__sbuf_t b = {0};
  const int bad = ea__study_case_fail(r->s, c, r->ident, EA_ERR_BACKEND, msg, &b);
  const size_t rows_len = b.len;
  if (bad < 0 || ea__trailer(&b, c))
    ea__set_fail(r, EA_ERR_NOMEM, "case %ld: out of memory", c);
  else
    ea__commit(r, j, &b, rows_len);
  ea__sbuf_free(&b);
  return 1;
}

/* Run the shard's cases in nw forked workers. Returns the number started at first (0:
 * none could be forked; nothing was computed, use threads). */
static int ea__run_processes(ea__run_t *r, int nw) {
  ea__proc_t *w = calloc((size_t)nw, sizeof *w);
  struct pollfd *pf = calloc((size_t)nw, sizeof *pf);
  int *slot = calloc((size_t)nw, sizeof *slot);
  r->requeue = calloc((size_t)nw + 1, sizeof *r->requeue);
  int started = 0;
  if (w && pf && slot && r->requeue) {
    for (int i = 0; i < nw; ++i)
      w[i].fd = -1;
    for (; started < nw; ++started)
      if (ea__spawn(r, w, nw, started)) break;
  }
  if (!started) {
    free(w);
    free(pf);
    free(slot);
    free(r->requeue);
    r->requeue = NULL;
    return 0;
  }
  for (int i = 0; i < started; ++i)
    ea__dispatch(r, &w[i]);
  int killed = 0;
  for (;;) {
    int np = 0;
    for (int i = 0; i < started; ++i)
      if (w[i].fd >= 0) {
        pf[np].fd = w[i].fd;
        pf[np].events = POLLIN;
        pf[np].revents = 0;
        slot[np++] = i;
      }
    if (!np) break;
    if (r->fail && !killed) {
      /* the run cannot complete (journal I/O, a worker's error): stop the workers now */
      for (int i = 0; i < started; ++i)
        if (w[i].pid > 0) kill(w[i].pid, SIGKILL);
      killed = 1;
    }
    const int n = poll(pf, (nfds_t)np, 1000);
    if (n < 0 && errno != EINTR) {
      ea__set_fail(r, EA_ERR_IO, "worker processes: poll: %s", strerror(errno));
      for (int i = 0; i < started; ++i)
        if (w[i].pid > 0) kill(w[i].pid, SIGKILL);
      killed = 1;
      for (int i = 0; i < started; ++i)
        if (w[i].fd >= 0) {
          w[i].j = -1;
          ea__reap(r, &w[i]);
        }
      break;
    }
    for (int q = 0; n > 0 && q < np; ++q) {
      if (!pf[q].revents) continue;
      ea__proc_t *x = &w[slot[q]];
      char buf[65536];
      const ssize_t got = read(x->fd, buf, sizeof buf);
      if (got < 0 && errno == EINTR) continue;
      if (got > 0) {
        ea__sbuf_put(&x->in, buf, (size_t)got);
        if (x->in.oom) ea__set_fail(r, EA_ERR_NOMEM, "worker input: out of memory");
        while (!killed && !x->in.oom && x->j >= 0 && ea__take_frame(r, x))
          ea__dispatch(r, x);
        continue;
      }
      if (killed) x->j = -1; /* stopped on purpose: its case is not a lost one */
      const int died_busy = ea__reap(r, x);
      /* a replacement takes the remaining cases (each death costs one case, so this ends) */
      if (died_busy && !killed && !r->fail && !r->stop &&
          (r->n_requeue > 0 || r->next < r->n_todo) && !ea__spawn(r, w, started, slot[q]))
        ea__dispatch(r, x);
    }
    int live = 0;
    for (int i = 0; i < started; ++i)
      live += w[i].fd >= 0;
    if (!live && !r->fail && !r->stop && (r->n_requeue > 0 || r->next < r->n_todo))
      ea__set_fail(r, EA_ERR_BACKEND, "every worker process died; %ld case(s) not computed",
                   r->n_todo - r->next + r->n_requeue);
  }
  free(w);
  free(pf);
  free(slot);
  free(r->requeue);
  r->requeue = NULL;
  return started;
}

/* Open (or create) the journal, keep the valid blocks of this study's
 * cases, truncate a torn tail. */
static ea_status_t ea__journal_open(ea__run_t *r, const char *key_line, ea_study_info_t *info,
                                    ea_error_t *err) {
  const char *path = r->set->checkpoint;
  int fd = open(path, O_RDWR | O_CREAT | O_APPEND, 0644);
  if (fd < 0)
    return ea_error_set(err, EA_ERR_IO, "checkpoint %s: cannot open: %s", path, strerror(errno));
  struct stat stt;
  if (fstat(fd, &stt) != 0) {
    close(fd);
    return ea_error_set(err, EA_ERR_IO, "checkpoint %s: %s", path, strerror(errno));
  }
  size_t size = (size_t)stt.st_size;
  char *text = malloc(size + 1);
  if (!text) {
    close(fd);
    return ea_error_set(err, EA_ERR_NOMEM, "checkpoint %s: out of memory", path);
  }
  size_t got = 0;
  while (got < size) {
    ssize_t n = pread(fd, text + got, size - got, (off_t)got);
    if (n <= 0) {
      if (n < 0 && errno == EINTR) continue;
      break;
    }
    got += (size_t)n;
  }
  size = got;
  text[size] = '\0';
  const size_t klen = strlen(key_line);
  size_t good = 0;
  if (size == 0 || (size < klen && !memcmp(text, key_line, size))) {
    /* new journal (or a torn header) */
    if (ftruncate(fd, 0) || ea__write_all(fd, key_line, klen) || (r->set->fsync && fsync(fd))) {
      free(text);
      close(fd);
      return ea_error_set(err, EA_ERR_IO, "checkpoint %s: cannot write: %s", path, strerror(errno));
    }
    free(text);
    r->fd = fd;
    return EA_OK;
  }
  if (size < klen || memcmp(text, key_line, klen)) {
    const int ours = !strncmp(text, EA__JOURNAL_MAGIC, strlen(EA__JOURNAL_MAGIC));
    free(text);
    close(fd);
    return ea_error_set(err, EA_ERR_INPUT,
                        ours ? "checkpoint %s belongs to another study (different name, grid, "
                               "arm, metric settings or min_time or at_rest task content); "
                               "remove it or pass --restart"
                             : "checkpoint %s is not a study journal; remove it or choose "
                               "another --checkpoint",
                        path);
  }
  good = klen;
  size_t block = klen, pos = klen;
  while (pos < size) {
    char *nl = memchr(text + pos, '\n', size - pos);
    if (!nl) break; /* torn last line */
    const size_t line_end = (size_t)(nl - text) + 1;
    if (text[pos] == '#') {
      long id;
      size_t bytes;
      unsigned crc;
      char tail;
      *nl = '\0';
      const int ok = sscanf(text + pos, "#case %ld %zu %8x%c", &id, &bytes, &crc, &tail) == 3;
      *nl = '\n';
      if (!ok || bytes != pos - block || ea_crc32(0, text + block, bytes) != (uint32_t)crc ||
          id < 0 || id >= r->s->n_cases)
        break;
      /* every row of the block must belong to the case */
      int rows_ok = bytes > 0;
      for (size_t q = block; rows_ok && q < pos;) {
        const char *e = memchr(text + q, '\n', pos - q);
        if (!e || ea__study_row_case(text + q, (size_t)(e - text) - q) != id) rows_ok = 0;
        q = e ? (size_t)(e - text) + 1 : pos;
      }
      if (!rows_ok) break;
      const long k1 = r->set->shard_k - 1, nn = r->set->shard_n;
      if (id % nn == k1) {
        const long j = id / nn;
        if (j < r->n_shard && !r->rows[j]) {
          char *copy = malloc(bytes + 1);
          if (!copy) {
            free(text);
            close(fd);
            return ea_error_set(err, EA_ERR_NOMEM, "checkpoint: out of memory");
          }
          memcpy(copy, text + block, bytes);
          copy[bytes] = '\0';
          r->rows[j] = copy;
          r->rows_len[j] = bytes;
          ++info->cases_skipped;
        }
      }
      block = line_end;
      good = line_end;
    }
    pos = line_end;
  }
  free(text);
  if (good < size) {
    if (ftruncate(fd, (off_t)good) || (r->set->fsync && fsync(fd))) {
      close(fd);
      return ea_error_set(err, EA_ERR_IO, "checkpoint %s: cannot truncate the torn tail: %s", path,
                          strerror(errno));
    }
    info->journal_dropped_bytes = (long)(size - good);
  }
  r->fd = fd;
  return EA_OK;
}

ea_status_t ea_study_run(const ea_study_t *s, const ea_study_settings_t *set_in, char **csv,
                         size_t *csv_len, ea_study_info_t *info, ea_error_t *err) {
  ea_study_info_t dummy;
  if (!info) info = &dummy;
  memset(info, 0, sizeof *info);
  if (csv) *csv = NULL;
  if (csv_len) *csv_len = 0;
  ea_study_settings_t set;
  if (set_in)
    set = *set_in;
  else
    ea_study_settings_default(&set);
  if (!s || !csv || s->n_cases < 1 || s->n_axes < 0)
    return info->status = ea_error_set(err, EA_ERR_ARG,
                                       "study run: NULL argument or unchecked study "
                                       "(call ea_study_check)");
  if (set.shard_n < 1 || set.shard_k < 1 || set.shard_k > set.shard_n)
    return info->status = ea_error_set(err, EA_ERR_ARG, "shard %d/%d: need 1 <= K <= N",
                                       set.shard_k, set.shard_n);
  const double t0 = ea__mono_s();
  ea__run_t r;
  memset(&r, 0, sizeof r);
  r.s = s;
  r.set = &set;
  r.fd = -1;
  const long k1 = set.shard_k - 1;
  r.n_shard = s->n_cases > k1 ? (s->n_cases - k1 + set.shard_n - 1) / set.shard_n : 0;
  info->cases_total = s->n_cases;
  info->cases_shard = r.n_shard;
  ea_status_t st = EA_OK;
  ea__sbuf_t head = {0};
  char hdr[4096], key[9];
  ea_study_key(s, &set, key);
  snprintf(r.ident, sizeof r.ident, "%s,%s", s->name, key);
  const size_t hlen = ea_study_csv_header(s, hdr, sizeof hdr);
  if (!hlen || hlen >= sizeof hdr) {
    st = ea_error_set(err, EA_ERR_NOMEM, "study run: header");
    goto out;
  }
  r.rows = calloc((size_t)r.n_shard + 1, sizeof *r.rows);
  r.rows_len = calloc((size_t)r.n_shard + 1, sizeof *r.rows_len);
  r.todo = malloc(((size_t)r.n_shard + 1) * sizeof *r.todo);
  if (!r.rows || !r.rows_len || !r.todo) {
    st = ea_error_set(err, EA_ERR_NOMEM, "study run: out of memory");
    goto out;
  }
  if (set.checkpoint && set.checkpoint[0]) {
    char key_line[128];
    snprintf(key_line, sizeof key_line, EA__JOURNAL_MAGIC " key=%s cases=%ld\n", key, s->n_cases);
    if ((st = ea__journal_open(&r, key_line, info, err))) goto out;
    r.last_sync = ea__mono_s();
  }
  for (long j = 0; j < r.n_shard; ++j)
    if (!r.rows[j]) r.todo[r.n_todo++] = j;
  r.done_total = r.n_shard - r.n_todo;
  int nt = set.threads;
  if (nt <= 0) {
    const long cores = sysconf(_SC_NPROCESSORS_ONLN);
    nt = cores > 0 ? (int)(cores > 256 ? 256 : cores) : 1;
  }
  if (nt > 1024) nt = 1024;
  if ((long)nt > r.n_todo) nt = r.n_todo > 0 ? (int)r.n_todo : 1;
  info->threads = nt;
  pthread_mutex_init(&r.mu, NULL);
  /* planner metrics in forked processes: MUMPS (sequential) serialises Ipopt calls
     within one process, so threads would wait for each other */
  const int plans = ((s->metrics & EA_STUDY_M_MIN_TIME) && set.min_time) ||
                    ((s->metrics & EA_STUDY_M_AT_REST) && set.at_rest);
  const int procs = r.n_todo > 0 && (set.workers == EA_STUDY_WORKERS_PROCESSES ||
                                     (set.workers == EA_STUDY_WORKERS_AUTO && plans && nt > 1));
  int forked = procs ? ea__run_processes(&r, nt) : 0;
  if (forked) {
    info->threads = forked;
    info->processes = 1;
  } else if (nt == 1) {
    ea__worker(&r);
  } else {
    pthread_t *tid = malloc((size_t)nt * sizeof *tid);
    int started = 0;
    if (tid)
      for (; started < nt; ++started)
        if (pthread_create(&tid[started], NULL, ea__worker, &r)) break;
    if (started == 0) ea__worker(&r); /* no threads: run here */
    for (int i = 0; i < started; ++i)
      pthread_join(tid[i], NULL);
    info->threads = started ? started : 1;
    free(tid);
  }
  pthread_mutex_destroy(&r.mu);
  info->cases_computed = r.computed;
  info->workers_lost = r.workers_lost;
  if (r.fd >= 0 && r.dirty && set.fsync && fsync(r.fd) && !r.fail) {
    r.fail = EA_ERR_IO;
    snprintf(r.failmsg, sizeof r.failmsg, "checkpoint journal %s: fsync: %s", set.checkpoint,
             strerror(errno));
  }
  if (r.fail) {
    st = ea_error_set(err, r.fail, "%s", r.failmsg);
    goto out;
  }
  for (long j = 0; j < r.n_shard; ++j)
    if (!r.rows[j]) {
      st = ea_error_set(err, EA_ERR_INTERRUPTED,
                        "study stopped after %ld new case(s); %ld of %ld case(s) of the shard "
                        "done%s",
                        r.computed, r.done_total, r.n_shard,
                        set.checkpoint ? "; rerun to resume from the checkpoint" : "");
      goto out;
    }
  ea__sbuf_put(&head, hdr, hlen);
  for (long j = 0; j < r.n_shard; ++j) {
    ea__sbuf_put(&head, r.rows[j], r.rows_len[j]);
    const int bad = ea__rows_failed(s, r.rows[j]);
    info->rows_failed += bad;
    info->cases_failed += bad > 0;
  }
  if (head.oom) {
    st = ea_error_set(err, EA_ERR_NOMEM, "study run: out of memory");
    goto out;
  }
  *csv = head.s;
  if (csv_len) *csv_len = head.len;
  head.s = NULL;
out:
  if (r.fd >= 0) close(r.fd);
  if (r.rows)
    for (long j = 0; j < r.n_shard; ++j)
      free(r.rows[j]);
  free(r.rows);
  free(r.rows_len);
  free(r.todo);
  ea__sbuf_free(&head);
  info->time_s = ea__mono_s() - t0;
  info->status = st;
  return st;
}

/* ---- merge ----------------------------------------------------------------- */

typedef struct {
  long id;
  int src;
  size_t start, len;
} ea__group_t;

static int ea__group_cmp(const void *a, const void *b) {
  const ea__group_t *x = a, *y = b;
  return (x->id > y->id) - (x->id < y->id);
}

ea_status_t ea_study_merge(const char *const *texts, const size_t *lens, const char *const *names,
                           int n, long expect_cases, char **out, size_t *out_len, ea_error_t *err) {
  if (!texts || !lens || !out || n < 1) return ea_error_set(err, EA_ERR_ARG, "merge: no inputs");
  *out = NULL;
  if (out_len) *out_len = 0;
  ea__group_t *g = NULL;
  size_t ng = 0, cap = 0;
  size_t hlen = 0;
  ea_status_t st = EA_OK;
  ea__sbuf_t o = {0};
  /* the study and study_key columns of the first row: every row must agree */
  char ref_id[200] = "", ref_where[300] = "";
  for (int i = 0; i < n; ++i) {
    const char *t = texts[i], *nm = names && names[i] ? names[i] : "input";
    const size_t len = lens[i];
    const char *e = len ? memchr(t, '\n', len) : NULL;
    if (!e || strncmp(t, "case_id,", 8)) {
      st = ea_error_set(err, EA_ERR_INPUT, "%s:1:1: not a study CSV (no 'case_id,...' header)", nm);
      goto out;
    }
    const size_t h = (size_t)(e - t) + 1;
    if (i == 0) {
      hlen = h;
    } else if (h != hlen || memcmp(t, texts[0], h)) {
      st = ea_error_set(err, EA_ERR_INPUT,
                        "%s:1:1: header differs from %s's (shards of different studies?)", nm,
                        names && names[0] ? names[0] : "the first input");
      goto out;
    }
    if (t[len - 1] != '\n') {
      long line = 1;
      for (size_t q = 0; q < len; ++q)
        line += t[q] == '\n';
      st = ea_error_set(err, EA_ERR_INPUT, "%s:%ld: the last row is truncated (no newline)", nm,
                        line);
      goto out;
    }
    long line = 1, prev = -1;
    for (size_t q = h; q < len;) {
      ++line;
      const char *le = memchr(t + q, '\n', len - q);
      const size_t ll = (size_t)(le - t) - q;
      const long id = ea__study_row_case(t + q, ll);
      if (id < 0) {
        st = ea_error_set(err, EA_ERR_INPUT, "%s:%ld:1: row without a case_id", nm, line);
        goto out;
      }
      {
        const char *c1 = memchr(t + q, ',', ll);
        const char *c2 = c1 ? memchr(c1 + 1, ',', (size_t)(t + q + ll - c1 - 1)) : NULL;
        const char *c3 = c2 ? memchr(c2 + 1, ',', (size_t)(t + q + ll - c2 - 1)) : NULL;
        if (!c3 || (size_t)(c3 - c1) >= sizeof ref_id) {
          st = ea_error_set(err, EA_ERR_INPUT, "%s:%ld:1: row without study and study_key", nm,
                            line);
          goto out;
        }
        const size_t il = (size_t)(c3 - c1 - 1);
        if (!ref_id[0]) {
          memcpy(ref_id, c1 + 1, il);
          ref_id[il] = '\0';
          snprintf(ref_where, sizeof ref_where, "%s:%ld", nm, line);
        } else if (strlen(ref_id) != il || memcmp(ref_id, c1 + 1, il)) {
          st = ea_error_set(err, EA_ERR_INPUT,
                            "%s:%ld: row of study,study_key '%.*s' but %s has '%s': the shards "
                            "come from different specs (or the spec, its arm or its planner task "
                            "changed between them) and cannot be merged",
                            nm, line, (int)il, c1 + 1, ref_where, ref_id);
          goto out;
        }
      }
      if (id == prev) {
        g[ng - 1].len += ll + 1;
      } else {
        if (id < prev) {
          st = ea_error_set(err, EA_ERR_INPUT,
                            "%s:%ld:1: case %ld after case %ld (rows out of "
                            "order)",
                            nm, line, id, prev);
          goto out;
        }
        if (ng == cap) {
          cap = cap ? 2 * cap : 1024;
          ea__group_t *ng2 = realloc(g, cap * sizeof *g);
          if (!ng2) {
            st = ea_error_set(err, EA_ERR_NOMEM, "merge: out of memory");
            goto out;
          }
          g = ng2;
        }
        g[ng++] = (ea__group_t){id, i, q, ll + 1};
        prev = id;
      }
      q += ll + 1;
    }
  }
  if (ng > 1) qsort(g, ng, sizeof *g, ea__group_cmp); /* g is NULL when no rows */
  for (size_t k = 1; k < ng; ++k)
    if (g[k].id == g[k - 1].id) {
      st = ea_error_set(err, EA_ERR_INPUT, "case %ld is in %s and in %s", g[k].id,
                        names ? names[g[k - 1].src] : "two inputs",
                        names ? names[g[k].src] : "another");
      goto out;
    }
  for (size_t k = 0; k < ng; ++k) {
    if (g[k].id != (long)k) {
      st = ea_error_set(err, EA_ERR_INPUT, "case %ld is missing (no shard has it)", (long)k);
      goto out;
    }
  }
  if (expect_cases > 0 && (long)ng != expect_cases) {
    st = ea_error_set(err, EA_ERR_INPUT,
                      "the shards hold %zu cases, expected %ld (cases %zu.. "
                      "missing)",
                      ng, expect_cases, ng);
    goto out;
  }
  ea__sbuf_put(&o, texts[0], hlen);
  for (size_t k = 0; k < ng; ++k)
    ea__sbuf_put(&o, texts[g[k].src] + g[k].start, g[k].len);
  if (o.oom) {
    st = ea_error_set(err, EA_ERR_NOMEM, "merge: out of memory");
    goto out;
  }
  *out = o.s;
  if (out_len) *out_len = o.len;
  o.s = NULL;
out:
  free(g);
  ea__sbuf_free(&o);
  return st;
}
