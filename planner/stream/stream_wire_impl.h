/* Private: the streamer's wire format (docs/protocol.md): frame types and
 * layout, encode / decode and the incremental parser (stream_frame.c), used by
 * the streamer, the controller simulator, the tests and the fuzz target. */
#ifndef EA_STREAM_WIRE_IMPL_H
#define EA_STREAM_WIRE_IMPL_H

#include "ea_stream.h"

#include <stddef.h>
#include <stdint.h>

/** Frame magic, bytes 'E' 'A' 'S' 'F' on the wire (0x46534145 read as LE u32). */
#define EA_PROTO_MAGIC 0x46534145u
/** Bytes of the fixed header (magic .. timestamp) and of the trailing CRC. */
#define EA_PROTO_HEADER_BYTES 20
#define EA_PROTO_CRC_BYTES 4
/** Largest frame on the wire [bytes]. */
#define EA_PROTO_FRAME_MAX 256

/** Frame types (docs/protocol.md). */
typedef enum ea_frame_type {
  EA_FRAME_HELLO = 0x01,     /**< streamer -> controller: session start */
  EA_FRAME_SETPOINT = 0x02,  /**< streamer -> controller: one setpoint */
  EA_FRAME_HEARTBEAT = 0x03, /**< either way: keep-alive, no payload */
  EA_FRAME_END = 0x04,       /**< streamer -> controller: session end */
  EA_FRAME_ACK = 0x81,       /**< controller -> streamer: acknowledgement */
  EA_FRAME_NACK = 0x82       /**< controller -> streamer: rejection */
} ea_frame_type_t;

/** Setpoint flags. */
enum { EA_SP_FLAG_LAST = 1u, EA_SP_FLAG_STOP = 2u };

/** END reasons. */
typedef enum ea_end_reason {
  EA_END_COMPLETE = 0, /**< every setpoint sent */
  EA_END_STOPPED = 1,  /**< controlled stop after NACK, timeout or interrupt */
  EA_END_REFUSED = 2   /**< handshake refused by the streamer */
} ea_end_reason_t;

/** What an END reason means, in words (docs/protocol.md, END): "complete", "stopped, a
 *  controlled stop after a NACK, an ACK timeout or an interrupt", "refused, ...". */
const char *ea_end_reason_text(uint32_t reason);
/** Its one-word name ("complete", "stopped", "refused", "unknown"). */
const char *ea_end_reason_name(uint32_t reason);

/** Decoded frame (all types share one flat struct; fields per type in
 *  docs/protocol.md). */
typedef struct ea_frame {
  uint8_t version;  /**< EA_PROTO_VERSION */
  uint8_t type;     /**< ::ea_frame_type_t */
  uint32_t seq;     /**< sequence number (streamer: HELLO 0, then +1 per frame) */
  uint64_t time_us; /**< [us] setpoint time since the session start (sender clock) */
  /* SETPOINT, HELLO (the trajectory's start) */
  uint32_t flags; /**< SETPOINT: EA_SP_FLAG_*; END: ::ea_end_reason_t */
  ea_setpoint_t sp;
  /* HELLO */
  uint32_t rate_hz;      /**< setpoint rate */
  uint32_t count;        /**< HELLO: setpoints planned; END: setpoints sent */
  uint32_t heartbeat_ms; /**< HELLO: heartbeat period */
  /* ACK / NACK */
  uint32_t ack_seq;      /**< highest sequence number accepted */
  uint32_t accepted;     /**< setpoints accepted so far */
  uint32_t rejected;     /**< frames rejected so far */
  uint16_t buffer_level; /**< setpoints buffered, not yet executed */
  uint16_t buffer_capacity;
  uint8_t state;    /**< ::ea_ctrl_state_t */
  uint8_t reason;   /**< ::ea_nack_reason_t */
  double actual[4]; /**< controller's positions: spool 0, spool 1, shoulder, base [rad] */
} ea_frame_t;

/** Encode f into buf (cap bytes, >= EA_PROTO_FRAME_MAX is always enough);
 *  returns the frame's length or 0 if f->type is unknown or cap too small. */
size_t ea_frame_encode(const ea_frame_t *f, uint8_t *buf, size_t cap);

/** Decode exactly one frame of len bytes. EA_ERR_PROTOCOL with err->msg if
 *  the magic, version, type, length or CRC is wrong, or a value is not finite. */
ea_status_t ea_frame_decode(const uint8_t *buf, size_t len, ea_frame_t *f, ea_error_t *err);

/** Incremental parser of a byte stream (TCP, serial): feed bytes, take
 *  frames. A bad frame is skipped by resynchronising on the next magic and
 *  counted. No allocation. */
typedef struct ea_frame_parser {
  uint8_t buf[2 * EA_PROTO_FRAME_MAX];
  size_t len;
  uint64_t bad_frames;    /**< frames dropped (CRC, length, version, type, values) */
  uint64_t skipped_bytes; /**< bytes discarded while resynchronising */
} ea_frame_parser_t;

void ea_frame_parser_init(ea_frame_parser_t *p);
/** Append up to len bytes; returns how many were taken (less when full:
 *  call ea_frame_parser_next and feed the rest). */
size_t ea_frame_parser_feed(ea_frame_parser_t *p, const uint8_t *data, size_t len);
/** Next complete frame: 1 = f filled, 0 = need more bytes, -1 = a bad frame
 *  was dropped (call again). */
int ea_frame_parser_next(ea_frame_parser_t *p, ea_frame_t *f);

#endif
