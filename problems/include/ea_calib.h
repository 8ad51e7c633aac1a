/**
 * @file ea_calib.h
 * @brief Calibration of an arm from its own measurements (docs/calibration.md):
 *        measurement records (problems/calib_record.c), damped-sinusoid fits of
 *        ring-downs (problems/calib_ringdown.c), the nonlinear least-squares fit
 *        of the arm's physical parameters with standard errors and identifiability
 *        (problems/calib_fit.c), and the calibrated arm file and JSON report
 *        (problems/calib_write.c).
 *
 * Never prints, never aborts: every call returns an ::ea_status_t and, on
 * failure only, a message in the caller's optional ::ea_error_t. Units: SI,
 * angles in radians.
 */
#ifndef EA_CALIB_H
#define EA_CALIB_H

#include "ea_fe.h"

#include <stdio.h>

#ifdef __cplusplus
extern "C" {
#endif

/* ------------------------------------------------------------------------ */
/* Measurement records (docs/calibration.md, "Measurement records")          */
/* ------------------------------------------------------------------------ */

/** Measured channels of a record, in this order. */
enum {
  EA_CALIB_CH_THETA0 = 0,  /**< theta0_rad: shoulder angle [rad] */
  EA_CALIB_CH_TORQUE,      /**< shoulder_torque_Nm [N m] */
  EA_CALIB_CH_TENSION,     /**< tension_N [N] */
  EA_CALIB_CH_TIP_X,       /**< tip_x_m [m] */
  EA_CALIB_CH_TIP_Y,       /**< tip_y_m [m] */
  EA_CALIB_CH_CABLE_ANGLE, /**< cable_angle_rad [rad] */
  EA_CALIB_NCH
};
/** Column name of a channel ("theta0_rad", ...). */
const char *ea_calib_channel_column(int ch);
/** Unit of a channel ("rad", "N m", "N", "m"). */
const char *ea_calib_channel_unit(int ch);

/** Kind of a record. */
typedef enum ea_calib_kind {
  EA_CALIB_STATIC = 0, /**< one row per held configuration */
  EA_CALIB_RINGDOWN    /**< one held configuration, sampled at a constant rate */
} ea_calib_kind_t;

/** A measurement record as read. Arrays hold rows values (malloc'd, owned). */
typedef struct ea_calib_record {
  char path[1024];            /**< file name as given (messages, report) */
  ea_calib_kind_t kind;       /**< static or ring-down */
  char arm_file[1024];        /**< '# arm_file:' ("" when absent; informative) */
  char source[256];           /**< '# source:' ("" when absent) */
  double noise[EA_CALIB_NCH]; /**< header noise per channel (tip x and y share
                                   noise_tip_m); NAN: not given (estimated) */
  double payload_kg;          /**< '# payload_kg:' [kg] (0 when absent or unknown) */
  int payload_unknown;        /**< 1: '# payload_kg: unknown' (or the caller marked it): every
                                   row carries the one unknown payload the fit estimates
                                   (EA_CALIB_P_PAYLOAD); a payload_kg column is ignored */
  int has[EA_CALIB_NCH];      /**< 1: the channel's column is present */
  int rows;                   /**< data rows */
  int *line;                  /**< file line of each row (1-based) */
  double *cable_length;       /**< static: commanded cable length per row [m] */
  double *payload;            /**< static: payload per row [kg] */
  double *t;                  /**< ring-down: time [s] */
  double *ch[EA_CALIB_NCH];   /**< per channel: values per row (NULL: absent) */
  double hold_cable_length;   /**< ring-down: '# cable_length_m:' [m] */
  double hold_theta0;         /**< ring-down: '# theta0_rad:' [rad] */
  double dt;                  /**< ring-down: sampling interval [s] */
} ea_calib_record_t;

/** Read a record file. Errors name file:line:column, the column and the value
 *  (an unknown or duplicate column, a missing required column or header, a value
 *  that is not a finite number, a row with too few or too many fields, a
 *  non-positive cable length, a time that does not advance at a constant rate).
 * @param[out] rec  filled on success (free with ea_calib_record_free); zeroed on failure */
ea_status_t ea_calib_record_read(const char *path, ea_calib_record_t *rec, ea_error_t *err);
/** The same from text (len bytes) named name in messages. */
ea_status_t ea_calib_record_parse(const char *name, const char *text, size_t len,
                                  ea_calib_record_t *rec, ea_error_t *err);
/** Free the arrays; a zeroed record is a no-op. */
void ea_calib_record_free(ea_calib_record_t *rec);

/* ------------------------------------------------------------------------ */
/* Ring-downs: damped sinusoids                                              */
/* ------------------------------------------------------------------------ */

/** Most modes fitted in one ring-down. */
#define EA_CALIB_MAX_MODES 6
/** Samples of a ring-down fitted, its first (8.192 s at 1 kHz): a ring-down's frequencies and
 *  decays are in its first decay times, and the fit's cost grows with the samples. */
#define EA_CALIB_RINGDOWN_MAX_SAMPLES 8192

/** A ring-down fitted by y_c(t) = o_c + sum_k exp(-sigma_k t) (a_ck cos w_k t +
 *  b_ck sin w_k t), the decay rates sigma_k and damped frequencies w_k shared by
 *  every channel c. */
typedef struct ea_ringdown_fit {
  ea_status_t status;
  int modes;                              /**< modes found and fitted */
  double freq_hz[EA_CALIB_MAX_MODES];     /**< undamped natural frequency sqrt(w^2 + sigma^2)
                                               / 2 pi [Hz], ascending */
  double freq_se_hz[EA_CALIB_MAX_MODES];  /**< its standard error [Hz] */
  double zeta[EA_CALIB_MAX_MODES];        /**< damping ratio sigma / sqrt(w^2 + sigma^2) */
  double zeta_se[EA_CALIB_MAX_MODES];     /**< its standard error */
  double sigma[EA_CALIB_MAX_MODES];       /**< decay rate [1/s] */
  double omega_d[EA_CALIB_MAX_MODES];     /**< damped angular frequency [rad/s] */
  double spectrum_hz[EA_CALIB_MAX_MODES]; /**< the spectrum's peak that started each mode [Hz] */
  int mode_index[EA_CALIB_MAX_MODES];     /**< FE mode (0-based) each fitted mode is, set by
                                               ea_calib_fit (-1: not matched) */
  double offset[EA_CALIB_NCH];            /**< o_c */
  double amp[EA_CALIB_NCH][EA_CALIB_MAX_MODES][2]; /**< (a_ck, b_ck) */
  double noise[EA_CALIB_NCH]; /**< noise used per channel (header, else the residual) */
  double rms[EA_CALIB_NCH];   /**< RMS residual per channel (NAN: absent) */
  int iterations;             /**< trust-region iterations */
} ea_ringdown_fit_t;

/** Fit up to max_modes damped sinusoids to a ring-down record (its first
 *  EA_CALIB_RINGDOWN_MAX_SAMPLES samples): the FFT (the falling half
 *  of a Hann window, zero padding, GSL's real FFT) of every channel gives the starting frequencies
 * (the highest peaks of the summed normalised spectra, well above its median), the amplitudes come
 * from linear least squares, then a trust-region nonlinear least squares fit (gsl_multifit_nlinear)
 * of all of it. EA_ERR_NOCONV when it does not converge; EA_ERR_INPUT when no mode stands out of
 * the noise. */
ea_status_t ea_ringdown_fit(const ea_calib_record_t *rec, int max_modes, double max_hz,
                            ea_ringdown_fit_t *fit, ea_error_t *err);
/** The fitted curve of channel ch at time t. */
double ea_ringdown_eval(const ea_ringdown_fit_t *fit, int ch, double t);

/* ------------------------------------------------------------------------ */
/* The fit                                                                   */
/* ------------------------------------------------------------------------ */

/** Physical parameters the fit can estimate. */
enum {
  EA_CALIB_P_EI = 0,   /**< beam.EI_Nm2 [N m^2] */
  EA_CALIB_P_RHO,      /**< beam.rho_kg_per_m [kg/m] */
  EA_CALIB_P_M_HAND,   /**< hand.mass_kg [kg] */
  EA_CALIB_P_X_C,      /**< cable.root_x_m [m] */
  EA_CALIB_P_Y_C,      /**< cable.root_y_m [m] */
  EA_CALIB_P_EA_CABLE, /**< cable.EA_N [N] */
  EA_CALIB_P_I_HAND,   /**< hand.Izz_kg_m2 [kg m^2] */
  EA_CALIB_P_PAYLOAD,  /**< the unknown payload of the records marked payload_unknown [kg]: not
                            an arm parameter (not in ea_arm_t, not written to the arm file);
                            tip mass = hand mass + this on the marked records' rows */
  EA_CALIB_NP
};
/** Short name of a parameter ("EI", "rho", "m_hand", "x_c", "y_c", "EA_c", "I_L", "payload"). */
const char *ea_calib_param_name(int k);
/** Arm-file key ("beam.EI_Nm2", ...). */
const char *ea_calib_param_key(int k);
/** A parameter by short name or arm-file key; EA_ERR_ARG if unknown. */
ea_status_t ea_calib_param_parse(const char *name, int *k);
/** 1 if parameter k is an arm-file parameter (all but EA_CALIB_P_PAYLOAD). */
int ea_calib_param_is_arm(int k);
/** The parameter's value in arm (NAN for EA_CALIB_P_PAYLOAD; set ignores it). */
double ea_calib_param_get(const ea_arm_t *arm, int k);
void ea_calib_param_set(ea_arm_t *arm, int k, double v);

/** Settings of the fit. */
typedef struct ea_calib_settings {
  unsigned fix_mask;    /**< bit k (EA_CALIB_P_*): hold parameter k at the prior */
  int fix_damping;      /**< 1: keep the prior's damping ratios */
  int damping_at_start; /**< 1 (default): mode 1's ratio is written as the ring-downs' strain-rate
                             damping coefficient gives it at the records' start (the first static
                             row), the convention of ea_traj_simulate (one coefficient, set by
                             zeta_1 at a simulation's start); 0: the weighted mean of the
                             ring-downs' ratios (damping modal, the same ratio everywhere) */
  int max_iter;         /**< trust-region iterations (default 100) */
  double ident_se;      /**< a parameter combination whose standard error exceeds this is
                             not identifiable: relative for EI, rho, m_hand, EA_c, I_L, in
                             units of the beam length for x_c, y_c (default 0.5: a parameter
                             known to +-50 % is fitted, its error reported; holding it at a
                             wrong prior would bias the others) */
  int modes;            /**< FE modes matched to a ring-down's sinusoids, 1..EA_CALIB_MAX_MODES
                             (default 3); every ring-down is fitted with up to
                             EA_CALIB_MAX_MODES sinusoids (harmonics of a large motion too) */
  int fe_elements;      /**< FE elements of the frequency model (default EA_FE_DEFAULT_ELEMENTS) */
  double payload_start; /**< starting value of the unknown payload [kg] (default 0) */
  double payload_scale; /**< its scale [kg] (default 0: the prior's hand mass): the fit's unknown
                             is (payload - payload_start) / payload_scale, and ident_se is in
                             units of it */
  double freq_floor;    /**< relative floor of a measured frequency's standard error: the FE
                             model's own error against the arm (default 1e-3) */
} ea_calib_settings_t;

void ea_calib_settings_default(ea_calib_settings_t *s);

/** How a parameter was treated. */
typedef enum ea_calib_state {
  EA_CALIB_FITTED = 0,     /**< estimated from the records */
  EA_CALIB_FIXED,          /**< held at the prior by the caller (fix_mask) */
  EA_CALIB_UNIDENTIFIABLE, /**< the records cannot tell it: held at the prior, said in notes */
  EA_CALIB_UNUSED,         /**< not in the model: the payload when no record marks it unknown */
} ea_calib_state_t;

/** Most identifiability notes. */
#define EA_CALIB_MAX_NOTES 12

/** Residuals of one record against its noise. */
typedef struct ea_calib_record_fit {
  ea_calib_kind_t kind;
  int n;                             /**< residuals (values compared) */
  double chi2;                       /**< sum of (residual / noise)^2 */
  double noise[EA_CALIB_NCH];        /**< noise used per channel (NAN: channel absent) */
  int noise_estimated[EA_CALIB_NCH]; /**< 1: not in the header, estimated by the fit */
  double rms[EA_CALIB_NCH];          /**< RMS residual per channel, in its unit (NAN: absent) */
  /* static: per row */
  double *alpha;              /**< fitted cable angle per row [rad] */
  double *pred[EA_CALIB_NCH]; /**< model value per row and channel */
  /* ring-down */
  ea_ringdown_fit_t ring;                   /**< the damped-sinusoid fit */
  double model_freq_hz[EA_CALIB_MAX_MODES]; /**< FE frequency of each fitted mode on the
                                                 calibrated arm [Hz] */
} ea_calib_record_fit_t;

/** Result of ea_calib_fit. */
typedef struct ea_calib_result {
  ea_status_t status;
  ea_arm_t prior; /**< the prior arm */
  ea_arm_t arm;   /**< the calibrated arm */
  ea_calib_state_t state[EA_CALIB_NP];
  double value[EA_CALIB_NP];              /**< estimate (SI) */
  double se[EA_CALIB_NP];                 /**< standard error (SI; NAN unless fitted) */
  double corr[EA_CALIB_NP * EA_CALIB_NP]; /**< correlations of the fitted parameters */
  int n_notes;
  char notes[EA_CALIB_MAX_NOTES][1024]; /**< identifiability, in words */
  int n_sv;
  double sv[EA_CALIB_NP]; /**< singular values of the noise-weighted Jacobian of the
                               fitted parameters (log for positive ones) at the solution */
  /* damping */
  int n_zeta; /**< damping ratios estimated (modes 1..n_zeta) */
  double zeta[EA_ARM_MAX_DAMPED_MODES], zeta_se[EA_ARM_MAX_DAMPED_MODES];
  int zeta_count[EA_ARM_MAX_DAMPED_MODES]; /**< ring-downs each came from */
  /* per record */
  int nrec;
  ea_calib_record_fit_t *rec;   /**< nrec entries (owned) */
  int contributes[EA_CALIB_NP]; /**< bit r (r < 32): record r informs parameter k */
  int n_residuals;              /**< residuals in the fit */
  int iterations;               /**< trust-region iterations */
  double chi2;                  /**< sum over the records */
  int dof;                      /**< residuals - fitted parameters - nuisance angles */
  double time_s;                /**< [s] wall time */
} ea_calib_result_t;

/** Fit the arm's parameters to the records.
 *
 * Static records: each row's configuration is its commanded cable length and a cable
 * angle (a nuisance parameter per row, fitted with the arm); every measured channel is a
 * residual against the elastica statics (ea_statics.h), weighted by its noise.
 * Ring-downs: damped sinusoids (ea_ringdown_fit) give frequencies and damping ratios; the
 * FE frequencies (eq. 24) at the hold are fitted to the frequencies; the damping ratios
 * are the weighted means over the ring-downs. Parameters the records cannot separate
 * (singular values of the noise-weighted Jacobian) are held at the prior and named in
 * res->notes. Trust-region Levenberg-Marquardt (gsl_multifit_nlinear).
 * @param[in]  prior  starting arm (its other values are kept)
 * @param[in]  recs   nrec records
 * @param[out] res    result (free with ea_calib_result_free), also on failure
 * @return EA_OK; EA_ERR_NOCONV when the fit does not converge; EA_ERR_INPUT for records
 *         that do not fit the arm (a configuration without a static solution) */
ea_status_t ea_calib_fit(const ea_arm_t *prior, const ea_calib_record_t *recs, int nrec,
                         const ea_calib_settings_t *s, ea_calib_result_t *res, ea_error_t *err);
void ea_calib_result_free(ea_calib_result_t *res);

/** Write the calibrated arm as an arm file (data/elasticarm.yaml's structure, loadable by
 *  ea_arm_load): every fitted value with a comment "estimate +- standard error, from
 *  RECORDS", held ones with why. recs: the records the result came from (their paths). */
ea_status_t ea_calib_write_arm(FILE *fp, const ea_calib_result_t *res,
                               const ea_calib_record_t *recs, const char *prior_path,
                               ea_error_t *err);
/** Write the JSON report: estimates, standard errors, correlations, each record's
 *  residual against its noise, identifiability. */
ea_status_t ea_calib_write_report(FILE *fp, const ea_calib_result_t *res,
                                  const ea_calib_record_t *recs, const char *prior_path,
                                  ea_error_t *err);
/** Write any arm as an arm file with optional comments per parameter (comment[k] for
 *  EA_CALIB_P_k, NULL or "" for none) and a header comment (NULL: none). */
ea_status_t ea_arm_write_yaml(FILE *fp, const ea_arm_t *arm, const char *header,
                              const char *const comment[EA_CALIB_NP], const char *damping_comment,
                              ea_error_t *err);

#ifdef __cplusplus
}
#endif
#endif /* EA_CALIB_H */
