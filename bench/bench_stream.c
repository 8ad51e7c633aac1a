/* Command streamer benchmark: send jitter at 1 kHz over TCP loopback against
 * the controller simulator (median, p99, max, late frames), and frame
 * encode / decode / parse throughput.
 *   bench_stream [seconds-of-stream (2)] [rate-hz (1000)] */
#include "stream_impl.h"
#include "test_stream_fixture.h"

#include <pthread.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#ifdef __linux__
#include <sys/prctl.h>
#endif

typedef struct {
  ea_ctrl_t *c;
  ea_ctrl_info_t info;
  ea_status_t st;
} sim_t;

static void *sim_main(void *p) {
  sim_t *s = p;
  s->st = ea_ctrl_run(s->c, &s->info, NULL);
  return NULL;
}

static double now_s(void) {
  return ea__mono_ns() * 1e-9;
}

int main(int argc, char **argv) {
  const double seconds = argc > 1 ? atof(argv[1]) : 2.0;
  const double rate = argc > 2 ? atof(argv[2]) : 1000.0;
  if (!(seconds > 0.1 && seconds < 600 && rate >= 1 && rate <= 100000)) {
    fprintf(stderr, "usage: bench_stream [seconds 0.1..600] [rate-hz 1..100000]\n");
    return 2;
  }
#if defined(__linux__) && defined(PR_SET_TIMERSLACK)
  prctl(PR_SET_TIMERSLACK, 1UL, 0UL, 0UL, 0UL); /* as the CLI does */
#endif
  ea_arm_t arm;
  ea_arm_default(&arm);
  struct timespec res;
  clock_getres(CLOCK_MONOTONIC, &res);
  printf("CLOCK_MONOTONIC resolution %ld ns\n", res.tv_nsec);

  /* ---- Throughput ---------------------------------------------------------- */
  fx_move_t m = fx_default_move();
  ea_joint_state_t q;
  fx_exact(&m, 0.3, &q);
  ea_frame_t f;
  memset(&f, 0, sizeof f);
  f.type = EA_FRAME_SETPOINT;
  ea_stream_map(&arm, &q, &f.sp);
  uint8_t buf[EA_PROTO_FRAME_MAX];
  const int N = 2000000;
  double t0 = now_s();
  size_t bytes = 0;
  for (int i = 0; i < N; ++i) {
    f.seq = (uint32_t)i;
    f.time_us = (uint64_t)i * 1000u;
    bytes += ea_frame_encode(&f, buf, sizeof buf);
  }
  const double t_enc = now_s() - t0;
  const size_t len = ea_frame_encode(&f, buf, sizeof buf);
  ea_frame_t g;
  int ok = 0;
  t0 = now_s();
  for (int i = 0; i < N; ++i) {
    buf[8] = (uint8_t)i; /* defeat caching of the result; CRC then fails half the time */
    ok += ea_frame_decode(buf, len, &g, NULL) == EA_OK;
  }
  const double t_dec = now_s() - t0;
  /* Parser over a long byte stream of valid frames. */
  const int M = 200000;
  uint8_t *stream = malloc((size_t)M * len);
  for (int i = 0; i < M; ++i) {
    f.seq = (uint32_t)i;
    ea_frame_encode(&f, stream + (size_t)i * len, len);
  }
  ea_frame_parser_t p;
  ea_frame_parser_init(&p);
  int parsed = 0;
  t0 = now_s();
  for (size_t off = 0; off < (size_t)M * len;) {
    off += ea_frame_parser_feed(&p, stream + off,
                                (size_t)M * len - off < 1460 ? (size_t)M * len - off : 1460);
    int r;
    while ((r = ea_frame_parser_next(&p, &g)) != 0)
      parsed += r > 0;
  }
  const double t_par = now_s() - t0;
  free(stream);
  printf("encode: %.2f M frames/s (%.0f MB/s); decode incl. CRC: %.2f M frames/s (%d valid); "
         "parser: %.2f M frames/s (%d of %d)\n",
         N / t_enc * 1e-6, bytes / t_enc * 1e-6, N / t_dec * 1e-6, ok, M / t_par * 1e-6, parsed, M);

  /* ---- Jitter on loopback ---------------------------------------------------- */
  m.T = seconds;
  ea_traj_t tr = {0};
  fx_make_traj(&m, &arm, 0.02, &tr);
  ea_setpoint_t *sp = NULL;
  int n = 0;
  ea_error_t err = {0};
  if (ea_stream_resample(&tr, &arm, rate, 1e-9, &sp, &n, &err)) {
    fprintf(stderr, "bench_stream: %s\n", err.msg);
    return 1;
  }
  ea_traj_free(&tr);
  ea_ctrl_settings_t cs;
  ea_ctrl_settings_default(&cs);
  cs.timeout_s = 5;
  sim_t sim;
  memset(&sim, 0, sizeof sim);
  if (ea_ctrl_open(&arm, "127.0.0.1:0", &cs, &sim.c, &err)) {
    fprintf(stderr, "bench_stream: %s\n", err.msg);
    return 1;
  }
  pthread_t th;
  pthread_create(&th, NULL, sim_main, &sim);
  char url[64];
  snprintf(url, sizeof url, "tcp://127.0.0.1:%d", ea_ctrl_port(sim.c));
  ea_stream_settings_t ss;
  ea_stream_settings_default(&ss);
  ss.rate_hz = rate;
  ea_stream_info_t info;
  const ea_status_t st = ea_stream_run(&arm, sp, n, url, &ss, &info, &err);
  pthread_join(th, NULL);
  printf("stream %d setpoints at %g Hz over TCP loopback: %s; acked %d, late %d (> half a "
         "period)\n  send jitter |t_send - deadline|: median %.1f us, p99 %.1f us, max %.1f us; "
         "max ACK latency %.2f ms\n",
         n, rate, st ? err.msg : "complete", info.frames_acked, info.frames_late,
         info.jitter_p50_us, info.jitter_p99_us, info.jitter_max_us, info.ack_latency_max_ms);
  ea_ctrl_free(sim.c);
  free(sp);
  return st ? 1 : 0;
}
