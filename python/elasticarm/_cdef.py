"""The C declarations the package calls (cffi ABI mode: no compiler at import).

cffi's cdef cannot read the public headers (they use the preprocessor), so
what is needed is written out here by hand. Enums are declared as int (their
size on every ABI the library builds for). The structs below mirror the
public headers exactly; the test test_abi.py compares every field's offset
and every struct's size with the C compiler's, reported by the library
itself (ea_abi_offsetof, ea_abi_sizeof in ea_abi.h), so a header change that
is not made here fails a test instead of reading the wrong bytes. Structs
that are large or change often (ea_task_t, ea_study_t, ea_refine_info_t) are
not mirrored: the package allocates ea_abi_sizeof() bytes and reads the few
fields it needs at the offsets the library reports.
"""

CDEF = r"""
typedef int ea_status_t;
typedef int ea_integrator_t;
typedef int ea_given_t;
typedef int ea_branch_t;
typedef int ea_fe_eig_backend_t;
typedef int ea_fe_scheme_t;
typedef int ea_ws_bound_t;
typedef int ea_task_point_kind_t;
typedef int ea_plan_start_t;
typedef int ea_study_workers_t;

const char *ea_version(void);
const char *ea_strerror(ea_status_t status);
const char *ea_status_name(ea_status_t status);
size_t ea_abi_sizeof(const char *type);
size_t ea_abi_offsetof(const char *type, const char *field);

typedef struct ea_error {
  ea_status_t status;
  char msg[512];
} ea_error_t;

/* ea_arm.h */
typedef struct ea_actuators {
  double spool_radius;
  double spool_gear_ratio;
  double spool_zero_length;
  double cable_length_min;
  double cable_length_max;
  double cable_speed_max;
  double cable_accel_max;
  double tension_max;
  double tension_min;
  double shoulder_torque_max;
  double shoulder_speed_max;
  double shoulder_angle_min;
  double shoulder_angle_max;
  double shoulder_accel_max;
  double base_speed_max;
  double base_accel_max;
  double base_angle_min;
  double base_angle_max;
} ea_actuators_t;

typedef struct ea_arm {
  double rho;
  double m_hand;
  double length;
  double EI;
  double x_c;
  double y_c;
  double g;
  double EA;
  double GA_s;
  double EA_cable;
  double I_zz;
  double I_hand;
  ea_actuators_t act;
  int n_damping;
  double damping_ratio[6];
} ea_arm_t;

void ea_arm_default(ea_arm_t *arm);
ea_status_t ea_arm_validate(const ea_arm_t *arm, ea_error_t *err);
double ea_arm_payload_from_factor(const ea_arm_t *arm, double gamma);
double ea_arm_tip_mass(const ea_arm_t *arm, double payload_kg);
ea_status_t ea_arm_load(const char *path, ea_arm_t *arm, ea_error_t *err);
ea_status_t ea_arm_load_string(const char *name, const char *text, size_t len, ea_arm_t *arm,
                               ea_error_t *err);

/* ea_statics.h */
typedef struct ea_load {
  double tip_mass;
} ea_load_t;
typedef struct ea_shooter ea_shooter_t;
ea_status_t ea_shooter_alloc(const ea_arm_t *arm, const void *s, ea_shooter_t **out,
                             ea_error_t *err);
void ea_shooter_free(ea_shooter_t *sh);
void ea_shooter_set_load(ea_shooter_t *sh, const ea_load_t *load);
ea_status_t ea_shoot_shape(ea_shooter_t *sh, const double p[4], int n, double *s, double *theta,
                           double *kappa, double *x, double *y);

typedef struct ea_statics_problem {
  ea_given_t given[2];
  double value[2];
} ea_statics_problem_t;
ea_statics_problem_t ea_statics_problem_cable(double cable_length, double alpha);
ea_statics_problem_t ea_statics_problem_tip(double x, double y);
ea_statics_problem_t ea_statics_problem_tension_theta0(double T, double theta0);
ea_statics_problem_t ea_statics_problem_tension_alpha(double T, double alpha);

typedef struct ea_statics_solution {
  double p[4];
  double tip[4];
  double cable_length;
  double shoulder_torque;
  double residual;
  int iterations;
  int cont_steps;
  ea_branch_t branch;
  double winding;
  ea_status_t status;
} ea_statics_solution_t;
ea_status_t ea_statics_solve(ea_shooter_t *sh, const ea_statics_problem_t *prob, const void *s,
                             const double *guess, ea_statics_solution_t *sol, ea_error_t *err);

/* ea_fe.h */
typedef struct ea_fe_settings {
  int elements;
  int modes;
  double newton_tol;
  int newton_max_iter;
  ea_fe_eig_backend_t eig_backend;
  int static_hold_tip;
} ea_fe_settings_t;
void ea_fe_settings_default(ea_fe_settings_t *s);
typedef struct ea_fe_model ea_fe_model_t;
ea_status_t ea_fe_model_alloc(const ea_arm_t *arm, const ea_fe_settings_t *s, ea_fe_model_t **out,
                              ea_error_t *err);
void ea_fe_model_free(ea_fe_model_t *m);
ea_status_t ea_fe_model_set_load(ea_fe_model_t *m, const ea_load_t *load);

typedef struct ea_fe_static_info {
  ea_status_t status;
  int iterations;
  double residual;
  double tip[3];
  double tension;
  double cable_length;
  double cable_angle;
  double theta0;
  double tip_shift;
  double time_s;
} ea_fe_static_info_t;

typedef struct ea_fe_modes_info {
  ea_status_t status;
  int modes;
  double freq_hz[16];
  double lambda[16];
  int stable;
  double time_assembly_s, time_eigen_s;
  int backend_info;
  int iterations;
  int fallback;
} ea_fe_modes_info_t;

/* ea_workspace.h */
typedef struct ea_config_point {
  double cable_length;
  double alpha;
  double x, y;
  double tension;
  double theta0;
  double kappa0;
  double shoulder_torque;
  double residual;
  int iterations;
  ea_status_t status;
  int stable;
  int admissible;
  char reason[96];
} ea_config_point_t;
ea_status_t ea_workspace_outer(ea_shooter_t *sh, const double *alpha, int n,
                               ea_config_point_t *out);
ea_status_t ea_workspace_inner(ea_shooter_t *sh, double cable_length, const double *alpha, int n,
                               ea_config_point_t *out);
const char *ea_ws_bound_name(ea_ws_bound_t b);

typedef struct ea_workspace_settings {
  double alpha_min, alpha_max;
  double inner_cable_length;
  int limits;
  int samples;
  int depth_samples;
  double tol;
} ea_workspace_settings_t;
void ea_workspace_settings_default(ea_workspace_settings_t *s);

typedef struct ea_workspace_extremum {
  double value;
  double alpha;
  double cable_length;
  double x, y;
  ea_ws_bound_t bound;
  ea_ws_bound_t bound2;
  ea_ws_bound_t at_end;
} ea_workspace_extremum_t;

typedef struct ea_workspace_metrics {
  double area;
  double area_error;
  ea_workspace_extremum_t reach;
  ea_workspace_extremum_t x_max;
  ea_workspace_extremum_t y_min;
  unsigned bounds;
  int pieces;
  long solves;
} ea_workspace_metrics_t;
ea_status_t ea_workspace_metrics(ea_shooter_t *sh, const ea_workspace_settings_t *set,
                                 ea_workspace_metrics_t *m, ea_error_t *err);

typedef struct ea_freq_point {
  double cable_length;
  double alpha;
  ea_statics_solution_t ode;
  ea_fe_static_info_t fe;
  ea_fe_modes_info_t modes;
  ea_status_t status;
  const char *stage;
  ea_error_t err;
} ea_freq_point_t;
ea_status_t ea_freq_point(ea_shooter_t *sh, ea_fe_model_t *m, double cable_length, double alpha,
                          const double *guess, ea_freq_point_t *pt);
ea_status_t ea_freq_sweep(ea_shooter_t *sh, ea_fe_model_t *m, const double *cable_length, int n,
                          double alpha, ea_freq_point_t *pts);

/* ea_task.h: ea_task_t itself is not mirrored (ea_abi_sizeof, ea_abi_offsetof) */
typedef struct ea_task_point {
  ea_task_point_kind_t kind;
  double given[3];
  double cable_length;
  double cable_angle;
  double base_angle;
  double reach;
  double height;
  double p[4];
  char where[300];
} ea_task_point_t;

typedef struct ea_task_limits {
  double tension_min;
  double tension_max;
  double cable_length_min;
  double cable_length_max;
  double cable_speed_max;
  double cable_accel_max;
  double cable_angle_speed_max;
  double cable_angle_accel_max;
  double shoulder_torque_max;
  double shoulder_speed_max;
  double base_speed_max;
  double base_accel_max;
  double min_first_frequency_hz;
  double max_modal_deflection_m;
  double resample_margin;
  int continuous_acceleration;
} ea_task_limits_t;

typedef struct ea_task ea_task_t;
const char *ea_task_objective_name(int o);
const char *ea_task_path_name(int p);
ea_status_t ea_task_check(ea_task_t *task, ea_error_t *err);
ea_status_t ea_task_load(const char *path, const char *default_arm, ea_task_t *task,
                         ea_error_t *err);
ea_status_t ea_task_load_string(const char *name, const char *text, size_t len,
                                const char *default_arm, ea_task_t *task, ea_error_t *err);

/* ea_traj.h */
typedef struct ea_traj {
  int n;
  double *data;
  double payload_kg;
  double tip_mass_kg;
  char arm_file[4096];
  int has_arm_hash;
  uint64_t arm_hash;
  char task[512];
  char run_id[64];
  char status[64];
} ea_traj_t;
const char *ea_traj_column_name(int c);
ea_status_t ea_traj_alloc(ea_traj_t *tr, int n);
void ea_traj_free(ea_traj_t *tr);
ea_status_t ea_traj_write(const ea_traj_t *tr, const char *path, ea_error_t *err);
ea_status_t ea_traj_read_any(ea_traj_t *tr, const char *path, int *simple, ea_error_t *err);

/* ea_simulate.h */
typedef struct ea_sim_settings {
  int elements;
  ea_fe_scheme_t scheme;
  double dt;
  double rho_inf;
  double settle;
  int cable_active;
  int drive_fe;
  double damping_ratio;
  double rayleigh_mass;
  double rayleigh_stiffness;
  double rest_tolerance;
  int keep_history;
  double max_wall_s;
  void (*progress)(void *data, double t_s, double t_end_s);
  void *progress_data;
} ea_sim_settings_t;
void ea_sim_settings_default(ea_sim_settings_t *s);
ea_status_t ea_sim_settings_validate(const ea_sim_settings_t *s, ea_error_t *err);

typedef struct ea_sim_info {
  ea_status_t status;
  double tip_mass;
  double damping_ratio;
  double duration;
  double simulated_time;
  int steps, newton_iterations, max_step_iterations;
  int start_newton_iterations;
  double start_tension;
  double start_theta0_mismatch;
  double start_tension_mismatch;
  double start_freq_hz[2];
  double modal_damping[16];
  int n_modal_damping;
  double rayleigh_mass, rayleigh_stiffness;
  double residual_rms;
  double residual_peak;
  double time_to_rest;
  double max_tracking_error;
  double max_tracking_error_time;
  double static_offset_start;
  double static_offset_end;
  double final_static_tip[2];
  double energy_start, energy_end, energy_drift_max, kinetic_max;
  double tension_min, tension_max;
  double tension_min_time, tension_max_time;
  double wall_time_s;
} ea_sim_info_t;

typedef struct ea_sim_history {
  int rows;
  double *data;
  double *loads;
} ea_sim_history_t;
void ea_sim_history_free(ea_sim_history_t *h);
ea_status_t ea_traj_simulate(const ea_arm_t *arm, const ea_traj_t *tr, double tip_mass,
                             const ea_sim_settings_t *s, ea_sim_history_t *hist,
                             ea_sim_info_t *info, ea_error_t *err);

/* ea_planner.h */
typedef struct ea_planner ea_planner_t;
typedef struct ea_plan_info {
  ea_status_t status;
  int ipopt_status;
  char ipopt_status_name[48];
  int iterations;
  int newton_steps;
  int ipopt_rows;
  int screen_resolves;
  int ipm_iterations;
  int ipm_fallback;
  int threads;
  int n_var, n_con, nnz_jac;
  double objective;
  double duration_s;
  double min_tension_margin_N;
  double peak_shoulder_torque_Nm;
  double max_statics_residual;
  double max_violation;
  char worst[160];
  int n_active;
  char active[16][40];
  int active_knots[16];
  int deriv_errors;
  int evals_g, evals_jac;
  double time_total_s;
  double time_guess_s;
  double time_statics_s;
  double time_ipopt_s;
  double time_rest_s;
  int between_passes;
  double time_freq_model_s;
  double min_first_frequency_hz;
  double max_modal_deflection_m;
  double time_dyn_model_s;
  double predicted_residual_m;
  double predicted_amplitude_m[4];
  double predicted_time_to_rest_s;
  double predicted_residual_worst_m;
  double max_modal_deviation_m;
  double min_dynamic_tension_margin_N;
  char message[512];
} ea_plan_info_t;

ea_status_t ea_planner_alloc(const ea_task_t *task, ea_planner_t **out, ea_error_t *err);
void ea_planner_free(ea_planner_t *pl);
ea_status_t ea_planner_solve(ea_planner_t *pl, ea_plan_start_t start, const ea_traj_t *prev,
                             ea_plan_info_t *info, ea_error_t *err);
ea_status_t ea_planner_trajectory(const ea_planner_t *pl, ea_traj_t *tr, ea_error_t *err);

/* ea_refine.h: ea_refine_info_t is not mirrored */
typedef struct ea_refine_info ea_refine_info_t;
ea_status_t ea_plan_rest_refine(ea_planner_t *pl, ea_plan_info_t *plan_info, void *info,
                                ea_error_t *err);
ea_status_t ea_plan_refine(ea_planner_t *pl, const void *s, ea_plan_info_t *plan_info,
                           ea_refine_info_t *info, ea_error_t *err);
int ea_plan_rest_check(const ea_task_t *task);
typedef struct ea_plan_verify {
  ea_status_t status;
  char message[512];
  ea_sim_settings_t settings;
  ea_sim_info_t sim;
  double predicted_residual_m;
  double predicted_time_to_rest_s;
  double residual_bound_m;
  double tension_bound_N;
  int passed;
  char failure[512];
  double base_travel_rad;
  double predicted_nonlinear_residual_m;
} ea_plan_verify_t;
void ea_plan_verify_judge(ea_plan_verify_t *v);
ea_status_t ea_plan_summary_write_ex(const ea_planner_t *pl, const ea_plan_info_t *info,
                                     const ea_refine_info_t *refine, const void *shape,
                                     const ea_plan_verify_t *verify, const char *run_id,
                                     const char *path, ea_error_t *err);

/* ea_study.h: ea_study_t is not mirrored */
typedef struct ea_study ea_study_t;
typedef struct ea_study_planner ea_study_planner_t;
typedef struct ea_study_settings {
  int threads;
  int shard_k, shard_n;
  const char *checkpoint;
  int fsync;
  double fsync_interval_s;
  long stop_after;
  const void *stop_request;
  void *min_time;
  void *min_time_data;
  const char *min_time_key;
  void *progress;
  void *progress_data;
  void *at_rest;
  void *at_rest_data;
  const char *at_rest_key;
  ea_study_workers_t workers;
} ea_study_settings_t;
typedef struct ea_study_info {
  ea_status_t status;
  long cases_total;
  long cases_shard;
  long cases_skipped;
  long cases_computed;
  long cases_failed;
  long rows_failed;
  long journal_dropped_bytes;
  int threads;
  int processes;
  long workers_lost;
  double time_s;
} ea_study_info_t;
void ea_study_free(ea_study_t *s);
ea_status_t ea_study_load(const char *path, const char *default_arm, ea_study_t *s,
                          ea_error_t *err);
ea_status_t ea_study_load_string(const char *name, const char *text, size_t len,
                                 const char *default_arm, ea_study_t *s, ea_error_t *err);
void ea_study_settings_default(ea_study_settings_t *set);
ea_status_t ea_study_use_planner(const ea_study_t *s, const char *default_arm,
                                 ea_study_settings_t *set, ea_study_planner_t **out,
                                 ea_error_t *err);
void ea_study_planner_free(ea_study_planner_t *p);
ea_status_t ea_study_run(const ea_study_t *s, const ea_study_settings_t *set, char **csv,
                         size_t *csv_len, ea_study_info_t *info, ea_error_t *err);

/* libc */
void free(void *p);
"""

#: Structs mirrored field by field above; test_abi.py checks each against C.
MIRRORED = (
    "ea_error_t", "ea_actuators_t", "ea_arm_t", "ea_load_t", "ea_statics_problem_t",
    "ea_statics_solution_t", "ea_fe_settings_t", "ea_fe_static_info_t", "ea_fe_modes_info_t",
    "ea_config_point_t", "ea_workspace_settings_t", "ea_workspace_extremum_t",
    "ea_workspace_metrics_t", "ea_freq_point_t", "ea_task_point_t", "ea_task_limits_t",
    "ea_traj_t", "ea_sim_settings_t", "ea_sim_info_t", "ea_sim_history_t", "ea_plan_info_t",
    "ea_plan_verify_t", "ea_study_settings_t", "ea_study_info_t",
)

#: Fields of the structs that are not mirrored, read at the library's offsets:
#: (type, field designator, cffi type of the field).
OPAQUE_FIELDS = {
    "ea_task_t": (
        ("name", "char[128]"), ("file", "char[512]"), ("arm_file", "char[512]"),
        ("arm", "ea_arm_t"), ("payload_kg", "double"), ("payload_factor", "double"),
        ("start", "ea_task_point_t"), ("goal", "ea_task_point_t"), ("n_via", "int"),
        ("path", "int"), ("objective", "int"), ("duration_s", "double"),
        ("limits", "ea_task_limits_t"), ("dynamics.modes", "int"),
        ("dynamics.residual_m", "double"), ("dynamics.refine.enabled", "int"),
        ("dynamics.refine.tolerance_m", "double"), ("dynamics.refine.by", "int"),
        ("dynamics.verify", "int"), ("knots", "int"),
    ),
    "ea_study_t": (("name", "char[128]"), ("n_cases", "long")),
    "ea_refine_info_t": (
        ("status", "int"), ("converged", "int"), ("stop_reason", "char[32]"),
        ("n_evals", "int"), ("duration_before_s", "double"),
        ("residual_peak_before_m", "double"), ("duration_s", "double"),
        ("residual_peak_m", "double"), ("residual_rms_m", "double"), ("time_s", "double"),
        ("message", "char[512]"), ("settings.tolerance_m", "double"),
        ("model_evals", "int"), ("time_model_s", "double"),
    ),
}
