/* resuspension_analysis.c — see resuspension_analysis.h. */
#include "resuspension_analysis.h"

#include <math.h>

double lub_shields_number(double eta, double shear_rate, double drho, double g, double a)
{
    return eta * fabs(shear_rate) / (drho * g * a);
}

double lub_acrivos_number(double eta, double shear_rate, double drho, double g, double h0)
{
    return 4.5 * eta * fabs(shear_rate) / (drho * g * h0);
}

void lub_profile_normal_viscosity(const double *phi, const double *phi_err, int n, double dy,
                                  double shields, double *eta, double *eta_err)
{
    /* Sweep from the top: above[i] = sum_{j > i} phi_j dy; the bin itself contributes
     * phi_i dy / 2 from its centre to its upper edge. */
    double above = 0.0, var_above = 0.0;
    for (int i = n - 1; i >= 0; --i) {
        eta[i] = (above + 0.5 * phi[i] * dy) / shields;
        if (eta_err) {
            double vi = phi_err ? phi_err[i] * phi_err[i] : 0.0;
            eta_err[i] = sqrt(var_above + 0.25 * vi * dy * dy) / shields;
            var_above += vi * dy * dy;
        }
        above += phi[i] * dy;
    }
}

double lub_profile_inventory(const double *phi, int n, double dy)
{
    double s = 0.0;
    for (int i = 0; i < n; ++i)
        s += phi[i];
    return s * dy;
}

double lub_profile_height(const double *phi, int n, double y0, double dy, double phi_level)
{
    for (int i = n - 1; i >= 0; --i) {
        if (phi[i] >= phi_level) {
            double yc = y0 + (i + 0.5) * dy;
            if (i == n - 1)
                return yc; /* profile still above the level in the top bin */
            /* interpolate between centre i (>= level) and centre i+1 (< level) */
            double t = (phi[i] - phi_level) / (phi[i] - phi[i + 1]);
            return yc + t * dy;
        }
    }
    return NAN;
}

double lub_profile_base(const double *phi, int n, double y0, double dy, double phi_level)
{
    for (int i = 0; i < n; ++i) {
        if (phi[i] >= phi_level) {
            const double yc = y0 + (i + 0.5) * dy;
            if (i == 0)
                return yc; /* profile already at the level in the bottom bin */
            /* between centre i - 1 (< level) and centre i (>= level), as
             * resuspension_consistency.py's half_max_crossings writes it */
            const double yl = y0 + (i - 0.5) * dy;
            return yl + (phi_level - phi[i - 1]) / (phi[i] - phi[i - 1]) * (yc - yl);
        }
    }
    return NAN;
}

int lub_profile_select_bulk(const double *phi, int n, double y0, double dy, double interface_width,
                            double floor_skip, double phi_min, int *keep)
{
    double phi_max = 0.0;
    for (int i = 0; i < n; ++i)
        if (phi[i] > phi_max)
            phi_max = phi[i];
    double y_int = lub_profile_height(phi, n, y0, dy, 0.5 * phi_max);
    int kept = 0;
    for (int i = 0; i < n; ++i) {
        double yc = y0 + (i + 0.5) * dy;
        int k = phi_max > 0 && isfinite(y_int) && yc <= y_int - interface_width &&
                yc - y0 >= floor_skip && phi[i] >= phi_min;
        keep[i] = k;
        kept += k;
    }
    return kept;
}

/* The window of width `width` centred on bin i (bins of dy, n of them): the sum over the bins
 * it overlaps of w v[j] (squared = 0) or w^2 v[j]^2 (squared = 1), w the overlap, with the sum
 * of the overlaps in *overlap (width > dy). */
static double window_sum(const double *v, int n, double dy, double width, int i, int squared,
                         double *overlap)
{
    const double half = 0.5 * width;
    const int reach = (int)ceil(half / dy);
    const double lo = (i + 0.5) * dy - half, hi = (i + 0.5) * dy + half;
    double sw = 0.0, sum = 0.0;
    const int j0 = i - reach < 0 ? 0 : i - reach, j1 = i + reach >= n ? n - 1 : i + reach;
    for (int j = j0; j <= j1; ++j) {
        const double a = fmax(lo, j * dy), b = fmin(hi, (j + 1) * dy);
        if (b <= a)
            continue;
        sw += b - a;
        sum += squared ? (b - a) * (b - a) * v[j] * v[j] : (b - a) * v[j];
    }
    *overlap = sw;
    return sum;
}

double lub_profile_coarse_bin(const double *phi, int n, double dy, double width, int i)
{
    if (!(width > dy))
        return phi[i];
    double sw;
    const double sp = window_sum(phi, n, dy, width, i, 0, &sw);
    return sp / sw;
}

void lub_profile_coarse_grain(const double *phi, const double *phi_err, int n, double dy,
                              double width, double *phi_cg, double *phi_cg_err)
{
    for (int i = 0; i < n; ++i) {
        phi_cg[i] = lub_profile_coarse_bin(phi, n, dy, width, i);
        if (!phi_cg_err)
            continue;
        if (!phi_err) {
            phi_cg_err[i] = NAN;
        } else if (!(width > dy)) {
            phi_cg_err[i] = phi_err[i];
        } else {
            double sw;
            const double se = window_sum(phi_err, n, dy, width, i, 1, &sw);
            phi_cg_err[i] = sqrt(se) / sw;
        }
    }
}
