/* Command streamer: the wire format (docs/protocol.md). Frame encode /
 * decode (CRC-32 from model/util/crc32.c), and an incremental parser that resynchronises on the
 * magic after a bad frame. Little-endian fixed layout, no allocation. */
#include "stream_impl.h"

#include <math.h>
#include <string.h>

/* ---- Little-endian helpers (independent of the host's byte order) ------ */

void ea__put_u16(uint8_t *p, uint16_t v) {
  p[0] = (uint8_t)v;
  p[1] = (uint8_t)(v >> 8);
}
void ea__put_u32(uint8_t *p, uint32_t v) {
  for (int i = 0; i < 4; ++i)
    p[i] = (uint8_t)(v >> (8 * i));
}
void ea__put_u64(uint8_t *p, uint64_t v) {
  for (int i = 0; i < 8; ++i)
    p[i] = (uint8_t)(v >> (8 * i));
}
void ea__put_f64(uint8_t *p, double v) {
  uint64_t u;
  memcpy(&u, &v, sizeof u);
  ea__put_u64(p, u);
}
uint16_t ea__get_u16(const uint8_t *p) {
  return (uint16_t)(p[0] | (p[1] << 8));
}
uint32_t ea__get_u32(const uint8_t *p) {
  uint32_t v = 0;
  for (int i = 3; i >= 0; --i)
    v = (v << 8) | p[i];
  return v;
}
uint64_t ea__get_u64(const uint8_t *p) {
  uint64_t v = 0;
  for (int i = 7; i >= 0; --i)
    v = (v << 8) | p[i];
  return v;
}
double ea__get_f64(const uint8_t *p) {
  const uint64_t u = ea__get_u64(p);
  double v;
  memcpy(&v, &u, sizeof v);
  return v;
}

/* ---- Setpoint in wire order ---------------------------------------------- */

void ea__setpoint_to_array(const ea_setpoint_t *sp, double v[EA_SETPOINT_DOUBLES]) {
  const double a[EA_SETPOINT_DOUBLES] = {
      sp->spool_pos[0], sp->spool_pos[1], sp->spool_vel[0],    sp->spool_vel[1], sp->spool_acc[0],
      sp->spool_acc[1], sp->shoulder_pos, sp->shoulder_vel,    sp->shoulder_acc, sp->base_pos,
      sp->base_vel,     sp->base_acc,     sp->shoulder_torque, sp->tension};
  memcpy(v, a, sizeof a);
}

void ea__setpoint_from_array(const double v[EA_SETPOINT_DOUBLES], ea_setpoint_t *sp) {
  sp->spool_pos[0] = v[0];
  sp->spool_pos[1] = v[1];
  sp->spool_vel[0] = v[2];
  sp->spool_vel[1] = v[3];
  sp->spool_acc[0] = v[4];
  sp->spool_acc[1] = v[5];
  sp->shoulder_pos = v[6];
  sp->shoulder_vel = v[7];
  sp->shoulder_acc = v[8];
  sp->base_pos = v[9];
  sp->base_vel = v[10];
  sp->base_acc = v[11];
  sp->shoulder_torque = v[12];
  sp->tension = v[13];
}

/* ---- Frames ---------------------------------------------------------------- */

enum {
  EA__HELLO_LEN = 16 + 8 * EA_SETPOINT_DOUBLES,   /* 128 */
  EA__SETPOINT_LEN = 4 + 8 * EA_SETPOINT_DOUBLES, /* 116 */
  EA__END_LEN = 8,
  EA__ACK_LEN = 20 + 8 * 4 /* 52 */
};

int ea__frame_payload_len(uint8_t type) {
  switch (type) {
  case EA_FRAME_HELLO:
    return EA__HELLO_LEN;
  case EA_FRAME_SETPOINT:
    return EA__SETPOINT_LEN;
  case EA_FRAME_HEARTBEAT:
    return 0;
  case EA_FRAME_END:
    return EA__END_LEN;
  case EA_FRAME_ACK:
  case EA_FRAME_NACK:
    return EA__ACK_LEN;
  default:
    return -1;
  }
}

static void ea__put_sp(uint8_t *p, const ea_setpoint_t *sp) {
  double v[EA_SETPOINT_DOUBLES];
  ea__setpoint_to_array(sp, v);
  for (int i = 0; i < EA_SETPOINT_DOUBLES; ++i)
    ea__put_f64(p + 8 * i, v[i]);
}

static int ea__get_sp(const uint8_t *p, ea_setpoint_t *sp) {
  double v[EA_SETPOINT_DOUBLES];
  int finite = 1;
  for (int i = 0; i < EA_SETPOINT_DOUBLES; ++i) {
    v[i] = ea__get_f64(p + 8 * i);
    finite &= isfinite(v[i]) != 0;
  }
  ea__setpoint_from_array(v, sp);
  return finite;
}

size_t ea_frame_encode(const ea_frame_t *f, uint8_t *buf, size_t cap) {
  const int plen = ea__frame_payload_len(f->type);
  if (plen < 0) return 0;
  const size_t total = EA_PROTO_HEADER_BYTES + (size_t)plen + EA_PROTO_CRC_BYTES;
  if (!buf || cap < total) return 0;
  memset(buf, 0, total);
  ea__put_u32(buf, EA_PROTO_MAGIC);
  buf[4] = EA_PROTO_VERSION;
  buf[5] = f->type;
  ea__put_u16(buf + 6, (uint16_t)plen);
  ea__put_u32(buf + 8, f->seq);
  ea__put_u64(buf + 12, f->time_us);
  uint8_t *p = buf + EA_PROTO_HEADER_BYTES;
  switch (f->type) {
  case EA_FRAME_HELLO:
    ea__put_u32(p, f->rate_hz);
    ea__put_u32(p + 4, f->count);
    ea__put_u32(p + 8, f->heartbeat_ms);
    ea__put_u32(p + 12, f->flags);
    ea__put_sp(p + 16, &f->sp);
    break;
  case EA_FRAME_SETPOINT:
    ea__put_u32(p, f->flags);
    ea__put_sp(p + 4, &f->sp);
    break;
  case EA_FRAME_END:
    ea__put_u32(p, f->flags);
    ea__put_u32(p + 4, f->count);
    break;
  case EA_FRAME_ACK:
  case EA_FRAME_NACK:
    ea__put_u32(p, f->ack_seq);
    ea__put_u32(p + 4, f->accepted);
    ea__put_u32(p + 8, f->rejected);
    ea__put_u16(p + 12, f->buffer_level);
    ea__put_u16(p + 14, f->buffer_capacity);
    p[16] = f->state;
    p[17] = f->reason;
    for (int i = 0; i < 4; ++i)
      ea__put_f64(p + 20 + 8 * i, f->actual[i]);
    break;
  default:
    break;
  }
  ea__put_u32(buf + EA_PROTO_HEADER_BYTES + plen,
              ea_crc32(0, buf, EA_PROTO_HEADER_BYTES + (size_t)plen));
  return total;
}

ea_status_t ea_frame_decode(const uint8_t *buf, size_t len, ea_frame_t *f, ea_error_t *err) {
  if (!buf || !f) return ea_error_set(err, EA_ERR_ARG, "frame decode: NULL argument");
  memset(f, 0, sizeof *f);
  if (len < EA_PROTO_HEADER_BYTES + EA_PROTO_CRC_BYTES)
    return ea_error_set(err, EA_ERR_PROTOCOL, "frame: %zu bytes, shorter than a header", len);
  if (ea__get_u32(buf) != EA_PROTO_MAGIC)
    return ea_error_set(err, EA_ERR_PROTOCOL, "frame: bad magic 0x%08x",
                        (unsigned)ea__get_u32(buf));
  if (buf[4] != EA_PROTO_VERSION)
    return ea_error_set(err, EA_ERR_PROTOCOL, "frame: protocol version %u, expected %d", buf[4],
                        EA_PROTO_VERSION);
  const int plen = ea__frame_payload_len(buf[5]);
  if (plen < 0) return ea_error_set(err, EA_ERR_PROTOCOL, "frame: unknown type 0x%02x", buf[5]);
  if (ea__get_u16(buf + 6) != (uint16_t)plen)
    return ea_error_set(err, EA_ERR_PROTOCOL,
                        "frame: type 0x%02x with payload length %u, "
                        "expected %d",
                        buf[5], ea__get_u16(buf + 6), plen);
  if (len != EA_PROTO_HEADER_BYTES + (size_t)plen + EA_PROTO_CRC_BYTES)
    return ea_error_set(err, EA_ERR_PROTOCOL, "frame: %zu bytes, expected %d", len,
                        EA_PROTO_HEADER_BYTES + plen + EA_PROTO_CRC_BYTES);
  const uint32_t crc = ea_crc32(0, buf, EA_PROTO_HEADER_BYTES + (size_t)plen);
  const uint32_t got = ea__get_u32(buf + EA_PROTO_HEADER_BYTES + plen);
  if (crc != got)
    return ea_error_set(err, EA_ERR_PROTOCOL, "frame: CRC 0x%08x, computed 0x%08x", (unsigned)got,
                        (unsigned)crc);
  f->version = buf[4];
  f->type = buf[5];
  f->seq = ea__get_u32(buf + 8);
  f->time_us = ea__get_u64(buf + 12);
  const uint8_t *p = buf + EA_PROTO_HEADER_BYTES;
  int finite = 1;
  switch (f->type) {
  case EA_FRAME_HELLO:
    f->rate_hz = ea__get_u32(p);
    f->count = ea__get_u32(p + 4);
    f->heartbeat_ms = ea__get_u32(p + 8);
    f->flags = ea__get_u32(p + 12);
    finite = ea__get_sp(p + 16, &f->sp);
    if (f->rate_hz == 0) return ea_error_set(err, EA_ERR_PROTOCOL, "frame: HELLO with rate 0");
    break;
  case EA_FRAME_SETPOINT:
    f->flags = ea__get_u32(p);
    finite = ea__get_sp(p + 4, &f->sp);
    break;
  case EA_FRAME_END:
    f->flags = ea__get_u32(p);
    f->count = ea__get_u32(p + 4);
    break;
  case EA_FRAME_ACK:
  case EA_FRAME_NACK:
    f->ack_seq = ea__get_u32(p);
    f->accepted = ea__get_u32(p + 4);
    f->rejected = ea__get_u32(p + 8);
    f->buffer_level = ea__get_u16(p + 12);
    f->buffer_capacity = ea__get_u16(p + 14);
    f->state = p[16];
    f->reason = p[17];
    for (int i = 0; i < 4; ++i) {
      f->actual[i] = ea__get_f64(p + 20 + 8 * i);
      finite &= isfinite(f->actual[i]) != 0;
    }
    if (f->state > EA_CTRL_FAULT || f->reason > EA_NACK_VERSION)
      return ea_error_set(err, EA_ERR_PROTOCOL, "frame: state %u / reason %u out of range",
                          f->state, f->reason);
    break;
  default:
    break;
  }
  if (!finite)
    return ea_error_set(err, EA_ERR_PROTOCOL,
                        "frame: type 0x%02x seq %u carries a non-finite "
                        "value",
                        f->type, (unsigned)f->seq);
  return EA_OK;
}

/* ---- Incremental parser ------------------------------------------------------ */

void ea_frame_parser_init(ea_frame_parser_t *p) {
  memset(p, 0, sizeof *p);
}

size_t ea_frame_parser_feed(ea_frame_parser_t *p, const uint8_t *data, size_t len) {
  const size_t room = sizeof p->buf - p->len;
  const size_t k = len < room ? len : room;
  if (k) memcpy(p->buf + p->len, data, k);
  p->len += k;
  return k;
}

static void ea__parser_drop(ea_frame_parser_t *p, size_t k) {
  if (k > p->len) k = p->len;
  memmove(p->buf, p->buf + k, p->len - k);
  p->len -= k;
}

int ea_frame_parser_next(ea_frame_parser_t *p, ea_frame_t *f) {
  static const uint8_t magic[4] = {0x45, 0x41, 0x53, 0x46}; /* "EASF" */
  /* Resynchronise: drop bytes before the first (possibly partial) magic. */
  size_t i = 0;
  while (i < p->len) {
    const size_t k = (p->len - i < 4) ? p->len - i : 4;
    if (!memcmp(p->buf + i, magic, k)) break;
    ++i;
  }
  if (i) {
    p->skipped_bytes += i;
    ea__parser_drop(p, i);
  }
  if (p->len < EA_PROTO_HEADER_BYTES) return 0;
  const int plen = ea__frame_payload_len(p->buf[5]);
  if (p->buf[4] != EA_PROTO_VERSION || plen < 0 || ea__get_u16(p->buf + 6) != (uint16_t)plen) {
    ++p->bad_frames;
    ea__parser_drop(p, 1);
    return -1;
  }
  const size_t total = EA_PROTO_HEADER_BYTES + (size_t)plen + EA_PROTO_CRC_BYTES;
  if (p->len < total) return 0;
  if (ea_frame_decode(p->buf, total, f, NULL) != EA_OK) {
    ++p->bad_frames;
    ea__parser_drop(p, 1);
    return -1;
  }
  ea__parser_drop(p, total);
  return 1;
}

const char *ea_end_reason_name(uint32_t reason) {
  return reason == EA_END_COMPLETE  ? "complete"
         : reason == EA_END_STOPPED ? "stopped"
         : reason == EA_END_REFUSED ? "refused"
                                    : "unknown";
}

const char *ea_end_reason_text(uint32_t reason) {
  return reason == EA_END_COMPLETE ? "complete, every setpoint sent"
         : reason == EA_END_STOPPED
             ? "stopped, a controlled stop after a NACK, an ACK timeout or an interrupt"
         : reason == EA_END_REFUSED ? "refused, the streamer's handshake check failed"
                                    : "unknown";
}
