/* Private: figures of the CLI (planner/app/): gnuplot driven through a pipe
 * (Debian gnuplot-nox, figure.c), a trajectory's figure (traj_figure.c) and a
 * plan's (plan_figure.c). Only the command-line tool draws. */
#ifndef EA_FIGURE_IMPL_H
#define EA_FIGURE_IMPL_H

#include "ea_calib.h"
#include "ea_planner.h"
#include "ea_simulate.h"
#include "ea_traj.h"
#include "ea_workspace.h"

/* ------------------------------------------------------------------------ */
/* Figures: gnuplot driven through a pipe (Debian gnuplot-nox).              */
/* The terminal follows the output's extension: .svg, .png (pngcairo), .pdf  */
/* ------------------------------------------------------------------------ */

typedef struct ea_plot ea_plot_t;

/** Start a figure for out_path (width x height pixels; 0 = 900 x 650). */
ea_status_t ea_plot_open(ea_plot_t **p, const char *out_path, int width, int height,
                         ea_error_t *err);
/** Append a gnuplot command line (printf-style). */
void ea_plot_cmd(ea_plot_t *p, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 2, 3)))
#endif
    ;
/** text as a single-quoted gnuplot string literal into buf (len bytes; truncated to
 *  fit): a quote written twice, line breaks as spaces, anything else as it is (no
 *  backslash escapes in single quotes); returns buf. Every text that comes from a
 *  user (a path, a task name, a CSV's labels) goes into a script this way. */
const char *ea_plot_quote(const char *text, char *buf, size_t len);
/** Inline data block $name: begin, rows of n numbers (NaN -> blank line,
 *  which breaks a curve), end. */
void ea_plot_data_begin(ea_plot_t *p, const char *name);
void ea_plot_data_row(ea_plot_t *p, int n, const double *v);
void ea_plot_data_end(ea_plot_t *p);
/** Run gnuplot on the script; on success the figure appears atomically at
 *  out_path. Frees p in every case. */
ea_status_t ea_plot_close(ea_plot_t *p, ea_error_t *err);
/** Free without drawing. */
void ea_plot_discard(ea_plot_t *p);

/** text for gnuplot's enhanced mode inside a single-quoted string, into buf (len
 *  bytes; truncated to fit): '_', '^', '{', '}', '@', '&' and '~' escaped as literals
 *  ('\\_' ...), a quote doubled, line breaks as spaces; returns buf. For labels made
 *  from names (a task's, a study's parameters and metrics). */
const char *ea_plot_enh(const char *text, char *buf, size_t len);

/** Palette of the maps: viridis (perceptually uniform, readable in grey and with
 *  colour-vision deficiency), 9 control points of matplotlib's table, as a
 *  'set palette defined' command. */
void ea_plot_palette_viridis(ea_plot_t *p);

/** Line colours of the figures: 8 distinguishable colours (Okabe-Ito, without the
 *  yellow, plus a dark red), as '#rrggbb'. */
#define EA_PLOT_NCOLOURS 8
const char *ea_plot_colour(int i);
/** A distinct style for curve i into buf ("lc rgb '#..' dt D", with points also
 *  "pt P"): the colour cycles fastest, then the dash type (and the point type);
 *  curves 0 to EA_PLOT_NSTYLES - 1 all differ. */
#define EA_PLOT_NSTYLES (EA_PLOT_NCOLOURS * 5)
const char *ea_plot_style(int i, int points, char *buf, size_t len);

/** A beam shape (n points, at most 101) shot from p as data rows, then a break. */
void ea_plot_beam(ea_plot_t *p, ea_shooter_t *sh, const double params[EA_NP], int n);

/** Workspace region (Fig. 3) as a closed polygon in the data block $name: the outer
 *  edge (outer[k], n cable angles ascending or descending; points without a solution
 *  left out), the side at the last angle along the cable to the inner edge, the inner
 *  edge back (the cable at inner_length from the cable root: root + L (cos, sin)
 *  alpha), the side at the first angle, and the first point again (so the first row
 *  equals the last). Returns the rows written (0: no outer point solved, no block). */
int ea_plot_region(ea_plot_t *p, const char *name, const ea_arm_t *arm,
                   const ea_config_point_t *outer, int n, double inner_length);

/** What a trajectory figure draws besides the trajectory. */
typedef struct ea_traj_figure_opts {
  const char *title;  /**< NULL: "trajectory" */
  ea_actuators_t lim; /**< limits drawn as dashed lines where finite (a plan's task
                           limits, else the arm file's) */
  /** First natural frequency model f1(L_c, alpha) [Hz] (a plan with a frequency
   *  model, NULL: none) and its lower limit (0: none). */
  ea_status_t (*f1)(const void *ctx, double cable_length, double cable_angle, double *hz);
  const void *f1_ctx;
  double f1_min_hz;
  /** A plan with dynamics: the reduced model's modal frequencies along the plan
   *  (NULL: none) and what the plan summary predicts (NAN when unknown). */
  const ea_rom_table_t *rom;
  double predicted_residual_m, max_modal_deviation_m, predicted_time_to_rest_s;
  /** What an FE transient of this very trajectory measured (NAN: none): the residual
   *  vibration's peak [m], and which check ran it (e.g. "plan --verify"). */
  double fe_residual_peak_m;
  const char *fe_check;
} ea_traj_figure_opts_t;

/** Defaults: no title, the arm's actuator limits, no models, NAN predictions. */
void ea_traj_figure_opts_default(ea_traj_figure_opts_t *o, const ea_arm_t *arm);
/** The task's limits as the figure's dashed lines (where the task sets them). */
void ea_traj_figure_opts_limits(ea_traj_figure_opts_t *o, const ea_task_limits_t *limits);

/** Figure of a trajectory in 4 x 2 panels, one unit per axis: (a) tip path and beam
 *  shapes (from its alpha, T, theta0, kappa0 columns, shot with sh, which carries
 *  the arm and load) in the workspace region of the load, (b) cable length [m],
 *  (c) angles [deg], (d) tension [N], (e) shoulder torque [N m], (f) cable speed
 *  [m/s], (g) angular rates [deg/s], (h) a plan's natural frequencies [Hz] (the
 *  frequency model's f1 or the reduced model's modes) with its dynamics
 *  predictions, else the cable acceleration [m/s^2]; limits dashed; when the base
 *  turns, a top view of the tip path beside (a). opts NULL: defaults.
 *  (.svg, .png, .pdf) */
ea_status_t ea_traj_figure(const ea_traj_t *tr, ea_shooter_t *sh, const ea_traj_figure_opts_t *opts,
                           const char *path, ea_error_t *err);

/** Figure of the last converged plan of pl (ea_traj_figure with the task's limits,
 *  its frequency model or reduced model, and from info (NULL: none) the dynamics
 *  predictions of the summary). (.svg, .png, .pdf) */
ea_status_t ea_plan_figure(ea_planner_t *pl, const ea_plan_info_t *info, const char *path,
                           ea_error_t *err);
/** ea_plan_figure with what an FE transient of the plan measured (fe_residual_peak_m [m],
 *  NAN: none) and which check ran it (fe_check), drawn beside the model's prediction. */
ea_status_t ea_plan_figure_fe(ea_planner_t *pl, const ea_plan_info_t *info,
                              double fe_residual_peak_m, const char *fe_check, const char *path,
                              ea_error_t *err);

/** Figure of a simulated trajectory (ea_traj_simulate with keep_history): (a) the
 *  planned and simulated tip paths at equal scale in a window at least 0.4 times
 *  as tall as wide (a small deviation does not squeeze it into a strip), (b) the
 *  deviation from the planned tip [mm] over time, its x and y parts and magnitude,
 *  (c) the distance from the final equilibrium [mm] on a log scale with the rest
 *  tolerance and the time to rest. */
ea_status_t ea_sim_figure(const ea_sim_history_t *h, const ea_sim_info_t *si,
                          const ea_sim_settings_t *s, const char *path, ea_error_t *err);

/** Fig. 3: the workspace region for each of ng payload factors gam[g] (outer[g * n +
 *  k] the outer edge at n cable angles), closed by the sides and the inner edge at
 *  inner_length; T = 0 beam shapes of the first payload (shot with sh, whose load is
 *  changed); with limits, the outer-edge points past an arm limit marked. */
ea_status_t ea_workspace_figure(const ea_arm_t *arm, ea_shooter_t *sh, const double *gam, int ng,
                                const ea_config_point_t *outer, int n, double inner_length,
                                int limits, const char *path, ea_error_t *err);

/** Shoulder-torque map over cable length Ls[j] x cable angle As[i] (cells[i * nL +
 *  j], ea_torque_map) in the viridis palette; cells past the shoulder torque limit
 *  lim->shoulder_torque_max hatched, cells past another limit (tension, cable length,
 *  shoulder angle) crossed, each said in the key. */
ea_status_t ea_torque_map_figure(const double *Ls, int nL, const double *As, int nA,
                                 const ea_config_point_t *cells, const ea_actuators_t *lim,
                                 double tip_mass, const char *path, ea_error_t *err);

/** Figure of a calibration: per cable angle (and payload) of the static records, the
 *  shoulder angle, and where measured the shoulder torque and the tension, against cable
 *  length, measured points on the calibrated model's curves; with ring-downs, their
 *  frequencies against cable length on the FE frequencies of the calibrated arm at each
 *  ring-down's cable angle (the paper's Fig. 5 with its experimental points). */
ea_status_t ea_calib_figure(const ea_calib_result_t *res, const ea_calib_record_t *recs, int nrec,
                            const char *path, ea_error_t *err);
/** Each ring-down (up to 6): its channel with the most signal, measured and fitted. */
ea_status_t ea_calib_ringdown_figure(const ea_calib_result_t *res, const ea_calib_record_t *recs,
                                     int nrec, const char *path, ea_error_t *err);

#endif
