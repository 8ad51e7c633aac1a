/* The stream and controller-sim subcommands as processes: a clean session
 * with a log, SIGINT to the streamer mid-stream (controlled stop, exit 1,
 * the simulator's log ends at rest), a dry run to a file, and a too-fast
 * trajectory refused before anything is sent. Loopback only, bounded. */
#include "ea_test.h"
#include "stream_impl.h"
#include "test_stream_fixture.h"

#include <signal.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

static const char *bin;

static void msleep(int ms) {
  struct timespec ts = {ms / 1000, (ms % 1000) * 1000000L};
  nanosleep(&ts, NULL);
}

/* fork + exec argv with stdout/stderr to files; returns pid. */
static pid_t spawn(char *const argv[], const char *out, const char *errf) {
  fflush(stdout); /* else the child's freopen flushes our buffer a second time */
  fflush(stderr);
  const pid_t pid = fork();
  if (pid == 0) {
    if (out && !freopen(out, "w", stdout)) _exit(127);
    if (errf && !freopen(errf, "w", stderr)) _exit(127);
    execv(argv[0], argv);
    _exit(127);
  }
  return pid;
}

/* Wait for pid at most ms; kill it if it overstays. Returns exit code or -1. */
static int wait_for(pid_t pid, int ms) {
  int status = 0;
  for (int t = 0; t < ms; t += 10) {
    if (waitpid(pid, &status, WNOHANG) == pid) return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    msleep(10);
  }
  kill(pid, SIGKILL);
  waitpid(pid, &status, 0);
  return -1;
}

static int read_port(const char *pf) {
  for (int t = 0; t < 300; ++t) {
    FILE *fp = fopen(pf, "r");
    int port = 0;
    if (fp) {
      const int ok = fscanf(fp, "%d", &port) == 1;
      fclose(fp);
      if (ok && port > 0) return port;
    }
    msleep(10);
  }
  return 0;
}

static pid_t start_sim(const char *log, int *port) {
  remove("cli_sim.port");
  char *argv[] = {(char *)bin, "controller-sim", "--listen", "127.0.0.1:0", "--port-file",
                  "cli_sim.port", "--log", (char *)log, "--timeout", "5", NULL};
  const pid_t pid = spawn(argv, "cli_sim.out", "cli_sim.err");
  *port = read_port("cli_sim.port");
  return pid;
}

/* Rows of a log (non-comment, non-header) and the velocities of the last. */
static int log_rows(const char *path, double *v_last) {
  FILE *fp = fopen(path, "r");
  if (!fp) return -1;
  char line[4096];
  int n = 0;
  while (fgets(line, sizeof line, fp)) {
    if (line[0] == '#' || !strncmp(line, "seq,", 4)) continue;
    ++n;
    /* seq,source,time,recv,spool0,spool1,spool_vel,spool_acc,sh,sh_vel,sh_acc,base,base_vel */
    double c[13];
    if (sscanf(line, "%lf,%lf,%lf,%lf,%lf,%lf,%lf,%lf,%lf,%lf,%lf,%lf,%lf", &c[0], &c[1], &c[2],
               &c[3], &c[4], &c[5], &c[6], &c[7], &c[8], &c[9], &c[10], &c[11], &c[12]) == 13)
      *v_last = fabs(c[6]) + fabs(c[9]) + fabs(c[12]);
  }
  fclose(fp);
  return n;
}

int main(void) {
  bin = getenv("EA_BINARY");
  if (!bin || access(bin, X_OK)) {
    printf("SKIP: EA_BINARY not set\n");
    return 0;
  }
  signal(SIGPIPE, SIG_IGN);
  ea_arm_t arm;
  ea_arm_default(&arm);
  fx_move_t m = fx_default_move();
  ea_traj_t tr = {0};
  fx_make_traj(&m, &arm, 0.02, &tr);
  ea_test_true(ea_traj_write(&tr, "cli_move.csv", NULL) == EA_OK, "fixture trajectory written");
  fx_move_t fast = m;
  fast.dL = 0.3;
  fx_make_traj(&fast, &arm, 0.02, &tr);
  ea_traj_write(&tr, "cli_fast.csv", NULL);
  ea_traj_free(&tr);

  /* 1. Clean session. */
  int port = 0;
  pid_t sim = start_sim("cli_sim_log.csv", &port);
  ea_test_true(port > 0, "controller-sim wrote its port");
  char url[64];
  snprintf(url, sizeof url, "tcp://127.0.0.1:%d", port);
  {
    char *argv[] = {(char *)bin, "stream", "cli_move.csv", "--to", url, "--json", NULL};
    const int rc = wait_for(spawn(argv, "cli_stream.json", "cli_stream.err"), 5000);
    ea_test_true(rc == 0, "stream: exit 0 for a complete session");
  }
  ea_test_true(wait_for(sim, 5000) == 0, "controller-sim: exit 0 after a clean session");
  double v = -1;
  int rows = log_rows("cli_sim_log.csv", &v);
  printf("log rows %d\n", rows);
  ea_test_true(rows == 601, "controller-sim log holds the 601 setpoints");

  /* 2. SIGINT to the streamer mid-stream. */
  sim = start_sim("cli_sim_log2.csv", &port);
  snprintf(url, sizeof url, "tcp://127.0.0.1:%d", port);
  {
    char *argv[] = {(char *)bin, "stream", "cli_move.csv", "--to", url, "--json", NULL};
    const pid_t st = spawn(argv, "cli_stream2.json", "cli_stream2.err");
    msleep(300);
    kill(st, SIGINT);
    const int rc = wait_for(st, 5000);
    ea_test_true(rc == 1, "stream: SIGINT -> controlled stop, exit 1");
    FILE *fp = fopen("cli_stream2.json", "r");
    char buf[4096] = {0};
    if (fp) {
      if (!fread(buf, 1, sizeof buf - 1, fp)) buf[0] = 0;
      fclose(fp);
    }
    ea_test_true(strstr(buf, "\"stop-interrupt\"") != NULL, "JSON summary says stop-interrupt");
  }
  wait_for(sim, 5000);
  v = -1;
  rows = log_rows("cli_sim_log2.csv", &v);
  printf("log rows %d, |v| at the end %g\n", rows, v);
  ea_test_true(rows > 0 && v == 0.0, "after SIGINT the controller log ends at rest");

  /* 3. Dry run to a file. */
  {
    char *argv[] = {(char *)bin, "stream", "cli_move.csv", "--to", "file:cli_dry.bin", NULL};
    const int rc = wait_for(spawn(argv, "cli_dry.out", "cli_dry.err"), 5000);
    struct stat sb;
    const int ok = stat("cli_dry.bin", &sb) == 0 && sb.st_size == 152 + 601 * 140 + 32;
    ea_test_true(rc == 0 && ok, "file: dry run writes HELLO + 601 setpoints + END");
  }

  /* 4. Too fast: refused before anything is sent. */
  {
    char *argv[] = {(char *)bin, "stream", "cli_fast.csv", "--to", "file:cli_fast.bin", NULL};
    remove("cli_fast.bin");
    const int rc = wait_for(spawn(argv, "cli_fast.out", "cli_fast.err"), 5000);
    ea_test_true(rc == 1 && access("cli_fast.bin", F_OK) != 0,
                 "too fast a trajectory: exit 1, nothing written");
  }
  const char *tmp[] = {"cli_move.csv", "cli_fast.csv", "cli_sim.port", "cli_sim.out",
                       "cli_sim.err", "cli_sim_log.csv", "cli_sim_log2.csv", "cli_stream.json",
                       "cli_stream.err", "cli_stream2.json", "cli_stream2.err", "cli_dry.bin",
                       "cli_dry.out", "cli_dry.err", "cli_fast.out", "cli_fast.err"};
  for (size_t i = 0; i < sizeof tmp / sizeof *tmp; ++i) remove(tmp[i]);
  return ea_test_summary("test_stream_cli");
}
