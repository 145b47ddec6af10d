/* stats.c — MSER truncation and AR(1)-corrected batch-means error bars (see stats.h). */
#include "stats.h"

#include <math.h>
#include <string.h>

double lub_stats_mean(const double *x, size_t n)
{
    if (n == 0)
        return NAN;
    double s = 0.0;
    for (size_t i = 0; i < n; ++i)
        s += x[i];
    return s / (double)n;
}

double lub_stats_var(const double *x, size_t n)
{
    if (n < 2)
        return NAN;
    double m = lub_stats_mean(x, n), s = 0.0;
    for (size_t i = 0; i < n; ++i)
        s += (x[i] - m) * (x[i] - m);
    return s / (double)(n - 1);
}

size_t lub_stats_mser(const double *x, size_t n, size_t batch, int *steady)
{
    if (batch < 1)
        batch = 1;
    size_t m = n / batch;
    if (m < 4) {
        if (steady)
            *steady = 0;
        return 0;
    }
    /* suffix sums of batch means, computed backwards: O(m) */
    double best = INFINITY;
    size_t best_d = 0;
    double s1 = 0.0, s2 = 0.0;
    /* MSER value for truncation d uses batches d..m-1; iterate d from m-1 down to 0 */
    size_t limit = m / 2;
    for (size_t dd = m; dd-- > 0;) {
        double y = 0.0;
        for (size_t k = 0; k < batch; ++k)
            y += x[dd * batch + k];
        y /= (double)batch;
        s1 += y;
        s2 += y * y;
        size_t cnt = m - dd;
        if (dd <= limit && cnt >= 2) {
            double mean = s1 / (double)cnt;
            double ss = s2 - (double)cnt * mean * mean;
            if (ss < 0)
                ss = 0;
            double val = ss / ((double)cnt * (double)cnt);
            if (val <= best) {
                best = val;
                best_d = dd;
            }
        }
    }
    /* not steady when the cut is one of the last two the search reaches, d >= m/2 - 1 */
    if (steady)
        *steady = (best_d + 1 < limit);
    return best_d * batch;
}

/* Lag-1 autocorrelation of y[0..m), 0 when the series is constant. */
static double lag1_correlation(const double *y, size_t m)
{
    double mean = lub_stats_mean(y, m), num = 0.0, den = 0.0;
    for (size_t i = 0; i < m; ++i) {
        double d = y[i] - mean;
        den += d * d;
        if (i + 1 < m)
            num += d * (y[i + 1] - mean);
    }
    return den > 0.0 ? num / den : 0.0;
}

double lub_stats_sem_batches(const double *x, size_t n, double *scratch, size_t *batches,
                             double *lag1)
{
    if (batches)
        *batches = 0;
    if (lag1)
        *lag1 = NAN;
    if (n < LUB_STATS_MIN_BATCHES)
        return NAN;
    memcpy(scratch, x, n * sizeof *x);
    size_t m = n;
    /* halve while the next level still keeps >= LUB_STATS_MIN_BATCHES batch means */
    while (m / 2 >= LUB_STATS_MIN_BATCHES) {
        size_t h = m / 2;
        for (size_t i = 0; i < h; ++i)
            scratch[i] = 0.5 * (scratch[2 * i] + scratch[2 * i + 1]);
        m = h;
    }
    double sem = sqrt(lub_stats_var(scratch, m) / (double)m);
    double r = lag1_correlation(scratch, m);
    if (r < 0.0)
        r = 0.0;
    if (r > LUB_STATS_MAX_LAG1)
        r = LUB_STATS_MAX_LAG1;
    if (batches)
        *batches = m;
    if (lag1)
        *lag1 = r;
    return sem * sqrt((1.0 + r) / (1.0 - r));
}

double lub_stats_sem(const double *x, size_t n, double *scratch)
{
    return lub_stats_sem_batches(x, n, scratch, NULL, NULL);
}

double lub_stats_sem_dof(size_t batches, double lag1)
{
    if (batches < 2 || !(lag1 >= 0.0) || !(lag1 < 1.0))
        return NAN;
    const double m = (double)batches, r2 = lag1 * lag1;
    /* var ln(sem^2) = var ln(s^2) + var ln((1 + r)/(1 - r)): 2 (1 + r^2)/((m - 1)(1 - r^2))
     * + (2/(1 - r^2))^2 (1 - r^2)/m; a chi-square variable of nu dof has var ln = 2/nu */
    return (1.0 - r2) / ((1.0 + r2) / (m - 1.0) + 2.0 / m);
}

double lub_stats_chi2_quantile(double dof, double z)
{
    if (!(dof > 0.0))
        return NAN;
    const double a = 2.0 / (9.0 * dof), c = 1.0 - a + z * sqrt(a);
    return c > 0.0 ? dof * c * c * c : 0.0;
}

double lub_stats_sem_upper_factor(size_t batches, double lag1)
{
    const double dof = lub_stats_sem_dof(batches, lag1);
    const double q = lub_stats_chi2_quantile(dof, -LUB_STATS_SEM_UPPER_Z);
    return q > 0.0 ? sqrt(dof / q) : (isnan(dof) ? NAN : INFINITY);
}

double lub_stats_drift_z(const double *x, size_t n, double *scratch)
{
    size_t h = n / 2;
    if (h < LUB_STATS_MIN_BATCHES)
        return NAN;
    double m1 = lub_stats_mean(x, h), m2 = lub_stats_mean(x + (n - h), h);
    double s1 = lub_stats_sem(x, h, scratch);
    double s2 = lub_stats_sem(x + (n - h), h, scratch);
    double den = sqrt(s1 * s1 + s2 * s2);
    if (!(den > 0))
        return (m1 == m2) ? 0.0 : INFINITY;
    return (m2 - m1) / den;
}

void lub_stats_analyse(const double *x, size_t n, size_t min_start, double *scratch,
                       lub_stats_result *r)
{
    const size_t d = lub_stats_mser(x, n, 5, NULL);
    lub_stats_analyse_window(x, n, d < min_start ? min_start : d, scratch, r);
}

void lub_stats_analyse_window(const double *x, size_t n, size_t start, double *scratch,
                              lub_stats_result *r)
{
    const size_t d = start > n ? n : start;
    r->start = d;
    r->n = n - d;
    r->mean = lub_stats_mean(x + d, r->n);
    r->sem = lub_stats_sem_batches(x + d, r->n, scratch, &r->batches, &r->lag1);
    double v = lub_stats_var(x + d, r->n);
    r->n_eff = (isfinite(r->sem) && r->sem > 0) ? v / (r->sem * r->sem) : NAN;
    r->drift_z = lub_stats_drift_z(x + d, r->n, scratch);
    r->steady = isfinite(r->drift_z) && fabs(r->drift_z) <= 3.0;
}

void lub_stats_ratio(const double *x, const double *y, size_t n, double *z, double *scratch,
                     double *ratio, double *sem, size_t *batches, double *lag1)
{
    const double mx = lub_stats_mean(x, n), my = lub_stats_mean(y, n);
    *ratio = (n > 0 && my != 0.0) ? mx / my : NAN;
    *sem = NAN;
    if (batches)
        *batches = 0;
    if (lag1)
        *lag1 = NAN;
    if (n < LUB_STATS_MIN_BATCHES || !isfinite(*ratio))
        return;
    for (size_t i = 0; i < n; ++i)
        z[i] = (x[i] - *ratio * y[i]) / my;
    *sem = lub_stats_sem_batches(z, n, scratch, batches, lag1);
}
