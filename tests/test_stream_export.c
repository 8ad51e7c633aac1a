/* The readable dry runs of a stream (docs/streaming.md, "Exports") against the wire:
 * the closed-form septic move (test_stream_fixture.h) streamed to file: (the exact
 * frames), csv: and ros-yaml:. The CSV's rows equal the binary frames decoded by the
 * protocol's parser, every field bit for bit, and its task-space columns equal
 * ea_stream_unmap of them; the HELLO and END lines carry the frames' fields. The ROS
 * file, loaded by libyaml (a YAML loader outside our code), has the documented fields:
 * joint_names [spool, shoulder, base], one point per setpoint with positions,
 * velocities, accelerations and effort equal to the frames' values, time_from_start
 * equal to their time. */
#include "ea_test.h"
#include "stream_impl.h"
#include "test_stream_fixture.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <yaml.h>

enum { MAXF = 4000 };
static ea_frame_t g_fr[MAXF];
static int g_nf = 0;

/* Decode every frame of a file: dry run. */
static int read_frames(const char *path) {
  FILE *fp = fopen(path, "rb");
  if (!fp) return 0;
  ea_frame_parser_t p;
  ea_frame_parser_init(&p);
  uint8_t b[4096];
  size_t k;
  while ((k = fread(b, 1, sizeof b, fp)) > 0) {
    size_t off = 0;
    while (off < k) {
      off += ea_frame_parser_feed(&p, b + off, k - off);
      int r;
      while ((r = ea_frame_parser_next(&p, &g_fr[g_nf])) != 0)
        if (r > 0 && g_nf < MAXF - 1) ++g_nf;
    }
  }
  fclose(fp);
  return p.bad_frames == 0;
}

static void check_csv(const ea_arm_t *arm, const char *path) {
  FILE *fp = fopen(path, "r");
  char line[8192];
  int fi = 0, rows = 0, bad = 0, hello = 0, end = 0;
  while (fp && fgets(line, sizeof line, fp)) {
    unsigned seq, rate, count, hb, reason;
    if (sscanf(line, "# hello: seq %u, rate_hz %u, count %u, heartbeat_ms %u", &seq, &rate, &count,
               &hb) == 4) {
      hello = g_fr[0].type == EA_FRAME_HELLO && seq == g_fr[0].seq && rate == g_fr[0].rate_hz &&
              count == g_fr[0].count && hb == g_fr[0].heartbeat_ms;
      fi = 1;
      continue;
    }
    if (sscanf(line, "# end: seq %u, reason %u (%*[a-z]), count %u", &seq, &reason, &count) == 3) {
      const ea_frame_t *e = &g_fr[g_nf - 1];
      end = e->type == EA_FRAME_END && seq == e->seq && reason == e->flags && count == e->count;
      continue;
    }
    if (line[0] == '#' || line[0] == 's') continue; /* comments, the header row */
    const ea_frame_t *f = &g_fr[fi++];
    char *p = line, *q;
    const unsigned long s = strtoul(p, &q, 10);
    const unsigned long long t = strtoull(q + 1, &q, 10);
    const unsigned long fl = strtoul(q + 1, &q, 10);
    double v[EA_SETPOINT_DOUBLES], w[EA_SETPOINT_DOUBLES];
    ea__setpoint_to_array(&f->sp, w);
    int ok = f->type == EA_FRAME_SETPOINT && s == f->seq && t == f->time_us && fl == f->flags;
    for (int i = 0; i < EA_SETPOINT_DOUBLES; ++i) {
      v[i] = strtod(q + 1, &q);
      ok &= v[i] == w[i];
    }
    ea_joint_state_t js;
    ea_stream_unmap(arm, &f->sp, &js);
    const double want[11] = {js.cable_length,
                             js.cable_length_rate,
                             js.cable_length_acc,
                             js.theta0,
                             js.theta0_rate,
                             js.theta0_acc,
                             js.base_angle,
                             js.base_angle_rate,
                             js.base_angle_acc,
                             js.tension,
                             js.kappa0};
    for (int i = 0; i < 11; ++i)
      ok &= strtod(q + 1, &q) == want[i];
    bad += !ok;
    ++rows;
  }
  if (fp) fclose(fp);
  char what[200];
  snprintf(what, sizeof what,
           "csv: %d rows equal the %d setpoint frames decoded, every field (%d differ)", rows,
           g_nf - 2, bad);
  ea_test_true(rows == g_nf - 2 && bad == 0, what);
  ea_test_true(hello && end, "csv: the HELLO and END lines carry the frames' fields");
}

/* libyaml's document tree: the value node of key in mapping node m (NULL if absent). */
static yaml_node_t *ymap(yaml_document_t *d, yaml_node_t *m, const char *key) {
  if (!m || m->type != YAML_MAPPING_NODE) return NULL;
  for (yaml_node_pair_t *p = m->data.mapping.pairs.start; p < m->data.mapping.pairs.top; ++p) {
    yaml_node_t *k = yaml_document_get_node(d, p->key);
    if (k && k->type == YAML_SCALAR_NODE && !strcmp((char *)k->data.scalar.value, key))
      return yaml_document_get_node(d, p->value);
  }
  return NULL;
}
static int yseq_len(yaml_node_t *s) {
  return s && s->type == YAML_SEQUENCE_NODE
             ? (int)(s->data.sequence.items.top - s->data.sequence.items.start)
             : -1;
}
static yaml_node_t *yseq(yaml_document_t *d, yaml_node_t *s, int i) {
  return yseq_len(s) > i ? yaml_document_get_node(d, s->data.sequence.items.start[i]) : NULL;
}
static const char *ystr(yaml_node_t *n) {
  return n && n->type == YAML_SCALAR_NODE ? (const char *)n->data.scalar.value : "";
}
/* The 3-vector field key of a point equals want (bit for bit)? */
static int yvec3(yaml_document_t *d, yaml_node_t *pt, const char *key, const double want[3]) {
  yaml_node_t *s = ymap(d, pt, key);
  if (yseq_len(s) != 3) return 0;
  for (int i = 0; i < 3; ++i)
    if (strtod(ystr(yseq(d, s, i)), NULL) != want[i]) return 0;
  return 1;
}

static void check_ros(const ea_arm_t *arm, const char *path) {
  FILE *fp = fopen(path, "rb");
  yaml_parser_t ps;
  yaml_document_t doc;
  yaml_parser_initialize(&ps);
  if (fp) yaml_parser_set_input_file(&ps, fp);
  const int loaded = fp && yaml_parser_load(&ps, &doc);
  ea_test_true(loaded, "ros-yaml: loads as a YAML document (libyaml)");
  if (!loaded) {
    yaml_parser_delete(&ps);
    if (fp) fclose(fp);
    return;
  }
  yaml_node_t *root = yaml_document_get_root_node(&doc);
  yaml_node_t *names = ymap(&doc, root, "joint_names"), *pts = ymap(&doc, root, "points");
  ea_test_true(yseq_len(names) == 3 && !strcmp(ystr(yseq(&doc, names, 0)), "spool") &&
                   !strcmp(ystr(yseq(&doc, names, 1)), "shoulder") &&
                   !strcmp(ystr(yseq(&doc, names, 2)), "base") &&
                   ymap(&doc, ymap(&doc, root, "header"), "frame_id") != NULL,
               "ros-yaml: header, joint_names [spool, shoulder, base]");
  int bad = 0, np = yseq_len(pts);
  for (int i = 0; i < np; ++i) {
    yaml_node_t *pt = yseq(&doc, pts, i);
    const ea_frame_t *f = &g_fr[i + 1];
    const ea_setpoint_t *s = &f->sp;
    const double pos[3] = {s->spool_pos[0], s->shoulder_pos, s->base_pos};
    const double vel[3] = {s->spool_vel[0], s->shoulder_vel, s->base_vel};
    const double acc[3] = {s->spool_acc[0], s->shoulder_acc, s->base_acc};
    const double eff[3] = {s->tension * arm->act.spool_radius / arm->act.spool_gear_ratio,
                           s->shoulder_torque, 0.0};
    yaml_node_t *tf = ymap(&doc, pt, "time_from_start");
    const unsigned long long us = strtoull(ystr(ymap(&doc, tf, "sec")), NULL, 10) * 1000000ULL +
                                  strtoull(ystr(ymap(&doc, tf, "nanosec")), NULL, 10) / 1000ULL;
    bad += !(yvec3(&doc, pt, "positions", pos) && yvec3(&doc, pt, "velocities", vel) &&
             yvec3(&doc, pt, "accelerations", acc) && yvec3(&doc, pt, "effort", eff) &&
             us == f->time_us);
  }
  char what[200];
  snprintf(what, sizeof what,
           "ros-yaml: %d points equal the %d setpoint frames (positions, velocities, "
           "accelerations, effort, time_from_start; %d differ)",
           np, g_nf - 2, bad);
  ea_test_true(np == g_nf - 2 && bad == 0, what);
  yaml_document_delete(&doc);
  yaml_parser_delete(&ps);
  fclose(fp);
}

int main(void) {
  ea_arm_t arm;
  ea_arm_default(&arm);
  fx_move_t m = fx_default_move();
  ea_traj_t tr = {0};
  fx_make_traj(&m, &arm, 0.02, &tr);
  ea_setpoint_t *sp = NULL;
  int n = 0;
  ea_error_t err = {0};
  ea_test_true(ea_stream_resample(&tr, &arm, 1000.0, 1e-9, &sp, &n, &err) == EA_OK,
               "the septic move resampled at 1 kHz");
  ea_traj_free(&tr);
  ea_stream_settings_t ss;
  ea_stream_settings_default(&ss);
  ss.realtime = 0;
  ss.wait_acks = 0;
  const char *url[3] = {"file:test_export.bin", "csv:test_export.csv", "ros-yaml:test_export.yaml"};
  for (int i = 0; i < 3; ++i) {
    char what[120];
    snprintf(what, sizeof what, "stream --to %s", url[i]);
    ea_test_true(ea_stream_run(&arm, sp, n, url[i], &ss, NULL, &err) == EA_OK, what);
  }
  free(sp);
  ea_test_true(read_frames("test_export.bin") && g_nf == n + 2 && g_fr[0].type == EA_FRAME_HELLO &&
                   g_fr[g_nf - 1].type == EA_FRAME_END,
               "file: the HELLO, every setpoint and the END decode");
  check_csv(&arm, "test_export.csv");
  check_ros(&arm, "test_export.yaml");
  remove("test_export.bin");
  remove("test_export.csv");
  remove("test_export.yaml");
  return ea_test_summary("test_stream_export");
}
