/* CLI: stream (trajectory -> controller) and controller-sim (docs/streaming.md). */
#include "cli_impl.h"
#include "stream_impl.h"

#include <errno.h>
#include <fcntl.h>
#include <math.h>
#include <sched.h>
#include <signal.h>
#include <stdlib.h>
#include <string.h>
#include <sys/mman.h>
#include <unistd.h>
#ifdef __linux__
#include <sys/prctl.h>
#endif

static volatile sig_atomic_t ea__cli_stop = 0;

static void ea__cli_on_sigint(int sig) {
  (void)sig;
  ea__cli_stop = 1;
  signal(SIGINT, SIG_DFL); /* a second Ctrl-C ends the process at once */
  signal(SIGTERM, SIG_DFL);
}

/* Real-time hygiene of the sending thread: 1 ns timer slack (the default
 * 50 us is added to every clock_nanosleep wake-up); with --rt also
 * SCHED_FIFO and locked memory, if the system allows it. */
static void ea__cli_realtime(int rt) {
#if defined(__linux__) && defined(PR_SET_TIMERSLACK)
  prctl(PR_SET_TIMERSLACK, 1UL, 0UL, 0UL, 0UL);
#endif
  if (!rt) return;
  struct sched_param sp;
  memset(&sp, 0, sizeof sp);
  sp.sched_priority = 50;
  if (sched_setscheduler(0, SCHED_FIFO, &sp) != 0)
    fprintf(stderr, "elasticarm stream: --rt: SCHED_FIFO not permitted (%s); continuing\n",
            strerror(errno));
  if (mlockall(MCL_CURRENT | MCL_FUTURE) != 0)
    fprintf(stderr, "elasticarm stream: --rt: mlockall failed (%s); continuing\n",
            strerror(errno));
}

static void ea__cli_install_stop(void) {
  struct sigaction sa;
  memset(&sa, 0, sizeof sa);
  sa.sa_handler = ea__cli_on_sigint;
  sigemptyset(&sa.sa_mask);
  sa.sa_flags = 0; /* no SA_RESTART: sleeps and polls return early */
  sigaction(SIGINT, &sa, NULL);
  sigaction(SIGTERM, &sa, NULL);
  signal(SIGPIPE, SIG_IGN);
}

/* ---- stream ------------------------------------------------------------------ */

static const char *ea__stream_help =
    "usage: elasticarm stream TRAJ --to DEST [options]\n\n"
    "Resample a trajectory file (docs/trajectory-format.md) at the controller rate,\n"
    "map it to spool, shoulder and base motor setpoints, check every limit of the arm\n"
    "file, then send it in real time (docs/protocol.md, docs/streaming.md).\n\n"
    "  --to DEST             tcp://HOST:PORT | udp://HOST:PORT | serial:DEVICE[@BAUD]\n"
    "                        | file:PATH (dry run, binary frames; file:- = stdout)\n"
    "  --rate-hz R           setpoint rate (default 1000)\n"
    "  --arm FILE            arm parameters (default data/elasticarm.yaml)\n"
    "  --json                summary as JSON on stdout\n"
    "  --no-realtime         send as fast as possible (default for file:)\n"
    "  --realtime            pace file: output too\n"
    "  --ack-timeout-ms T    controlled stop when a frame waits T ms for its ACK (100)\n"
    "  --start-tol-m X       handshake tolerance on the cable length (0.001)\n"
    "  --start-tol-rad X     handshake tolerance on theta0 and base (0.01)\n"
    "  --time-scale S|auto   play the plan S >= 1 times slower (rates / S, accelerations\n"
    "                        / S^2); auto = the least S that meets the speed and\n"
    "                        acceleration limits between the plan's samples (default 1)\n"
    "  --rt                  SCHED_FIFO priority 50 and locked memory (if permitted)\n\n"
    "On NACK, ACK timeout or SIGINT: a controlled stop within the limits, then END.\n"
    "Exit: 0 complete, 1 stopped / refused / link lost, 2 usage or input error.\n";

int ea__cli_stream(int argc, char **argv) {
  const char *cmd = "stream", *traj_path = NULL, *to = NULL, *arm_file = NULL;
  ea_stream_settings_t s;
  ea_stream_settings_default(&s);
  int json = 0, realtime = -1, rt = 0, time_scale_auto = 0;
  double time_scale = 1.0;
  for (int i = 1; i < argc; ++i) {
    const char *a = argv[i], *v;
    if (!strcmp(a, "--help") || !strcmp(a, "-h")) {
      fputs(ea__stream_help, stdout);
      return EA_EXIT_OK;
    } else if (!strcmp(a, "--to")) {
      if (!(to = ea__cli_value(cmd, argc, argv, &i))) return EA_EXIT_USAGE;
    } else if (!strcmp(a, "--arm")) {
      if (!(arm_file = ea__cli_value(cmd, argc, argv, &i))) return EA_EXIT_USAGE;
    } else if (!strcmp(a, "--rate-hz")) {
      if (!(v = ea__cli_value(cmd, argc, argv, &i)) ||
          ea__cli_double(cmd, a, v, 1, 100000, &s.rate_hz))
        return EA_EXIT_USAGE;
    } else if (!strcmp(a, "--ack-timeout-ms")) {
      double ms;
      if (!(v = ea__cli_value(cmd, argc, argv, &i)) || ea__cli_double(cmd, a, v, 1, 60000, &ms))
        return EA_EXIT_USAGE;
      s.ack_timeout_s = ms * 1e-3;
    } else if (!strcmp(a, "--start-tol-m")) {
      if (!(v = ea__cli_value(cmd, argc, argv, &i)) ||
          ea__cli_double(cmd, a, v, 0, 1, &s.start_tol_cable))
        return EA_EXIT_USAGE;
    } else if (!strcmp(a, "--start-tol-rad")) {
      if (!(v = ea__cli_value(cmd, argc, argv, &i)) ||
          ea__cli_double(cmd, a, v, 0, 1, &s.start_tol_angle))
        return EA_EXIT_USAGE;
    } else if (!strcmp(a, "--json")) {
      json = 1;
    } else if (!strcmp(a, "--no-realtime")) {
      realtime = 0;
    } else if (!strcmp(a, "--realtime")) {
      realtime = 1;
    } else if (!strcmp(a, "--time-scale")) {
      if (!(v = ea__cli_value(cmd, argc, argv, &i))) return EA_EXIT_USAGE;
      if (!strcmp(v, "auto"))
        time_scale_auto = 1;
      else if (ea__cli_double(cmd, a, v, 1, 1000, &time_scale))
        return EA_EXIT_USAGE;
    } else if (!strcmp(a, "--rt")) {
      rt = 1;
    } else if (a[0] == '-' && a[1]) {
      return ea__cli_usage_error(cmd, "unknown option '%s'", a);
    } else if (!traj_path) {
      traj_path = a;
    } else {
      return ea__cli_usage_error(cmd, "more than one trajectory ('%s')", a);
    }
  }
  if (!traj_path) return ea__cli_usage_error(cmd, "no trajectory file");
  if (!to) return ea__cli_usage_error(cmd, "no destination (--to tcp://HOST:PORT, ...)");
  const int to_file = !strncmp(to, "file:", 5);
  const int to_stdout = !strcmp(to, "file:-");
  if (json && to_stdout) return ea__cli_usage_error(cmd, "--json needs stdout: not with file:-");
  s.realtime = realtime >= 0 ? realtime : !to_file;
  s.wait_acks = !to_file;
  FILE *out = to_stdout ? stderr : stdout;

  ea_arm_t arm;
  int rc = ea__cli_load_arm(cmd, arm_file, &arm);
  if (rc) return rc;
  ea_traj_t tr = {0};
  ea_error_t err = {0};
  ea_status_t st = ea_traj_read(&tr, traj_path, &err);
  if (st) return ea__cli_fail(cmd, st, &err);
  ea_setpoint_t *sp = NULL;
  int n = 0;
  if (time_scale_auto) {
    st = ea_stream_min_time_scale(&tr, &arm, s.rate_hz, s.limit_tol, &time_scale, &err);
    if (st) {
      ea_traj_free(&tr);
      fprintf(stderr, "elasticarm %s: refused: %s\n", cmd, err.msg);
      return EA_EXIT_FAIL;
    }
    if (time_scale > 1.0)
      fprintf(stderr, "elasticarm %s: --time-scale auto: playing the plan %.6g times slower\n",
              cmd, time_scale);
  }
  st = ea_stream_resample_scaled(&tr, &arm, s.rate_hz, time_scale, s.limit_tol, &sp, &n, &err);
  if (st == EA_ERR_INADMISSIBLE) {
    double need = 0;
    ea_error_t e2 = {0};
    fprintf(stderr, "elasticarm %s: refused: %s\n", cmd, err.msg);
    if (ea_stream_min_time_scale(&tr, &arm, s.rate_hz, s.limit_tol, &need, &e2) == EA_OK)
      fprintf(stderr, "elasticarm %s: (the plan meets its limits at its samples; the "
              "interpolant between them needs --time-scale %.6g, or --time-scale auto)\n",
              cmd, need * 1.000001);
    ea_traj_free(&tr);
    return EA_EXIT_FAIL;
  }
  ea_traj_free(&tr);
  if (st) return ea__cli_fail(cmd, st, &err);
  ea__cli_install_stop();
  ea__cli_realtime(rt);
  s.stop_request = &ea__cli_stop;
  ea_stream_info_t info;
  st = ea_stream_run(&arm, sp, n, to, &s, &info, &err);
  free(sp);
  if (json) {
    ea_json_t j;
    ea_json_init(&j, stdout, 1);
    ea_json_obj_begin(&j, NULL);
    ea_json_str(&j, "status", ea_status_name(st));
    ea_json_str(&j, "end", ea_stream_end_name(info.end));
    ea_json_str(&j, "message", st ? err.msg : "");
    ea_json_str(&j, "to", to);
    ea_json_num(&j, "rate_hz", s.rate_hz);
    ea_json_int(&j, "setpoints", info.setpoints);
    ea_json_int(&j, "frames_sent", info.frames_sent);
    ea_json_int(&j, "stop_frames", info.stop_frames);
    ea_json_int(&j, "frames_acked", info.frames_acked);
    ea_json_int(&j, "frames_late", info.frames_late);
    ea_json_int(&j, "acks", info.acks);
    ea_json_int(&j, "nacks", info.nacks);
    ea_json_int(&j, "nack_reason", info.nack_reason);
    ea_json_int(&j, "controller_rejected", info.ctrl_rejected);
    ea_json_int(&j, "controller_state", info.ctrl_state);
    ea_json_int(&j, "buffer_min", info.buffer_min);
    ea_json_int(&j, "buffer_max", info.buffer_max);
    ea_json_num(&j, "jitter_p50_us", info.jitter_p50_us);
    ea_json_num(&j, "jitter_p99_us", info.jitter_p99_us);
    ea_json_num(&j, "jitter_max_us", info.jitter_max_us);
    ea_json_num(&j, "ack_latency_max_ms", info.ack_latency_max_ms);
    ea_json_num(&j, "duration_s", info.duration_s);
    ea_json_obj_end(&j);
    ea_json_end(&j);
  } else {
    fprintf(out,
            "stream %s -> %s: %s\n"
            "  setpoints %d at %g Hz, frames sent %d (stop ramp %d), acknowledged %d, late %d\n"
            "  acks %d, nacks %d, controller rejected %d, buffer level %d..%d\n"
            "  send jitter p50 %.1f us, p99 %.1f us, max %.1f us; max ACK latency %.2f ms; "
            "%.3f s\n",
            traj_path, to, ea_stream_end_name(info.end), info.setpoints, s.rate_hz,
            info.frames_sent, info.stop_frames, info.frames_acked, info.frames_late, info.acks,
            info.nacks, info.ctrl_rejected, info.buffer_min, info.buffer_max, info.jitter_p50_us,
            info.jitter_p99_us, info.jitter_max_us, info.ack_latency_max_ms, info.duration_s);
  }
  if (st) {
    fprintf(stderr, "elasticarm %s: %s\n", cmd, err.msg[0] ? err.msg : ea_strerror(st));
    return (st == EA_ERR_ARG || st == EA_ERR_IO) ? EA_EXIT_USAGE : EA_EXIT_FAIL;
  }
  return EA_EXIT_OK;
}

/* ---- controller-sim ---------------------------------------------------------------- */

static const char *ea__ctrl_help =
    "usage: elasticarm controller-sim [--listen HOST:PORT] [options]\n\n"
    "A controller that speaks the streamer's protocol (docs/protocol.md): checks every\n"
    "frame (CRC, sequence, limits of the arm file, continuity), answers ACK/NACK, logs\n"
    "the setpoints it accepted, stops by itself when the link or the streamer goes\n"
    "silent. Serves one session and exits.\n\n"
    "  --listen HOST:PORT    numeric address (default 127.0.0.1:0 = loopback, any port;\n"
    "                        the port is printed); serial:DEVICE[@BAUD] for a tty\n"
    "  --udp                 UDP instead of TCP\n"
    "  --arm FILE            arm parameters (default data/elasticarm.yaml)\n"
    "  --log FILE            CSV of the accepted setpoints, written atomically at the end\n"
    "  --port-file FILE      write the bound port to FILE once listening\n"
    "  --max-frames N        end the session after N setpoints (own stop)\n"
    "  --timeout S           give up after S s without a connection or frame (10)\n"
    "  --watchdog-ms W       stop by itself after W ms without a frame while moving (100)\n"
    "  --initial L,TH,B      report cable length [m], theta0, base [rad] at HELLO\n"
    "                        (default: the trajectory's start, as if homed there)\n"
    "  --fault F             drop-after=N | delay-ack-ms=D | withhold-ack | corrupt-every=N\n"
    "  --json                summary as JSON on stdout\n"
    "Exit: 0 clean session, 1 faults / rejected frames / link lost, 2 usage error.\n";

static int ea__parse_fault(const char *cmd, const char *v, ea_ctrl_settings_t *s) {
  long n;
  if (!strncmp(v, "drop-after=", 11)) {
    if (ea__cli_int(cmd, "--fault drop-after", v + 11, 1, 100000000, &n)) return -1;
    s->fault = EA_FAULT_DROP_AFTER;
  } else if (!strncmp(v, "delay-ack-ms=", 13)) {
    if (ea__cli_int(cmd, "--fault delay-ack-ms", v + 13, 1, 60000, &n)) return -1;
    s->fault = EA_FAULT_DELAY_ACK;
  } else if (!strcmp(v, "withhold-ack")) {
    n = 0;
    s->fault = EA_FAULT_WITHHOLD_ACK;
  } else if (!strncmp(v, "corrupt-every=", 14)) {
    if (ea__cli_int(cmd, "--fault corrupt-every", v + 14, 1, 100000000, &n)) return -1;
    s->fault = EA_FAULT_CORRUPT_EVERY;
  } else {
    ea__cli_usage_error(cmd, "--fault: '%s' is not drop-after=N, delay-ack-ms=D, withhold-ack "
                        "or corrupt-every=N", v);
    return -1;
  }
  s->fault_arg = n;
  return 0;
}

int ea__cli_controller_sim(int argc, char **argv) {
  const char *cmd = "controller-sim", *listen_at = "127.0.0.1:0", *arm_file = NULL;
  const char *log_path = NULL, *port_file = NULL;
  ea_ctrl_settings_t s;
  ea_ctrl_settings_default(&s);
  int json = 0;
  for (int i = 1; i < argc; ++i) {
    const char *a = argv[i], *v;
    if (!strcmp(a, "--help") || !strcmp(a, "-h")) {
      fputs(ea__ctrl_help, stdout);
      return EA_EXIT_OK;
    } else if (!strcmp(a, "--listen")) {
      if (!(listen_at = ea__cli_value(cmd, argc, argv, &i))) return EA_EXIT_USAGE;
    } else if (!strcmp(a, "--udp")) {
      s.udp = 1;
    } else if (!strcmp(a, "--arm")) {
      if (!(arm_file = ea__cli_value(cmd, argc, argv, &i))) return EA_EXIT_USAGE;
    } else if (!strcmp(a, "--log")) {
      if (!(log_path = ea__cli_value(cmd, argc, argv, &i))) return EA_EXIT_USAGE;
    } else if (!strcmp(a, "--port-file")) {
      if (!(port_file = ea__cli_value(cmd, argc, argv, &i))) return EA_EXIT_USAGE;
    } else if (!strcmp(a, "--max-frames")) {
      long n;
      if (!(v = ea__cli_value(cmd, argc, argv, &i)) ||
          ea__cli_int(cmd, a, v, 1, 2000000000L, &n))
        return EA_EXIT_USAGE;
      s.max_frames = (int)n;
    } else if (!strcmp(a, "--timeout")) {
      if (!(v = ea__cli_value(cmd, argc, argv, &i)) ||
          ea__cli_double(cmd, a, v, 0.01, 86400, &s.timeout_s))
        return EA_EXIT_USAGE;
    } else if (!strcmp(a, "--watchdog-ms")) {
      double ms;
      if (!(v = ea__cli_value(cmd, argc, argv, &i)) || ea__cli_double(cmd, a, v, 1, 60000, &ms))
        return EA_EXIT_USAGE;
      s.watchdog_s = ms * 1e-3;
    } else if (!strcmp(a, "--initial")) {
      double *vals = NULL;
      int nv = 0;
      if (!(v = ea__cli_value(cmd, argc, argv, &i)) || ea__cli_list(cmd, a, v, &vals, &nv))
        return EA_EXIT_USAGE;
      if (nv != 3) {
        free(vals);
        return ea__cli_usage_error(cmd, "--initial needs L_c,theta0,base (3 values)");
      }
      memcpy(s.initial, vals, sizeof s.initial);
      free(vals);
      s.has_initial = 1;
    } else if (!strcmp(a, "--fault")) {
      if (!(v = ea__cli_value(cmd, argc, argv, &i)) || ea__parse_fault(cmd, v, &s))
        return EA_EXIT_USAGE;
    } else if (!strcmp(a, "--json")) {
      json = 1;
    } else {
      return ea__cli_usage_error(cmd, "unknown argument '%s'", a);
    }
  }
  ea_arm_t arm;
  int rc = ea__cli_load_arm(cmd, arm_file, &arm);
  if (rc) return rc;
  ea__cli_install_stop();
  s.stop_request = &ea__cli_stop;
  ea_error_t err = {0};
  ea_ctrl_t *c = NULL;
  ea_status_t st;
  if (!strncmp(listen_at, "serial:", 7)) {
    char dev[512];
    long bps = 921600;
    snprintf(dev, sizeof dev, "%s", listen_at + 7);
    char *at = strrchr(dev, '@');
    if (at) {
      *at = '\0';
      if (ea__cli_int(cmd, "--listen serial baud", at + 1, 1, 100000000, &bps))
        return EA_EXIT_USAGE;
    }
    const int fd = open(dev, O_RDWR | O_NOCTTY | O_CLOEXEC);
    if (fd < 0) {
      fprintf(stderr, "elasticarm %s: %s: %s\n", cmd, dev, strerror(errno));
      return EA_EXIT_FAIL;
    }
    st = ea__serial_setup(fd, bps, &err);
    if (!st) st = ea__ctrl_open_fd(&arm, fd, &s, &c, &err);
    else close(fd);
    if (st) return ea__cli_fail(cmd, st, &err);
    fprintf(stderr, "elasticarm %s: serving %s\n", cmd, dev);
  } else {
    st = ea_ctrl_open(&arm, listen_at, &s, &c, &err);
    if (st) return ea__cli_fail(cmd, st, &err);
    fprintf(stderr, "elasticarm %s: listening on %s %s (port %d)\n", cmd, s.udp ? "udp" : "tcp",
            listen_at, ea_ctrl_port(c));
    if (port_file) {
      ea_afile_t pf;
      if (ea_afile_open(&pf, port_file, &err) == EA_OK) {
        fprintf(pf.fp, "%d\n", ea_ctrl_port(c));
        ea_afile_commit(&pf, &err);
      }
    }
  }
  ea_ctrl_info_t info;
  st = ea_ctrl_run(c, &info, &err);
  int rc_log = 0;
  if (log_path) {
    ea_error_t e2 = {0};
    if (ea_ctrl_log_write(c, log_path, &e2)) {
      fprintf(stderr, "elasticarm %s: %s\n", cmd, e2.msg);
      rc_log = EA_EXIT_FAIL;
    }
  }
  int logged = 0;
  ea_ctrl_log(c, &logged);
  if (json) {
    ea_json_t j;
    ea_json_init(&j, stdout, 1);
    ea_json_obj_begin(&j, NULL);
    ea_json_str(&j, "status", ea_status_name(st));
    ea_json_str(&j, "message", st ? err.msg : "");
    ea_json_int(&j, "sessions", info.sessions);
    ea_json_int(&j, "accepted", info.accepted);
    ea_json_int(&j, "rejected", info.rejected);
    ea_json_int(&j, "rejected_crc", info.rejected_crc);
    ea_json_int(&j, "rejected_sequence", info.rejected_seq);
    ea_json_int(&j, "rejected_limit", info.rejected_limit);
    ea_json_int(&j, "rejected_continuity", info.rejected_continuity);
    ea_json_int(&j, "gaps", info.gaps);
    ea_json_int(&j, "own_stop_frames", info.own_stop_frames);
    ea_json_bool(&j, "end_received", info.end_received);
    ea_json_int(&j, "end_reason", info.end_reason);
    ea_json_int(&j, "final_state", info.final_state);
    ea_json_int(&j, "max_buffer", info.max_buffer);
    ea_json_int(&j, "logged", logged);
    ea_json_obj_end(&j);
    ea_json_end(&j);
  } else {
    printf("controller-sim: %s\n  sessions %d, accepted %d, rejected %d (crc %d, sequence %d, "
           "limit %d, continuity %d), gaps %d, own stop %d, END %s, logged %d\n",
           st ? err.msg : "clean session", info.sessions, info.accepted, info.rejected,
           info.rejected_crc, info.rejected_seq, info.rejected_limit, info.rejected_continuity,
           info.gaps, info.own_stop_frames, info.end_received ? "received" : "not received",
           logged);
  }
  ea_ctrl_free(c);
  if (rc_log) return rc_log;
  return st ? EA_EXIT_FAIL : EA_EXIT_OK;
}
