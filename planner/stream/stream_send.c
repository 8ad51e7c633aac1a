/* Command streamer: handshake, real-time pacing on CLOCK_MONOTONIC with
 * absolute deadlines, ACK bookkeeping, controlled stop, summary
 * (docs/streaming.md). Never prints. */
#include "stream_impl.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

void ea_stream_settings_default(ea_stream_settings_t *s) {
  memset(s, 0, sizeof *s);
  s->rate_hz = 1000.0;
  s->limit_tol = 1e-6;
  s->continuity_tol = 0.05;
  s->stop_margin = 0.9;
  s->ack_timeout_s = 0.1;
  s->handshake_timeout_s = 1.0;
  s->end_timeout_s = 1.0;
  s->heartbeat_s = 0.1;
  s->start_tol_cable = 1e-3;
  s->start_tol_angle = 0.01;
  s->realtime = 1;
  s->wait_acks = 1;
  s->stop_request = NULL;
}

ea_status_t ea_stream_settings_validate(const ea_stream_settings_t *s, ea_error_t *err) {
#define EA__CHK(cond, ...)                                                                         \
  if (!(cond)) return ea_error_set(err, EA_ERR_ARG, __VA_ARGS__);
  EA__CHK(isfinite(s->rate_hz) && s->rate_hz >= 1 && s->rate_hz <= 100000,
          "rate_hz %g outside [1, 100000]", s->rate_hz)
  EA__CHK(s->limit_tol >= 0 && s->limit_tol < 0.1, "limit_tol %g outside [0, 0.1)", s->limit_tol)
  EA__CHK(s->continuity_tol >= 0 && s->continuity_tol < 1, "continuity_tol %g outside [0, 1)",
          s->continuity_tol)
  EA__CHK(s->stop_margin > 0 && s->stop_margin <= 1, "stop_margin %g outside (0, 1]",
          s->stop_margin)
  EA__CHK(s->ack_timeout_s > 0 && s->ack_timeout_s <= 60, "ack_timeout_s %g outside (0, 60]",
          s->ack_timeout_s)
  EA__CHK(s->handshake_timeout_s > 0 && s->handshake_timeout_s <= 600,
          "handshake_timeout_s %g outside (0, 600]", s->handshake_timeout_s)
  EA__CHK(s->end_timeout_s > 0 && s->end_timeout_s <= 600, "end_timeout_s %g outside (0, 600]",
          s->end_timeout_s)
  EA__CHK(s->heartbeat_s > 0 && s->heartbeat_s <= 60, "heartbeat_s %g outside (0, 60]",
          s->heartbeat_s)
  EA__CHK(s->start_tol_cable >= 0 && s->start_tol_angle >= 0, "negative start tolerance")
#undef EA__CHK
  return EA_OK;
}

const char *ea_stream_end_name(ea_stream_end_t e) {
  static const char *const names[] = {"complete",         "refused",        "stop-nack",
                                      "stop-ack-timeout", "stop-interrupt", "disconnected",
                                      "controller-fault", "error"};
  return (e >= 0 && e <= EA_STREAM_ERROR) ? names[e] : "?";
}

/* ---- Session state --------------------------------------------------------- */

typedef struct {
  const ea_arm_t *arm;
  const ea_stream_settings_t *s;
  ea_stream_info_t *info;
  ea__transport_t tr;
  ea_frame_parser_t parser;
  int acks_on;        /* handshake and ACKs in use */
  uint32_t seq;       /* last sequence number sent */
  uint32_t acked_seq; /* highest sequence number acknowledged */
  int64_t *send_ns;   /* send time of each sequence number */
  int send_cap;
  int link_lost;
  int nacked;
  int have_ack;          /* an ACK (any) was received */
  int fault_seen;        /* an answer reported state FAULT */
  uint32_t answered_seq; /* highest sequence number an answer named */
  ea_frame_t last_ack;
  uint8_t buf[EA_PROTO_FRAME_MAX];
} ea__sess_t;

static ea_status_t ea__send(ea__sess_t *x, ea_frame_t *f, ea_error_t *err) {
  if (f->type != EA_FRAME_HEARTBEAT)
    f->seq = ++x->seq;
  else
    f->seq = x->seq;
  f->version = EA_PROTO_VERSION;
  const size_t len = ea_frame_encode(f, x->buf, sizeof x->buf);
  if (!len) return ea_error_set(err, EA_ERR_ARG, "cannot encode frame type %d", f->type);
  if (f->type != EA_FRAME_HEARTBEAT && (int)f->seq < x->send_cap)
    x->send_ns[f->seq] = ea__mono_ns();
  ea_status_t st = ea__transport_send(&x->tr, x->buf, len, err);
  if (st == EA_ERR_NET) x->link_lost = 1;
  return st;
}

static void ea__handle(ea__sess_t *x, const ea_frame_t *f) {
  ea_stream_info_t *in = x->info;
  if (f->type != EA_FRAME_ACK && f->type != EA_FRAME_NACK) {
    if (f->type != EA_FRAME_HEARTBEAT) ++in->ack_bad_frames;
    return;
  }
  const int64_t now = ea__mono_ns();
  if (f->type == EA_FRAME_ACK) ++in->acks;
  if (f->type == EA_FRAME_NACK) {
    if (!in->nacks) in->nack_reason = f->reason;
    ++in->nacks;
    x->nacked = 1;
  }
  x->have_ack = 1;
  x->last_ack = *f;
  if (f->state == EA_CTRL_FAULT) x->fault_seen = 1;
  if (f->seq > x->answered_seq && f->seq <= x->seq) x->answered_seq = f->seq;
  in->ctrl_state = f->state;
  in->ctrl_rejected = (int)f->rejected;
  in->frames_acked = (int)f->accepted;
  if (in->acks + in->nacks == 1) in->buffer_min = in->buffer_max = f->buffer_level;
  if (f->buffer_level < in->buffer_min) in->buffer_min = f->buffer_level;
  if (f->buffer_level > in->buffer_max) in->buffer_max = f->buffer_level;
  if (f->ack_seq > x->acked_seq && f->ack_seq <= x->seq) {
    for (uint32_t q = x->acked_seq + 1; q <= f->ack_seq; ++q)
      if ((int)q < x->send_cap && x->send_ns[q]) {
        const double ms = (now - x->send_ns[q]) * 1e-6;
        if (ms > in->ack_latency_max_ms) in->ack_latency_max_ms = ms;
      }
    x->acked_seq = f->ack_seq;
  }
}

/* Read and handle what the controller sent, waiting at most timeout_ms. */
static void ea__poll_in(ea__sess_t *x, int timeout_ms) {
  if (!x->acks_on || x->link_lost) return;
  uint8_t rb[1024];
  for (int round = 0; round < 64; ++round) {
    const long k = ea__transport_recv(&x->tr, rb, sizeof rb, round ? 0 : timeout_ms);
    if (k < 0) {
      x->link_lost = 1;
      return;
    }
    if (k == 0) return;
    size_t off = 0;
    while (off < (size_t)k) {
      off += ea_frame_parser_feed(&x->parser, rb + off, (size_t)k - off);
      ea_frame_t f;
      int r;
      while ((r = ea_frame_parser_next(&x->parser, &f)) != 0)
        if (r > 0) ea__handle(x, &f);
    }
    x->info->ack_bad_frames = (int)x->parser.bad_frames;
  }
}

/* Oldest frame sent but not acknowledged has waited longer than the timeout? */
static int ea__ack_overdue(const ea__sess_t *x, int64_t now) {
  if (!x->acks_on || x->acked_seq >= x->seq) return 0;
  const uint32_t q = x->acked_seq + 1;
  if ((int)q >= x->send_cap || !x->send_ns[q]) return 0;
  return (now - x->send_ns[q]) * 1e-9 > x->s->ack_timeout_s;
}

static void ea__summarise(ea_stream_info_t *in, double *jit, int nj, double period_us) {
  in->frames_late = 0;
  for (int i = 0; i < nj; ++i)
    in->frames_late += jit[i] > 0.5 * period_us;
  in->jitter_p50_us = ea__quantile(jit, nj, 0.5);
  in->jitter_p99_us = ea__quantile(jit, nj, 0.99);
  in->jitter_max_us = nj ? jit[nj - 1] : NAN;
}

/* Time of the setpoint in slot k on the wire [us] (docs/protocol.md: k * 1e6 / rate). */
static uint64_t ea__slot_us(long k, double period_s) {
  return (uint64_t)llround(k * period_s * 1e6);
}

/* Is sp reachable in one period from rest, or rest from sp (the continuity rule between
 * sp and sp held at rest, *tail)? If not, err says which velocities and what one period
 * at the acceleration limits allows; what = "start" or "end". */
static ea_status_t ea__check_rest(const ea_arm_t *arm, const ea_setpoint_t *sp,
                                  const ea_setpoint_t *rest, int first, double period, double tol,
                                  ea_error_t *err) {
  if (!ea_stream_check_continuity(arm, first ? rest : sp, first ? sp : rest, period, tol, NULL))
    return EA_OK;
  const ea_actuators_t *a = &arm->act;
  const double ks = a->spool_gear_ratio / a->spool_radius;
  return ea_error_set(err, EA_ERR_INADMISSIBLE,
                      "the trajectory does not %s at rest: its %s setpoint moves the spool at "
                      "%.6g rad/s (cable %.6g m/s), the shoulder at %.6g rad/s, the base at "
                      "%.6g rad/s, where a controller holding still reaches at most %.3g, %.3g, "
                      "%.3g rad/s in one period (%g s); nothing sent",
                      first ? "start" : "end", first ? "first" : "last", sp->spool_vel[0],
                      sp->spool_vel[0] / ks, sp->shoulder_vel, sp->base_vel,
                      a->cable_accel_max * ks * period, a->shoulder_accel_max * period,
                      a->base_accel_max * period, period);
}

/* Everything is checked before anything is sent, by the controller's own rules: every
 * limit of every setpoint, the continuity rule between consecutive setpoints at their
 * times on the wire, a start at rest (the controller holds the start before the first
 * setpoint), and an end at rest (it holds the last one after it). A last setpoint that
 * still moves, by less than one period at the acceleration limits takes to stop, gets a
 * frame at rest after it (*tail, *has_tail = 1; its position the trapezoid's); one that
 * moves faster is refused. */
static ea_status_t ea__check_all(const ea_arm_t *arm, const ea_setpoint_t *sp, int n,
                                 const ea_stream_settings_t *s, ea_setpoint_t *tail, int *has_tail,
                                 ea_error_t *err) {
  const double period = 1.0 / s->rate_hz, ctol = s->continuity_tol;
  *has_tail = 0;
  for (int k = 0; k < n; ++k) {
    ea_error_t e = {0};
    const double t = ea__slot_us(k, period) * 1e-6;
    if (ea_stream_check_limits(arm, &sp[k], s->limit_tol, &e))
      return ea_error_set(err, EA_ERR_INADMISSIBLE, "setpoint %d (t = %.6f s): %s; nothing sent", k,
                          t, e.msg);
    if (k == 0) {
      ea_setpoint_t rest;
      ea_stream_at_rest(&sp[0], &rest);
      if (ea__check_rest(arm, &sp[0], &rest, 1, period, ctol, err)) return EA_ERR_INADMISSIBLE;
      continue;
    }
    const double dt = (double)(ea__slot_us(k, period) - ea__slot_us(k - 1, period)) * 1e-6;
    if (ea_stream_check_continuity(arm, &sp[k - 1], &sp[k], dt, ctol, &e))
      return ea_error_set(err, EA_ERR_INADMISSIBLE,
                          "setpoints %d and %d (t = %.6f and %.6f s) are not continuous: %s; "
                          "nothing sent",
                          k - 1, k, t - dt, t, e.msg);
  }
  const ea_setpoint_t *l = &sp[n - 1];
  if (l->spool_vel[0] == 0 && l->spool_vel[1] == 0 && l->shoulder_vel == 0 && l->base_vel == 0)
    return EA_OK;
  ea_stream_at_rest(l, tail);
  for (int i = 0; i < 2; ++i)
    tail->spool_pos[i] += 0.5 * l->spool_vel[i] * period;
  tail->shoulder_pos += 0.5 * l->shoulder_vel * period;
  tail->base_pos += 0.5 * l->base_vel * period;
  if (ea__check_rest(arm, l, tail, 0, period, ctol, err)) return EA_ERR_INADMISSIBLE;
  ea_error_t e = {0};
  if (ea_stream_check_limits(arm, tail, s->limit_tol, &e))
    return ea_error_set(err, EA_ERR_INADMISSIBLE,
                        "the frame at rest after the last setpoint (%d): %s; nothing sent", n - 1,
                        e.msg);
  *has_tail = 1;
  return EA_OK;
}

/* The controller's reported position (in its HELLO answer) is the trajectory's start? */
static ea_status_t ea__check_start(const ea__sess_t *x, const ea_setpoint_t *sp0, ea_error_t *err) {
  const ea_arm_t *arm = x->arm;
  const ea_stream_settings_t *s = x->s;
  ea_setpoint_t act = *sp0;
  act.spool_pos[0] = x->last_ack.actual[0];
  act.spool_pos[1] = x->last_ack.actual[1];
  act.shoulder_pos = x->last_ack.actual[2];
  act.base_pos = x->last_ack.actual[3];
  ea_joint_state_t qa, qs;
  ea_stream_unmap(arm, &act, &qa);
  ea_stream_unmap(arm, sp0, &qs);
  const double L1 = arm->act.spool_zero_length +
                    x->last_ack.actual[1] * arm->act.spool_radius / arm->act.spool_gear_ratio;
  const double dL = fmax(fabs(qa.cable_length - qs.cable_length), fabs(L1 - qs.cable_length));
  const double dth = fabs(qa.theta0 - qs.theta0), db = fabs(qa.base_angle - qs.base_angle);
  if (dL > s->start_tol_cable || dth > s->start_tol_angle || db > s->start_tol_angle)
    return ea_error_set(err, EA_ERR_INADMISSIBLE,
                        "refused: controller is not at the trajectory's start: cable length "
                        "%.6g m (start %.6g, tol %g), theta0 %.6g rad (start %.6g), base %.6g "
                        "rad (start %.6g, tol %g); nothing sent",
                        qa.cable_length, qs.cable_length, s->start_tol_cable, qa.theta0, qs.theta0,
                        qa.base_angle, qs.base_angle, s->start_tol_angle);
  return EA_OK;
}

/* HELLO and, with ACKs, its answer (resent over UDP) and the start check. On failure
 * info->end says why; *refused = 1 when an END (refused) is due. */
static ea_status_t ea__handshake(ea__sess_t *x, const ea_setpoint_t *sp, int n, const char *url,
                                 int hb_ms, int *refused, ea_error_t *err) {
  const ea_stream_settings_t *s = x->s;
  ea_frame_t h;
  memset(&h, 0, sizeof h);
  h.type = EA_FRAME_HELLO;
  h.rate_hz = (uint32_t)llround(s->rate_hz);
  h.count = (uint32_t)n;
  h.heartbeat_ms = (uint32_t)hb_ms;
  h.sp = sp[0];
  x->seq = (uint32_t)-1; /* HELLO is sequence number 0 */
  ea_status_t st = ea__send(x, &h, err);
  if (st || !x->acks_on) return st;
  const int64_t t_end = ea__mono_ns() + (int64_t)(s->handshake_timeout_s * 1e9);
  int64_t t_resend = ea__mono_ns() + (int64_t)hb_ms * 1000000;
  while (!x->have_ack && !x->link_lost && ea__mono_ns() < t_end &&
         !(s->stop_request && *s->stop_request)) {
    ea__poll_in(x, 5);
    if (x->tr.kind == EA__TR_UDP && !x->have_ack && ea__mono_ns() > t_resend) {
      ea_frame_t hb = h; /* datagrams may be lost: repeat the HELLO itself */
      const size_t len = ea_frame_encode(&hb, x->buf, sizeof x->buf);
      if (ea__transport_send(&x->tr, x->buf, len, NULL)) x->link_lost = 1;
      t_resend += (int64_t)hb_ms * 1000000;
    }
  }
  if (s->stop_request && *s->stop_request) {
    x->info->end = EA_STREAM_STOP_INTERRUPT;
    return ea_error_set(err, EA_ERR_INTERRUPTED, "interrupted during the handshake");
  }
  if (!x->have_ack)
    return ea_error_set(err, EA_ERR_NET, "%s: no answer to HELLO within %g s%s", url,
                        s->handshake_timeout_s, x->link_lost ? " (link closed)" : "");
  if (x->last_ack.type == EA_FRAME_NACK || x->last_ack.ack_seq != 0 ||
      x->last_ack.state != EA_CTRL_READY) {
    x->info->end = EA_STREAM_REFUSED;
    *refused = 1;
    return ea_error_set(
        err, EA_ERR_PROTOCOL, "controller answered HELLO with %s (state %u, reason %u)",
        x->last_ack.type == EA_FRAME_NACK ? "NACK" : "ACK", x->last_ack.state, x->last_ack.reason);
  }
  if ((st = ea__check_start(x, &sp[0], err))) {
    x->info->end = EA_STREAM_REFUSED;
    *refused = 1;
  }
  return st;
}

/* Pacing of the frames: slot k is due at t0 + k period. */
typedef struct {
  int64_t t0, period_ns;
  int64_t t_first; /* when the first setpoint frame went out (0: none yet) */
  double period_s;
  double *jit; /* |send time - deadline| [us] of every paced frame */
  int nj;
} ea__pace_t;

/* Send one setpoint frame in slot k (flags as given); 0 or nonzero if the link failed. */
static int ea__send_slot(ea__sess_t *x, ea__pace_t *pc, long k, const ea_setpoint_t *sp,
                         uint32_t flags, const volatile sig_atomic_t *stop) {
  const int64_t deadline = pc->t0 + k * pc->period_ns;
  if (x->s->realtime) ea__sleep_until_ns(deadline, stop);
  ea_frame_t f;
  memset(&f, 0, sizeof f);
  f.type = EA_FRAME_SETPOINT;
  f.time_us = ea__slot_us(k, pc->period_s);
  f.flags = flags;
  f.sp = *sp;
  const int64_t now = ea__mono_ns();
  if (!pc->t_first) pc->t_first = now;
  if (x->s->realtime) pc->jit[pc->nj++] = fabs((double)(now - deadline)) * 1e-3;
  return ea__send(x, &f, NULL) != EA_OK;
}

/* The setpoints on absolute deadlines until the last or a reason to stop (info->end);
 * returns the index of the last setpoint sent (-1: none). */
static int ea__send_setpoints(ea__sess_t *x, ea__pace_t *pc, const ea_setpoint_t *sp, int n) {
  const ea_stream_settings_t *s = x->s;
  ea_stream_info_t *info = x->info;
  int last_sent = -1;
  info->end = EA_STREAM_COMPLETE;
  for (long k = 0; k < n; ++k) {
    if (s->realtime) ea__sleep_until_ns(pc->t0 + k * pc->period_ns, s->stop_request);
    if (s->stop_request && *s->stop_request) {
      info->end = EA_STREAM_STOP_INTERRUPT;
      break;
    }
    if (ea__send_slot(x, pc, k, &sp[k], (k == n - 1) ? EA_SP_FLAG_LAST : 0, s->stop_request)) {
      info->end = EA_STREAM_DISCONNECTED;
      break;
    }
    ++info->frames_sent;
    last_sent = (int)k;
    ea__poll_in(x, 0);
    if (x->link_lost) {
      info->end = EA_STREAM_DISCONNECTED;
      break;
    }
    if (x->fault_seen) {
      info->end = EA_STREAM_CTRL_FAULT;
      break;
    }
    if (x->nacked) {
      info->end = EA_STREAM_STOP_NACK;
      break;
    }
    if (ea__ack_overdue(x, ea__mono_ns())) {
      info->end = EA_STREAM_STOP_ACK_TIMEOUT;
      break;
    }
  }
  return last_sent;
}

/* After the setpoints stop: wait (at most the ACK timeout, heartbeats keeping the
 * controller's watchdog fed) for the answers to the frames still in flight, so that the
 * controller's highest accepted setpoint is known. Returns the index of the setpoint a stop
 * ramp must start from and sets *slot to its slot: the last one the controller accepted
 * when every frame was answered (-1: it accepted none), else the last one sent (its
 * silence says nothing was refused). */
static int ea__last_accepted(ea__sess_t *x, int last_sent, long *slot, int *known) {
  *slot = last_sent;
  *known = 0;
  if (!x->acks_on || last_sent < 0) return last_sent;
  const int64_t t_end = ea__mono_ns() + (int64_t)(x->s->ack_timeout_s * 1e9);
  int64_t t_hb = 0;
  while (x->answered_seq < x->seq && !x->link_lost && ea__mono_ns() < t_end) {
    if (ea__mono_ns() >= t_hb) {
      ea_frame_t hb;
      memset(&hb, 0, sizeof hb);
      hb.type = EA_FRAME_HEARTBEAT;
      ea__send(x, &hb, NULL);
      t_hb = ea__mono_ns() + 10000000;
    }
    ea__poll_in(x, 1);
  }
  if (x->answered_seq < x->seq) return last_sent;
  *known = 1;
  /* sequence number q is setpoint q - 1 (HELLO is 0) */
  const int acc = (int)x->acked_seq - 1;
  *slot = acc;
  return acc;
}

/* Controlled stop from setpoint from (in slot from_slot, the last the controller
 * accepted), its frames in the slots after it. Returns the ramp's length, or -1 if no
 * ramp fits in ramp_cap setpoints (nothing sent); a ramp setpoint beyond the limits or
 * not continuous with the one before it is never sent (*cut = 1). */
static int ea__send_stop(ea__sess_t *x, ea__pace_t *pc, const ea_setpoint_t *from, long from_slot,
                         ea_setpoint_t *ramp, int ramp_cap, int *cut) {
  const ea_stream_settings_t *s = x->s;
  const int m = ea_stream_stop_ramp(x->arm, from, s->rate_hz, s->stop_margin, ramp, ramp_cap);
  *cut = 0;
  long k = from_slot + 1;
  for (int j = 0; j < m; ++j, ++k) {
    ea_error_t e = {0};
    const ea_setpoint_t *prev = j ? &ramp[j - 1] : from;
    const double dt =
        (double)(ea__slot_us(k, pc->period_s) - ea__slot_us(k - 1, pc->period_s)) * 1e-6;
    if (ea_stream_check_limits(x->arm, &ramp[j], s->limit_tol, &e) ||
        ea_stream_check_continuity(x->arm, prev, &ramp[j], dt, s->continuity_tol, &e)) {
      *cut = 1; /* never beyond the limits, never a jump */
      break;
    }
    const uint32_t flags = EA_SP_FLAG_STOP | (j == m - 1 ? EA_SP_FLAG_LAST : 0);
    if (ea__send_slot(x, pc, k, &ramp[j], flags, NULL)) break;
    ++x->info->frames_sent;
    ++x->info->stop_frames;
    ea__poll_in(x, 0);
    if (x->link_lost) break;
  }
  return m;
}

/* END (complete or stopped) in slot k and, with ACKs, its acknowledgement. */
static void ea__send_end(ea__sess_t *x, const ea__pace_t *pc, long k, int hb_ms) {
  const ea_stream_settings_t *s = x->s;
  ea_stream_info_t *info = x->info;
  if (x->link_lost) {
    if (info->end == EA_STREAM_COMPLETE) info->end = EA_STREAM_DISCONNECTED;
    return;
  }
  ea_frame_t f;
  memset(&f, 0, sizeof f);
  f.type = EA_FRAME_END;
  f.time_us = ea__slot_us(k, pc->period_s);
  f.flags = info->end == EA_STREAM_COMPLETE ? EA_END_COMPLETE : EA_END_STOPPED;
  f.count = (uint32_t)info->frames_sent;
  if (ea__send(x, &f, NULL) != EA_OK || !x->acks_on) return;
  const uint32_t end_seq = x->seq;
  const int64_t t_end = ea__mono_ns() + (int64_t)(s->end_timeout_s * 1e9);
  int64_t t_hb = ea__mono_ns() + (int64_t)hb_ms * 1000000;
  while (x->acked_seq < end_seq && !x->link_lost && ea__mono_ns() < t_end) {
    ea__poll_in(x, 2);
    if (ea__mono_ns() > t_hb) {
      ea_frame_t hb;
      memset(&hb, 0, sizeof hb);
      hb.type = EA_FRAME_HEARTBEAT;
      ea__send(x, &hb, NULL);
      t_hb += (int64_t)hb_ms * 1000000;
    }
  }
  if (x->acked_seq < end_seq && info->end == EA_STREAM_COMPLETE)
    info->end = x->link_lost ? EA_STREAM_DISCONNECTED : EA_STREAM_STOP_ACK_TIMEOUT;
  if (x->fault_seen && info->end == EA_STREAM_COMPLETE) info->end = EA_STREAM_CTRL_FAULT;
}

/* The outcome: status and message from info->end; stop says how the controlled stop
 * went ("controlled stop in N frames", or why there was none). */
static ea_status_t ea__outcome(const ea__sess_t *x, const char *stop, ea_error_t *err) {
  const ea_stream_info_t *info = x->info;
  const int before = info->frames_sent - info->stop_frames;
  switch (info->end) {
  case EA_STREAM_COMPLETE:
    if (x->acks_on && info->frames_acked != info->frames_sent)
      return ea_error_set(err, EA_ERR_PROTOCOL, "controller accepted %d of %d setpoints",
                          info->frames_acked, info->frames_sent);
    return EA_OK;
  case EA_STREAM_STOP_NACK:
    return ea_error_set(err, EA_ERR_PROTOCOL,
                        "controller rejected a frame (NACK reason %d) after %d setpoints: %s",
                        info->nack_reason, before, stop);
  case EA_STREAM_STOP_ACK_TIMEOUT:
    return ea_error_set(err, EA_ERR_NET, "no acknowledgement for %g s after %d setpoints: %s",
                        x->s->ack_timeout_s, before, stop);
  case EA_STREAM_STOP_INTERRUPT:
    return ea_error_set(err, EA_ERR_INTERRUPTED, "interrupted after %d setpoints: %s", before,
                        stop);
  case EA_STREAM_DISCONNECTED:
    return ea_error_set(err, EA_ERR_NET,
                        "link lost after %d setpoints: the controller's watchdog must stop the "
                        "arm",
                        info->frames_sent);
  case EA_STREAM_CTRL_FAULT:
    return ea_error_set(err, EA_ERR_PROTOCOL,
                        "controller reported state FAULT after %d setpoints (it stops the arm on "
                        "its own and takes no more setpoints): stream ended",
                        before);
  default:
    return ea_error_set(err, EA_ERR_NET, "stream failed");
  }
}

/* A session: check, open, handshake, setpoints, controlled stop, END, outcome. */
ea_status_t ea_stream_run(const ea_arm_t *arm, const ea_setpoint_t *sp, int n, const char *url,
                          const ea_stream_settings_t *s_in, ea_stream_info_t *info,
                          ea_error_t *err) {
  ea_stream_info_t dummy;
  if (!info) info = &dummy;
  memset(info, 0, sizeof *info);
  info->ctrl_state = -1;
  info->end = EA_STREAM_ERROR;
  info->jitter_p50_us = info->jitter_p99_us = info->jitter_max_us = NAN;
  ea_stream_settings_t sdef;
  if (!s_in) ea_stream_settings_default(&sdef);
  const ea_stream_settings_t *s = s_in ? s_in : &sdef;
  ea_status_t st;
  if (!arm || !sp || n < 1 || !url)
    return info->status = ea_error_set(err, EA_ERR_ARG, "stream: no setpoints or no destination");
  if ((st = ea_stream_settings_validate(s, err))) return info->status = st;
  info->setpoints = n;
  ea_setpoint_t tail;
  int has_tail = 0;
  if ((st = ea__check_all(arm, sp, n, s, &tail, &has_tail, err))) return info->status = st;

  ea__sess_t x;
  memset(&x, 0, sizeof x);
  x.arm = arm;
  x.s = s;
  x.info = info;
  ea_frame_parser_init(&x.parser);
  /* A stop within the arm file's limits takes about 1.5 v_max / a_max (under
   * a second for data/elasticarm.yaml); 20 s of setpoints is ample. */
  const int ramp_cap = (int)ceil(20.0 * s->rate_hz) + 16;
  const int n_all = n + has_tail; /* the setpoints and the frame at rest after them */
  x.send_cap = n_all + ramp_cap + 8;
  x.send_ns = calloc((size_t)x.send_cap, sizeof *x.send_ns);
  ea__pace_t pc = {0};
  pc.jit = malloc((size_t)(n_all + ramp_cap) * sizeof *pc.jit);
  ea_setpoint_t *ramp = malloc((size_t)ramp_cap * sizeof *ramp);
  ea_setpoint_t *all = malloc((size_t)n_all * sizeof *all);
  if (!x.send_ns || !pc.jit || !ramp || !all) {
    free(x.send_ns);
    free(pc.jit);
    free(ramp);
    free(all);
    return info->status = ea_error_set(err, EA_ERR_NOMEM, "stream: out of memory");
  }
  memcpy(all, sp, (size_t)n * sizeof *all);
  if (has_tail) all[n] = tail;
  info->rest_frame = has_tail;
  info->stop_from = -1;
  const int hb_ms = (int)fmax(1.0, s->heartbeat_s * 1e3);
  pc.period_s = 1.0 / s->rate_hz;
  pc.period_ns = (int64_t)llround(1e9 * pc.period_s);
  int refused = 0;
  if (!(st = ea__transport_open(&x.tr, url, err))) {
    x.acks_on = s->wait_acks && !EA__TR_IS_DRY(x.tr.kind);
    x.tr.arm = arm;
    st = ea__handshake(&x, all, n_all, url, hb_ms, &refused, err);
  }
  if (!st) {
    /* first deadline 1 ms from now (at once when not paced) */
    pc.t0 = ea__mono_ns() + (s->realtime ? 1000000 : 0);
    const int last_sent = ea__send_setpoints(&x, &pc, all, n_all);
    long k = last_sent + 1; /* END's slot: after the last setpoint or ramp frame */
    char stop[200] = "no controlled stop (nothing was sent)";
    const int stopping = info->end == EA_STREAM_STOP_NACK ||
                         info->end == EA_STREAM_STOP_ACK_TIMEOUT ||
                         info->end == EA_STREAM_STOP_INTERRUPT;
    long from_slot = -1;
    int known = 0;
    const int from = stopping ? ea__last_accepted(&x, last_sent, &from_slot, &known) : -1;
    if (stopping && last_sent >= 0 && from < 0)
      snprintf(stop, sizeof stop, "no controlled stop: the controller accepted no setpoint");
    if (from >= 0) {
      int cut = 0;
      info->stop_from = from;
      const int m = ea__send_stop(&x, &pc, &all[from], from_slot, ramp, ramp_cap, &cut);
      k = from_slot + 1 + info->stop_frames;
      if (k <= last_sent) k = last_sent + 1;
      if (m < 0)
        snprintf(stop, sizeof stop,
                 "no controlled stop: it would take more than %d setpoints (%g s) at the arm's "
                 "acceleration limits; the controller's own stop must act",
                 ramp_cap, ramp_cap / s->rate_hz);
      else if (cut)
        snprintf(stop, sizeof stop,
                 "controlled stop cut after %d of %d frames: a ramp setpoint was beyond the "
                 "limits or not continuous",
                 info->stop_frames, m);
      else
        snprintf(stop, sizeof stop, "controlled stop in %d frames from setpoint %d, %s",
                 info->stop_frames, from,
                 known ? "the last the controller accepted"
                       : "the last sent (unanswered: none was reported rejected)");
    }
    info->duration_s = pc.t_first ? (ea__mono_ns() - pc.t_first) * 1e-9 : 0.0;
    ea__send_end(&x, &pc, k, hb_ms);
    st = ea__outcome(&x, stop, err);
  } else if (refused && !x.link_lost) {
    ea_frame_t f;
    memset(&f, 0, sizeof f);
    f.type = EA_FRAME_END;
    f.flags = EA_END_REFUSED;
    ea__send(&x, &f, NULL);
  }
  if (x.tr.is_open) {
    ea_error_t e2 = {0};
    ea_status_t cst = ea__transport_close(&x.tr, 1, &e2);
    if (cst && st == EA_OK) {
      st = cst;
      if (err) *err = e2;
    }
  }
  if (pc.nj) ea__summarise(info, pc.jit, pc.nj, pc.period_s * 1e6);
  free(x.send_ns);
  free(pc.jit);
  free(ramp);
  free(all);
  info->status = st;
  if (st && err && err->status != st) ea_error_set(err, st, "%s", ea_strerror(st));
  return st;
}
