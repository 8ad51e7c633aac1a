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
#include "ea_traj.h"

#ifdef __cplusplus
extern "C" {
#endif

/** Settings of a trajectory simulation. */
typedef struct ea_sim_settings {
  int elements;              /**< FE elements (default EA_FE_DEFAULT_ELEMENTS) */
  ea_fe_scheme_t scheme;     /**< time integrator (default EA_FE_SCHEME_GENALPHA, rho_inf 0.9:
                                  bench/bench_sim's work-precision table) */
  double dt;                 /**< [s] time step (default 1e-3: the residual within 1e-4 of the
                                  dt -> 0 limit, bench/bench_sim) */
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
  double wall_time_s;
} ea_sim_info_t;

/** Tip history: rows of (t [s], tip x [m], tip y [m], tip theta [rad],
 *  planned tip x [m], planned tip y [m]). Owned; ea_sim_history_free. */
typedef struct ea_sim_history {
  int rows;
  double *data; /**< rows x 6 */
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

/** How ea_rom_table_cached got its table. */
typedef struct ea_rom_cache_info {
  int loaded;        /**< 1: read from the cache */
  int built;         /**< 1: built (ea_rom_table_build) */
  int saved;         /**< 1: written to the cache */
  char path[1200];   /**< cache file ("" = no cache) */
  char message[600]; /**< why it was not saved, if it was not */
} ea_rom_cache_info_t;

/** The cache folder: $EA_CACHE_DIR ("" or "off": none), else $XDG_CACHE_HOME/elasticarm, else
 *  $HOME/.cache/elasticarm; NULL when there is none. */
const char *ea_rom_cache_dir(char *buf, size_t len);
/** The reduced-model table for arm, tip mass [kg], settings, box and grid: loaded from
 *  cache_dir when a file there was made from exactly these inputs, else built (and saved,
 *  atomically; a cache that cannot be written is not an error: info->message says why).
 *  cache_dir NULL: always built. */
ea_status_t ea_rom_table_cached(const ea_arm_t *arm, double tip_mass, const ea_rom_settings_t *s,
                                const double box[4], int nL, int na, const char *cache_dir,
                                ea_rom_table_t **out, ea_rom_cache_info_t *info, ea_error_t *err);

#ifdef __cplusplus
}
#endif
#endif
