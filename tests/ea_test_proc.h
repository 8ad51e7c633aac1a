/* Test helper: the CLI as a child process (fork + exec, outputs to files), waited for with
 * a bound, and the port a controller-sim writes to its --port-file. */
#ifndef EA_TEST_PROC_H
#define EA_TEST_PROC_H

#include <signal.h>
#include <stdio.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

static inline void ea_test_msleep(int ms) {
  struct timespec ts = {ms / 1000, (ms % 1000) * 1000000L};
  nanosleep(&ts, NULL);
}

/* fork + exec argv with stdout and stderr to the files out and err (NULL: inherited);
 * returns the child's pid. */
static inline pid_t ea_test_spawn(char *const argv[], const char *out, const char *err) {
  fflush(stdout); /* else the child's freopen flushes our buffer a second time */
  fflush(stderr);
  const pid_t pid = fork();
  if (pid == 0) {
    if (out && !freopen(out, "w", stdout)) _exit(127);
    if (err && !freopen(err, "w", stderr)) _exit(127);
    execv(argv[0], argv);
    _exit(127);
  }
  return pid;
}

/* Wait for pid at most ms; kill it if it overstays. Returns its exit code, or -1. */
static inline int ea_test_wait_for(pid_t pid, int ms) {
  int status = 0;
  for (int t = 0; t < ms; t += 10) {
    if (waitpid(pid, &status, WNOHANG) == pid) return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    ea_test_msleep(10);
  }
  kill(pid, SIGKILL);
  waitpid(pid, &status, 0);
  return -1;
}

/* The port written to the file pf, waiting at most tries x 10 ms (0: none). */
static inline int ea_test_read_port(const char *pf, int tries) {
  for (int t = 0; t < tries; ++t) {
    FILE *fp = fopen(pf, "r");
    int port = 0;
    if (fp) {
      const int ok = fscanf(fp, "%d", &port) == 1;
      fclose(fp);
      if (ok && port > 0) return port;
    }
    ea_test_msleep(10);
  }
  return 0;
}

#endif
