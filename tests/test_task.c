/* Task loader: good files load, and every bad input is rejected with
 * file:line:column and the key in the message (docs/task-format.md). */
#include "ea_planner.h"
#include "ea_problems.h"
#include "ea_test.h"

#include <malloc.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#define OKTASK "start: {tip: [0.3, -0.2]}\ngoal: {tip: [0.6, -0.2]}\n"

typedef struct {
  const char *name;
  const char *yaml;
  ea_status_t status; /* expected */
  const char *where;  /* "bad.yaml:L:C" expected in the message */
  const char *key;    /* another substring expected (key / reason) */
} ea_case_t;

static const ea_case_t cases[] = {
    {"unknown top-level key", OKTASK "speed: 3\n", EA_ERR_INPUT, "bad.yaml:3:1", "'speed'"},
    {"unknown key in limits", OKTASK "limits:\n  tension_min: 1\n", EA_ERR_INPUT, "bad.yaml:4:3",
     "'tension_min'"},
    {"wrong type: tip not a list", "start: {tip: 0.3}\ngoal: {tip: [0.6, -0.2]}\n", EA_ERR_INPUT,
     "bad.yaml:1:14", "'tip'"},
    {"wrong type: tip element text", "start: {tip: [0.3, abc]}\ngoal: {tip: [0.6, -0.2]}\n",
     EA_ERR_INPUT, "bad.yaml:1:20", "'abc' is not a number"},
    {"NaN coordinate", "start:\n  tip: [nan, -0.2]\ngoal: {tip: [0.6, -0.2]}\n", EA_ERR_INPUT,
     "bad.yaml:2:9", "not finite"},
    {".nan coordinate", "start:\n  tip: [0.3, .nan]\ngoal: {tip: [0.6, -0.2]}\n", EA_ERR_INPUT,
     "bad.yaml:2:14", "'tip'"},
    {"NaN limit", OKTASK "limits:\n  cable_speed_max_m_per_s: NaN\n", EA_ERR_INPUT, "bad.yaml:4:28",
     "cable_speed_max_m_per_s"},
    {"tip with 4 numbers", "start: {tip: [0.3, -0.2, 0, 1]}\ngoal: {tip: [0.6, -0.2]}\n",
     EA_ERR_INPUT, "bad.yaml:1:14", "'tip'"},
    {"missing goal", "start: {tip: [0.3, -0.2]}\n", EA_ERR_INPUT, "bad.yaml:1:1", "'goal'"},
    {"tip and actuators both",
     "start: {tip: [0.3, -0.2], cable_length_m: 0.3}\ngoal: {tip: [0.6, -0.2]}\n", EA_ERR_INPUT,
     "bad.yaml:1:8", "not both"},
    {"3-D tip with base angle",
     "start: {tip: [0.3, 0.1, -0.2], base_angle_rad: 0.1}\ngoal: {tip: [0.6, -0.2]}\n",
     EA_ERR_INPUT, "bad.yaml:1:48", "base_angle_rad"},
    {"goal outside the workspace (payload)",
     "payload_factor: 0.5\nstart: {tip: [0.3, -0.2]}\ngoal:\n  tip: [0.78, -0.2]\n",
     EA_ERR_INFEASIBLE, "bad.yaml:4:3", "goal: outside the workspace"},
    {"start inside the shortest cable", "start: {tip: [0.2, -0.1]}\ngoal: {tip: [0.6, -0.2]}\n",
     EA_ERR_INFEASIBLE, "bad.yaml:1:8", "cable length"},
    {"contradictory tension limits", OKTASK "limits:\n  tension_min_N: 5\n  tension_max_N: 2\n",
     EA_ERR_INPUT, "bad.yaml:4:3", "tension_min_N = 5 >= tension_max_N = 2"},
    {"limit above the arm's", OKTASK "limits:\n  cable_speed_max_m_per_s: 9\n", EA_ERR_INPUT,
     "bad.yaml:4:3", "exceeds the arm's limit"},
    {"cable length below the arm's shortest", OKTASK "limits:\n  cable_length_min_m: 0.1\n",
     EA_ERR_INPUT, "bad.yaml:4:3", "cable_length_min_m"},
    {"min_time with a duration", OKTASK "objective: {type: min_time, duration_s: 2}\n",
     EA_ERR_INPUT, "bad.yaml:3:41", "duration_s"},
    /* the path transcription asked for where it cannot run (it fell back to the knots) */
    {"path transcription on a free path", OKTASK "path: free\nsolver:\n  transcription: path\n",
     EA_ERR_INPUT, "bad.yaml:5:18", "path is free"},
    {"path transcription with the frequency model",
     OKTASK "path: line\nlimits:\n  min_first_frequency_Hz: 0.5\nsolver:\n  transcription: "
            "path\n",
     EA_ERR_INPUT, "bad.yaml:7:18", "frequency model"},
    {"min_effort without a duration", OKTASK "objective: {type: min_effort}\n", EA_ERR_INPUT,
     "bad.yaml:3:12", "duration_s"},
    {"unknown objective", OKTASK "objective: fastest\n", EA_ERR_INPUT, "bad.yaml:3:12",
     "'objective'"},
    {"unknown path", OKTASK "path: curvy\n", EA_ERR_INPUT, "bad.yaml:3:7", "'path'"},
    {"polyline without vias", OKTASK "path: polyline\n", EA_ERR_INPUT, "bad.yaml:3:7", "'path'"},
    {"knots out of range", OKTASK "knots: 2\n", EA_ERR_INPUT, "bad.yaml:3:8", "'knots'"},
    {"knots not an integer", OKTASK "knots: 10.5\n", EA_ERR_INPUT, "bad.yaml:3:8", "'knots'"},
    {"both payload keys", OKTASK "payload_kg: 0.1\npayload_factor: 0.1\n", EA_ERR_INPUT,
     "bad.yaml:4:17", "payload"},
    {"negative payload", OKTASK "payload_kg: -0.1\n", EA_ERR_INPUT, "bad.yaml:3:13",
     "'payload_kg'"},
    {"duplicate key", OKTASK "knots: 10\nknots: 20\n", EA_ERR_INPUT, "bad.yaml:4:1",
     "duplicate key 'knots'"},
    {"figure extension", OKTASK "outputs: {figure: plan.gif}\n", EA_ERR_INPUT, "bad.yaml:3:19",
     "'figure'"},
    {"solver bool", OKTASK "solver: {derivative_test: maybe}\n", EA_ERR_INPUT, "bad.yaml:3:27",
     "'derivative_test'"},
    {"solver threads out of range", OKTASK "solver: {threads: 3}\n", EA_ERR_INPUT, "bad.yaml:3:19",
     "outside [0, 2]"},
    {"YAML syntax error", OKTASK "limits: [1, 2\n", EA_ERR_PARSE, "bad.yaml:4:1", "YAML"},
    {"top level not a mapping", "- 1\n- 2\n", EA_ERR_INPUT, "bad.yaml:1:1", "mapping"},
    {"missing arm file", "arm_file: /nonexistent/arm.yaml\n" OKTASK, EA_ERR_IO, "bad.yaml:1:11",
     "arm_file"},
};

/* A task whose start point is depth levels of flow sequences [[[...]]]
 * (the root mapping is level 1). */
static char *nested_task(int depth) {
  const int n = depth - 1;
  char *s = malloc((size_t)(2 * n) + 64);
  if (!s) return NULL;
  char *p = s + sprintf(s, "start: ");
  memset(p, '[', (size_t)n);
  memset(p + n, ']', (size_t)n);
  strcpy(p + 2 * n, "\ngoal: {tip: [0.6, -0.2]}\n");
  return s;
}

/* Nesting is capped at 64 levels, with the position of the first level too
 * many: before the cap a 100k-level input took 23 s (quadratic in libyaml's
 * scanner) and reached the loader. */
static void test_depth_cap(void) {
  char buf[1024];
  static const int depths[] = {64, 65, 100000};
  for (size_t i = 0; i < sizeof depths / sizeof *depths; ++i) {
    char *text = nested_task(depths[i]);
    ea_task_t t;
    ea_error_t e = {0};
    const ea_status_t st = ea_task_load_string("deep.yaml", text, strlen(text), NULL, &t, &e);
    if (depths[i] <= 64) {
      /* at the cap the document loads; the loader then rejects the value */
      snprintf(buf, sizeof buf, "%d levels load, 'start' rejected -> %s: %s", depths[i],
               ea_status_name(st), e.msg);
      ea_test_true(st == EA_ERR_INPUT && strstr(e.msg, "deep.yaml:1:8: start must be a mapping"),
                   buf);
    } else {
      /* level 65 is the 64th '[' (column 8 + 63) */
      snprintf(buf, sizeof buf, "%d levels refused at the cap -> %s: %s", depths[i],
               ea_status_name(st), e.msg);
      ea_test_true(st == EA_ERR_PARSE && strstr(e.msg, "deep.yaml:1:71: ") &&
                       strstr(e.msg, "deeper than the limit of 64 levels"),
                   buf);
    }
    free(text);
  }
  /* block style and mappings count too */
  char text[2048] = "start:\n  ";
  for (int i = 0; i < 70; ++i)
    strcat(text, "- ");
  strcat(text, "x\ngoal: {tip: [0.6, -0.2]}\n");
  ea_task_t t;
  ea_error_t e = {0};
  ea_status_t st = ea_task_load_string("deep.yaml", text, strlen(text), NULL, &t, &e);
  snprintf(buf, sizeof buf, "70 block sequences refused -> %s: %s", ea_status_name(st), e.msg);
  ea_test_true(st == EA_ERR_PARSE && strstr(e.msg, "deep.yaml:2:") && strstr(e.msg, "64 levels"),
               buf);
  strcpy(text, "start: ");
  for (int i = 0; i < 70; ++i)
    strcat(text, "{a: ");
  strcat(text, "1");
  for (int i = 0; i < 70; ++i)
    strcat(text, "}");
  strcat(text, "\n");
  st = ea_task_load_string("deep.yaml", text, strlen(text), NULL, &t, &e);
  snprintf(buf, sizeof buf, "70 flow mappings refused -> %s: %s", ea_status_name(st), e.msg);
  ea_test_true(st == EA_ERR_PARSE && strstr(e.msg, "deep.yaml:1:") && strstr(e.msg, "64 levels"),
               buf);
}

/* A FIFO or a directory given as input is refused at once with a message
 * naming the path, by every loader that reads a path here (the arm file:
 * test_arm_file). Without the check a FIFO with no writer blocks the open
 * forever: the alarm turns that into a failure instead of a hang. */
static void test_not_regular(void) {
  char dir[] = "/tmp/ea_test_task_XXXXXX";
  if (!mkdtemp(dir)) {
    ea_test_true(0, "mkdtemp");
    return;
  }
  char fifo[64], buf[1024];
  snprintf(fifo, sizeof fifo, "%s/in.fifo", dir);
  ea_test_true(mkfifo(fifo, 0600) == 0, "mkfifo");
  const char *paths[] = {fifo, dir};
  const char *kinds[] = {"is a FIFO (named pipe), not a regular file",
                         "is a directory, not a regular file"};
  for (int k = 0; k < 2; ++k) {
    alarm(20);
    ea_task_t t;
    ea_error_t e = {0};
    ea_status_t st = ea_task_load(paths[k], NULL, &t, &e);
    snprintf(buf, sizeof buf, "task loader: %s -> %s: %s", k ? "directory" : "FIFO",
             ea_status_name(st), e.msg);
    ea_test_true(st == EA_ERR_IO && strstr(e.msg, paths[k]) && strstr(e.msg, kinds[k]), buf);

    ea_study_t s;
    st = ea_study_load(paths[k], NULL, &s, &e);
    snprintf(buf, sizeof buf, "study spec loader: %s -> %s: %s", k ? "directory" : "FIFO",
             ea_status_name(st), e.msg);
    ea_test_true(st == EA_ERR_IO && strstr(e.msg, paths[k]) && strstr(e.msg, kinds[k]), buf);

    ea_traj_t tr = {0};
    st = ea_traj_read(&tr, paths[k], &e);
    snprintf(buf, sizeof buf, "trajectory reader: %s -> %s: %s", k ? "directory" : "FIFO",
             ea_status_name(st), e.msg);
    ea_test_true(st == EA_ERR_IO && strstr(e.msg, paths[k]) && strstr(e.msg, kinds[k]), buf);
    alarm(0);
  }
  unlink(fifo);
  rmdir(dir);
}

/* Write text (len bytes) to dir/name; returns the path (static buffer). */
static const char *write_file(const char *dir, const char *name, const char *text, size_t len) {
  static char path[256];
  snprintf(path, sizeof path, "%s/%s", dir, name);
  FILE *f = fopen(path, "wb");
  if (f) {
    fwrite(text, 1, len, f);
    fclose(f);
  }
  return path;
}

/* Trajectory reader: metadata masses must be finite and >= 0 (they set the
 * tip load of `simulate` and `figure`; 'inf' was taken as a tip mass), the
 * version a number, and a NUL byte is an error, each with line:column. */
static void test_traj_meta(void) {
  char dir[] = "/tmp/ea_test_traj_XXXXXX", head[1024] = "", body[4096], buf[1024];
  if (!mkdtemp(dir)) {
    ea_test_true(0, "mkdtemp");
    return;
  }
  for (int c = 0; c < EA_TRAJ_NCOL; ++c)
    snprintf(head + strlen(head), sizeof head - strlen(head), c ? ",%s" : "%s",
             ea_traj_column_name(c));
  char rows[512] = "";
  for (int r = 0; r < 2; ++r) {
    for (int c = 0; c < EA_TRAJ_NCOL; ++c)
      snprintf(rows + strlen(rows), sizeof rows - strlen(rows), c ? ",%d" : "%d", c == 0 ? r : 1);
    strcat(rows, "\n");
  }
  static const struct {
    const char *name, *meta, *want;
    ea_status_t st;
  } tcases[] = {
      {"good", "# elasticarm-trajectory 1\n# tip_mass_kg: 0.23\n", "", EA_OK},
      {"tip mass inf", "# elasticarm-trajectory 1\n# tip_mass_kg: inf\n",
       "t.csv:2:16: 'tip_mass_kg': 'inf' is not a finite mass >= 0", EA_ERR_INPUT},
      {"payload negative", "# elasticarm-trajectory 1\n# payload_kg: -0.5\n",
       "t.csv:2:15: 'payload_kg': '-0.5' is not a finite mass >= 0", EA_ERR_INPUT},
      {"payload text", "# elasticarm-trajectory 1\n# payload_kg: 0.1 kg\n",
       "t.csv:2:15: 'payload_kg': '0.1 kg'", EA_ERR_INPUT},
      {"arm hash short", "# elasticarm-trajectory 1\n# arm_hash: 9b1839058\n",
       "t.csv:2:13: 'arm_hash': '9b1839058' is not 16 hexadecimal digits", EA_ERR_INPUT},
      {"arm hash text after", "# elasticarm-trajectory 1\n# arm_hash: 9b183905826f2ad8 x\n",
       "t.csv:2:13: 'arm_hash'", EA_ERR_INPUT},
      {"arm hash good", "# elasticarm-trajectory 1\n# arm_hash: 9B183905826f2ad8\n", "", EA_OK},
      {"version too large", "# elasticarm-trajectory 4294967297\n",
       "t.csv:1:25: trajectory format version '4294967297', expected 1", EA_ERR_INPUT},
  };
  for (size_t i = 0; i < sizeof tcases / sizeof *tcases; ++i) {
    snprintf(body, sizeof body, "%s%s\n%s", tcases[i].meta, head, rows);
    const char *path = write_file(dir, "t.csv", body, strlen(body));
    ea_traj_t tr = {0};
    ea_error_t e = {0};
    const ea_status_t st = ea_traj_read(&tr, path, &e);
    snprintf(buf, sizeof buf, "trajectory %s -> %s: %s", tcases[i].name, ea_status_name(st), e.msg);
    ea_test_true(st == tcases[i].st && (st == EA_OK || strstr(e.msg, tcases[i].want)), buf);
    if (st == EA_OK) {
      if (i == 0)
        ea_test_true(tr.n == 2 && tr.tip_mass_kg == 0.23, "good trajectory: 2 rows, tip mass 0.23");
      else
        ea_test_true(tr.has_arm_hash && tr.arm_hash == 0x9b183905826f2ad8u,
                     "arm hash read (either case of hexadecimal digits)");
      ea_traj_free(&tr);
    }
  }
  /* a NUL byte after the last value of the second data row, then junk: the
     row's text ends at the NUL, so without the check the junk is ignored */
  snprintf(body, sizeof body, "# elasticarm-trajectory 1\n%s\n%s", head, rows);
  size_t len = strlen(body);
  body[len - 1] = '\0';
  memcpy(body + len, "junk\n", 6);
  len += 5;
  const char *path = write_file(dir, "t.csv", body, len);
  ea_traj_t tr = {0};
  ea_error_t e = {0};
  const ea_status_t st = ea_traj_read(&tr, path, &e);
  snprintf(buf, sizeof buf, "trajectory NUL byte -> %s: %s", ea_status_name(st), e.msg);
  ea_test_true(st == EA_ERR_INPUT && strstr(e.msg, "t.csv:4:") && strstr(e.msg, "NUL byte"), buf);
  unlink(path);
  rmdir(dir);
}

/* A trajectory read into a struct that already holds one replaces it: the
 * heap in use after read, read again, free is what it was before, to glibc's
 * bookkeeping (mallinfo2 counts chunks cached for reuse as in use: measured
 * 640 bytes), far below the 72 kB of samples a leaked read keeps (under ASan
 * the leak checker sees the leak too). */
static void test_traj_reuse(void) {
  char dir[] = "/tmp/ea_test_traj_reuse_XXXXXX", path[300];
  if (!mkdtemp(dir)) {
    ea_test_true(0, "mkdtemp");
    return;
  }
  snprintf(path, sizeof path, "%s/t.csv", dir);
  ea_traj_t w = {0};
  ea_error_t e = {0};
  int ok = ea_traj_alloc(&w, 500) == EA_OK;
  for (int i = 0; ok && i < w.n; ++i) {
    EA_TRAJ_AT(&w, i, EA_TRAJ_t) = 0.001 * i;
    EA_TRAJ_AT(&w, i, EA_TRAJ_cable_length) = 0.4;
    EA_TRAJ_AT(&w, i, EA_TRAJ_cable_angle) = -0.5;
    EA_TRAJ_AT(&w, i, EA_TRAJ_tension) = 1.0;
  }
  ok = ok && ea_traj_write(&w, path, &e) == EA_OK;
  ea_traj_free(&w);
  ea_traj_t tr = {0};
  ok = ok && ea_traj_read(&tr, path, &e) == EA_OK; /* warm-up: stdio, locale */
  ea_traj_free(&tr);
  struct mallinfo2 m0 = mallinfo2();
  const size_t before = m0.uordblks + m0.hblkhd;
  ok = ok && ea_traj_read(&tr, path, &e) == EA_OK && ea_traj_read(&tr, path, &e) == EA_OK &&
       tr.n == 500;
  ea_traj_free(&tr);
  struct mallinfo2 m1 = mallinfo2();
  const size_t after = m1.uordblks + m1.hblkhd;
  printf("heap in use before %zu, after two reads into one struct and a free %zu bytes (%s)\n",
         before, after, e.msg);
  ea_test_true(ok && after < before + 4096,
               "trajectory read into a used struct: its 72 kB of samples not leaked (4 kB)");
  unlink(path);
  rmdir(dir);
}

/* dynamics.robust.from_calibration: the corners at +-k standard errors of a calibration
 * report's EI and hand mass (docs/task-format.md), by hand: EI 0.8 +- 0.004 N m^2, hand
 * 0.25 +- 0.001 kg, payload 0.05 kg, k = 2: half-widths 2 0.004 / 0.8 = 0.01 and
 * 2 0.001 / 0.30; and the errors, each at its file:line:column. */
static void test_robust_calibration(void) {
  const char *src = getenv("EA_SOURCE_DIR");
  char dir[] = "/tmp/ea_robust_XXXXXX", buf[2048], arm_src[1024];
  if (!src || !mkdtemp(dir)) {
    ea_test_true(0, "robust from_calibration: EA_SOURCE_DIR and a temporary folder");
    return;
  }
  snprintf(arm_src, sizeof arm_src, "%s/data/elasticarm.yaml", src);
  for (int a = 0; a < 2; ++a) { /* arm.yaml: the report's values; arm2.yaml: EI 0.7 */
    FILE *in = fopen(arm_src, "r");
    char line[1024], text[16384] = "";
    size_t n = 0;
    while (in && fgets(line, sizeof line, in)) {
      if (strstr(line, "EI_Nm2:"))
        snprintf(line, sizeof line, "  EI_Nm2: %s\n", a ? "0.7" : "0.8");
      else if (strstr(line, "mass_kg:") && strstr(line, "m_h"))
        snprintf(line, sizeof line, "  mass_kg: 0.25\n");
      n += (size_t)snprintf(text + n, sizeof text - n, "%s", line);
    }
    if (in) fclose(in);
    write_file(dir, a ? "arm2.yaml" : "arm.yaml", text, n);
  }
  static const char *const report =
      "{\n  \"elasticarm_calibration\": \"1\",\n  \"status\": \"EA_OK\",\n"
      "  \"parameters\": [\n"
      "    {\"name\": \"EI\", \"state\": \"fitted\", \"estimate\": 0.8, \"standard_error\": "
      "0.004},\n"
      "    {\"name\": \"m_hand\", \"state\": \"%s\", \"estimate\": 0.25, \"standard_error\": %s}\n"
      "  ]\n}\n";
  snprintf(buf, sizeof buf, report, "fitted", "0.001");
  write_file(dir, "report.json", buf, strlen(buf));
  snprintf(buf, sizeof buf, report, "not_identifiable", "null");
  write_file(dir, "unident.json", buf, strlen(buf));
  write_file(dir, "broken.json", "{\n  \"status\": \"EA_OK\",\n  \"parameters\": [\n", 41);
  static const struct {
    const char *arm, *report, *more, *want;
  } c[] = {
      {"arm.yaml", "report.json", "k: 2", NULL},
      {"arm.yaml", "missing.json", "k: 2", "t.yaml:12:23: dynamics.robust.from_calibration"},
      {"arm.yaml", "broken.json", "k: 2", "broken.json:4:"},
      {"arm.yaml", "unident.json", "k: 2", "unident.json:6:"},
      {"arm2.yaml", "report.json", "k: 2", "t.yaml:12:23: dynamics.robust.from_calibration"},
      {"arm.yaml", "report.json", "EI: 0.1", "give either 'from_calibration'"},
      {"arm.yaml", "report.json", "k: 20", "t.yaml:13:8: key 'k'"},
  };
  for (size_t i = 0; i < sizeof c / sizeof *c; ++i) {
    char task[1024];
    const int n = snprintf(task, sizeof task,
                           "name: r\narm_file: %s\npayload_kg: 0.05\nstart:\n  tip: [0.3, -0.2]\n"
                           "goal:\n  tip: [0.6, -0.2]\npath: line\ndynamics:\n  modes: 1\n"
                           "  robust:\n    from_calibration: %s\n    %s\n",
                           c[i].arm, c[i].report, c[i].more);
    const char *path = write_file(dir, "t.yaml", task, (size_t)n);
    ea_task_t t;
    ea_error_t e = {0};
    const ea_status_t st = ea_task_load(path, NULL, &t, &e);
    if (!c[i].want) {
      ea_test_true(st == EA_OK, "robust from_calibration: the task loads");
      if (st == EA_OK) {
        ea_test_rel(t.dynamics.robust_EI, 2 * 0.004 / 0.8, 1e-12,
                    "robust EI half-width: k se / EI");
        ea_test_rel(t.dynamics.robust_tip_mass, 2 * 0.001 / (0.25 + 0.05), 1e-12,
                    "robust tip-mass half-width: k se / (hand + payload)");
      } else {
        printf("  %s\n", e.msg);
      }
    } else {
      snprintf(buf, sizeof buf, "robust from_calibration: %s with %s, '%s': error naming '%s' (%s)",
               c[i].report, c[i].arm, c[i].more, c[i].want, e.msg);
      ea_test_true(st != EA_OK && strstr(e.msg, c[i].want), buf);
    }
  }
  static const char *const names[] = {"arm.yaml",     "arm2.yaml",   "report.json",
                                      "unident.json", "broken.json", "t.yaml"};
  for (size_t i = 0; i < sizeof names / sizeof *names; ++i) {
    snprintf(buf, sizeof buf, "%s/%s", dir, names[i]);
    unlink(buf);
  }
  rmdir(dir);
}

int main(void) {
  char buf[1024];
  test_robust_calibration();
  test_traj_reuse();
  test_depth_cap();
  test_traj_meta();
  test_not_regular();
  for (size_t i = 0; i < sizeof cases / sizeof *cases; ++i) {
    const ea_case_t *c = &cases[i];
    ea_task_t t;
    ea_error_t e = {0};
    ea_status_t st = ea_task_load_string("bad.yaml", c->yaml, strlen(c->yaml), NULL, &t, &e);
    const int ok = st == c->status && strstr(e.msg, c->where) && strstr(e.msg, c->key);
    snprintf(buf, sizeof buf, "%s -> %s: %s", c->name, ea_status_name(st), e.msg);
    ea_test_true(ok, buf);
  }

  /* The examples load (or are rejected as designed). */
  const char *src = getenv("EA_SOURCE_DIR");
  if (!src) src = ".";
  static const struct {
    const char *file;
    ea_status_t st;
  } ex[] = {{"paper-line.yaml", EA_OK},
            {"pick-place-3d.yaml", EA_OK},
            {"polyline-effort.yaml", EA_OK},
            {"infeasible-line.yaml", EA_OK}, /* feasible ends; the planner rejects it */
            {"infeasible-goal.yaml", EA_ERR_INFEASIBLE}};
  for (size_t i = 0; i < sizeof ex / sizeof *ex; ++i) {
    char path[1024];
    snprintf(path, sizeof path, "%s/problems/examples/%s", src, ex[i].file);
    ea_task_t t;
    ea_error_t e = {0};
    ea_status_t st = ea_task_load(path, NULL, &t, &e);
    snprintf(buf, sizeof buf, "example %s -> %s (%s)", ex[i].file, ea_status_name(st), e.msg);
    ea_test_true(st == ex[i].st, buf);
    if (!strcmp(ex[i].file, "paper-line.yaml") && st == EA_OK) {
      /* eq. 18-20 at beta = 0 and 1; payload factor 0 (eq. 17) */
      ea_test_abs(t.payload_kg, 0.0, 0.0, "paper-line payload 0 kg");
      ea_test_rel(t.start.cable_length, hypot(0.3 - 0.098, -0.2 + 0.006), 1e-15, "L_c(0) eq. 19");
      ea_test_rel(t.goal.cable_angle, atan2(-0.2 + 0.006, 0.6 - 0.098), 1e-15, "alpha(1) eq. 20");
      ea_test_true(t.path == EA_TASK_PATH_LINE && t.knots == 100 && !t.base_moves,
                   "paper-line: line, 100 knots, planar");
    }
    if (!strcmp(ex[i].file, "pick-place-3d.yaml") && st == EA_OK) {
      ea_test_rel(t.goal.base_angle, atan2(0.55, 0.0), 1e-15, "3-D goal base angle atan2(y, x)");
      ea_test_rel(t.goal.reach, 0.55, 1e-15, "3-D goal reach hypot(x, y)");
      ea_test_true(t.base_moves, "pick-place: the base moves");
    }
    if (!strcmp(ex[i].file, "infeasible-goal.yaml"))
      ea_test_true(strstr(e.msg, "infeasible-goal.yaml:9:3: goal: outside the workspace") != NULL,
                   "infeasible goal names file:line:col and 'goal'");
  }

  /* Programmatic tasks go through the same checks. */
  ea_task_t t;
  ea_task_init(&t, NULL);
  t.start = ea_task_point_planar(0.3, -0.2, 0.0);
  t.goal = ea_task_point_actuators(0.45, -0.3, 0.5);
  ea_error_t e = {0};
  ea_test_true(ea_task_check(&t, &e) == EA_OK && t.base_moves, "C task with actuator goal");
  t.limits.base_speed_max = NAN;
  ea_test_true(ea_task_check(&t, &e) == EA_ERR_INPUT && strstr(e.msg, "base_speed_max"),
               "C task: NaN limit rejected");
  return ea_test_summary("test_task");
}
