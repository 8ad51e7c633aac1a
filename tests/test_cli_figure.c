/* The figures as the CLI draws them: every figure command writes a non-empty file,
 * and the script it gives gnuplot (kept by a wrapper named gnuplot first on PATH,
 * which then runs the real one) has the properties the figures promise:
 * - Fig. 3: each workspace region is a closed polygon (first point = last point)
 *   with its inner edge on the circle L_c = inner about the cable root, and its
 *   area (shoelace) is the area `workspace --json` computes by quadrature;
 * - the torque map uses the viridis palette and hatches exactly the cells whose
 *   shoulder torque (from its own CSV) is past the arm file's limit;
 * - simulate: the tip-path window is never a strip (trajectory at rest);
 * - plan figures: one unit per y axis, keys outside the panels, the workspace
 *   region closed, the active speed limit drawn; a plan with dynamics shows the
 *   summary's modal deviation and the model's frequencies along the plan, which
 *   match an independent FE modal solve (`frequencies`) at the first knot; a
 *   min_vibration plan draws its FE frequency model the same way;
 * - study figures: every combination drawn (15 curves, 30 workspace regions, more
 *   than the 8 and 12 of before), each in its own style, labels with units. */
#include "ea_test.h"
#include "ea_test_cli.h"

#include <dirent.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#define DIR_OUT "test_cli_figure.d"
#define DIR_GP "test_cli_figure.d/gp"

static const char *src;
static char *scripts[64];
static int n_scripts;

static long file_size(const char *path) {
  struct stat sb;
  return stat(path, &sb) == 0 ? (long)sb.st_size : -1;
}

static char *slurp_alloc(const char *path) {
  FILE *fp = fopen(path, "rb");
  if (!fp) return NULL;
  fseek(fp, 0, SEEK_END);
  const long n = ftell(fp);
  fseek(fp, 0, SEEK_SET);
  char *b = n >= 0 ? malloc((size_t)n + 1) : NULL;
  if (b) b[fread(b, 1, (size_t)n, fp)] = '\0';
  fclose(fp);
  return b;
}

static void clear_scripts(void) {
  for (int i = 0; i < n_scripts; ++i)
    free(scripts[i]);
  n_scripts = 0;
  DIR *d = opendir(DIR_GP);
  if (!d) return;
  struct dirent *e;
  char p[600];
  while ((e = readdir(d)))
    if (e->d_name[0] != '.') {
      snprintf(p, sizeof p, "%s/%s", DIR_GP, e->d_name);
      remove(p);
    }
  closedir(d);
}

/* Run the CLI; the gnuplot scripts it ran, in order, into scripts[]. */
static int capture(const char *args) {
  clear_scripts();
  const int rc = run(args);
  for (int i = 0; i < 64; ++i) {
    char p[600];
    snprintf(p, sizeof p, "%s/%03d.gp", DIR_GP, i);
    char *s = slurp_alloc(p);
    if (!s) break;
    scripts[n_scripts++] = s;
  }
  return rc;
}

/* The script whose output is the figure named name (its temporary starts with it). */
static const char *script_for(const char *name) {
  for (int i = 0; i < n_scripts; ++i)
    if (strstr(scripts[i], name)) return scripts[i];
  return "";
}

/* Rows of two numbers of data block $name (blank lines skipped); returns the count. */
static int block(const char *s, const char *name, double (*xy)[2], int max) {
  char head[80];
  snprintf(head, sizeof head, "$%s << EOD\n", name);
  const char *p = strstr(s, head);
  if (!p) return -1;
  p += strlen(head);
  int n = 0;
  while (*p && strncmp(p, "EOD\n", 4)) {
    double a, b;
    if (*p != '\n' && sscanf(p, "%lf %lf", &a, &b) == 2 && n < max) {
      xy[n][0] = a;
      xy[n][1] = b;
      ++n;
    }
    p = strchr(p, '\n');
    if (!p) break;
    ++p;
  }
  return n;
}

/* The text of the first line of block $name after its header, and of its last. */
static int block_closed(const char *s, const char *name) {
  char head[80];
  snprintf(head, sizeof head, "$%s << EOD\n", name);
  const char *p = strstr(s, head);
  if (!p) return 0;
  p += strlen(head);
  const char *end = strstr(p, "EOD\n");
  if (!end || end == p) return 0;
  const char *first_end = strchr(p, '\n');
  const char *last = end - 1; /* the '\n' ending the last row */
  const char *ls = last;
  while (ls > p && ls[-1] != '\n')
    --ls;
  return (size_t)(first_end - p) == (size_t)(last - ls) && !strncmp(p, ls, (size_t)(last - ls));
}

static double shoelace(double (*xy)[2], int n) {
  double a = 0;
  for (int i = 0; i + 1 < n; ++i)
    a += xy[i][0] * xy[i + 1][1] - xy[i + 1][0] * xy[i][1];
  return 0.5 * fabs(a);
}

/* Count of occurrences of needle in s. */
static int count(const char *s, const char *needle) {
  int n = 0;
  for (const char *p = strstr(s, needle); p; p = strstr(p + 1, needle))
    ++n;
  return n;
}

/* The wrapper: gnuplot first on PATH keeps each script as DIR_GP/NNN.gp, then runs
 * the real gnuplot on it. 0 or 1 (said why). */
static int install_wrapper(void) {
  const char *path = getenv("PATH");
  char real[1024] = "";
  if (path) {
    char *copy = strdup(path);
    for (char *tok = strtok(copy, ":"); tok && !real[0]; tok = strtok(NULL, ":")) {
      char c[1024];
      snprintf(c, sizeof c, "%s/gnuplot", tok);
      if (access(c, X_OK) == 0) snprintf(real, sizeof real, "%s", c);
    }
    free(copy);
  }
  if (!real[0]) {
    printf("no gnuplot on PATH\n");
    return 1;
  }
  mkdir(DIR_OUT, 0777);
  mkdir(DIR_OUT "/bin", 0777);
  mkdir(DIR_GP, 0777);
  FILE *fp = fopen(DIR_OUT "/bin/gnuplot", "w");
  if (!fp) {
    printf("cannot write %s/bin/gnuplot\n", DIR_OUT);
    return 1;
  }
  fprintf(fp,
          "#!/bin/sh\nd=\"$EA_TEST_GP_DIR\"\nn=$(ls \"$d\" | wc -l)\nf=\"$d/$(printf %%03d "
          "\"$n\").gp\"\ncat > \"$f\"\nexec \"%s\" \"$@\" < \"$f\"\n",
          real);
  fclose(fp);
  chmod(DIR_OUT "/bin/gnuplot", 0755);
  char cwd[1024], np[4096];
  if (!getcwd(cwd, sizeof cwd)) return 1;
  snprintf(np, sizeof np, "%s/%s/bin:%s", cwd, DIR_OUT, path ? path : "");
  setenv("PATH", np, 1);
  char gd[1100];
  snprintf(gd, sizeof gd, "%s/%s", cwd, DIR_GP);
  setenv("EA_TEST_GP_DIR", gd, 1);
  return 0;
}

/* ---- Fig. 3 ------------------------------------------------------------------ */

/* workspace --no-limits --points N --figure: the figure's region polygons (their
 * shoelace areas into poly[]) against the table's areas (area[]); checks the
 * polygons are closed and hold the N inner-edge points. */
static void workspace_areas(int points, double area[4], double poly[4]) {
  char args[200];
  snprintf(args, sizeof args, "workspace --no-limits --points %d --figure %s/ws.svg", points,
           DIR_OUT);
  remove(DIR_OUT "/ws.svg");
  const int rc = capture(args);
  /* the areas from its table: "gamma area_m2 ..." then one row per payload */
  double inner = NAN;
  const char *row = strstr(out, "area_m2");
  if (sscanf(out, "region: cable angle %*g to %*g deg, inner cable %lf m", &inner) != 1)
    inner = NAN;
  for (int g = 0; g < 4; ++g) {
    area[g] = poly[g] = NAN;
    if (row) row = strchr(row, '\n');
    if (row && sscanf(++row, "%*g %lf", &area[g]) != 1) area[g] = NAN;
  }
  ea_test_true(rc == 0 && file_size(DIR_OUT "/ws.svg") > 1000 && n_scripts == 1,
               "workspace --figure: a non-empty figure, one gnuplot script");
  const char *s = script_for("ws.svg");
  static double xy[2000][2];
  for (int g = 0; g < 4; ++g) {
    char name[32], what[200];
    snprintf(name, sizeof name, "region%d", g);
    const int n = block(s, name, xy, 2000);
    snprintf(what, sizeof what,
             "Fig. 3 (%d points) payload %d: the region is a closed polygon (first row = last)",
             points, g);
    ea_test_true(n > 2 * points && block_closed(s, name), what);
    /* the inner edge: rows on the circle of radius inner about the cable root
     * (0.098, -0.006) m, Table 1 in data/elasticarm.yaml */
    int on_inner = 0;
    for (int k = 0; k < n; ++k)
      on_inner += fabs(hypot(xy[k][0] - 0.098, xy[k][1] + 0.006) - inner) < 1e-8;
    snprintf(what, sizeof what, "Fig. 3 (%d points) payload %d: %d rows on the inner edge", points,
             g, points);
    ea_test_true(on_inner == points, what);
    poly[g] = shoelace(xy, n);
  }
}

static void test_workspace(void) {
  /* The region's area (shoelace of the figure's polygon) against the workspace
   * area by quadrature (workspace_region.c), a convergence study: the polygon has
   * chords for the edges' arcs, an error of order dalpha^2 (1 deg apart at 71
   * points: measured 4.4e-5 to 6.1e-5 relative; tolerance 1.5e-4), which falls by
   * 4 when the spacing halves (141 points: measured ratios 3.9999 to 4.0001; accepted
   * 3.8 to 4.2). */
  double a71[4], p71[4], a141[4], p141[4];
  workspace_areas(71, a71, p71);
  workspace_areas(141, a141, p141);
  for (int g = 0; g < 4; ++g) {
    char what[200];
    snprintf(what, sizeof what, "Fig. 3 payload %d: region area (shoelace, 71 points) = area", g);
    ea_test_rel(p71[g], a71[g], 1.5e-4, what);
    const double ratio = (a71[g] - p71[g]) / (a141[g] - p141[g]);
    printf("  payload %d: polygon area error %.3g (71 points), %.3g (141), ratio %.4f\n", g,
           a71[g] - p71[g], a141[g] - p141[g], ratio);
    snprintf(what, sizeof what, "Fig. 3 payload %d: the polygon's area error is O(dalpha^2)", g);
    ea_test_true(ratio > 3.8 && ratio < 4.2, what);
  }
  /* With the limits, the outer-edge points past one are marked. */
  const int rc = capture("workspace --figure " DIR_OUT "/ws.svg");
  const char *s = script_for("ws.svg");
  ea_test_true(rc == 0 && strstr(s, "$past2 << EOD") && strstr(s, "$past3 << EOD") &&
                   !strstr(s, "$past0 << EOD") && strstr(s, "outer edge past an arm limit"),
               "Fig. 3 with limits: the outer edge past the torque limit marked for gamma = 0.25, "
               "0.5 only (the torque limit binds there, `workspace --json` region_bounds)");
}

/* ---- torque map --------------------------------------------------------------- */

/* Cells of a torque-map CSV with a statics solution and |torque| > limit. */
static int csv_cells_past(const char *csv, double limit, double (*cells)[2], int max) {
  FILE *fp = fopen(csv, "r");
  if (!fp) return -1;
  char line[1024];
  int n = 0;
  if (!fgets(line, sizeof line, fp)) {
    fclose(fp);
    return -1;
  }
  while (fgets(line, sizeof line, fp)) {
    double v[9];
    char status[32];
    if (sscanf(line, "%lf,%lf,%lf,%lf,%lf,%lf,%lf,%lf,%lf,%31[^,]", &v[0], &v[1], &v[2], &v[3],
               &v[4], &v[5], &v[6], &v[7], &v[8], status) != 10)
      continue;
    if (!strcmp(status, "EA_OK") && fabs(v[7]) > limit && n < max) {
      cells[n][0] = v[0];
      cells[n][1] = v[1] * 180.0 / M_PI;
      ++n;
    }
  }
  fclose(fp);
  return n;
}

static void test_torque_map(void) {
  /* an arm file with a shoulder torque limit of 2 N m (the data file's is 4) */
  char arm[600], *text;
  snprintf(arm, sizeof arm, "%s/data/elasticarm.yaml", src);
  text = slurp_alloc(arm);
  char *at = text ? strstr(text, "torque_max_Nm: 4.0") : NULL;
  ea_test_true(at != NULL, "the arm file has torque_max_Nm: 4.0");
  if (!at) {
    free(text);
    return;
  }
  memcpy(at, "torque_max_Nm: 2.0", 18);
  FILE *fp = fopen(DIR_OUT "/arm2.yaml", "w");
  fputs(text, fp);
  fclose(fp);
  free(text);
  const char *fig = DIR_OUT "/tm.png";
  remove(fig);
  int rc = capture("torque-map --arm " DIR_OUT "/arm2.yaml --csv " DIR_OUT
                   "/tm.csv --figure " DIR_OUT "/tm.png");
  const char *s = script_for("tm.png");
  ea_test_true(rc == 0 && file_size(fig) > 1000, "torque-map --figure: a non-empty PNG");
  ea_test_true(strstr(s, "set palette defined (0 '#440154'") && strstr(s, "8 '#fde725')") &&
                   !strstr(s, "set palette rgb"),
               "torque map: the viridis palette, no rainbow");
  static double want[4000][2], got[4000][2];
  const int nw = csv_cells_past(DIR_OUT "/tm.csv", 2.0, want, 4000);
  const int ng = block(s, "torque", got, 4000);
  printf("  cells past |torque| = 2 N m in the CSV: %d, hatched: %d\n", nw, ng);
  int match = nw == ng && nw > 20;
  for (int i = 0; match && i < nw; ++i)
    match = fabs(want[i][0] - got[i][0]) < 1e-9 && fabs(want[i][1] - got[i][1]) < 1e-6;
  ea_test_true(match, "torque map: the hatched cells are exactly those past the arm file's "
                      "torque limit (from the map's own CSV)");
  ea_test_true(strstr(s, "past the shoulder torque limit (|EI {/Symbol k}_0| > 2 N m)") &&
                   strstr(s, "fs transparent pattern"),
               "torque map: the key says what the hatching means, with the limit");
  /* the data file's arm: no cell past 4 N m at payload 0, the title says so */
  rc = capture("torque-map --csv " DIR_OUT "/tm0.csv --figure " DIR_OUT "/tm0.svg");
  s = script_for("tm0.svg");
  ea_test_true(rc == 0 && csv_cells_past(DIR_OUT "/tm0.csv", 4.0, want, 4000) == 0 &&
                   block(s, "torque", got, 4000) == 0 && strstr(s, "(no cell past it)"),
               "torque map, payload 0: no cell past 4 N m, none hatched, the title says so");
}

/* ---- simulate ----------------------------------------------------------------- */

static void test_simulate(void) {
  FILE *fp = fopen(DIR_OUT "/atrest.csv", "w");
  fputs("t_s,cable_length_m,cable_angle_rad\n0,0.4,-0.5\n0.5,0.4,-0.5\n1,0.4,-0.5\n", fp);
  fclose(fp);
  const char *fig = DIR_OUT "/sim.svg";
  remove(fig);
  const int rc =
      capture("simulate " DIR_OUT "/atrest.csv --settle 0.2 --figure " DIR_OUT "/sim.svg");
  const char *s = script_for("sim.svg");
  double x0 = NAN, x1 = NAN, y0 = NAN, y1 = NAN;
  const char *p = strstr(s, "set xrange [");
  if (p) sscanf(p, "set xrange [%lf:%lf]", &x0, &x1);
  p = strstr(s, "set yrange [");
  if (p) sscanf(p, "set yrange [%lf:%lf]", &y0, &y1);
  printf("  tip-path window %.4g x %.4g m\n", x1 - x0, y1 - y0);
  ea_test_true(rc == 0 && file_size(fig) > 1000, "simulate --figure: a non-empty figure");
  ea_test_true((y1 - y0) >= 0.4 * (x1 - x0) * (1 - 1e-6) &&
                   (x1 - x0) >= 0.4 * (y1 - y0) * (1 - 1e-6) && fmax(x1 - x0, y1 - y0) >= 0.01 &&
                   strstr(s, "set size ratio -1"),
               "simulate figure at rest: the equal-scale tip-path window at least 0.4 as tall as "
               "wide (and as wide as tall), at least 10 mm (no strip)");
  /* the tip inside it */
  static double xy[5000][2];
  const int n = block(s, "sim", xy, 5000); /* columns t, x */
  (void)n;
  const char *q = strstr(s, "$sim << EOD\n");
  double t, x, y;
  ea_test_true(q && sscanf(q + 12, "%lf %lf %lf", &t, &x, &y) == 3 && x > x0 && x < x1 && y > y0 &&
                   y < y1,
               "simulate figure: the tip inside the window");
}

/* ---- plans ------------------------------------------------------------------- */

/* Every y label has exactly one unit "[...]". */
static int one_unit_per_axis(const char *s, int *labels) {
  int ok = 1;
  *labels = 0;
  for (const char *p = strstr(s, "set ylabel '"); p; p = strstr(p + 1, "set ylabel '")) {
    const char *e = strchr(p + 12, '\'');
    if (!e) return 0;
    int open = 0, close = 0;
    for (const char *c = p + 12; c < e; ++c) {
      open += *c == '[';
      close += *c == ']';
    }
    ok &= open == 1 && close == 1;
    ++*labels;
  }
  return ok;
}

/* Every "set key" is outside the graph (it never hides a curve). */
static int keys_outside(const char *s) {
  int n = 0;
  for (const char *p = strstr(s, "set key "); p; p = strstr(p + 1, "set key ")) {
    const char *e = strchr(p, '\n');
    char line[200];
    snprintf(line, sizeof line, "%.*s", e ? (int)(e - p) : 100, p);
    if (strstr(line, "box opaque") && !strstr(line, "outside") && !strstr(line, "below") &&
        strcmp(line, "set key box opaque"))
      return 0;
    ++n;
  }
  return n > 1;
}

/* The first data row of $hist, n columns. */
static int hist_row0(const char *s, double *v, int n) {
  const char *p = strstr(s, "$hist << EOD\n");
  if (!p) return 0;
  p += 13;
  for (int i = 0; i < n; ++i) {
    char *e;
    v[i] = strtod(p, &e);
    if (e == p) return i;
    p = e;
  }
  return n;
}

static int columns_row0(const char *s) {
  const char *p = strstr(s, "$hist << EOD\n");
  if (!p) return 0;
  p += 13;
  const char *e = strchr(p, '\n');
  int n = 0, in = 0;
  for (; p < e; ++p) {
    if (*p != ' ' && !in) ++n;
    in = *p != ' ';
  }
  return n;
}

/* f_i at (L_c, alpha) from an FE modal solve (`frequencies`). */
static double fe_frequency(double L, double alpha, int mode) {
  char args[300];
  snprintf(args, sizeof args, "frequencies --cable-length %.12g --cable-angle-deg %.12g --json", L,
           alpha * 180.0 / M_PI);
  if (run(args) != 0) return NAN;
  return json_list("frequencies_Hz", mode);
}

static void test_plans(void) {
  char args[1400];
  /* the paper's line, min_time: the cable speed limit is active */
  snprintf(args, sizeof args,
           "plan %s/problems/examples/paper-line.yaml -o %s/pl.csv --figure %s/pl.svg --quiet", src,
           DIR_OUT, DIR_OUT);
  remove(DIR_OUT "/pl.svg");
  int rc = capture(args);
  const char *s = script_for("pl.svg");
  int labels = 0;
  ea_test_true(rc == 0 && file_size(DIR_OUT "/pl.svg") > 1000, "plan --figure: non-empty figure");
  ea_test_true(one_unit_per_axis(s, &labels) && labels == 9,
               "plan figure: 9 panels, every y axis with exactly one unit");
  ea_test_true(keys_outside(s), "plan figure: every key outside its panel");
  ea_test_true(block_closed(s, "region"), "plan figure: the workspace region closed");
  ea_test_true(strstr(s, "0.25 w l dt 2") && strstr(s, "+v_{max}"),
               "plan figure: the active cable speed limit (0.25 m/s) drawn in the speed panel");
  /* a plan with dynamics: the summary's modal deviation and the reduced model's
   * frequencies along the plan */
  snprintf(args, sizeof args,
           "plan %s/problems/examples/paper-line-rest.yaml -o %s/rest.csv --figure %s/rest.svg "
           "--quiet --json",
           src, DIR_OUT, DIR_OUT);
  rc = capture(args);
  const double dev = json_num("max_modal_deviation_m");
  s = script_for("rest.svg");
  char want[120];
  snprintf(want, sizeof want, "modal tip deviation during the motion: up to %.3g mm", 1e3 * dev);
  printf("  summary: max_modal_deviation_m %.6g\n", dev);
  ea_test_true(rc == 0 && isfinite(dev) && strstr(s, want) != NULL,
               "plan with dynamics: the figure shows the summary's modal tip deviation");
  double v[21];
  const int nc = columns_row0(s);
  ea_test_true(nc == 18 + 2 && hist_row0(s, v, nc) == nc && strstr(s, "t 'f_2'"),
               "plan with dynamics: two modal frequencies along the plan");
  if (nc == 20) {
    /* Reduced-model table (14 x 10 grid, bicubic) against an FE solve at the first
     * knot: measured 3.6e-5 (f1), 6.7e-6 (f2); tolerance 2e-4. */
    ea_test_rel(v[18], fe_frequency(v[1], v[2], 0), 2e-4,
                "plan with dynamics: f1 at the first knot = FE modal solve");
    ea_test_rel(v[19], fe_frequency(v[1], v[2], 1), 2e-4,
                "plan with dynamics: f2 at the first knot = FE modal solve");
  }
  /* min_vibration with a frequency limit: the FE frequency model along the plan */
  snprintf(args, sizeof args,
           "plan %s/problems/examples/paper-line-smooth.yaml -o %s/smooth.csv --figure "
           "%s/smooth.svg --quiet",
           src, DIR_OUT, DIR_OUT);
  rc = capture(args);
  s = script_for("smooth.svg");
  const int nc2 = columns_row0(s);
  ea_test_true(rc == 0 && file_size(DIR_OUT "/smooth.svg") > 1000 && nc2 == 19 &&
                   strstr(s, "0.9 w l dt 2") && strstr(s, "f_{1,min}"),
               "min_vibration plan: drawn, with f1 along the plan and its 0.9 Hz limit");
  if (nc2 == 19 && hist_row0(s, v, 19) == 19) {
    /* the frequency model's bicubic spline against an FE solve at the first knot:
     * measured 4.1e-4; tolerance 1e-3 */
    ea_test_rel(v[18], fe_frequency(v[1], v[2], 0), 1e-3,
                "min_vibration plan: f1 at the first knot = FE modal solve");
  }
  /* a trajectory file through `figure`: the same figure with the arm file's limits */
  snprintf(args, sizeof args, "figure %s/pl.csv -o %s/traj.pdf", DIR_OUT, DIR_OUT);
  rc = capture(args);
  s = script_for("traj.pdf");
  ea_test_true(rc == 0 && file_size(DIR_OUT "/traj.pdf") > 1000 && one_unit_per_axis(s, &labels) &&
                   labels == 9,
               "figure TRAJ.csv -o .pdf: non-empty, one unit per axis");
}

/* ---- studies ------------------------------------------------------------------ */

static void test_study(void) {
  FILE *fp = fopen(DIR_OUT "/spec.yaml", "w");
  fprintf(fp,
          "name: figtest\narm_file: %s/data/elasticarm.yaml\ngrid:\n"
          "  payload_factor: [0, 0.25]\n  EI_Nm2: [0.6, 0.7, 0.8]\n"
          "  length_m: [0.85, 0.88, 0.91, 0.94, 0.97]\nmetrics:\n  workspace: {points: 21}\n"
          "  torque_map:\n    cable_lengths_m: 0.3:0.1:0.6\n    cable_angles_deg: -40:20:0\n",
          src);
  fclose(fp);
  const int rc = capture("study " DIR_OUT "/spec.yaml -o " DIR_OUT "/st.csv --figures " DIR_OUT
                         "/st --no-checkpoint --quiet --threads 2");
  ea_test_true(rc == 0 && file_size(DIR_OUT "/st-workspace.svg") > 1000 &&
                   file_size(DIR_OUT "/st-torque_min.svg") > 1000 && n_scripts == 9,
               "study --figures: 9 non-empty figures (workspace, 4 region metrics, 4 map metrics)");
  /* the workspace figure: all 30 regions, each closed */
  const char *s = script_for("st-workspace.svg");
  int closed = 0;
  for (int c = 0; c < 30; ++c) {
    char name[16];
    snprintf(name, sizeof name, "ws%d", c);
    closed += block_closed(s, name);
  }
  printf("  workspace figure: %d closed regions\n", closed);
  ea_test_true(closed == 30, "study workspace figure: every one of the 30 cases, region closed");
  /* a metric figure: 15 combinations (EI x L) against the payload factor */
  s = script_for("st-torque_min.svg");
  const char *plot = strstr(s, "\nplot ");
  int curves = 0, distinct = 1;
  char styles[64][64];
  for (const char *p = plot ? strstr(plot, " w lp lw 2 ") : NULL; p && curves < 64;
       p = strstr(p + 1, " w lp lw 2 ")) {
    const char *t = strstr(p, " t '");
    snprintf(styles[curves], sizeof styles[0], "%.*s", t ? (int)(t - p) : 40, p);
    for (int j = 0; j < curves; ++j)
      distinct &= strcmp(styles[j], styles[curves]) != 0;
    ++curves;
  }
  printf("  torque_min figure: %d curves\n", curves);
  ea_test_true(curves == 15 && distinct, "study metric figure: all 15 combinations, 15 styles");
  ea_test_true(strstr(s, "t 'EI = 0.6 N m^2, L = 0.85 m'") && !strstr(s, "EI\\_Nm2") &&
                   !strstr(s, "EI_Nm2") && !strstr(s, "length\\_m") &&
                   strstr(s, "set xlabel 'payload factor {/Symbol g} [-]'") &&
                   strstr(s, "set ylabel 'lowest shoulder torque over the map [N m]'"),
               "study metric figure: labels and axes in words with units, no raw column names");
  ea_test_true(count(s, "lc rgb '#0072b2'") == 2, "study metric figure: a colour used twice at "
                                                  "most among 15 curves (8 colours x dash types)");
}

int main(void) {
  char arm[600];
  if (cli_setup(arm, sizeof arm)) return 1;
  src = getenv("EA_SOURCE_DIR");
  if (install_wrapper()) return 1;
  /* the reduced model's table (plans with dynamics) in a cache of the test's own */
  setenv("EA_CACHE_DIR", DIR_OUT "/cache", 1);
  test_workspace();
  test_torque_map();
  test_simulate();
  test_plans();
  test_study();
  clear_scripts();
  return ea_test_summary("test_cli_figure");
}
