/* stats.h — steady-state detection and error bars for sampled time series (generic; used by
 * every scene that averages a fluctuating observable).
 *
 * Rules (also in the README):
 *  - End of the transient: MSER-5 (White 1997; Marginal Standard Error Rule on batch means of
 *    5 samples): the truncation d minimises  sum_{k>=d} (y_k - mean_{>=d})^2 / (m - d)^2  over
 *    the batch means y, searched over d = 0 .. m/2 only (integer division: about the first
 *    half). A series whose optimum falls in the search limit region, the last two cuts the
 *    search reaches (d >= m/2 - 1), is flagged "not steady": a transient still going on puts
 *    the optimum at the limit, and one batch of noise can move it one cut before. (Until
 *    2026-12-07 this comment said d > m/2 - 1, the limit alone; the code has always flagged
 *    both, and the resuspension height_steady verdicts were made with it.)
 *    Callers may impose a minimum start (e.g. a minimum strain) and take the later of the two.
 *  - Standard error of the mean of the retained samples: batch means with an AR(1)
 *    correction. The series is halved by averaging neighbours (Flyvbjerg-Petersen blocking)
 *    down to the coarsest level that keeps >= LUB_STATS_MIN_BATCHES (32) batch means; with
 *    s the standard error of the mean of those m batch means (sample variance / m) and r
 *    their lag-1 autocorrelation, clipped to [0, LUB_STATS_MAX_LAG1], the estimate is
 *    s sqrt((1 + r)/(1 - r)), the standard error of the mean of an AR(1) sequence of lag-1
 *    correlation r. The correction carries the error of correlations that outlast one batch:
 *    the plain blocking plateau needs batches of several correlation times, which a short run
 *    cannot give. (Before, the estimate was the largest plain blocking SEM over the levels
 *    keeping >= 16 blocks; on 10-strain simple-shear runs it was 1.5-3x below the scatter of
 *    independent runs for phi, see the README "Steady state and error bars".) An effective
 *    number of independent samples is n_eff = var / sem^2.
 *  - Steady-state verdict (drift test): the retained samples are split in two halves; the run
 *    is "steady" when |mean_1 - mean_2| <= 3 sqrt(sem_1^2 + sem_2^2) (SEMs as above, each half
 *    >= 32 samples). The MSER flag alone is not the verdict: on a stationary noisy series its
 *    optimum often falls late by chance. Short correlated windows raise false alarms well
 *    above the 0.27 % of a normal z: the halves' SEMs, from 32 batch means over a few
 *    correlation times, are too small on average. Measured on stationary AR(1) series of
 *    correlation time tau (60000-140000 each): P(|z| > 3) = 7.1 % over a window of 6 tau, 3.9 % at
 *    10 tau, 1.6 % at 20 tau, 0.7 % at 40 tau (var(z) 2.6 / 1.9 / 1.25 / 1.03); shear.stats
 *    checks the first three.
 *  - "Known to x %" (the /target_rel_error stop): a one-sided 90 % upper confidence bound of
 *    sem / |mean| is <= x/100 (lub_stats_sem_upper_factor below; until 2026-12-07 the sem
 *    itself, which a stop at the first low estimate undercut).
 * All functions are pure: they read the arrays and write the outputs; no allocation except
 * lub_stats_sem, which uses a caller-provided scratch array of n doubles.
 */
#ifndef LUBDEM_STATS_H
#define LUBDEM_STATS_H

#include <stddef.h>

/* Batch means kept at the level the error bar is read from, and the clip of their lag-1
 * autocorrelation (sqrt((1 + r)/(1 - r)) <= 6.2). */
#define LUB_STATS_MIN_BATCHES 32
#define LUB_STATS_MAX_LAG1 0.95

typedef struct {
    size_t start; /* first sample of the steady part */
    size_t n;     /* samples used */
    double mean;
    double sem;     /* standard error of the mean (AR(1)-corrected batch means); NaN if n < 32 */
    size_t batches; /* batch means the sem is read from (0 if n < 32) */
    double lag1;    /* their lag-1 correlation as the correction used it (clipped; NaN if n < 32) */
    double n_eff;   /* effective number of independent samples */
    int steady;     /* 1 if the drift test passes on the retained samples */
    double drift_z; /* (mean_2 - mean_1) / sqrt(sem_1^2 + sem_2^2) of the two halves */
} lub_stats_result;

double lub_stats_mean(const double *x, size_t n);
double lub_stats_var(const double *x, size_t n); /* unbiased sample variance */

/* MSER with batch means of `batch` samples (5 recommended). Returns the truncation index in
 * samples (a multiple of batch); *steady (may be NULL) is 0 when the cut d in batches is
 * >= m/2 - 1 (m = n / batch) or m < 4, else 1 (rule above; shear.stats pins the boundary). */
size_t lub_stats_mser(const double *x, size_t n, size_t batch, int *steady);

/* Standard error of the mean of x[0..n) (AR(1)-corrected batch means, rule above). scratch:
 * n doubles. Returns NaN if n < 32; 0 for a constant series. */
double lub_stats_sem(const double *x, size_t n, double *scratch);

/* The same estimate with its parts: *batches (unless NULL) the number m of batch means it is
 * read from, *lag1 (unless NULL) their lag-1 correlation r as the correction used it (clipped
 * to [0, LUB_STATS_MAX_LAG1]); 0 and NaN if n < 32. */
double lub_stats_sem_batches(const double *x, size_t n, double *scratch, size_t *batches,
                             double *lag1);

/* How far the sem may be below the true standard error, for a stop that must keep its promise
 * (the /target_rel_error stop of simple_shear). sem^2 = s^2 (1 + r)/(1 - r) has two noisy
 * parts: the variance s^2 of m batch means (m - 1 degrees of freedom when they are
 * independent; with a lag-1 correlation r (AR(1)) var s^2 is (1 + r^2)/(1 - r^2) times larger)
 * and their lag-1 correlation r (var r = (1 - r^2)/m, Bartlett). To first order
 * var ln sem^2 = 2 (1 + r^2)/((m - 1)(1 - r^2)) + 4/((1 - r^2) m); lub_stats_sem_dof is the
 * dof nu of the chi-square variable with the same variance of its logarithm (2/nu):
 * nu = (1 - r^2)/((1 + r^2)/(m - 1) + 2/m), NaN if m < 2 or r is NaN or >= 1 (10.5 for m = 32,
 * r = 0; 9.3 for r = 0.3; 6.2 for m = 63, r = 0.8; 0.8 at the clip r = 0.95 with m = 32).
 * lub_stats_chi2_quantile is the Wilson-Hilferty approximation of the chi-square quantile of
 * nu degrees of freedom at the standard normal quantile z (at z = -1.28: within 1.5 % of the
 * exact quantile for nu >= 3; below it for smaller nu, which errs on the safe side; 0 where
 * the cube root's argument is negative). lub_stats_sem_upper_factor is
 * sqrt(nu / chi2_{0.10}(nu)): sem times it is a one-sided 90 % upper confidence bound of the
 * standard error (1.42 for m = 32, r = 0; 1.46 for r = 0.3; 1.26 for m = 63, r = 0; 1.63 for
 * r = 0.8; infinite if the quantile is 0; NaN with nu). */
#define LUB_STATS_SEM_UPPER_Z 1.2815515655446004 /* the standard normal's 90 % quantile */
double lub_stats_sem_dof(size_t batches, double lag1);
double lub_stats_chi2_quantile(double dof, double z);
double lub_stats_sem_upper_factor(size_t batches, double lag1);

/* Drift z-score of the two halves of x[0..n) (NaN if a half has < 32 samples). */
double lub_stats_drift_z(const double *x, size_t n, double *scratch);

/* Whole analysis: start = max(MSER truncation, min_start); mean and its standard error after it;
 * drift test on the retained samples. */
void lub_stats_analyse(const double *x, size_t n, size_t min_start, double *scratch,
                       lub_stats_result *r);

/* The same analysis over the window x[start..n) chosen by the caller (no MSER truncation of
 * its own): series averaged over one common window keep their linear relations (stress parts
 * that add up to their total). start > n is taken as n. */
void lub_stats_analyse_window(const double *x, size_t n, size_t start, double *scratch,
                              lub_stats_result *r);

/* Ratio of two time averages over the same samples, R = mean(x)/mean(y) (e.g. mu =
 * <sigma_xy>/<P> at imposed volume, where the mean of the sampled ratios x_k/y_k is biased by
 * the fluctuations of y), and its standard error by the delta method: the SEM (rule above) of
 * z_k = (x_k - R y_k)/mean(y). z and scratch: n doubles each (z receives that series).
 * *ratio is NaN if mean(y) is 0 or n is 0; *sem is NaN if n < 32 or *ratio is not finite.
 * *batches and *lag1 (unless NULL): as lub_stats_sem_batches gives them for z (0 and NaN
 * without a sem). */
void lub_stats_ratio(const double *x, const double *y, size_t n, double *z, double *scratch,
                     double *ratio, double *sem, size_t *batches, double *lag1);

#endif
