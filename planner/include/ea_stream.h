/**
 * @file ea_stream.h
 * @brief Command streamer (docs/streaming.md): a trajectory resampled at the
 *        controller rate, mapped to motor setpoints, checked against every
 *        limit, and sent with a handshake, ACKs and a controlled stop
 *        (planner/stream/). The frame codec (docs/protocol.md) and the
 *        controller simulator are private (stream_wire_impl.h, ctrl_sim_impl.h).
 */
#ifndef EA_STREAM_H
#define EA_STREAM_H

#include "ea_arm.h"
#include "ea_traj.h"

#include <signal.h>

#ifdef __cplusplus
extern "C" {
#endif

/* Command streamer (docs/streaming.md) and its wire format (docs/protocol.md):
 * trajectory -> actuator setpoints at the controller rate -> frames -> a
 * transport (tcp, udp, serial, file) -> a controller (or controller-sim). */

/** Version of the wire format (docs/protocol.md). */
#define EA_PROTO_VERSION 1

/** One actuator setpoint in motor coordinates (what goes on the wire). */
typedef struct ea_setpoint {
  double spool_pos[2];    /**< [rad] spool motor positions (both spools; equal) */
  double spool_vel[2];    /**< [rad/s] */
  double spool_acc[2];    /**< [rad/s^2] */
  double shoulder_pos;    /**< [rad] shoulder motor = theta0 */
  double shoulder_vel;    /**< [rad/s] */
  double shoulder_acc;    /**< [rad/s^2] */
  double base_pos;        /**< [rad] base motor */
  double base_vel;        /**< [rad/s] */
  double base_acc;        /**< [rad/s^2] */
  double shoulder_torque; /**< [N m] feed-forward EI kappa0 */
  double tension;         /**< [N] cable tension feed-forward */
} ea_setpoint_t;

/** Number of doubles of an ::ea_setpoint_t on the wire. */
#define EA_SETPOINT_DOUBLES 14

/** The same point in the trajectory's (joint) coordinates. */
typedef struct ea_joint_state {
  double cable_length, cable_length_rate, cable_length_acc; /**< [m], [m/s], [m/s^2] */
  double theta0, theta0_rate, theta0_acc;                   /**< [rad], [rad/s], [rad/s^2] */
  double base_angle, base_angle_rate, base_angle_acc;       /**< [rad], [rad/s], [rad/s^2] */
  double tension;                                           /**< [N] */
  double kappa0;                                            /**< [1/m] */
} ea_joint_state_t;

/** Joint state -> motor setpoint: spool = (L_c - zero_length) / radius *
 *  gear_ratio (both spools), shoulder = theta0, base = base angle, torque
 *  feed-forward EI kappa0, tension feed-forward T. */
void ea_stream_map(const ea_arm_t *arm, const ea_joint_state_t *q, ea_setpoint_t *sp);
/** Inverse of ea_stream_map (spool 0 is used for the cable length). */
void ea_stream_unmap(const ea_arm_t *arm, const ea_setpoint_t *sp, ea_joint_state_t *q);

/** The trajectory that setpoints sp[0..n-1] at times t[i] [s] describe (e.g. what a
 *  controller accepted), to simulate it (ea_traj_simulate): per row the joint values of
 *  ea_stream_unmap (cable length, theta0, base angle with their rates and accelerations;
 *  the tension and shoulder-torque feed-forwards), and the cable angle and the tip from the
 *  statics of the row's cable length and shoulder angle for arm at tip mass tip_mass [kg],
 *  warm-started along the rows (the cable angle's rate by centred differences). Rows whose time
 * does not increase are left out (*skipped counts them; may be NULL). tr (zeroed or a trajectory)
 * is replaced. EA_ERR_INADMISSIBLE naming the setpoint when a row has no static solution. */
ea_status_t ea_stream_setpoints_traj(const ea_arm_t *arm, double tip_mass, const ea_setpoint_t *sp,
                                     const double *t, int n, ea_traj_t *tr, int *skipped,
                                     ea_error_t *err);

/** Check one setpoint against every limit of the arm file (ranges, speeds,
 *  accelerations, tension, shoulder torque; both spools must agree). tol is a
 *  relative slack (e.g. 1e-9). On failure err->msg names the quantity, its
 *  value and the bound; returns EA_ERR_INADMISSIBLE. */
ea_status_t ea_stream_check_limits(const ea_arm_t *arm, const ea_setpoint_t *sp, double tol,
                                   ea_error_t *err);

/** The protocol's continuity rule between consecutive setpoints (docs/protocol.md,
 *  "What each side checks"), dt [s] apart: per axis (spool, shoulder, base)
 *  |p1 - p0 - (v0 + v1) dt / 2| <= tol v_max dt + a_max dt^2 and
 *  |v1 - v0| <= (1 + tol) a_max dt, limits from the arm file in motor units. The
 *  controller applies it to every setpoint after the first (tol 0.05 by default); the
 *  streamer applies the same rule before it sends anything. EA_ERR_INADMISSIBLE with
 *  err->msg naming the axis, the jump and the bound. */
ea_status_t ea_stream_check_continuity(const ea_arm_t *arm, const ea_setpoint_t *prev,
                                       const ea_setpoint_t *next, double dt, double tol,
                                       ea_error_t *err);

/** sp held at rest: the same positions and feed-forwards, zero rates and accelerations
 *  (what a controller does after the last setpoint, and where it stands before the
 *  first). */
void ea_stream_at_rest(const ea_setpoint_t *sp, ea_setpoint_t *rest);

/** Evaluate a trajectory at time t [s] (clamped to its span): quintic
 *  Hermite of value, rate and acceleration for cable length and base angle;
 *  theta0 quintic with the accelerations of the cubic Hermite of theta0 and
 *  its rate at the samples (the mean of both sides: equal for a planned,
 *  C2 theta0, so the quintic is that cubic);
 *  tension and kappa0 cubic Hermite with centred-difference slopes. */
ea_status_t ea_stream_traj_eval(const ea_traj_t *tr, double t, ea_joint_state_t *q);

/** Resample tr at rate_hz: n = ceil(duration * rate) + 1 setpoints at
 *  t_k = t_0 + min(k / rate, duration), mapped to motor coordinates and
 *  checked against the arm's limits (tol relative slack). *out is malloc'd
 *  (caller frees); on a limit violation err->msg names the sample and time. */
ea_status_t ea_stream_resample(const ea_traj_t *tr, const ea_arm_t *arm, double rate_hz, double tol,
                               ea_setpoint_t **out, int *n, ea_error_t *err);

/** Same, with the trajectory played time_scale (>= 1) times slower: t_plan =
 *  t / time_scale, rates / time_scale, accelerations / time_scale^2 (a
 *  uniform time scaling keeps the path; the feed-forwards, quasi-static, are
 *  unchanged). time_scale = 1 is ea_stream_resample. */
ea_status_t ea_stream_resample_scaled(const ea_traj_t *tr, const ea_arm_t *arm, double rate_hz,
                                      double time_scale, double tol, ea_setpoint_t **out, int *n,
                                      ea_error_t *err);

/** Smallest time scale s >= 1 for which ea_stream_resample_scaled(tr, arm,
 *  rate_hz, s, tol) passes the limits check: the interpolant between the
 *  plan's samples can exceed a speed or acceleration limit the plan meets
 *  only at its samples (e.g. at bang-bang switches). EA_ERR_INADMISSIBLE if
 *  a limit no time scaling changes fails (range, tension, torque). */
ea_status_t ea_stream_min_time_scale(const ea_traj_t *tr, const ea_arm_t *arm, double rate_hz,
                                     double tol, double *scale, ea_error_t *err);

/** Controlled stop from sp (position, velocity, acceleration of each axis):
 *  every axis follows v(s) = v0 h00(s) + T a0 h10(s) (cubic Hermite in
 *  s = t / T to v = a = 0; a0 = 0 for an axis accelerating away from rest, v0 a0 > 0,
 *  so that no axis speeds up), all axes with one common duration T, the
 *  shortest multiple of 1/rate_hz that keeps every |acceleration| within
 *  margin * limit. Feed-forwards are held. Writes at most max setpoints
 *  (the last at rest) to out; returns their number (>= 1), or -1 if max is
 *  too small. */
int ea_stream_stop_ramp(const ea_arm_t *arm, const ea_setpoint_t *sp, double rate_hz, double margin,
                        ea_setpoint_t *out, int max);

/** Controller states reported in ACK/NACK. */
typedef enum ea_ctrl_state {
  EA_CTRL_IDLE = 0,     /**< no session */
  EA_CTRL_READY = 1,    /**< session open, holding position */
  EA_CTRL_RUNNING = 2,  /**< executing setpoints */
  EA_CTRL_STOPPING = 3, /**< executing a controlled stop */
  EA_CTRL_DONE = 4,     /**< session ended, at rest */
  EA_CTRL_FAULT = 5     /**< stopped after a fault; needs a new session */
} ea_ctrl_state_t;

/** NACK reasons (also in ACK: 0). */
typedef enum ea_nack_reason {
  EA_NACK_NONE = 0,
  EA_NACK_CRC = 1,        /**< bad CRC or malformed frame */
  EA_NACK_SEQUENCE = 2,   /**< duplicate or out-of-order sequence number */
  EA_NACK_LIMIT = 3,      /**< setpoint beyond the arm's limits */
  EA_NACK_CONTINUITY = 4, /**< jump from the previous setpoint */
  EA_NACK_OVERFLOW = 5,   /**< controller buffer full */
  EA_NACK_STATE = 6,      /**< frame not allowed in this state */
  EA_NACK_VERSION = 7     /**< unsupported protocol version */
} ea_nack_reason_t;

/* ---- Streamer ---------------------------------------------------------- */

/** Streamer settings (ea_stream_settings_default fills them). */
typedef struct ea_stream_settings {
  double rate_hz;             /**< setpoint rate (default 1000) */
  double limit_tol;           /**< relative slack of the limits check (default 1e-6) */
  double continuity_tol;      /**< slack of the continuity rule (default 0.05, the protocol's) */
  double stop_margin;         /**< stop ramp uses at most this fraction of the accel limits (0.9) */
  double ack_timeout_s;       /**< outstanding frames without an ACK this long -> stop (0.1) */
  double handshake_timeout_s; /**< wait for the HELLO answer (1.0) */
  double end_timeout_s;       /**< wait for the END answer (1.0) */
  double heartbeat_s;         /**< heartbeat period when no setpoint is due (0.1) */
  double start_tol_cable;     /**< [m] handshake tolerance on L_c (1e-3) */
  double start_tol_angle;     /**< [rad] handshake tolerance on theta0 and base (0.01) */
  int realtime;               /**< 1: pace at rate_hz (default); 0: as fast as possible */
  int wait_acks;              /**< 1: handshake and ACKs (default); 0: dry run (file:) */
  const volatile sig_atomic_t *stop_request; /**< nonzero -> controlled stop (SIGINT) */
} ea_stream_settings_t;

void ea_stream_settings_default(ea_stream_settings_t *s);
ea_status_t ea_stream_settings_validate(const ea_stream_settings_t *s, ea_error_t *err);

/** Why the stream ended. */
typedef enum ea_stream_end {
  EA_STREAM_COMPLETE = 0,     /**< every setpoint sent and acknowledged */
  EA_STREAM_REFUSED,          /**< handshake: controller not at the trajectory's start */
  EA_STREAM_STOP_NACK,        /**< controller rejected a frame: controlled stop */
  EA_STREAM_STOP_ACK_TIMEOUT, /**< acknowledgements stopped: controlled stop */
  EA_STREAM_STOP_INTERRUPT,   /**< stop requested (SIGINT): controlled stop */
  EA_STREAM_DISCONNECTED,     /**< link lost: the controller's watchdog must stop */
  EA_STREAM_CTRL_FAULT,       /**< controller reported FAULT: it stopped on its own */
  EA_STREAM_ERROR             /**< could not start (connect, handshake timeout) */
} ea_stream_end_t;

const char *ea_stream_end_name(ea_stream_end_t e);

/** Summary of a stream. */
typedef struct ea_stream_info {
  ea_status_t status; /**< EA_OK only for EA_STREAM_COMPLETE */
  ea_stream_end_t end;
  int setpoints;              /**< setpoints of the resampled trajectory */
  int frames_sent;            /**< setpoint frames written (stop ramp included) */
  int stop_frames;            /**< of which stop ramp */
  int stop_from;              /**< setpoint index the stop ramp started from (-1: no ramp) */
  int rest_frame;             /**< 1: a frame at rest was appended after the last setpoint */
  int frames_acked;           /**< setpoints the controller reported accepted */
  int frames_late;            /**< sent more than half a period after their deadline */
  int nacks;                  /**< NACK frames received */
  int acks;                   /**< ACK frames received */
  int ctrl_rejected;          /**< frames the controller reported rejected */
  int ctrl_state;             /**< last reported ::ea_ctrl_state_t (-1 none) */
  int nack_reason;            /**< reason of the first NACK */
  int buffer_min, buffer_max; /**< controller buffer level seen in ACKs */
  int ack_bad_frames;         /**< malformed frames received from the controller */
  double jitter_p50_us, jitter_p99_us, jitter_max_us; /**< |send time - deadline| */
  double ack_latency_max_ms; /**< longest wait for an outstanding frame's ACK */
  double duration_s;         /**< wall time of the setpoint phase */
} ea_stream_info_t;

/** Stream setpoints sp[0..n-1] to the transport named by url
 *  ("tcp://HOST:PORT", "udp://HOST:PORT", "serial:DEVICE[@BAUD]",
 *  "file:PATH", "file:-" = stdout): handshake, paced sending, ACKs, and on
 *  NACK / ACK timeout / stop request a controlled stop. Never prints.
 * @param[out] info summary (always filled)
 * @return EA_OK if complete; EA_ERR_INADMISSIBLE refused handshake;
 *         EA_ERR_PROTOCOL NACK; EA_ERR_NET link; EA_ERR_INTERRUPTED stop request */
ea_status_t ea_stream_run(const ea_arm_t *arm, const ea_setpoint_t *sp, int n, const char *url,
                          const ea_stream_settings_t *s, ea_stream_info_t *info, ea_error_t *err);

/* ------------------------------------------------------------------------ */
/* Measurement records of a simulated session (planner/stream/stream_record.c) */
/* ------------------------------------------------------------------------ */

/** What a simulated controller's sensors record (docs/calibration.md, "Measurement records"
 *  and "The controller simulator as the arm"). */
typedef struct ea_record_settings {
  double min_hold_s;       /**< [s] shortest run of setpoints at rest that is a hold (default 1) */
  double static_fraction;  /**< the last part of every hold averaged into the static record, as a
                                fraction of the shortest hold (default 1/3) */
  unsigned long seed;      /**< seed of the sensor noise (GSL mt19937; default 1) */
  double noise_theta0_rad; /**< [rad] standard deviation of the shoulder encoder (default 5e-4) */
  double noise_torque_Nm;  /**< [N m] of the shoulder torque sensor (default 0.01) */
  double noise_tension_N;  /**< [N] of the cable tension sensor (default 0.05) */
  double noise_tip_m;      /**< [m] of a tip position measurement (default 5e-4) */
  double payload_kg;       /**< [kg] the payload simulated (header '# payload_kg:') */
  char arm_file[1024];     /**< header '# arm_file:' ("" none) */
  char source[256];        /**< header '# source:' */
} ea_record_settings_t;

void ea_record_settings_default(ea_record_settings_t *s);

/** A hold found in a session's setpoints. */
typedef struct ea_record_hold {
  int first, last;     /**< setpoint indices of the run at rest */
  double t_start;      /**< [s] setpoint time of its first setpoint */
  double t_end;        /**< [s] of its last (the session's last hold: t_end of the history) */
  double cable_length; /**< [m] commanded (ea_stream_unmap) */
  double theta0;       /**< [rad] commanded */
  int ringdown;        /**< 1: a motion precedes it (it has a ring-down record) */
} ea_record_hold_t;

/** What ea_record_write wrote. */
typedef struct ea_record_info {
  int holds;                /**< holds found (rows of the static record) */
  int ringdowns;            /**< ring-down records */
  int averaged_samples;     /**< samples averaged per static row */
  double averaged_window_s; /**< [s] the window they span */
  char static_path[1100];   /**< the static record ("" none) */
} ea_record_info_t;

/** The holds of setpoints sp[0..n-1] at times t[i] (rows whose time does not increase are
 *  left out, as ea_stream_setpoints_traj does): maximal runs of consecutive setpoints whose
 *  spool, shoulder and base positions equal the run's first within 1e-9 rad and whose
 *  velocities and accelerations are within 1e-9 of 0, lasting at least min_hold_s; a run
 *  that reaches the last setpoint lasts until t_last (the controller holds it).
 * @param[out] holds malloc'd array (free()), *n_holds entries; NULL when none */
ea_status_t ea_record_find_holds(const ea_arm_t *arm, const ea_setpoint_t *sp, const double *t,
                                 int n, double min_hold_s, double t_last, ea_record_hold_t **holds,
                                 int *n_holds, ea_error_t *err);

struct ea_sim_history;

/** Write the measurement records of a simulated session into folder dir (created): from the
 *  FE history h (ea_traj_simulate with keep_history: tip and loads at the setpoint times) of
 *  the setpoints sp[0..n-1] at times t, the holds of ea_record_find_holds; every sample of a
 *  hold gets Gaussian sensor noise (s->seed; theta0, torque, tension, tip x, tip y in this
 *  order per sample). dir/static.csv: one row per hold, the mean over the last
 *  averaged_window_s of the hold of the sensed theta0 (the commanded one plus encoder
 *  noise), shoulder torque, cable tension and tip; its noise headers are those of a row
 *  (the sensor's / sqrt(samples averaged)). dir/ringdown-NNN.csv for hold NNN (1-based) when
 *  a motion precedes it: t_s from the hold's start, shoulder_torque_Nm, tension_N, tip_x_m,
 *  tip_y_m at every history row of the hold; its noise headers are the sensors'. Noise
 *  levels of 0 are left out of the headers. Files written atomically.
 * @return EA_OK; EA_ERR_INPUT when there is no hold; EA_ERR_IO; EA_ERR_NOMEM. */
ea_status_t ea_record_write(const char *dir, const ea_record_settings_t *s, const ea_arm_t *arm,
                            const ea_setpoint_t *sp, const double *t, int n,
                            const struct ea_sim_history *h, ea_record_info_t *info,
                            ea_error_t *err);

#ifdef __cplusplus
}
#endif
#endif /* EA_STREAM_H */
