/* Private: the controller simulator with fault injection (stream_ctrl.c):
 * a test tool for the streamer, served by `elasticarm controller-sim` and
 * used by the tests. Never prints. */
#ifndef EA_CTRL_SIM_IMPL_H
#define EA_CTRL_SIM_IMPL_H

#include "stream_wire_impl.h"

/** Faults the simulator injects. */
typedef enum ea_ctrl_fault {
  EA_FAULT_NONE = 0,
  EA_FAULT_DROP_AFTER,    /**< close the link after N accepted setpoints */
  EA_FAULT_DELAY_ACK,     /**< delay every ACK by N ms */
  EA_FAULT_WITHHOLD_ACK,  /**< answer HELLO, never acknowledge setpoints */
  EA_FAULT_CORRUPT_EVERY, /**< flip a byte of every N-th received frame */
  EA_FAULT_STATE_AFTER    /**< enter FAULT after N accepted setpoints (own stop; ACK says so) */
} ea_ctrl_fault_t;

/** Simulator settings (ea_ctrl_settings_default fills them). */
typedef struct ea_ctrl_settings {
  int udp;               /**< 0: TCP (default), 1: UDP */
  int max_frames;        /**< stop after this many setpoints (0 = no limit) */
  double timeout_s;      /**< give up when no session/frame for this long (10) */
  double watchdog_s;     /**< RUNNING without a frame this long -> own stop (0.1) */
  int buffer_capacity;   /**< simulated setpoint buffer (256) */
  double limit_tol;      /**< relative slack of the limits check (1e-6) */
  double continuity_tol; /**< relative slack of the continuity check (0.05) */
  ea_ctrl_fault_t fault;
  long fault_arg;    /**< N or ms of the fault */
  int has_initial;   /**< 1: report initial[] at HELLO; 0: adopt the HELLO's start */
  double initial[3]; /**< L_c [m], theta0 [rad], base [rad] */
  const volatile sig_atomic_t *stop_request; /**< nonzero -> end */
} ea_ctrl_settings_t;

void ea_ctrl_settings_default(ea_ctrl_settings_t *s);

/** One logged setpoint. */
typedef struct ea_ctrl_log_row {
  uint32_t seq;  /**< sequence number (0 for the simulator's own stop) */
  double time_s; /**< [s] setpoint time from the frame (own stop: extrapolated) */
  double recv_s; /**< [s] receive time since the first setpoint */
  int source;    /**< 0 received, 1 stop ramp received, 2 own stop (watchdog, drop) */
  ea_setpoint_t sp;
} ea_ctrl_log_row_t;

/** Simulator summary. */
typedef struct ea_ctrl_info {
  ea_status_t status;
  int sessions; /**< HELLOs answered */
  int accepted; /**< setpoints accepted */
  int rejected; /**< frames rejected (all reasons) */
  int rejected_crc, rejected_seq, rejected_limit, rejected_continuity;
  int gaps;            /**< setpoints missing between accepted sequence numbers */
  int own_stop_frames; /**< setpoints of the simulator's own stop */
  int fault_state;     /**< 1: entered FAULT by the injected drive fault */
  int end_received;    /**< 1 if END arrived */
  uint32_t end_reason; /**< its reason */
  int final_state;     /**< ::ea_ctrl_state_t at exit */
  int max_buffer;      /**< highest buffer level */
} ea_ctrl_info_t;

typedef struct ea_ctrl ea_ctrl_t;

/** Bind and listen on "HOST:PORT" (PORT 0 = ephemeral; see ea_ctrl_port).
 *  HOST must be a numeric address; loopback unless the caller chose otherwise. */
ea_status_t ea_ctrl_open(const ea_arm_t *arm, const char *listen, const ea_ctrl_settings_t *s,
                         ea_ctrl_t **out, ea_error_t *err);
/** Bound port. */
int ea_ctrl_port(const ea_ctrl_t *c);
/** Serve one session: accept, handshake, check and log setpoints, answer,
 *  until END, the link drops, max_frames, a timeout or a stop request.
 *  Never prints. */
ea_status_t ea_ctrl_run(ea_ctrl_t *c, ea_ctrl_info_t *info, ea_error_t *err);
/** The log: rows in receive order (own stop rows last). Owned by c. */
const ea_ctrl_log_row_t *ea_ctrl_log(const ea_ctrl_t *c, int *n);
/** Write the log as CSV, atomically. */
ea_status_t ea_ctrl_log_write(const ea_ctrl_t *c, const char *path, ea_error_t *err);
void ea_ctrl_free(ea_ctrl_t *c);

/** Like ea_ctrl_open, but serve the byte stream fd (a serial line, a pty
 *  master); c takes ownership of fd. */
ea_status_t ea__ctrl_open_fd(const ea_arm_t *arm, int fd, const ea_ctrl_settings_t *s,
                             ea_ctrl_t **out, ea_error_t *err);

/** A controller without a transport, for checking a frame sequence offline (the
 *  property tests): frames go in by ea__ctrl_feed_bytes, answers are dropped. The
 *  same checks as ea_ctrl_run's, except the buffer (set buffer_capacity high: frames
 *  arrive faster than real time). */
ea_status_t ea__ctrl_open_mem(const ea_arm_t *arm, const ea_ctrl_settings_t *s, ea_ctrl_t **out,
                              ea_error_t *err);
/** A new session on the same controller: state IDLE, counters and log cleared. */
void ea__ctrl_reset(ea_ctrl_t *c);
/** Feed n received bytes; returns 1 once the session ended (END handled). */
int ea__ctrl_feed_bytes(ea_ctrl_t *c, const uint8_t *b, size_t n);
/** The session's counters so far. */
const ea_ctrl_info_t *ea__ctrl_info(const ea_ctrl_t *c);

#endif
