/* Controller simulator: speaks the protocol (docs/protocol.md) on TCP, UDP
 * or a serial line, checks every frame (CRC, sequence, limits, continuity),
 * answers with ACK/NACK, logs what it accepted, stops by itself on a lost
 * link or a silent streamer, and injects faults on request. Never prints. */
#include "stream_impl.h"

#include <errno.h>
#include <math.h>
#include <netdb.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <poll.h>
#include <stdlib.h>
#include <string.h>
#include <sys/socket.h>
#include <time.h>
#include <unistd.h>

void ea_ctrl_settings_default(ea_ctrl_settings_t *s) {
  memset(s, 0, sizeof *s);
  s->timeout_s = 10.0;
  s->watchdog_s = 0.1;
  s->buffer_capacity = 256;
  s->limit_tol = 1e-6;
  s->continuity_tol = 0.05;
}

typedef struct {
  int64_t due_ns;
  ea_frame_t f;
} ea__pending_t;

struct ea_ctrl {
  ea_arm_t arm;
  ea_ctrl_settings_t s;
  int listen_fd; /* TCP listening socket, UDP socket, or -1 */
  int fd;        /* connection (TCP), the UDP socket, or the serial fd */
  int kind;      /* EA__TR_TCP, EA__TR_UDP, EA__TR_SERIAL */
  int port;
  struct sockaddr_storage peer;
  socklen_t peer_len;
  int have_peer;
  ea_frame_parser_t parser;
  uint64_t parser_bad_seen;
  /* session */
  ea_ctrl_state_t state;
  double rate_hz;
  uint32_t last_seq; /* highest sequence number accepted (HELLO = 0) */
  int have_last;
  ea_setpoint_t last; /* last accepted setpoint */
  uint64_t last_time_us;
  int64_t first_recv_ns, last_frame_ns;
  double actual[4];
  long setpoint_frames; /* SETPOINT frames parsed (for corrupt-every) */
  ea_ctrl_info_t info;
  /* delayed ACKs */
  ea__pending_t *pend;
  int pend_cap, pend_head, pend_n;
  /* log */
  ea_ctrl_log_row_t *log;
  int log_n, log_cap;
  ea_setpoint_t *ramp;
  int ramp_cap;
};

static void ea__ctrl_init_common(ea_ctrl_t *c, const ea_arm_t *arm, const ea_ctrl_settings_t *s) {
  c->arm = *arm;
  if (s)
    c->s = *s;
  else
    ea_ctrl_settings_default(&c->s);
  c->listen_fd = c->fd = -1;
  ea_frame_parser_init(&c->parser);
  c->state = EA_CTRL_IDLE;
  c->info.final_state = EA_CTRL_IDLE;
}

static ea_status_t ea__ctrl_alloc_bufs(ea_ctrl_t *c, ea_error_t *err) {
  c->pend_cap = 8192;
  c->pend = calloc((size_t)c->pend_cap, sizeof *c->pend);
  c->log_cap = 4096;
  c->log = malloc((size_t)c->log_cap * sizeof *c->log);
  c->ramp_cap = 200000;
  c->ramp = malloc((size_t)c->ramp_cap * sizeof *c->ramp);
  if (!c->pend || !c->log || !c->ramp) return ea_error_set(err, EA_ERR_NOMEM, "controller-sim");
  return EA_OK;
}

/* A controller with its settings and buffers, not yet bound to a transport. */
static ea_status_t ea__ctrl_new(const ea_arm_t *arm, const ea_ctrl_settings_t *s, ea_ctrl_t **out,
                                ea_error_t *err) {
  ea_ctrl_t *c = calloc(1, sizeof *c);
  if (!c) return ea_error_set(err, EA_ERR_NOMEM, "controller-sim");
  ea__ctrl_init_common(c, arm, s);
  ea_status_t st = ea__ctrl_alloc_bufs(c, err);
  if (st) {
    ea_ctrl_free(c);
    return st;
  }
  *out = c;
  return EA_OK;
}

ea_status_t ea_ctrl_open(const ea_arm_t *arm, const char *listen_at, const ea_ctrl_settings_t *s,
                         ea_ctrl_t **out, ea_error_t *err) {
  if (!arm || !listen_at || !out) return ea_error_set(err, EA_ERR_ARG, "controller-sim: NULL");
  *out = NULL;
  ea_ctrl_t *c = NULL;
  ea_status_t st = ea__ctrl_new(arm, s, &c, err);
  if (st) return st;
  c->kind = c->s.udp ? EA__TR_UDP : EA__TR_TCP;
  char host[256], service[16];
  int port;
  if ((st = ea__split_hostport(listen_at, host, sizeof host, &port, err))) {
    ea_ctrl_free(c);
    return st;
  }
  snprintf(service, sizeof service, "%d", port);
  struct addrinfo hints, *res = NULL;
  memset(&hints, 0, sizeof hints);
  hints.ai_family = AF_UNSPEC;
  hints.ai_socktype = c->s.udp ? SOCK_DGRAM : SOCK_STREAM;
  hints.ai_flags = AI_NUMERICHOST | AI_NUMERICSERV | AI_PASSIVE;
  const int gai = getaddrinfo(host, service, &hints, &res);
  if (gai) {
    ea_ctrl_free(c);
    return ea_error_set(err, EA_ERR_ARG,
                        "--listen %s: %s (give a numeric address, e.g. "
                        "127.0.0.1:PORT)",
                        listen_at, gai_strerror(gai));
  }
  const int fd = socket(res->ai_family, res->ai_socktype | SOCK_CLOEXEC, res->ai_protocol);
  const int one = 1;
  if (fd >= 0) setsockopt(fd, SOL_SOCKET, SO_REUSEADDR, &one, sizeof one);
  if (fd < 0 || bind(fd, res->ai_addr, res->ai_addrlen) != 0 || (!c->s.udp && listen(fd, 1) != 0)) {
    const int e = errno;
    if (fd >= 0) close(fd);
    freeaddrinfo(res);
    ea_ctrl_free(c);
    return ea_error_set(err, EA_ERR_NET, "--listen %s: %s", listen_at, strerror(e));
  }
  freeaddrinfo(res);
  struct sockaddr_storage ss;
  socklen_t sl = sizeof ss;
  getsockname(fd, (struct sockaddr *)&ss, &sl);
  c->port = ss.ss_family == AF_INET6 ? ntohs(((struct sockaddr_in6 *)&ss)->sin6_port)
                                     : ntohs(((struct sockaddr_in *)&ss)->sin_port);
  c->listen_fd = fd;
  if (c->s.udp) c->fd = fd;
  *out = c;
  return EA_OK;
}

ea_status_t ea__ctrl_open_fd(const ea_arm_t *arm, int fd, const ea_ctrl_settings_t *s,
                             ea_ctrl_t **out, ea_error_t *err) {
  if (!arm || fd < 0 || !out) return ea_error_set(err, EA_ERR_ARG, "controller-sim: bad fd");
  *out = NULL;
  ea_ctrl_t *c = NULL;
  ea_status_t st = ea__ctrl_new(arm, s, &c, err);
  if (st) return st;
  c->kind = EA__TR_SERIAL;
  c->fd = fd;
  *out = c;
  return EA_OK;
}

int ea_ctrl_port(const ea_ctrl_t *c) {
  return c ? c->port : -1;
}

void ea_ctrl_free(ea_ctrl_t *c) {
  if (!c) return;
  if (c->fd >= 0 && c->fd != c->listen_fd) close(c->fd);
  if (c->listen_fd >= 0) close(c->listen_fd);
  free(c->pend);
  free(c->log);
  free(c->ramp);
  free(c);
}

const ea_ctrl_log_row_t *ea_ctrl_log(const ea_ctrl_t *c, int *n) {
  if (n) *n = c ? c->log_n : 0;
  return c ? c->log : NULL;
}

/* ---- Sending -------------------------------------------------------------------- */

static void ea__ctrl_write(ea_ctrl_t *c, const ea_frame_t *f) {
  uint8_t buf[EA_PROTO_FRAME_MAX];
  const size_t len = ea_frame_encode(f, buf, sizeof buf);
  if (!len || c->fd < 0) return;
  if (c->kind == EA__TR_UDP) {
    if (c->have_peer)
      (void)sendto(c->fd, buf, len, MSG_NOSIGNAL, (struct sockaddr *)&c->peer, c->peer_len);
    return;
  }
  size_t off = 0;
  while (off < len) {
    ssize_t k = c->kind == EA__TR_SERIAL ? write(c->fd, buf + off, len - off)
                                         : send(c->fd, buf + off, len - off, MSG_NOSIGNAL);
    if (k < 0 && errno == EINTR) continue;
    if (k <= 0) return; /* the read side notices a dead link */
    off += (size_t)k;
  }
}

static int ea__ctrl_buffer_level(const ea_ctrl_t *c, int64_t now) {
  if (!c->first_recv_ns || c->rate_hz <= 0) return 0;
  const double executed = floor((now - c->first_recv_ns) * 1e-9 * c->rate_hz) + 1;
  const double level = (double)c->info.accepted - executed;
  return level < 0 ? 0 : (int)fmin(level, 65535);
}

/* Answer frame seq: ACK (reason 0) or NACK. Subject to the ACK faults. */
static void ea__ctrl_answer(ea_ctrl_t *c, uint32_t seq, int nack, int reason) {
  const int64_t now = ea__mono_ns();
  ea_frame_t f;
  memset(&f, 0, sizeof f);
  f.type = nack ? EA_FRAME_NACK : EA_FRAME_ACK;
  f.seq = seq;
  f.ack_seq = c->last_seq;
  f.accepted = (uint32_t)c->info.accepted;
  f.rejected = (uint32_t)c->info.rejected;
  const int lvl = ea__ctrl_buffer_level(c, now);
  if (lvl > c->info.max_buffer) c->info.max_buffer = lvl;
  f.buffer_level = (uint16_t)lvl;
  f.buffer_capacity = (uint16_t)c->s.buffer_capacity;
  f.state = (uint8_t)c->state;
  f.reason = (uint8_t)reason;
  memcpy(f.actual, c->actual, sizeof f.actual);
  if (c->s.fault == EA_FAULT_WITHHOLD_ACK && c->info.sessions > 0 && c->state != EA_CTRL_READY)
    return;
  if (c->s.fault == EA_FAULT_DELAY_ACK && c->s.fault_arg > 0) {
    if (c->pend_n == c->pend_cap) return; /* queue full: this ACK is lost */
    ea__pending_t *p = &c->pend[(c->pend_head + c->pend_n++) % c->pend_cap];
    p->due_ns = now + (int64_t)c->s.fault_arg * 1000000;
    p->f = f;
    return;
  }
  ea__ctrl_write(c, &f);
}

static void ea__ctrl_flush_pending(ea_ctrl_t *c, int64_t now) {
  while (c->pend_n && c->pend[c->pend_head].due_ns <= now) {
    ea__ctrl_write(c, &c->pend[c->pend_head].f);
    c->pend_head = (c->pend_head + 1) % c->pend_cap;
    --c->pend_n;
  }
}

/* ---- Log ------------------------------------------------------------------------ */

static void ea__ctrl_log(ea_ctrl_t *c, uint32_t seq, double t, int64_t recv_ns, int source,
                         const ea_setpoint_t *sp) {
  if (c->log_n == c->log_cap) {
    const int cap = c->log_cap * 2;
    ea_ctrl_log_row_t *nl = realloc(c->log, (size_t)cap * sizeof *nl);
    if (!nl) return; /* keep running; the log is short by this row */
    c->log = nl;
    c->log_cap = cap;
  }
  ea_ctrl_log_row_t *r = &c->log[c->log_n++];
  r->seq = seq;
  r->time_s = t;
  r->recv_s = c->first_recv_ns ? (recv_ns - c->first_recv_ns) * 1e-9 : 0.0;
  r->source = source;
  r->sp = *sp;
}

static void ea__ctrl_set_actual(ea_ctrl_t *c, const ea_setpoint_t *sp) {
  c->actual[0] = sp->spool_pos[0];
  c->actual[1] = sp->spool_pos[1];
  c->actual[2] = sp->shoulder_pos;
  c->actual[3] = sp->base_pos;
}

/* The simulator's own controlled stop (link lost, watchdog, END while moving). */
static void ea__ctrl_own_stop(ea_ctrl_t *c) {
  if (!c->have_last) return;
  const ea_setpoint_t *l = &c->last;
  if (l->spool_vel[0] == 0 && l->shoulder_vel == 0 && l->base_vel == 0)
    return; /* already at rest: hold the position */
  const double rate = c->rate_hz > 0 ? c->rate_hz : 1000.0;
  const int m = ea_stream_stop_ramp(&c->arm, l, rate, 0.9, c->ramp, c->ramp_cap);
  const int64_t now = ea__mono_ns();
  for (int j = 0; j < m; ++j) {
    ea__ctrl_log(c, 0, c->last_time_us * 1e-6 + (j + 1) / rate, now, 2, &c->ramp[j]);
    ++c->info.own_stop_frames;
  }
  if (m > 0) {
    c->last = c->ramp[m - 1];
    ea__ctrl_set_actual(c, &c->last);
  }
}

/* ---- Checks ---------------------------------------------------------------------- */

static void ea__ctrl_reject(ea_ctrl_t *c, uint32_t seq, int reason) {
  ++c->info.rejected;
  switch (reason) {
  case EA_NACK_CRC:
    ++c->info.rejected_crc;
    break;
  case EA_NACK_SEQUENCE:
    ++c->info.rejected_seq;
    break;
  case EA_NACK_LIMIT:
    ++c->info.rejected_limit;
    break;
  case EA_NACK_CONTINUITY:
    ++c->info.rejected_continuity;
    break;
  default:
    break;
  }
  ea__ctrl_answer(c, seq, 1, reason);
}

/* Handle one frame; returns 1 when the session is over. */
static int ea__ctrl_frame(ea_ctrl_t *c, const ea_frame_t *f) {
  const int64_t now = ea__mono_ns();
  c->last_frame_ns = now;
  switch (f->type) {
  case EA_FRAME_HELLO:
    if (c->state != EA_CTRL_IDLE && c->state != EA_CTRL_DONE) {
      ea__ctrl_reject(c, f->seq, EA_NACK_STATE);
      return 0;
    }
    ++c->info.sessions;
    c->rate_hz = f->rate_hz;
    c->last_seq = f->seq;
    c->have_last = 0;
    if (c->s.has_initial) {
      ea_joint_state_t q;
      memset(&q, 0, sizeof q);
      q.cable_length = c->s.initial[0];
      q.theta0 = c->s.initial[1];
      q.base_angle = c->s.initial[2];
      ea_setpoint_t sp;
      ea_stream_map(&c->arm, &q, &sp);
      ea__ctrl_set_actual(c, &sp);
    } else {
      ea__ctrl_set_actual(c, &f->sp); /* homed to the plan's start */
    }
    c->state = EA_CTRL_READY;
    ea__ctrl_answer(c, f->seq, 0, 0);
    return 0;
  case EA_FRAME_HEARTBEAT:
    if (c->state != EA_CTRL_IDLE) ea__ctrl_answer(c, f->seq, 0, 0);
    return 0;
  case EA_FRAME_END:
    if (c->state == EA_CTRL_IDLE) return 0;
    if (f->seq <= c->last_seq) {
      ea__ctrl_reject(c, f->seq, EA_NACK_SEQUENCE);
      return 0;
    }
    c->last_seq = f->seq;
    c->info.end_received = 1;
    c->info.end_reason = f->flags;
    ea__ctrl_own_stop(c); /* no-op when the streamer left the arm at rest */
    c->state = c->state == EA_CTRL_FAULT ? EA_CTRL_FAULT : EA_CTRL_DONE;
    ea__ctrl_answer(c, f->seq, 0, 0);
    return 1;
  case EA_FRAME_SETPOINT: {
    ++c->setpoint_frames;
    if (c->s.fault == EA_FAULT_CORRUPT_EVERY && c->s.fault_arg > 0 &&
        c->setpoint_frames % c->s.fault_arg == 0) {
      /* A bit error on the line: flip one payload byte of the frame as it
       * arrived and run it through the real decoder (which must refuse it). */
      uint8_t buf[EA_PROTO_FRAME_MAX];
      const size_t len = ea_frame_encode(f, buf, sizeof buf);
      buf[EA_PROTO_HEADER_BYTES + (size_t)(c->setpoint_frames % 100)] ^= 0x10;
      ea_frame_t g;
      if (ea_frame_decode(buf, len, &g, NULL) != EA_OK) {
        ea__ctrl_reject(c, c->last_seq, EA_NACK_CRC);
        return 0;
      }
    }
    if (c->state != EA_CTRL_READY && c->state != EA_CTRL_RUNNING && c->state != EA_CTRL_STOPPING) {
      ea__ctrl_reject(c, f->seq, EA_NACK_STATE);
      return 0;
    }
    if (f->seq <= c->last_seq) {
      ea__ctrl_reject(c, f->seq, EA_NACK_SEQUENCE);
      return 0;
    }
    if (ea_stream_check_limits(&c->arm, &f->sp, c->s.limit_tol, NULL) != EA_OK) {
      ea__ctrl_reject(c, f->seq, EA_NACK_LIMIT);
      return 0;
    }
    if (c->have_last) {
      const double dt = ((double)f->time_us - (double)c->last_time_us) * 1e-6;
      if (ea_stream_check_continuity(&c->arm, &c->last, &f->sp, dt, c->s.continuity_tol, NULL)) {
        ea__ctrl_reject(c, f->seq, EA_NACK_CONTINUITY);
        return 0;
      }
    } else if (fabs(f->sp.spool_pos[0] - c->actual[0]) * c->arm.act.spool_radius /
                       c->arm.act.spool_gear_ratio >
                   1e-3 ||
               fabs(f->sp.shoulder_pos - c->actual[2]) > 0.01 ||
               fabs(f->sp.base_pos - c->actual[3]) > 0.01) {
      /* The first setpoint must start where the arm is (the streamer's
       * default handshake tolerances: 1 mm of cable, 0.01 rad). */
      ea__ctrl_reject(c, f->seq, EA_NACK_CONTINUITY);
      return 0;
    }
    if (ea__ctrl_buffer_level(c, now) >= c->s.buffer_capacity) {
      ea__ctrl_reject(c, f->seq, EA_NACK_OVERFLOW);
      return 0;
    }
    if (f->seq > c->last_seq + 1 && c->have_last) c->info.gaps += (int)(f->seq - c->last_seq - 1);
    if (!c->first_recv_ns) c->first_recv_ns = now;
    c->last_seq = f->seq;
    c->last = f->sp;
    c->have_last = 1;
    c->last_time_us = f->time_us;
    ea__ctrl_set_actual(c, &f->sp);
    ++c->info.accepted;
    ea__ctrl_log(c, f->seq, f->time_us * 1e-6, now, (f->flags & EA_SP_FLAG_STOP) ? 1 : 0, &f->sp);
    c->state = (f->flags & EA_SP_FLAG_STOP) ? EA_CTRL_STOPPING : EA_CTRL_RUNNING;
    if (c->s.fault == EA_FAULT_STATE_AFTER && c->info.accepted >= c->s.fault_arg) {
      /* a drive fault: stop on its own, report FAULT, take no more setpoints */
      ea__ctrl_own_stop(c);
      c->state = EA_CTRL_FAULT;
      c->info.fault_state = 1;
    }
    ea__ctrl_answer(c, f->seq, 0, 0);
    if (c->s.fault == EA_FAULT_DROP_AFTER && c->info.accepted >= c->s.fault_arg) return 2;
    if (c->s.max_frames > 0 && c->info.accepted >= c->s.max_frames) return 2;
    return 0;
  }
  default:
    ea__ctrl_reject(c, f->seq, EA_NACK_STATE);
    return 0;
  }
}

/* ---- Session loop ------------------------------------------------------------------ */

static void ea__ctrl_drop_link(ea_ctrl_t *c) {
  if (c->kind == EA__TR_TCP && c->fd >= 0) {
    close(c->fd);
    c->fd = -1;
  }
  c->have_peer = 0;
}

/* How a session ended. */
typedef struct {
  int done, link_lost, dropped, timed_out, interrupted, watchdog;
} ea__ctrl_end_t;

/* TCP: accept one connection, until the timeout or a stop request. */
static void ea__ctrl_accept(ea_ctrl_t *c, ea__ctrl_end_t *e) {
  const ea_ctrl_settings_t *s = &c->s;
  const int64_t t_idle = ea__mono_ns(), timeout_ns = (int64_t)(s->timeout_s * 1e9);
  while (c->fd < 0) {
    if (s->stop_request && *s->stop_request) {
      e->interrupted = 1;
      return;
    }
    struct pollfd pf = {c->listen_fd, POLLIN, 0};
    if (poll(&pf, 1, 20) > 0) {
      c->fd = accept(c->listen_fd, NULL, NULL);
      if (c->fd >= 0) {
        const int one = 1; /* small ACKs go out at once (no Nagle + delayed-ACK stall) */
        setsockopt(c->fd, IPPROTO_TCP, TCP_NODELAY, &one, sizeof one);
        return;
      }
    }
    if (ea__mono_ns() - t_idle > timeout_ns) {
      e->timed_out = 1;
      return;
    }
  }
}

/* Read what arrived (UDP: from the session's peer only): bytes, 0 for nothing to do,
 * -1 for a lost link. */
static ssize_t ea__ctrl_read(ea_ctrl_t *c, uint8_t *rb, size_t cap) {
  ssize_t k;
  if (c->kind == EA__TR_UDP) {
    struct sockaddr_storage from;
    socklen_t fl = sizeof from;
    k = recvfrom(c->fd, rb, cap, 0, (struct sockaddr *)&from, &fl);
    if (k > 0) {
      if (!c->have_peer) {
        memcpy(&c->peer, &from, fl);
        c->peer_len = fl;
        c->have_peer = 1;
      } else if (fl != c->peer_len || memcmp(&from, &c->peer, fl)) {
        return 0; /* one session at a time: ignore other senders */
      }
    }
  } else {
    k = read(c->fd, rb, cap);
  }
  if (k < 0 && (errno == EINTR || errno == EAGAIN)) return 0;
  if (k <= 0) return c->kind != EA__TR_UDP ? -1 : 0;
  return k;
}

/* Feed k bytes to the parser and handle every frame (a bad one: NACK). */
static void ea__ctrl_feed(ea_ctrl_t *c, const uint8_t *rb, size_t k, ea__ctrl_end_t *e) {
  size_t off = 0;
  while (off < k && !e->done) {
    off += ea_frame_parser_feed(&c->parser, rb + off, k - off);
    ea_frame_t f;
    int pr;
    while (!e->done && (pr = ea_frame_parser_next(&c->parser, &f)) != 0) {
      if (pr < 0) {
        ea__ctrl_reject(c, c->last_seq, EA_NACK_CRC);
        continue;
      }
      const int r2 = ea__ctrl_frame(c, &f);
      if (r2 == 1) e->done = 1;
      if (r2 == 2) e->done = e->dropped = 1;
    }
  }
}

/* The session: frames until END, a drop, a lost link, the timeout or a stop request;
 * the watchdog stops the arm when the streamer goes silent while it moves. */
static void ea__ctrl_session(ea_ctrl_t *c, ea__ctrl_end_t *e) {
  const ea_ctrl_settings_t *s = &c->s;
  const int64_t timeout_ns = (int64_t)(s->timeout_s * 1e9);
  int64_t t_idle = ea__mono_ns();
  uint8_t rb[4096];
  while (!e->done && c->fd >= 0 && !e->timed_out && !e->interrupted) {
    if (s->stop_request && *s->stop_request) {
      e->interrupted = 1;
      break;
    }
    const int64_t now0 = ea__mono_ns();
    ea__ctrl_flush_pending(c, now0);
    if ((c->state == EA_CTRL_RUNNING || c->state == EA_CTRL_STOPPING) &&
        (now0 - c->last_frame_ns) * 1e-9 > s->watchdog_s) {
      e->watchdog = 1;
      ea__ctrl_own_stop(c);
      c->state = EA_CTRL_FAULT;
    }
    if (now0 - t_idle > timeout_ns) {
      e->timed_out = 1;
      break;
    }
    struct pollfd pf = {c->fd, POLLIN, 0};
    const int r = poll(&pf, 1, 1);
    if (r < 0 && errno != EINTR) {
      e->link_lost = 1;
      break;
    }
    if (r <= 0) continue;
    const ssize_t k = ea__ctrl_read(c, rb, sizeof rb);
    if (k < 0) {
      e->link_lost = 1;
      break;
    }
    if (k == 0) continue;
    t_idle = ea__mono_ns();
    ea__ctrl_feed(c, rb, (size_t)k, e);
  }
}

/* Deliver the delayed ACKs (the END answer among them) before closing: wait until
 * each is due (at most 2 s in all), then flush it. Bounded by the queue's own due
 * times, not by a window from now, so a descheduled simulator still delivers every
 * ACK it owes. */
static void ea__ctrl_drain(ea_ctrl_t *c) {
  const int64_t cap = ea__mono_ns() + 2000000000;
  while (c->pend_n) {
    const int64_t now = ea__mono_ns();
    if (now >= cap) {
      ea__ctrl_flush_pending(c, INT64_MAX); /* give up waiting: send them now */
      break;
    }
    ea__ctrl_flush_pending(c, now);
    struct timespec ts = {0, 200000};
    nanosleep(&ts, NULL);
  }
}

/* The session's outcome as a status and message. */
static ea_status_t ea__ctrl_outcome(const ea_ctrl_t *c, const ea__ctrl_end_t *e, ea_error_t *err) {
  const ea_ctrl_settings_t *s = &c->s;
  const ea_ctrl_info_t *in = &c->info;
  if (e->interrupted) return ea_error_set(err, EA_ERR_INTERRUPTED, "controller-sim interrupted");
  if (e->dropped && s->fault == EA_FAULT_DROP_AFTER)
    return ea_error_set(err, EA_ERR_NET,
                        "fault injected: link dropped after %d setpoints; own "
                        "stop in %d setpoints",
                        in->accepted, in->own_stop_frames);
  if (e->dropped)
    return ea_error_set(err, EA_ERR_NET, "--max-frames %d reached; own stop in %d setpoints",
                        s->max_frames, in->own_stop_frames);
  if (e->timed_out && !in->sessions)
    return ea_error_set(err, EA_ERR_NET, "no session within %g s", s->timeout_s);
  if (e->timed_out)
    return ea_error_set(err, EA_ERR_NET, "no frame for %g s; own stop in %d setpoints",
                        s->timeout_s, in->own_stop_frames);
  if (e->link_lost)
    return ea_error_set(err, EA_ERR_NET, "link lost after %d setpoints; own stop in %d setpoints",
                        in->accepted, in->own_stop_frames);
  if (e->watchdog)
    return ea_error_set(err, EA_ERR_NET,
                        "watchdog: no frame for %g s while moving; own stop in "
                        "%d setpoints",
                        s->watchdog_s, in->own_stop_frames);
  if (in->fault_state)
    return ea_error_set(err, EA_ERR_PROTOCOL,
                        "fault injected: state FAULT after %d setpoints; own stop in %d setpoints",
                        (int)s->fault_arg, in->own_stop_frames);
  if (in->rejected)
    return ea_error_set(err, EA_ERR_PROTOCOL,
                        "%d frames rejected (crc %d, sequence %d, limit %d, "
                        "continuity %d)",
                        in->rejected, in->rejected_crc, in->rejected_seq, in->rejected_limit,
                        in->rejected_continuity);
  if (in->end_received && in->end_reason != EA_END_COMPLETE)
    return ea_error_set(err, EA_ERR_INTERRUPTED, "stream ended early (END reason %u: %s)",
                        (unsigned)in->end_reason, ea_end_reason_text(in->end_reason));
  if (in->own_stop_frames)
    return ea_error_set(err, EA_ERR_PROTOCOL,
                        "the stream ended while the arm still moved: own stop in %d setpoints",
                        in->own_stop_frames);
  return EA_OK;
}

/* One session: accept (TCP), serve, drain the ACKs, own stop when it did not end
 * cleanly, outcome. */
ea_status_t ea_ctrl_run(ea_ctrl_t *c, ea_ctrl_info_t *info, ea_error_t *err) {
  if (!c) return ea_error_set(err, EA_ERR_ARG, "controller-sim: NULL");
  ea__ctrl_end_t e = {0};
  if (c->kind == EA__TR_TCP) ea__ctrl_accept(c, &e);
  ea__ctrl_session(c, &e);
  if (e.done && !e.dropped) ea__ctrl_drain(c);
  if (e.dropped || e.link_lost || e.timed_out || e.interrupted) {
    ea__ctrl_own_stop(c);
    if (c->state != EA_CTRL_IDLE) c->state = EA_CTRL_FAULT;
  }
  ea__ctrl_drop_link(c);
  c->info.final_state = c->state;
  const ea_status_t st = ea__ctrl_outcome(c, &e, err);
  c->info.status = st;
  if (info) *info = c->info;
  return st;
}

ea_status_t ea_ctrl_log_write(const ea_ctrl_t *c, const char *path, ea_error_t *err) {
  if (!c || !path) return ea_error_set(err, EA_ERR_ARG, "controller-sim log: NULL");
  ea_afile_t f;
  ea_status_t st = ea_afile_open(&f, path, err);
  if (st) return st;
  fprintf(f.fp, "# elasticarm controller-sim log, protocol %d\n", EA_PROTO_VERSION);
  fprintf(f.fp, "# source: 0 received, 1 stop ramp received, 2 own stop\n");
  fprintf(f.fp, "seq,source,time_s,recv_s,spool0_rad,spool1_rad,spool_vel_rad_per_s,"
                "spool_acc_rad_per_s2,shoulder_rad,shoulder_vel_rad_per_s,"
                "shoulder_acc_rad_per_s2,base_rad,base_vel_rad_per_s,base_acc_rad_per_s2,"
                "shoulder_torque_Nm,tension_N,cable_length_m\n");
  for (int i = 0; i < c->log_n; ++i) {
    const ea_ctrl_log_row_t *r = &c->log[i];
    ea_joint_state_t q;
    ea_stream_unmap(&c->arm, &r->sp, &q);
    fprintf(f.fp, "%u,%d,%.9f,%.9f", (unsigned)r->seq, r->source, r->time_s, r->recv_s);
    double v[EA_SETPOINT_DOUBLES];
    ea__setpoint_to_array(&r->sp, v);
    for (int j = 0; j < EA_SETPOINT_DOUBLES; ++j)
      if (j != 3 && j != 5) fprintf(f.fp, ",%.17g", v[j]); /* spool 1 vel/acc = spool 0 */
    fprintf(f.fp, ",%.17g\n", q.cable_length);
  }
  return ea_afile_commit(&f, err);
}

/* ---- Offline (no transport) --------------------------------------------------------- */

ea_status_t ea__ctrl_open_mem(const ea_arm_t *arm, const ea_ctrl_settings_t *s, ea_ctrl_t **out,
                              ea_error_t *err) {
  if (!arm || !out) return ea_error_set(err, EA_ERR_ARG, "controller-sim: NULL");
  *out = NULL;
  ea_ctrl_t *c = NULL;
  ea_status_t st = ea__ctrl_new(arm, s, &c, err);
  if (st) return st;
  c->kind = EA__TR_SERIAL; /* a byte stream; fd -1: answers go nowhere */
  *out = c;
  return EA_OK;
}

void ea__ctrl_reset(ea_ctrl_t *c) {
  if (!c) return;
  ea_frame_parser_init(&c->parser);
  c->parser_bad_seen = 0;
  c->state = EA_CTRL_IDLE;
  c->rate_hz = 0;
  c->last_seq = 0;
  c->have_last = 0;
  c->last_time_us = 0;
  c->first_recv_ns = c->last_frame_ns = 0;
  c->setpoint_frames = 0;
  memset(&c->info, 0, sizeof c->info);
  c->info.final_state = EA_CTRL_IDLE;
  c->pend_head = c->pend_n = 0;
  c->log_n = 0;
}

int ea__ctrl_feed_bytes(ea_ctrl_t *c, const uint8_t *b, size_t n) {
  ea__ctrl_end_t e = {0};
  ea__ctrl_feed(c, b, n, &e);
  return e.done;
}

const ea_ctrl_info_t *ea__ctrl_info(const ea_ctrl_t *c) {
  return c ? &c->info : NULL;
}
