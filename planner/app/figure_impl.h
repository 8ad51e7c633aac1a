/* Private: figures of the CLI (planner/app/): gnuplot driven through a pipe
 * (Debian gnuplot-nox, figure.c), a trajectory's figure (traj_figure.c) and a
 * plan's (plan_figure.c). Only the command-line tool draws. */
#ifndef EA_FIGURE_IMPL_H
#define EA_FIGURE_IMPL_H

#include "ea_planner.h"
#include "ea_traj.h"

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

/** Figure of a trajectory: tip path and beam shapes (from its alpha, T,
 *  theta0, kappa0 columns, shot with sh, which carries the arm and load) in
 *  the workspace, actuator coordinates, tension and torque, and rates over
 *  time. title may be NULL. (.svg, .png, .pdf) */
ea_status_t ea_traj_figure(const ea_traj_t *tr, ea_shooter_t *sh, double cable_length_min,
                           double tension_min, const char *title, const char *path,
                           ea_error_t *err);

/** Figure of the last converged plan of pl: tip path and beam shapes in the
 *  workspace of its payload, and the time histories (.svg, .png, .pdf). */
ea_status_t ea_plan_figure(ea_planner_t *pl, const char *path, ea_error_t *err);

#endif
