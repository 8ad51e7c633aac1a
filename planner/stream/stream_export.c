/* Readable dry runs of a stream (docs/streaming.md, "Exports"): the frames the streamer
 * would send, decoded from their wire bytes and written as a table (csv:) or in the
 * layout of ROS's trajectory_msgs/JointTrajectory as YAML (ros-yaml:). Both write
 * what the wire carries, so they equal a file: dry run decoded, field for field. */
#include "stream_impl.h"

#include <errno.h>
#include <stdio.h>
#include <string.h>

/* The setpoint block's 14 doubles, their CSV names (docs/protocol.md, "Setpoint block"). */
static const char *const ea__sp_names[EA_SETPOINT_DOUBLES] = {
    "spool0_pos_rad",          "spool1_pos_rad",
    "spool0_vel_rad_per_s",    "spool1_vel_rad_per_s",
    "spool0_acc_rad_per_s2",   "spool1_acc_rad_per_s2",
    "shoulder_pos_rad",        "shoulder_vel_rad_per_s",
    "shoulder_acc_rad_per_s2", "base_pos_rad",
    "base_vel_rad_per_s",      "base_acc_rad_per_s2",
    "shoulder_torque_ff_Nm",   "tension_ff_N"};

/* One frame as CSV: HELLO and END as '#' lines, a SETPOINT as a row of the wire's values
 * and the task-space values they map back to (ea_stream_unmap). */
static void ea__csv_frame(FILE *fp, const ea_arm_t *arm, const ea_frame_t *f) {
  if (f->type == EA_FRAME_HELLO) {
    fprintf(fp,
            "# elasticarm-frames 1 (docs/streaming.md, Exports; wire format docs/protocol.md "
            "version %u)\n# hello: seq %u, rate_hz %u, count %u, heartbeat_ms %u\n",
            f->version, f->seq, f->rate_hz, f->count, f->heartbeat_ms);
    fputs("seq,time_us,flags", fp);
    for (int i = 0; i < EA_SETPOINT_DOUBLES; ++i)
      fprintf(fp, ",%s", ea__sp_names[i]);
    fputs(",cable_length_m,cable_length_rate_m_per_s,cable_length_acc_m_per_s2,theta0_rad,"
          "theta0_rate_rad_per_s,theta0_acc_rad_per_s2,base_angle_rad,base_angle_rate_rad_per_s,"
          "base_angle_acc_rad_per_s2,tension_N,kappa0_per_m\n",
          fp);
    return;
  }
  if (f->type == EA_FRAME_END) {
    fprintf(fp, "# end: seq %u, reason %u (%s), count %u\n", f->seq, f->flags,
            ea_end_reason_name(f->flags), f->count);
    return;
  }
  if (f->type != EA_FRAME_SETPOINT) return; /* heartbeats carry nothing to tabulate */
  double v[EA_SETPOINT_DOUBLES];
  ea__setpoint_to_array(&f->sp, v);
  fprintf(fp, "%u,%llu,%u", f->seq, (unsigned long long)f->time_us, f->flags);
  for (int i = 0; i < EA_SETPOINT_DOUBLES; ++i)
    fprintf(fp, ",%.17g", v[i]);
  ea_joint_state_t q;
  ea_stream_unmap(arm, &f->sp, &q);
  const double t[11] = {
      q.cable_length, q.cable_length_rate, q.cable_length_acc, q.theta0,         q.theta0_rate,
      q.theta0_acc,   q.base_angle,        q.base_angle_rate,  q.base_angle_acc, q.tension,
      q.kappa0};
  for (int i = 0; i < 11; ++i)
    fprintf(fp, ",%.17g", t[i]);
  fputc('\n', fp);
}

/* v as a YAML float that reads back to the same double: %.17g, with ".0" when that
 * would look like an integer (a float64[] field takes no integers in strict loaders). */
static const char *ea__yfloat(double v, char *buf, size_t len) {
  snprintf(buf, len, "%.17g", v);
  if (!strpbrk(buf, ".eEni")) snprintf(buf + strlen(buf), len - strlen(buf), ".0");
  return buf;
}

/* One frame in the JointTrajectory layout (ROS 2 field names): the HELLO opens the
 * message, each SETPOINT is a point, the END a comment. Joints spool (spool 0; both
 * spools are equal in protocol version 1), shoulder, base; effort is each motor's
 * feed-forward torque: T r / g at the spool, EI kappa0 at the shoulder, 0 at the base. */
static void ea__ros_frame(FILE *fp, const ea_arm_t *arm, const ea_frame_t *f) {
  if (f->type == EA_FRAME_HELLO) {
    fprintf(fp,
            "# trajectory_msgs/JointTrajectory (ROS 2 field names), from elasticarm stream:\n"
            "# the setpoints at %u Hz exactly as the wire carries them (docs/streaming.md,\n"
            "# Exports). Units: rad, rad/s, rad/s^2 at the motor shafts; effort N m.\n"
            "header:\n  stamp: {sec: 0, nanosec: 0}\n  frame_id: ''\n"
            "joint_names: [spool, shoulder, base]\npoints:\n",
            f->rate_hz);
    return;
  }
  if (f->type == EA_FRAME_END) {
    fprintf(fp, "# end: seq %u, reason %u (%s), count %u\n", f->seq, f->flags,
            ea_end_reason_name(f->flags), f->count);
    return;
  }
  if (f->type != EA_FRAME_SETPOINT) return;
  const ea_setpoint_t *s = &f->sp;
  const double spool_torque = s->tension * arm->act.spool_radius / arm->act.spool_gear_ratio;
  const double row[4][3] = {{s->spool_pos[0], s->shoulder_pos, s->base_pos},
                            {s->spool_vel[0], s->shoulder_vel, s->base_vel},
                            {s->spool_acc[0], s->shoulder_acc, s->base_acc},
                            {spool_torque, s->shoulder_torque, 0.0}};
  static const char *const key[4] = {"  - positions", "    velocities", "    accelerations",
                                     "    effort"};
  char a[40], b[40], c[40];
  for (int r = 0; r < 4; ++r)
    fprintf(fp, "%s: [%s, %s, %s]\n", key[r], ea__yfloat(row[r][0], a, sizeof a),
            ea__yfloat(row[r][1], b, sizeof b), ea__yfloat(row[r][2], c, sizeof c));
  fprintf(fp, "    time_from_start: {sec: %llu, nanosec: %llu}\n",
          (unsigned long long)(f->time_us / 1000000u),
          (unsigned long long)(f->time_us % 1000000u * 1000u));
}

ea_status_t ea__export_frame(ea__transport_t *t, const uint8_t *buf, size_t len, ea_error_t *err) {
  ea_frame_t f;
  ea_status_t st = ea_frame_decode(buf, len, &f, err);
  if (st) return st;
  if (!t->arm) return ea_error_set(err, EA_ERR_ARG, "export: no arm for the task-space values");
  if (t->kind == EA__TR_CSV)
    ea__csv_frame(t->file.fp, t->arm, &f);
  else
    ea__ros_frame(t->file.fp, t->arm, &f);
  if (ferror(t->file.fp)) return ea_error_set(err, EA_ERR_IO, "write: %s", strerror(errno));
  return EA_OK;
}
