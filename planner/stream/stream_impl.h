/* Private: command streamer internals shared by planner/stream/stream_*.c, the
 * stream tests and the fuzz target. */
#ifndef EA_STREAM_IMPL_H
#define EA_STREAM_IMPL_H

#include "ctrl_sim_impl.h"
#include "ea_util.h"

#include <stddef.h>
#include <stdint.h>

/* ---- Time (CLOCK_MONOTONIC: ea__mono_ns of ea_util.h) ------------------ */

/** Sleep until the absolute monotonic time t_ns (clock_nanosleep
 *  TIMER_ABSTIME; restarts on EINTR unless *stop becomes nonzero). */
void ea__sleep_until_ns(int64_t t_ns, const volatile sig_atomic_t *stop);
/** q-quantile (0..1) of v[0..n-1]; sorts v in place. NAN if n == 0. */
double ea__quantile(double *v, int n, double q);

/* ---- Transports ---------------------------------------------------------- */

/** Transports: the network and serial links, and the dry runs into a file (file: the
 *  frames' bytes; csv: and ros-yaml: the frames decoded, stream_export.c). */
typedef enum ea__tr_kind {
  EA__TR_TCP = 0,
  EA__TR_UDP,
  EA__TR_SERIAL,
  EA__TR_FILE,
  EA__TR_CSV,
  EA__TR_ROS
} ea__tr_kind_t;

typedef struct ea__transport {
  ea__tr_kind_t kind;
  int fd;              /**< socket / tty; -1 for the dry runs */
  ea_afile_t file;     /**< dry runs: written atomically, "-" = stdout */
  const ea_arm_t *arm; /**< csv:, ros-yaml: the arm whose mapping gives the task-space values */
  int is_open;
} ea__transport_t;

/** Is url a dry run into a file (file:, csv:, ros-yaml:): no controller, no ACKs? */
int ea__url_is_dry_run(const char *url);
/** A dry run's transport is one of these kinds. */
#define EA__TR_IS_DRY(k) ((k) == EA__TR_FILE || (k) == EA__TR_CSV || (k) == EA__TR_ROS)
/** csv:, ros-yaml: decode the frame in buf and write it as text (stream_export.c). */
ea_status_t ea__export_frame(ea__transport_t *t, const uint8_t *buf, size_t len, ea_error_t *err);

/** Split "HOST:PORT" ("[v6]:PORT" too); port in [0, 65535]. */
ea_status_t ea__split_hostport(const char *s, char *host, size_t hcap, int *port, ea_error_t *err);
/** Baud rate constant of termios for bits/s; 0 if unsupported. */
unsigned ea__baud_constant(long bps);
/** Put a tty fd in raw 8N1 mode at bps. */
ea_status_t ea__serial_setup(int fd, long bps, ea_error_t *err);
/** Open the transport named by url (see ea_stream_run). */
ea_status_t ea__transport_open(ea__transport_t *t, const char *url, ea_error_t *err);
/** Write all len bytes (one datagram for UDP). EA_ERR_NET on a lost link. */
ea_status_t ea__transport_send(ea__transport_t *t, const uint8_t *buf, size_t len, ea_error_t *err);
/** Read what is available, waiting at most timeout_ms (0 = poll). Returns
 *  bytes read (0 = none), -1 if the link is closed or failed. File: 0. */
long ea__transport_recv(ea__transport_t *t, uint8_t *buf, size_t cap, int timeout_ms);
/** Close; file transport: commit = 1 renames the file into place. */
ea_status_t ea__transport_close(ea__transport_t *t, int commit, ea_error_t *err);

/* ---- Little-endian helpers ---------------------------------------------- */

void ea__put_u16(uint8_t *p, uint16_t v);
void ea__put_u32(uint8_t *p, uint32_t v);
void ea__put_u64(uint8_t *p, uint64_t v);
void ea__put_f64(uint8_t *p, double v);
uint16_t ea__get_u16(const uint8_t *p);
uint32_t ea__get_u32(const uint8_t *p);
uint64_t ea__get_u64(const uint8_t *p);
double ea__get_f64(const uint8_t *p);

/** Payload length of a frame type; -1 if the type is unknown. */
int ea__frame_payload_len(uint8_t type);

/* ---- Setpoint helpers ---------------------------------------------------- */

/** Pack / unpack the 14 doubles of a setpoint in wire order. */
void ea__setpoint_to_array(const ea_setpoint_t *sp, double v[EA_SETPOINT_DOUBLES]);
void ea__setpoint_from_array(const double v[EA_SETPOINT_DOUBLES], ea_setpoint_t *sp);

#endif
