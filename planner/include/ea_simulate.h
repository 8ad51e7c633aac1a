/**
 * @file ea_simulate.h
 * @brief The FE transient of a trajectory file as one library call: the ground
 *        truth for vibration that `elasticarm simulate`, `controller-sim
 *        --simulate`, `plan --verify` and studies share.
 *
 * The trajectory (docs/trajectory-format.md) drives the nonlinear FE model
 * (docs/fe.md) by the shoulder angle theta0(t) and the cable: passive (default),
 * with the moving rest length L0(t) = L_c(t) / (1 + T(t) / EA_c), or active, with
 * the tension T(t). Between samples the drive follows the cubic Hermite of the
 * file's values and rates, as the format promises. Never prints.
 */
#ifndef EA_SIMULATE_H
#define EA_SIMULATE_H

#include "ea_fe.h"
#include "ea_task.h"
#include "ea_traj.h"

#ifdef __cplusplus
extern "C" {
#endif

/** Settings of a trajectory simulation. */
typedef struct ea_sim_settings {
  int elements;              /**< FE elements (default EA_FE_DEFAULT_ELEMENTS) */
  ea_fe_scheme_t scheme;     /**< time integrator (default EA_FE_SCHEME_GENALPHA, rho_inf 0.9:
                                  bench/bench_sim's work-precision table) */
  double dt;                 /**< [s] time step (default 1e-3: the residual peak close to its
                                  dt -> 0 limit on bench/bench_sim's cases; docs/cli-fe.md) */
  double rho_inf;            /**< generalized-alpha spectral radius (default 0.9) */
  double settle;             /**< [s] simulated after the motion (default 3) */
  int cable_active;          /**< 0: passive cable (default), 1: active (tension drives) */
  int drive_fe;              /**< 0: theta0 and T from the file (default); 1: re-solved by FE
                                  statics holding the planned tip at every sample */
  double damping_ratio;      /**< zeta at the first mode of the start state, by strain-rate
                                  damping (0 = undamped; default NAN: the arm file's measured
                                  ratio of mode 1, damping.modal_ratios, undamped without one;
                                  the strain-rate damping then gives the higher modes their
                                  own ratios, reported in ea_sim_info_t.modal_damping) */
  double rayleigh_mass;      /**< [1/s] explicit mass damping a (used when damping_ratio = 0) */
  double rayleigh_stiffness; /**< [s] explicit strain-rate damping b (idem) */
  double rest_tolerance;     /**< [m] "at rest": |tip - final equilibrium| stays below this
                                  (default 1e-3) */
  int keep_history;          /**< 1: return the tip history (ea_sim_history_t) */
  double max_wall_s;         /**< [s] wall-time cap of the whole simulation (0: none, the
                                  default): past it the transient stops with
                                  EA_ERR_INTERRUPTED, the message saying how far it got */
  /** Progress of the transient (NULL: none, the default): called from the calling thread
   *  as the simulated time t_s advances to t_end_s (motion + settle), every 1 % of it; the
   *  library never prints. */
  void (*progress)(void *data, double t_s, double t_end_s);
  void *progress_data; /**< passed to progress */
} ea_sim_settings_t;

void ea_sim_settings_default(ea_sim_settings_t *s);
/** Check s; err names the bad field, its value and the bound. */
ea_status_t ea_sim_settings_validate(const ea_sim_settings_t *s, ea_error_t *err);

/** What a trajectory simulation found. Lengths [m], times [s] from the trajectory's
 *  first sample. */
typedef struct ea_sim_info {
  ea_status_t status;
  double tip_mass;       /**< [kg] m_L simulated */
  double damping_ratio;  /**< zeta at mode 1 used (the settings' or the arm file's) */
  double duration;       /**< [s] the motion (last sample time - first) */
  double simulated_time; /**< [s] motion + settle, as stepped */
  int steps, newton_iterations, max_step_iterations;
  int start_newton_iterations;   /**< continuation to the start equilibrium */
  double start_tension;          /**< [N] FE cable tension at the start equilibrium */
  double start_theta0_mismatch;  /**< [rad] |theta0 of this arm's statics - the file's| at t0 */
  double start_tension_mismatch; /**< [N] the same for the tension */
  double start_freq_hz[2];       /**< first two frequencies at the start (damping only) */
  double modal_damping[EA_FE_MAX_MODES]; /**< damping ratios of the start's modes */
  int n_modal_damping;
  double rayleigh_mass, rayleigh_stiffness; /**< damping used */
  double residual_rms;            /**< RMS of |tip - final equilibrium| after the motion */
  double residual_peak;           /**< peak of the same (the residual vibration) */
  double time_to_rest;            /**< first time after which |tip - final equilibrium| <=
                                       rest_tolerance until the end; NAN if not at rest by then */
  double max_tracking_error;      /**< max |tip - planned tip| during the motion */
  double max_tracking_error_time; /**< when */
  double static_offset_start;     /**< |FE start equilibrium - planned start tip| */
  double static_offset_end;       /**< |final FE equilibrium - planned end tip| */
  double final_static_tip[2];     /**< final FE equilibrium for the held inputs */
  double energy_start, energy_end, energy_drift_max, kinetic_max; /**< [J] */
  double tension_min, tension_max; /**< [N] extremes of the FE cable tension over the motion and
                                        the settle (passive cable: 0 when slack), beside the
                                        planned quasi-static tension column; NAN if not run) */
  double tension_min_time, tension_max_time; /**< [s] when, from the first sample */
  double wall_time_s;
} ea_sim_info_t;

/** Tip history: rows of (t [s], tip x [m], tip y [m], tip theta [rad],
 *  planned tip x [m], planned tip y [m]), and the loads at the same times. Owned;
 *  ea_sim_history_free. */
typedef struct ea_sim_history {
  int rows;
  double *data;  /**< rows x 6 */
  double *loads; /**< rows x 2: shoulder torque [N m] (the moment the beam carries at the
                      clamp, ea_fe_sim_settings_t.output_loads) and cable tension [N] */
} ea_sim_history_t;
void ea_sim_history_free(ea_sim_history_t *h);

/** Simulate trajectory tr on arm with tip mass tip_mass [kg] (<= 0: the arm's hand plus the
 *  trajectory's recorded payload). Statics of the start for this arm and load, its FE
 *  equilibrium, continuation to the file's inputs at t = 0 (ea_fe_static_continue), then the
 *  transient over the motion and the settling time.
 * @param[out] hist history if s->keep_history (else untouched); may be NULL
 * @param[out] info summary; filled as far as it got on failure
 * @return EA_OK; EA_ERR_INPUT for a trajectory whose values the drive refuses (T < 0, ...);
 *         EA_ERR_INADMISSIBLE if the start has no static solution; EA_ERR_NOCONV/... if the
 *         FE did not converge (err says where). */
ea_status_t ea_traj_simulate(const ea_arm_t *arm, const ea_traj_t *tr, double tip_mass,
                             const ea_sim_settings_t *s, ea_sim_history_t *hist,
                             ea_sim_info_t *info, ea_error_t *err);

/** The planned (quasi-static) tip at trajectory time t [s]: the cubic Hermite of L_c and
 *  alpha with their rates (docs/trajectory-format.md), tip = root + L_c (cos, sin) alpha.
 *  Holds the end values outside the samples. */
void ea_traj_planned_tip(const ea_traj_t *tr, const ea_arm_t *arm, double t, double xy[2]);

/** Fill the statics columns (T, theta0, kappa0, torque, tip) of every row from the cable
 *  length and angle columns, warm-started along the rows (a simple CSV has only those);
 *  the theta0 rate column becomes NAN ("not known": ea_traj_simulate takes centred
 *  differences; such a trajectory is not written to a file).
 *  err names the first row without a static solution. */
ea_status_t ea_traj_fill_statics(ea_traj_t *tr, ea_shooter_t *sh, ea_error_t *err);

/** What the reduced model (ea_rom_table_t) predicts for a trajectory: the modal states
 *  integrated along the file's cubic Hermite of (L_c, alpha) (RK4, dt), then free vibration
 *  for settle seconds at the goal. */
typedef struct ea_rom_prediction {
  int modes;
  double eta[EA_ROM_MAX_MODES];      /**< [sqrt(kg) m] modal coordinates at the end of the motion */
  double eta_rate[EA_ROM_MAX_MODES]; /**< [sqrt(kg) m / s] their rates */
  double amplitude_m[EA_ROM_MAX_MODES]; /**< [m] tip amplitude of each mode's free vibration */
  double residual_peak;                 /**< [m] peak |tip - goal| over the settling time */
  double max_deviation;                 /**< [m] peak modal tip deviation during the motion */
  double min_tension_change;            /**< [N] most negative modal tension change */
} ea_rom_prediction_t;

/** Integrate the reduced model along trajectory tr (dt [s], e.g. 1e-4; settle [s]). */
ea_status_t ea_traj_rom_predict(const ea_rom_table_t *tb, const ea_traj_t *tr, double dt,
                                double settle, ea_rom_prediction_t *out, ea_error_t *err);

/** The nonlinear reduced model's coefficients (ea_romnl_sample) at n points of tr's path, equally
 *  spaced in time; tb: the linear table whose mode signs they take. */
ea_status_t ea_traj_romnl_sample(ea_romnl_t *r, const ea_rom_table_t *tb, const ea_traj_t *tr,
                                 int n, ea_error_t *err);
/** ea_traj_rom_predict with the nonlinear reduced model (sampled on tr's path, or on a path tr
 *  follows): RK4 of step dt [s] (1e-4), the free vibration over settle [s] at the goal by the
 * linear table tb. *path_dist (may be NULL): the largest distance [m, alpha weighted 0.5 m/rad] of
 * tr's configurations from the sampled path; beyond a millimetre or so, sample tr's own path.
 *  EA_ERR_INTEGRATION when the modal state leaves the model's range. */
ea_status_t ea_traj_romnl_predict(const ea_rom_table_t *tb, const ea_romnl_t *r,
                                  const ea_traj_t *tr, double dt, double settle,
                                  ea_rom_prediction_t *out, double *path_dist, ea_error_t *err);

/** How ea_rom_table_cached got its table. */
typedef struct ea_rom_cache_info {
  int loaded;         /**< 1: read from the cache */
  int built;          /**< 1: built (ea_rom_table_build) */
  int saved;          /**< 1: written to the cache */
  int rejected;       /**< 1: a file at the path was not used (damaged: size or CRC-32;
                           another format or table; not a regular file; unreadable) */
  int save_failed;    /**< 1: built but could not be written to the cache */
  char path[1200];    /**< cache file ("" = no cache) */
  char message[2000]; /**< why a file there was not used and/or why the table was not saved
                           ("" = neither happened); for the caller to show as a warning */
} ea_rom_cache_info_t;

/** The cache folder: $EA_CACHE_DIR ("" or "off": none), else $XDG_CACHE_HOME/elasticarm, else
 *  $HOME/.cache/elasticarm; NULL when there is none. */
const char *ea_rom_cache_dir(char *buf, size_t len);
/** The reduced-model table for arm, tip mass [kg], settings, box and grid: loaded from
 *  cache_dir when a file there was made from exactly these inputs by this table format and
 *  library version and its CRC-32 holds, else built (and saved, atomically). A file that is
 *  damaged, of another format, or not a regular file (opened without blocking) is not used
 *  and a cache that cannot be written is not an error: info->rejected / info->save_failed
 *  and info->message say so. cache_dir NULL: always built. */
ea_status_t ea_rom_table_cached(const ea_arm_t *arm, double tip_mass, const ea_rom_settings_t *s,
                                const double box[4], int nL, int na, const char *cache_dir,
                                ea_rom_table_t **out, ea_rom_cache_info_t *info, ea_error_t *err);

/* ------------------------------------------------------------------------ */
/* A trajectory against the limits of its task (planner/traj/traj_shape.c)  */
/* ------------------------------------------------------------------------ */

/** The limits ea_traj_check_limits checks, in this order. */
typedef enum ea_traj_limit {
  EA_TRAJ_LIMIT_CABLE_LENGTH = 0, /**< L_c in [cable_length_min, cable_length_max] */
  EA_TRAJ_LIMIT_CABLE_SPEED,      /**< |dL_c/dt| <= cable_speed_max */
  EA_TRAJ_LIMIT_CABLE_ACCEL,      /**< |d2L_c/dt2| <= cable_accel_max */
  EA_TRAJ_LIMIT_ANGLE_SPEED,      /**< |dalpha/dt| <= cable_angle_speed_max (if finite) */
  EA_TRAJ_LIMIT_ANGLE_ACCEL,      /**< |d2alpha/dt2| <= cable_angle_accel_max (if finite) */
  EA_TRAJ_LIMIT_TENSION_MIN,      /**< T >= tension_min */
  EA_TRAJ_LIMIT_TENSION_MAX,      /**< T <= tension_max */
  EA_TRAJ_LIMIT_TORQUE,           /**< |EI kappa0| <= shoulder_torque_max */
  EA_TRAJ_LIMIT_SHOULDER_ANGLE,   /**< theta0 in the arm's shoulder range */
  EA_TRAJ_LIMIT_SHOULDER_SPEED,   /**< |dtheta0/dt| <= shoulder_speed_max (if finite) */
  EA_TRAJ_LIMIT_SHOULDER_ACCEL,   /**< |d2theta0/dt2| <= the arm's shoulder_accel_max */
  EA_TRAJ_LIMIT_BASE_ANGLE,       /**< base in the arm's base range */
  EA_TRAJ_LIMIT_BASE_SPEED,       /**< |base rate| <= base_speed_max */
  EA_TRAJ_LIMIT_BASE_ACCEL,       /**< |base acceleration| <= base_accel_max */
  EA_TRAJ_LIMIT_FIRST_FREQUENCY,  /**< f1 >= min_first_frequency_Hz (ea_traj_shape_zv only) */
  EA_TRAJ_LIMIT_MODAL_DEFLECTION, /**< acc / omega1^2 <= max_modal_deflection_m (idem) */
  EA_TRAJ_LIMIT_COUNT
} ea_traj_limit_t;

/** Name of a limit ("cable acceleration", ...). */
const char *ea_traj_limit_name(ea_traj_limit_t i);

/** What ea_traj_check_limits found. Relative excess: |value| / limit - 1 for magnitudes,
 *  (T_min - T) / T_min, and the distance outside a range over its width: <= 0 held. */
typedef struct ea_traj_limits_check {
  int samples;                        /**< points checked */
  int statics_failures;               /**< samples without a static solution with T > 0 */
  double first_failure_s;             /**< [s] time of the first such sample (NAN: none) */
  double excess[EA_TRAJ_LIMIT_COUNT]; /**< worst relative excess (-INFINITY: not checked) */
  double value[EA_TRAJ_LIMIT_COUNT];  /**< the value there (SI) */
  double bound[EA_TRAJ_LIMIT_COUNT];  /**< the bound it is compared with (SI) */
  double time_s[EA_TRAJ_LIMIT_COUNT]; /**< [s] where */
  int worst;                          /**< the limit of the largest excess */
  double min_tension_margin_N;        /**< [N] min of T - tension_min */
  double peak_shoulder_torque_Nm;     /**< [N m] max |EI kappa0| */
  double max_theta0_deviation_rad;    /**< [rad] |theta0 interpolant - statics theta0| */
} ea_traj_limits_check_t;

/** Check trajectory tr against every limit of task (checked; its arm, payload and limits)
 *  with the file's interpolant (docs/trajectory-format.md), between the samples too: on every
 *  interval the cubic Hermites of L_c, alpha, base and theta0 at both ends, at the extrema of
 *  each value and rate, and at rate_hz (at least 4 points per interval), the tension and
 *  torque from the statics solved at the interpolated (L_c, alpha) (warm-started along the
 *  samples). A limit is broken when its relative excess is above tol (e.g. 1e-9).
 *  @return EA_OK when every limit holds; EA_ERR_INADMISSIBLE naming the worst limit, its
 *          value, bound and time (or the first time without a static solution). */
ea_status_t ea_traj_check_limits(const ea_task_t *task, const ea_traj_t *tr, double rate_hz,
                                 double tol, ea_traj_limits_check_t *out, ea_error_t *err);

/* ------------------------------------------------------------------------ */
/* Zero-vibration input shaping (planner/traj/traj_shape.c)                  */
/* ------------------------------------------------------------------------ */

/** Settings of ea_traj_shape_zv. */
typedef struct ea_shape_settings {
  double damping_ratio; /**< zeta of the shaper, [0, 1) (default NAN: the arm file's
                             damping.modal_ratios[0], 0 without one) */
  int elements;         /**< FE elements of the first frequency (default EA_FE_DEFAULT_ELEMENTS) */
  double check_rate_hz; /**< [Hz] samples per second of the limits check (default 1000) */
  double limit_tol;     /**< relative slack of the limits check (default 1e-9) */
} ea_shape_settings_t;

void ea_shape_settings_default(ea_shape_settings_t *s);

/** What ea_traj_shape_zv did. Frequencies are those of the input's samples. */
typedef struct ea_shape_info {
  ea_status_t status;
  char message[512];
  double damping_ratio; /**< zeta used */
  double amplitude[2];  /**< impulse amplitudes 1 / (1 + K), K / (1 + K) */
  double f1_start_hz, f1_goal_hz, f1_min_hz, f1_max_hz;         /**< [Hz] FE first frequency */
  double delay_start_s, delay_goal_s, delay_min_s, delay_max_s; /**< [s] 1 / (2 f_d) */
  double duration_in_s;                                         /**< [s] the input's duration */
  double duration_s;                                            /**< [s] the shaped trajectory's */
  int samples_in, samples;      /**< rows of the input and of the output */
  int echo_samples_merged;      /**< echo times m_k left out: within 1e-3 of the shortest input
                                     interval of an input sample, which stands for both */
  double max_merge_s;           /**< [s] the largest such distance */
  double max_path_deviation_m;  /**< [m] largest distance of a sample's tip from the task's
                                     line or polyline (NAN: free path) */
  ea_traj_limits_check_t check; /**< the shaped trajectory against the task's limits */
  double time_s;                /**< [s] wall time */
} ea_shape_info_t;

/** Zero-vibration (ZV) input shaping of a rest-to-rest trajectory whose delay follows the
 *  first natural frequency along the motion (docs/planner.md, "ZV-shaped plans"). Each input
 *  sample k (time t_k, actuator coordinates q_k) is echoed at m_k = t_k + tau_k, tau_k =
 *  1 / (2 f1_k sqrt(1 - zeta^2)), f1_k the FE first frequency (passive cable, the task's tip
 *  mass) at (L_c, alpha)_k; the echo D(t) is the C2 cubic spline through (m_k, q_k) with rest
 *  at both ends; the shaped command is A1 q(t) + A2 D(t) (q: the input's cubic Hermite, both
 *  held at their end values outside their spans), A1 = 1 / (1 + K), A2 = K / (1 + K), K =
 *  exp(-zeta pi / sqrt(1 - zeta^2)), sampled at the union of the t_k and m_k with the exact
 *  values, rates and accelerations, so the file's cubic Hermite is the shaped command exactly
 *  (an m_k within 1e-3 of the shortest input interval of some t_k is left out: near it the
 *  file's cubic approximates the echo's breakpoint). Its statics columns
 *  (T, theta0, kappa0, torque, tip) come from the statics at every sample, theta0's rate from
 *  the C2 spline through them with rest at both ends. The result is checked against every
 *  limit of task (ea_traj_check_limits; with min_first_frequency_Hz or max_modal_deflection_m
 *  also those, at the samples) and refused if it breaks one.
 * @param task the task of the plan (checked: arm, payload, limits, path)
 * @param in   the plan: at rest at both ends
 * @param s    settings (NULL = defaults)
 * @param[out] out  the shaped trajectory (ea_traj_t rules of ea_traj.h); freed on failure
 * @param[out] info what was done, the limits check (may be NULL)
 * @return EA_OK; EA_ERR_ARG (input not at rest at its ends, not the task's payload);
 *         EA_ERR_NOCONV/EA_ERR_UNSTABLE (no FE frequency at a sample); EA_ERR_INADMISSIBLE
 *         (the shaped trajectory breaks a limit or leaves the workspace: err says which,
 *         where, by how much). */
ea_status_t ea_traj_shape_zv(const ea_task_t *task, const ea_traj_t *in,
                             const ea_shape_settings_t *s, ea_traj_t *out, ea_shape_info_t *info,
                             ea_error_t *err);

#ifdef __cplusplus
}
#endif
#endif
