/* simple_shear_series.h — the sampled time series of a `simple_shear` run and their steady-state
 * statistics: the end of the transient, the means and standard errors the summary reports, and
 * the /target_rel_error check ("run until mu is known to 2 %"). The estimators are those of
 * stats.h (MSER-5 truncation, AR(1)-corrected batch means, drift test); the README's "Steady
 * state and error bars" states the rules.
 *
 * Units: each series is in the run's units (stress in eta gd or P, see scene_simple_shear.c);
 * strain is the shear strain of the sampled configuration.
 *
 * Ownership: a lub_ss_series owns its arrays (lub_ss_series_reserve allocates and grows them,
 * lub_ss_series_free releases them); zero it before first use. Error behaviour: reserve returns
 * -1 when out of memory (the arrays keep their contents); the checkpoint functions return -1
 * with the message in lub_ckpt_error. The statistics are pure functions of the series (they use
 * the series' own scratch arrays).
 */
#ifndef LUBDEM_SIMPLE_SHEAR_SERIES_H
#define LUBDEM_SIMPLE_SHEAR_SERIES_H

#include <stddef.h>

#include "checkpoint_file.h"
#include "simple_shear_spec.h"

/* The observables of a sample, in summary order (lub_ss_obs_names). */
enum {
    SS_OBS_PHI,
    SS_OBS_P, /* -sigma_yy */
    SS_OBS_MU,
    SS_OBS_ETA, /* eta_r = sigma_xy/(eta gd) */
    SS_OBS_IV,
    SS_OBS_SXY,
    SS_OBS_ETA11,
    SS_OBS_ETA22,
    SS_OBS_ETA33,
    SS_OBS_L1, /* sigma_11/sigma_22 */
    SS_OBS_L3, /* sigma_33/sigma_22 */
    SS_OBS_Z,
    SS_OBS_ZC,
    SS_OBS_XY_NC,
    SS_OBS_XY_SC,
    SS_OBS_XY_NL,
    SS_OBS_XY_SL,
    SS_OBS_XY_KIN,
    SS_OBS_YY_NC,
    SS_OBS_YY_SC,
    SS_OBS_YY_NL,
    SS_OBS_YY_SL,
    SS_OBS_YY_KIN,
    SS_OBS_CRUSHED,
    SS_OBS_SLIDING,
    SS_OBS_Q6,
    SS_OBS_COUNT
};

/* The summary's (and the checkpoint's "series/") name of each observable. */
extern const char *const lub_ss_obs_names[SS_OBS_COUNT];

typedef struct {
    double *v[SS_OBS_COUNT];   /* v[k][i]: observable k at sample i */
    double *strain;            /* strain of sample i */
    size_t n, cap;             /* samples held, room */
    double *scratch, *ratio_z; /* cap doubles each, for the estimators */
} lub_ss_series;

/* Grows the arrays to hold cap samples; 0, or -1 (no memory; contents kept). */
int lub_ss_series_reserve(lub_ss_series *ser, size_t cap);
void lub_ss_series_free(lub_ss_series *ser);

/* Appends one sample (values in lub_ss_obs_names order) when there is room; 0, or -1 (full:
 * the sample is not kept; the room is reserved for the whole run beforehand). */
int lub_ss_series_append(lub_ss_series *ser, double strain, const double values[SS_OBS_COUNT]);

/* End of the transient: the first sample at or after transient_strain, moved later to the
 * latest MSER-5 truncation of the control-relevant series (phi and mu at imposed pressure,
 * P and eta_r at imposed volume), which are written to watch[] (terminated by -1) unless
 * watch is NULL. The summary's steady window starts there; so does the target-error stop's. */
size_t lub_ss_steady_start(const lub_ss_series *ser, int pressure, double transient_strain,
                           int watch[3]);

/* The /target_rel_error check: 1 when the summary written now would call the run steady (no
 * drift of any watched series) and the headline (mu at imposed pressure, eta_r at imposed
 * volume), averaged over at least /target_min_strain (mu: from the later of sigma_xy's and P's
 * own starts), is known to /target_rel_error of its mean at 90 % confidence: its standard
 * error times lub_stats_sem_upper_factor (a one-sided 90 % upper confidence bound, stats.h) is
 * at most /target_rel_error |mean|. *chk (unless NULL) receives the check's record over the
 * headline's window, whether the window qualifies or not; *zero_mean (unless NULL) is set when
 * that window is steady with a mean of 0, which has no relative error. */
typedef struct {
    double rel_error; /* the standard error over |mean| (NaN: no error bar or a mean of 0) */
    double rel_bound; /* its 90 % upper confidence bound, the value the stop tests */
    size_t batches;   /* batch means the error is read from (0: none) */
    double lag1;      /* their lag-1 correlation as the AR(1) correction used it */
    double dof;       /* the chi-square degrees of freedom of the bound (lub_stats_sem_dof) */
} lub_ss_target_check;
int lub_ss_target_reached(const lub_ss_params *p, lub_ss_series *ser, int *zero_mean,
                          lub_ss_target_check *chk);

/* The steady-state statistics of every observable over the summary's window, and of the ratio
 * observables (mu, sigma11/sigma22, sigma33/sigma22, Iv) over theirs: from[k] is the first
 * sample observable k is averaged from (start, or for a ratio the later of start and its two
 * series' own MSER-5 truncations; n when nothing is left). */
typedef struct {
    size_t start;         /* first sample of the steady window */
    int steady;           /* no significant drift of the watched series after start */
    double worst_drift_z; /* largest |z| of the drift tests */
    double mean[SS_OBS_COUNT], sem[SS_OBS_COUNT];
    size_t from[SS_OBS_COUNT];
} lub_ss_steady_stats;

/* 1 for the ratio observables, whose window may start after the summary's (from[k]). */
int lub_ss_obs_is_ratio(int k);

/* gd: the shear rate, s0: the stress unit (eta gd or P) in scene units. */
void lub_ss_series_statistics(const lub_ss_params *p, double gd, double s0, lub_ss_series *ser,
                              lub_ss_steady_stats *st);

/* The series into checkpoint c ("series/strain", "series/<name>"), and back into ser (room for
 * rows samples reserved). */
int lub_ss_series_save(lub_ckpt *c, const lub_ss_series *ser);
int lub_ss_series_load(lub_ckpt *c, lub_ss_series *ser, size_t rows);

#endif
