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
    fprintf(stderr, "elasticarm stream: --rt: mlockall failed (%s); continuing\n", strerror(errno));
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
    "                        | csv:PATH (dry run, the frames decoded: a table of motor\n"
    "                        and task-space values) | ros-yaml:PATH (dry run, the\n"
    "                        setpoints as a ROS JointTrajectory in YAML)\n"
    "  --rate-hz R           setpoint rate (default 1000)\n"
    "  --arm FILE            arm parameters: the trajectory's '# arm_file:' by default\n"
    "                        (said on stderr), else the default arm file (see\n"
    "                        elasticarm --help); refused when it differs from the\n"
    "                        trajectory's\n"
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

/* What the stream command was asked. */
typedef struct {
  const char *traj_path, *to, *arm_file;
  int json, realtime, rt, time_scale_auto;
  double time_scale;
} ea__stream_opts_t;

/* stream's options into o and s; 0, or an exit code (-1: help printed, exit 0). */
static int ea__stream_parse(int argc, char **argv, ea__stream_opts_t *o, ea_stream_settings_t *s) {
  const char *cmd = "stream";
  static const ea__cli_opt_t opts[] = {{"help", 0, 'h'},
                                       {"to", 1, 0},
                                       {"arm", 1, 0},
                                       {"rate-hz", 1, 0},
                                       {"ack-timeout-ms", 1, 0},
                                       {"start-tol-m", 1, 0},
                                       {"start-tol-rad", 1, 0},
                                       {"json", 0, 0},
                                       {"no-realtime", 0, 0},
                                       {"realtime", 0, 0},
                                       {"time-scale", 1, 0},
                                       {"rt", 0, 0},
                                       {NULL, 0, 0}};
  ea__cli_args_t g;
  ea__cli_args_init(&g, cmd, argc, argv, opts);
  int r;
  while ((r = ea__cli_args_next(&g)) > 0) {
    const char *a = g.opt, *v = g.arg;
    if (!a) {
      if (o->traj_path) return ea__cli_usage_error(cmd, "more than one trajectory ('%s')", v);
      o->traj_path = v;
    } else if (!strcmp(a, "--help") || !strcmp(a, "-h")) {
      fputs(ea__stream_help, stdout);
      return -1;
    } else if (!strcmp(a, "--to")) {
      o->to = v;
    } else if (!strcmp(a, "--arm")) {
      o->arm_file = v;
    } else if (!strcmp(a, "--rate-hz")) {
      if (ea__cli_double(cmd, a, v, 1, 100000, &s->rate_hz)) return EA_EXIT_USAGE;
    } else if (!strcmp(a, "--ack-timeout-ms")) {
      double ms;
      if (ea__cli_double(cmd, a, v, 1, 60000, &ms)) return EA_EXIT_USAGE;
      s->ack_timeout_s = ms * 1e-3;
    } else if (!strcmp(a, "--start-tol-m")) {
      if (ea__cli_double(cmd, a, v, 0, 1, &s->start_tol_cable)) return EA_EXIT_USAGE;
    } else if (!strcmp(a, "--start-tol-rad")) {
      if (ea__cli_double(cmd, a, v, 0, 1, &s->start_tol_angle)) return EA_EXIT_USAGE;
    } else if (!strcmp(a, "--json")) {
      o->json = 1;
    } else if (!strcmp(a, "--no-realtime")) {
      o->realtime = 0;
    } else if (!strcmp(a, "--realtime")) {
      o->realtime = 1;
    } else if (!strcmp(a, "--time-scale")) {
      if (!strcmp(v, "auto"))
        o->time_scale_auto = 1;
      else if (ea__cli_double(cmd, a, v, 1, 1000, &o->time_scale))
        return EA_EXIT_USAGE;
    } else if (!strcmp(a, "--rt")) {
      o->rt = 1;
    }
  }
  if (r < 0) return EA_EXIT_USAGE;
  if (!o->traj_path) return ea__cli_usage_error(cmd, "no trajectory file");
  if (!o->to) return ea__cli_usage_error(cmd, "no destination (--to tcp://HOST:PORT, ...)");
  return 0;
}

/* The trajectory, the arm it was planned for, and its setpoints at s->rate_hz, checked
 * against the limits (time-scaled when asked); 0 or an exit code. */
static int ea__stream_setpoints(const ea__stream_opts_t *o, const ea_stream_settings_t *s,
                                ea_arm_t *arm, char *arm_used, size_t len, ea_setpoint_t **sp,
                                int *n) {
  const char *cmd = "stream";
  ea_traj_t tr = {0};
  ea_error_t err = {0};
  int rc = ea__cli_check_plan_pair(cmd, o->traj_path); /* not another run's summary beside it */
  if (rc) return rc;
  ea_status_t st = ea_traj_read(&tr, o->traj_path, &err);
  if (st) return ea__cli_fail(cmd, st, &err);
  /* The arm the plan was made for: its limits and motor mapping. */
  rc =
      ea__cli_arm_for_traj(cmd, o->traj_path, o->arm_file, &tr, EA__ARM_STRICT, arm, arm_used, len);
  if (rc) {
    ea_traj_free(&tr);
    return rc;
  }
  double time_scale = o->time_scale;
  if (o->time_scale_auto) {
    st = ea_stream_min_time_scale(&tr, arm, s->rate_hz, s->limit_tol, &time_scale, &err);
    if (st) {
      ea_traj_free(&tr);
      fprintf(stderr, "elasticarm %s: refused: %s\n", cmd, err.msg);
      return EA_EXIT_FAIL;
    }
    if (time_scale > 1.0)
      fprintf(stderr, "elasticarm %s: --time-scale auto: playing the plan %.6g times slower\n", cmd,
              time_scale);
  }
  st = ea_stream_resample_scaled(&tr, arm, s->rate_hz, time_scale, s->limit_tol, sp, n, &err);
  if (st == EA_ERR_INADMISSIBLE) {
    double need = 0;
    ea_error_t e2 = {0};
    fprintf(stderr, "elasticarm %s: refused: %s\n", cmd, err.msg);
    if (ea_stream_min_time_scale(&tr, arm, s->rate_hz, s->limit_tol, &need, &e2) == EA_OK)
      fprintf(stderr,
              "elasticarm %s: (the plan meets its limits at its samples; the "
              "interpolant between them needs --time-scale %.6g, or --time-scale auto)\n",
              cmd, need * 1.000001);
    ea_traj_free(&tr);
    return EA_EXIT_FAIL;
  }
  ea_traj_free(&tr);
  if (st) return ea__cli_fail(cmd, st, &err);
  return 0;
}

static void ea__stream_json(const ea__stream_opts_t *o, const ea_stream_settings_t *s,
                            const char *arm_used, ea_status_t st, const ea_error_t *err,
                            const ea_stream_info_t *info) {
  ea_json_t j;
  ea_json_init(&j, stdout, 1);
  ea_json_obj_begin(&j, NULL);
  ea_json_str(&j, "status", ea_status_name(st));
  ea_json_str(&j, "end", ea_stream_end_name(info->end));
  ea_json_str(&j, "message", st ? err->msg : "");
  ea_json_str(&j, "to", o->to);
  ea_json_str(&j, "arm_file", arm_used[0] ? arm_used : ea__cli_default_arm());
  ea_json_num(&j, "rate_hz", s->rate_hz);
  ea_json_int(&j, "setpoints", info->setpoints);
  ea_json_int(&j, "frames_sent", info->frames_sent);
  ea_json_int(&j, "stop_frames", info->stop_frames);
  ea_json_int(&j, "frames_acked", info->frames_acked);
  ea_json_int(&j, "frames_late", info->frames_late);
  ea_json_int(&j, "acks", info->acks);
  ea_json_int(&j, "nacks", info->nacks);
  ea_json_int(&j, "nack_reason", info->nack_reason);
  ea_json_int(&j, "controller_rejected", info->ctrl_rejected);
  ea_json_int(&j, "controller_state", info->ctrl_state);
  ea_json_int(&j, "buffer_min", info->buffer_min);
  ea_json_int(&j, "buffer_max", info->buffer_max);
  ea_json_num(&j, "jitter_p50_us", info->jitter_p50_us);
  ea_json_num(&j, "jitter_p99_us", info->jitter_p99_us);
  ea_json_num(&j, "jitter_max_us", info->jitter_max_us);
  ea_json_num(&j, "ack_latency_max_ms", info->ack_latency_max_ms);
  ea_json_num(&j, "duration_s", info->duration_s);
  ea_json_obj_end(&j);
  ea_json_end(&j);
}

int ea__cli_stream(int argc, char **argv) {
  const char *cmd = "stream";
  ea_stream_settings_t s;
  ea_stream_settings_default(&s);
  ea__stream_opts_t o = {0};
  o.realtime = -1;
  o.time_scale = 1.0;
  int rc = ea__stream_parse(argc, argv, &o, &s);
  if (rc) return rc < 0 ? EA_EXIT_OK : rc;
  const int to_file = ea__url_is_dry_run(o.to);
  const int to_stdout = to_file && !strcmp(strchr(o.to, ':') + 1, "-");
  if (o.json && to_stdout)
    return ea__cli_usage_error(cmd, "--json needs stdout: not with %s", o.to);
  s.realtime = o.realtime >= 0 ? o.realtime : !to_file;
  s.wait_acks = !to_file;
  FILE *out = to_stdout ? stderr : stdout;
  ea_arm_t arm;
  char arm_used[512];
  ea_setpoint_t *sp = NULL;
  int n = 0;
  if ((rc = ea__stream_setpoints(&o, &s, &arm, arm_used, sizeof arm_used, &sp, &n))) return rc;
  ea__cli_install_stop();
  ea__cli_realtime(o.rt);
  s.stop_request = &ea__cli_stop;
  ea_stream_info_t info;
  ea_error_t err = {0};
  const ea_status_t st = ea_stream_run(&arm, sp, n, o.to, &s, &info, &err);
  free(sp);
  if (o.json) {
    ea__stream_json(&o, &s, arm_used, st, &err, &info);
  } else if (info.end == EA_STREAM_ERROR && !info.frames_sent) {
    fprintf(out, "stream %s -> %s: not sent (%d setpoints at %g Hz)\n", o.traj_path, o.to,
            info.setpoints, s.rate_hz);
  } else {
    fprintf(out,
            "stream %s -> %s: %s\n"
            "  setpoints %d at %g Hz%s, frames sent %d (stop ramp %d), acknowledged %d, late %d\n",
            o.traj_path, o.to, ea_stream_end_name(info.end), info.setpoints, s.rate_hz,
            info.rest_frame ? " and one at rest after them" : "", info.frames_sent,
            info.stop_frames, info.frames_acked, info.frames_late);
    if (s.wait_acks)
      fprintf(out, "  acks %d, nacks %d, controller rejected %d, buffer level %d..%d\n", info.acks,
              info.nacks, info.ctrl_rejected, info.buffer_min, info.buffer_max);
    if (isnan(info.jitter_p50_us))
      fprintf(out, "  not paced (written as fast as possible); %.3f s\n", info.duration_s);
    else
      fprintf(out,
              "  send jitter p50 %.1f us, p99 %.1f us, max %.1f us; max ACK latency %.2f ms; "
              "%.3f s\n",
              info.jitter_p50_us, info.jitter_p99_us, info.jitter_max_us, info.ack_latency_max_ms,
              info.duration_s);
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
    "  --arm FILE            arm parameters (default: see elasticarm --help)\n"
    "  --log FILE            CSV of the accepted setpoints, written atomically at the end\n"
    "  --port-file FILE      write the bound port to FILE once listening\n"
    "  --max-frames N        end the session after N setpoints (own stop)\n"
    "  --timeout S           give up after S s without a connection or frame (10)\n"
    "  --watchdog-ms W       stop by itself after W ms without a frame while moving (100)\n"
    "  --initial L,TH,B      report cable length [m], theta0, base [rad] at HELLO\n"
    "                        (default: the trajectory's start, as if homed there)\n"
    "  --fault F             drop-after=N | delay-ack-ms=D | withhold-ack | corrupt-every=N\n"
    "                        | fault-after=N (state FAULT after N setpoints)\n"
    "  --json                summary as JSON on stdout\n"
    "  --simulate TIP.csv    after the session, run the FE transient (docs/fe.md) driven by\n"
    "                        the setpoints accepted (the log, stop ramps included: what the\n"
    "                        arm did): shoulder angle theta0(t), passive cable with moving\n"
    "                        rest length L_c / (1 + T / EA_c); write t_s, tip_x_m, tip_y_m,\n"
    "                        tip_theta_rad atomically; residual vibration in the summary\n"
    "  --elements N          FE elements of --simulate (default %d)\n"
    "  --payload-kg M        payload at the tip for --simulate (default 0)\n"
    "  --settle S            simulated time after the last setpoint [s] (default 1)\n"
    "  --record DIR          after the session, the measurement records of the FE transient\n"
    "                        (docs/calibration.md): DIR/static.csv (one row per hold: runs\n"
    "                        of setpoints at rest of at least --record-min-hold S, default\n"
    "                        1) and DIR/ringdown-NNN.csv per hold after a motion, with\n"
    "                        Gaussian sensor noise: --noise-seed N (1), --noise-theta0-rad\n"
    "                        (0.0005), --noise-torque-Nm (0.01), --noise-tension-N (0.05),\n"
    "                        --noise-tip-m (0.0005); 0 = none\n"
    "Exit: 0 clean session, 1 faults / rejected frames / link lost / simulation failed,\n"
    "2 usage error.\n";

/* ---- controller-sim --simulate: FE transient of what the controller accepted ---- */

/* err->msg := prefix + err->msg (the message may not be a snprintf argument of itself). */
static ea_status_t ea__err_prefix(ea_error_t *err, ea_status_t st, const char *prefix) {
  char old[sizeof err->msg];
  /* a callee that returned st without setting err leaves an older message behind */
  snprintf(old, sizeof old, "%s", (err->status == st && err->msg[0]) ? err->msg : ea_strerror(st));
  return ea_error_set(err, st, "%s%s", prefix, old);
}

typedef struct {
  int ran; /* 1: simulated (ok or not) */
  ea_status_t status;
  ea_error_t err;
  int samples, skipped;     /* log rows used; rows whose time did not increase */
  double t_first, duration; /* [s] setpoint time of the first row, span of the rows */
  double settle;
  int rows; /* tip rows written */
  ea_sim_info_t si;
  double start_static_tip[2];
  int recorded;              /* 1: --record tried */
  ea_status_t record_status; /* its outcome */
  ea_error_t record_err;
  ea_record_info_t record; /* what it wrote */
} ea__ctrl_sim_t;

/* The FE transient of the logged setpoints (in receive order, own stop last) as
 * `simulate` runs a trajectory file (ea_traj_simulate): the rows become a trajectory
 * (ea_stream_setpoints_traj: theta0 and the tension feed-forward drive a passive cable),
 * held after the last row for the settling time; dt 1 ms, energy scheme, the arm file's
 * damping. The tip history (t, x, y, theta) is written atomically to path (NULL: none);
 * with rs, the measurement records into rs_dir (ea_record_write). Never prints. */
static ea_status_t ea__ctrl_simulate(const ea_arm_t *arm, const ea_ctrl_t *c, double tip_mass,
                                     long elements, double settle, const char *path,
                                     const char *rs_dir, const ea_record_settings_t *rs,
                                     ea__ctrl_sim_t *r) {
  memset(r, 0, sizeof *r);
  r->ran = 1;
  r->settle = settle;
  ea_error_t *err = &r->err;
  int nlog = 0;
  const ea_ctrl_log_row_t *log = ea_ctrl_log(c, &nlog);
  if (nlog < 1)
    return r->status = ea_error_set(err, EA_ERR_INPUT, "--simulate: no setpoint was accepted");
  ea_setpoint_t *sp = malloc(sizeof *sp * (size_t)nlog);
  double *t = malloc(sizeof *t * (size_t)nlog);
  ea_traj_t tr = {0};
  ea_sim_history_t h = {0};
  ea_afile_t af = {0};
  ea_status_t st = (sp && t) ? EA_OK : ea_error_set(err, EA_ERR_NOMEM, "--simulate: %d rows", nlog);
  for (int i = 0; !st && i < nlog; ++i) {
    sp[i] = log[i].sp;
    t[i] = log[i].time_s;
  }
  if (!st && (st = ea_stream_setpoints_traj(arm, tip_mass, sp, t, nlog, &tr, &r->skipped, err)))
    ea__err_prefix(err, st, "--simulate: the log: ");
  if (!st) {
    r->t_first = EA_TRAJ_AT(&tr, 0, EA_TRAJ_t);
    r->samples = tr.n;
    r->duration = EA_TRAJ_AT(&tr, tr.n - 1, EA_TRAJ_t) - r->t_first;
    if (!(r->duration + settle > 0))
      st =
          ea_error_set(err, EA_ERR_INPUT, "--simulate: one setpoint and --settle 0: nothing to do");
  }
  if (!st) {
    ea_sim_settings_t s;
    ea_sim_settings_default(&s);
    s.elements = (int)elements;
    s.scheme = EA_FE_SCHEME_ENERGY;
    s.dt = 1e-3;
    s.settle = settle;
    s.keep_history = 1;
    if ((st = ea_traj_simulate(arm, &tr, tip_mass, &s, &h, &r->si, err)))
      ea__err_prefix(err, st, "--simulate: ");
  }
  if (!st && h.rows > 0) {
    r->start_static_tip[0] = h.data[1]; /* row 0: the start equilibrium under the drive */
    r->start_static_tip[1] = h.data[2];
  }
  if (!st && rs_dir) {
    r->recorded = 1;
    r->record_status =
        ea_record_write(rs_dir, rs, arm, sp, t, nlog, &h, &r->record, &r->record_err);
  }
  /* tip history, atomically */
  if (!st && path && !(st = ea_afile_open(&af, path, err))) {
    fprintf(af.fp, "t_s,tip_x_m,tip_y_m,tip_theta_rad\n");
    for (int k = 0; k < h.rows; ++k) {
      const double *v = h.data + 6 * k;
      fprintf(af.fp, "%.9g,%.12g,%.12g,%.12g\n", v[0], v[1], v[2], v[3]);
    }
    st = ea_afile_commit(&af, err);
    if (!st) r->rows = h.rows;
  }
  ea_afile_abort(&af);
  ea_sim_history_free(&h);
  ea_traj_free(&tr);
  free(t);
  free(sp);
  return r->status = st;
}

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
  } else if (!strncmp(v, "fault-after=", 12)) {
    if (ea__cli_int(cmd, "--fault fault-after", v + 12, 1, 100000000, &n)) return -1;
    s->fault = EA_FAULT_STATE_AFTER;
  } else if (!strncmp(v, "corrupt-every=", 14)) {
    if (ea__cli_int(cmd, "--fault corrupt-every", v + 14, 1, 100000000, &n)) return -1;
    s->fault = EA_FAULT_CORRUPT_EVERY;
  } else {
    ea__cli_usage_error(cmd,
                        "--fault: '%s' is not drop-after=N, delay-ack-ms=D, withhold-ack, "
                        "corrupt-every=N or fault-after=N",
                        v);
    return -1;
  }
  s->fault_arg = n;
  return 0;
}

/* Options of controller-sim. */
typedef struct {
  const char *listen_at, *arm_file, *log_path, *port_file, *sim_path, *record_dir;
  ea_record_settings_t rec;
  ea_ctrl_settings_t s;
  int json;
  long sim_elements;
  double sim_payload, sim_settle;
} ea__ctrl_opts_t;

/* Options; 0, -1 (help printed: exit 0) or the exit code. */
static int ea__ctrl_parse(const char *cmd, int argc, char **argv, ea__ctrl_opts_t *o) {
  o->listen_at = "127.0.0.1:0";
  ea_ctrl_settings_default(&o->s);
  o->sim_elements = EA_FE_DEFAULT_ELEMENTS;
  o->sim_settle = 1.0;
  ea_record_settings_default(&o->rec);
  static const ea__cli_opt_t opts[] = {{"help", 0, 'h'},
                                       {"listen", 1, 0},
                                       {"udp", 0, 0},
                                       {"arm", 1, 0},
                                       {"log", 1, 0},
                                       {"port-file", 1, 0},
                                       {"max-frames", 1, 0},
                                       {"timeout", 1, 0},
                                       {"watchdog-ms", 1, 0},
                                       {"initial", 1, 0},
                                       {"fault", 1, 0},
                                       {"json", 0, 0},
                                       {"simulate", 1, 0},
                                       {"elements", 1, 0},
                                       {"payload-kg", 1, 0},
                                       {"settle", 1, 0},
                                       {"record", 1, 0},
                                       {"noise-seed", 1, 0},
                                       {"noise-theta0-rad", 1, 0},
                                       {"noise-torque-Nm", 1, 0},
                                       {"noise-tension-N", 1, 0},
                                       {"noise-tip-m", 1, 0},
                                       {"record-min-hold", 1, 0},
                                       {NULL, 0, 0}};
  ea__cli_args_t g;
  ea__cli_args_init(&g, cmd, argc, argv, opts);
  int r;
  while ((r = ea__cli_args_next(&g)) > 0) {
    const char *a = g.opt, *v = g.arg;
    if (!a) {
      return ea__cli_usage_error(cmd, "unknown argument '%s'", v);
    } else if (!strcmp(a, "--help") || !strcmp(a, "-h")) {
      printf(ea__ctrl_help, EA_FE_DEFAULT_ELEMENTS);
      return -1;
    } else if (!strcmp(a, "--listen")) {
      o->listen_at = v;
    } else if (!strcmp(a, "--udp")) {
      o->s.udp = 1;
    } else if (!strcmp(a, "--arm")) {
      o->arm_file = v;
    } else if (!strcmp(a, "--log")) {
      o->log_path = v;
    } else if (!strcmp(a, "--port-file")) {
      o->port_file = v;
    } else if (!strcmp(a, "--max-frames")) {
      long n;
      if (ea__cli_int(cmd, a, v, 1, 2000000000L, &n)) return EA_EXIT_USAGE;
      o->s.max_frames = (int)n;
    } else if (!strcmp(a, "--timeout")) {
      if (ea__cli_double(cmd, a, v, 0.01, 86400, &o->s.timeout_s)) return EA_EXIT_USAGE;
    } else if (!strcmp(a, "--watchdog-ms")) {
      double ms;
      if (ea__cli_double(cmd, a, v, 1, 60000, &ms)) return EA_EXIT_USAGE;
      o->s.watchdog_s = ms * 1e-3;
    } else if (!strcmp(a, "--initial")) {
      double *vals = NULL;
      int nv = 0;
      if (ea__cli_list(cmd, a, v, &vals, &nv)) return EA_EXIT_USAGE;
      if (nv != 3) {
        free(vals);
        return ea__cli_usage_error(cmd, "--initial needs L_c,theta0,base (3 values)");
      }
      memcpy(o->s.initial, vals, sizeof o->s.initial);
      free(vals);
      o->s.has_initial = 1;
    } else if (!strcmp(a, "--fault")) {
      if (ea__parse_fault(cmd, v, &o->s)) return EA_EXIT_USAGE;
    } else if (!strcmp(a, "--json")) {
      o->json = 1;
    } else if (!strcmp(a, "--simulate")) {
      o->sim_path = v;
    } else if (!strcmp(a, "--elements")) {
      if (ea__cli_int(cmd, a, v, 1, 512, &o->sim_elements)) return EA_EXIT_USAGE;
    } else if (!strcmp(a, "--payload-kg")) {
      if (ea__cli_double(cmd, a, v, 0.0, 1e3, &o->sim_payload)) return EA_EXIT_USAGE;
    } else if (!strcmp(a, "--settle")) {
      if (ea__cli_double(cmd, a, v, 0.0, 1e3, &o->sim_settle)) return EA_EXIT_USAGE;
    } else if (!strcmp(a, "--record")) {
      o->record_dir = v;
    } else if (!strcmp(a, "--noise-seed")) {
      long seed;
      if (ea__cli_int(cmd, a, v, 0, 2147483647L, &seed)) return EA_EXIT_USAGE;
      o->rec.seed = (unsigned long)seed;
    } else if (!strcmp(a, "--noise-theta0-rad")) {
      if (ea__cli_double(cmd, a, v, 0.0, 1.0, &o->rec.noise_theta0_rad)) return EA_EXIT_USAGE;
    } else if (!strcmp(a, "--noise-torque-Nm")) {
      if (ea__cli_double(cmd, a, v, 0.0, 100.0, &o->rec.noise_torque_Nm)) return EA_EXIT_USAGE;
    } else if (!strcmp(a, "--noise-tension-N")) {
      if (ea__cli_double(cmd, a, v, 0.0, 1000.0, &o->rec.noise_tension_N)) return EA_EXIT_USAGE;
    } else if (!strcmp(a, "--noise-tip-m")) {
      if (ea__cli_double(cmd, a, v, 0.0, 1.0, &o->rec.noise_tip_m)) return EA_EXIT_USAGE;
    } else if (!strcmp(a, "--record-min-hold")) {
      if (ea__cli_double(cmd, a, v, 1e-3, 1e4, &o->rec.min_hold_s)) return EA_EXIT_USAGE;
    }
  }
  if (r < 0) return EA_EXIT_USAGE;
  if (o->sim_path && o->json && !strcmp(o->sim_path, "-"))
    return ea__cli_usage_error(cmd, "--json and --simulate - both want stdout");
  return 0;
}

/* The controller on a serial line (serial:DEVICE[@BAUD]) or a socket (HOST:PORT, the
 * bound port said on stderr and written to --port-file). 0 or the exit code. */
static int ea__ctrl_start(const char *cmd, const ea__ctrl_opts_t *o, const ea_arm_t *arm,
                          ea_ctrl_t **c) {
  ea_error_t err = {0};
  ea_status_t st;
  if (!strncmp(o->listen_at, "serial:", 7)) {
    char dev[512];
    long bps = 921600;
    snprintf(dev, sizeof dev, "%s", o->listen_at + 7);
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
    if (!st)
      st = ea__ctrl_open_fd(arm, fd, &o->s, c, &err);
    else
      close(fd);
    if (st) return ea__cli_fail(cmd, st, &err);
    fprintf(stderr, "elasticarm %s: serving %s\n", cmd, dev);
    return 0;
  }
  if ((st = ea_ctrl_open(arm, o->listen_at, &o->s, c, &err))) return ea__cli_fail(cmd, st, &err);
  fprintf(stderr, "elasticarm %s: listening on %s %s (port %d)\n", cmd, o->s.udp ? "udp" : "tcp",
          o->listen_at, ea_ctrl_port(*c));
  if (o->port_file) {
    ea_afile_t pf;
    if (ea_afile_open(&pf, o->port_file, &err) == EA_OK) {
      fprintf(pf.fp, "%d\n", ea_ctrl_port(*c));
      ea_afile_commit(&pf, &err);
    }
  }
  return 0;
}

/* The summary of the session (and of --simulate), as JSON or text. */
static void ea__ctrl_report(const ea__ctrl_opts_t *o, ea_status_t st, const ea_error_t *err,
                            const ea_ctrl_info_t *info, int logged, const ea__ctrl_sim_t *sim) {
  if (o->json) {
    ea_json_t j;
    ea_json_init(&j, stdout, 1);
    ea_json_obj_begin(&j, NULL);
    ea_json_str(&j, "status", ea_status_name(st));
    ea_json_str(&j, "message", st ? err->msg : "");
    ea_json_int(&j, "sessions", info->sessions);
    ea_json_int(&j, "accepted", info->accepted);
    ea_json_int(&j, "rejected", info->rejected);
    ea_json_int(&j, "rejected_crc", info->rejected_crc);
    ea_json_int(&j, "rejected_sequence", info->rejected_seq);
    ea_json_int(&j, "rejected_limit", info->rejected_limit);
    ea_json_int(&j, "rejected_continuity", info->rejected_continuity);
    ea_json_int(&j, "gaps", info->gaps);
    ea_json_int(&j, "own_stop_frames", info->own_stop_frames);
    ea_json_bool(&j, "end_received", info->end_received);
    ea_json_int(&j, "end_reason", info->end_reason);
    ea_json_str(&j, "end_reason_name",
                info->end_received ? ea_end_reason_name(info->end_reason) : "");
    ea_json_int(&j, "final_state", info->final_state);
    ea_json_int(&j, "max_buffer", info->max_buffer);
    ea_json_int(&j, "logged", logged);
    if (sim->ran) {
      const int have = sim->status == EA_OK, res = have && sim->settle > 0;
      ea_json_str(&j, "sim_status", ea_status_name(sim->status));
      ea_json_str(&j, "sim_message", sim->status ? sim->err.msg : "");
      ea_json_str(&j, "sim_tip_file", o->sim_path ? o->sim_path : "");
      ea_json_int(&j, "sim_samples", sim->samples);
      ea_json_int(&j, "sim_skipped", sim->skipped);
      ea_json_int(&j, "sim_elements", (int)o->sim_elements);
      ea_json_num(&j, "sim_payload_kg", o->sim_payload);
      ea_json_num(&j, "sim_t_first_s", sim->t_first);
      ea_json_num(&j, "sim_motion_duration_s", sim->duration);
      ea_json_num(&j, "sim_settle_s", sim->settle);
      ea_json_int(&j, "sim_tip_rows", sim->rows);
      ea_json_int(&j, "sim_steps", sim->si.steps);
      ea_json_num(&j, "sim_wall_time_s", sim->si.wall_time_s);
      ea_json_vec(&j, "sim_start_static_tip_m", sim->start_static_tip, have ? 2 : 0);
      ea_json_num(&j, "residual_vibration_rms_m", res ? sim->si.residual_rms : NAN);
      ea_json_num(&j, "residual_vibration_peak_m", res ? sim->si.residual_peak : NAN);
      ea_json_vec(&j, "sim_final_static_tip_m", sim->si.final_static_tip, res ? 2 : 0);
      ea_json_num(&j, "sim_damping_ratio", sim->si.damping_ratio);
    }
    if (sim->recorded) {
      ea_json_str(&j, "record_status", ea_status_name(sim->record_status));
      ea_json_str(&j, "record_message", sim->record_status ? sim->record_err.msg : "");
      ea_json_str(&j, "record_dir", o->record_dir);
      ea_json_int(&j, "record_holds", sim->record.holds);
      ea_json_int(&j, "record_ringdowns", sim->record.ringdowns);
      ea_json_int(&j, "record_averaged_samples", sim->record.averaged_samples);
      ea_json_num(&j, "record_averaged_window_s", sim->record.averaged_window_s);
    }
    ea_json_obj_end(&j);
    ea_json_end(&j);
  } else {
    printf("controller-sim: %s\n  sessions %d, accepted %d, rejected %d (crc %d, sequence %d, "
           "limit %d, continuity %d), gaps %d, own stop %d, END %s, logged %d\n",
           st ? err->msg : "clean session", info->sessions, info->accepted, info->rejected,
           info->rejected_crc, info->rejected_seq, info->rejected_limit, info->rejected_continuity,
           info->gaps, info->own_stop_frames, info->end_received ? "received" : "not received",
           logged);
    if (sim->ran && sim->status == EA_OK) {
      printf("  FE transient of the %d accepted setpoints (%.4g s + %.4g s settling, %ld "
             "elements, damping ratio %.4g): %d tip rows -> %s, wall %.3f s\n",
             sim->samples, sim->duration, sim->settle, o->sim_elements, sim->si.damping_ratio,
             sim->rows, o->sim_path ? o->sim_path : "(not written)", sim->si.wall_time_s);
      if (sim->recorded && sim->record_status == EA_OK)
        printf("  records: %d holds -> %s (means of the last %d samples, %.4g s, of each), %d "
               "ring-downs in %s\n",
               sim->record.holds, sim->record.static_path, sim->record.averaged_samples,
               sim->record.averaged_window_s, sim->record.ringdowns, o->record_dir);
      if (sim->settle > 0)
        printf("  residual vibration after the last setpoint: rms %.4f mm, peak %.4f mm about "
               "the final equilibrium tip (%.6f, %.6f) m\n",
               1e3 * sim->si.residual_rms, 1e3 * sim->si.residual_peak, sim->si.final_static_tip[0],
               sim->si.final_static_tip[1]);
    }
  }
}

/* controller-sim: options, the arm, serve one session, the log, --simulate, summary. */
int ea__cli_controller_sim(int argc, char **argv) {
  const char *cmd = "controller-sim";
  ea__ctrl_opts_t o;
  memset(&o, 0, sizeof o);
  int rc = ea__ctrl_parse(cmd, argc, argv, &o);
  if (rc) return rc < 0 ? EA_EXIT_OK : rc;
  ea_arm_t arm;
  if ((rc = ea__cli_load_arm(cmd, o.arm_file, &arm))) return rc;
  ea__cli_install_stop();
  o.s.stop_request = &ea__cli_stop;
  ea_ctrl_t *c = NULL;
  if ((rc = ea__ctrl_start(cmd, &o, &arm, &c))) return rc;
  ea_error_t err = {0};
  ea_ctrl_info_t info;
  const ea_status_t st = ea_ctrl_run(c, &info, &err);
  int rc_log = 0;
  if (o.log_path) {
    ea_error_t e2 = {0};
    if (ea_ctrl_log_write(c, o.log_path, &e2)) {
      fprintf(stderr, "elasticarm %s: %s\n", cmd, e2.msg);
      rc_log = EA_EXIT_FAIL;
    }
  }
  int logged = 0;
  ea_ctrl_log(c, &logged);
  ea__ctrl_sim_t sim;
  memset(&sim, 0, sizeof sim);
  if (o.sim_path || o.record_dir) {
    o.rec.payload_kg = o.sim_payload;
    snprintf(o.rec.arm_file, sizeof o.rec.arm_file, "%s",
             o.arm_file ? o.arm_file : ea__cli_default_arm());
    ea__ctrl_simulate(&arm, c, ea_arm_tip_mass(&arm, o.sim_payload), o.sim_elements, o.sim_settle,
                      o.sim_path, o.record_dir, &o.rec, &sim);
  }
  ea__ctrl_report(&o, st, &err, &info, logged, &sim);
  if (sim.ran && sim.status)
    fprintf(stderr, "elasticarm %s: %s\n", cmd,
            sim.err.msg[0] ? sim.err.msg : ea_strerror(sim.status));
  if (sim.recorded && sim.record_status)
    fprintf(stderr, "elasticarm %s: --record: %s\n", cmd,
            sim.record_err.msg[0] ? sim.record_err.msg : ea_strerror(sim.record_status));
  ea_ctrl_free(c);
  if (rc_log) return rc_log;
  return (st || (sim.ran && sim.status) || (sim.recorded && sim.record_status)) ? EA_EXIT_FAIL
                                                                                : EA_EXIT_OK;
}
