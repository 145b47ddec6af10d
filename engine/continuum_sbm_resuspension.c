/* continuum_sbm_resuspension.c — steady SBM resuspension profile
 * (see continuum_sbm_resuspension.h). */
#include "continuum_sbm_resuspension.h"

#include <math.h>
#include <stddef.h>

static const double GL_X[5] = {-0.9061798459386640, -0.5384693101056831, 0.0, 0.5384693101056831,
                               0.9061798459386640};
static const double GL_W[5] = {0.2369268850561891, 0.4786286704993665, 0.5688888888888889,
                               0.4786286704993665, 0.2369268850561891};

/* integrand in v: eta(s)/s^2 ds/dv with s = sb v^m */
static double integrand(const lub_normal_law *L, double sb, int m, double v, lub_resusp_work *w)
{
    if (!(v > 0.0))
        return 0.0;
    if (L->kind == LUB_NLAW_POWER) /* lambda m s_b^(n-1) v^(m(n-1)-1): no s to underflow */
        return L->lambda * (double)m * pow(sb, L->n - 1.0) * pow(v, m * (L->n - 1.0) - 1.0);
    double vm1 = pow(v, m - 1), s = sb * vm1 * v;
    if (!(s > 0.0)) {
        if (w)
            w->underflow = 1;
        return 0.0;
    }
    const double eta = lub_normal_law_eta_s(L, s);
    if (w && (eta == 0.0 || fpclassify(eta) == FP_SUBNORMAL))
        w->underflow = 1;
    /* eta/s^2 m sb v^(m-1) = (eta/s) m/v: s^2 underflows (to 0 or a subnormal) long before eta/s
     * does for a law eta ~ s^n with n < 2 */
    return eta / s * (double)m / v;
}

/* one panel; counts it against the bound (and sees a stop request) */
static double gl5(const lub_normal_law *L, double sb, int m, double a, double b, lub_resusp_work *w)
{
    if (w) {
        if (w->status)
            return 0.0;
        if (w->stop && *w->stop) {
            w->status = LUB_RESUSP_STOPPED;
            return 0.0;
        }
        if (w->max_panels > 0 && ++w->panels > w->max_panels) {
            w->status = LUB_RESUSP_BUDGET;
            return 0.0;
        }
    }
    double c = 0.5 * (a + b), h = 0.5 * (b - a), acc = 0.0;
    for (int k = 0; k < 5; ++k)
        acc += GL_W[k] * integrand(L, sb, m, c + h * GL_X[k], w);
    return acc * h;
}

static double adapt(const lub_normal_law *L, double sb, int m, double a, double b, double whole,
                    double tol, int depth, lub_resusp_work *w)
{
    double c = 0.5 * (a + b);
    double left = gl5(L, sb, m, a, c, w), right = gl5(L, sb, m, c, b, w), est = left + right;
    /* the floor 4e-16 |est| stops refinement at round-off (no runaway recursion) */
    if (depth <= 0 || fabs(est - whole) <= fmax(tol, 4e-16 * fabs(est)) || (w && w->status))
        return est;
    return adapt(L, sb, m, a, c, left, 0.5 * tol, depth - 1, w) +
           adapt(L, sb, m, c, b, right, 0.5 * tol, depth - 1, w);
}

/* int_{v1}^{v2} of the integrand, 8 panels each refined adaptively */
static double integral_v(const lub_normal_law *L, double sb, int m, double v1, double v2,
                         lub_resusp_work *w)
{
    double acc = 0.0;
    const int P = 8;
    for (int i = 0; i < P; ++i) {
        double a = v1 + (v2 - v1) * i / P, b = v1 + (v2 - v1) * (i + 1) / P;
        double g = gl5(L, sb, m, a, b, w);
        acc += adapt(L, sb, m, a, b, g, 1e-14 * fabs(g) + 1e-300, 24, w);
    }
    return acc;
}

int lub_resusp_solve(const lub_normal_law *L, double shields, double inventory, lub_resusp *out,
                     const char **why)
{
    return lub_resusp_solve_bounded(L, shields, inventory, NULL, out, why);
}

int lub_resusp_solve_bounded(const lub_normal_law *L, double shields, double inventory,
                             lub_resusp_work *work, lub_resusp *out, const char **why)
{
    if (!(shields > 0.0) || !(inventory > 0.0) || !isfinite(shields) || !isfinite(inventory)) {
        *why = "shields and inventory must be finite and > 0";
        return -1;
    }
    if (!(L->phi_m > 0.0 && L->phi_m < 1.0)) {
        *why = "phi_m must be in ]0,1[";
        return -1;
    }
    if (L->kind == LUB_NLAW_POWER && !(L->n > 1.0 && L->lambda > 0.0)) {
        *why = "power law needs lambda > 0 and n > 1 (n <= 1 gives an unbounded height)";
        return -1;
    }
    if (L->kind == LUB_NLAW_OZENDA_M4 && L->direction == 3) {
        *why = "the Ozenda M4 closure has eta_33 = 0 (tau_zz = 0): no resuspension along the "
               "vorticity direction";
        return -1;
    }
    double target = inventory / shields;
    /* bracket s_b: eta increases without bound for every law */
    double lo = 0.0, hi = 1.0;
    int k = 0;
    while (lub_normal_law_eta_s(L, hi) < target && k++ < 2000) {
        lo = hi;
        hi *= 2.0;
    }
    if (!(lub_normal_law_eta_s(L, hi) >= target)) {
        *why = "the normal viscosity law does not reach inventory/Sh";
        return -1;
    }
    for (int it = 0; it < 300 && hi - lo > 1e-16 * hi; ++it) {
        double mid = 0.5 * (lo + hi);
        if (lub_normal_law_eta_s(L, mid) < target)
            lo = mid;
        else
            hi = mid;
    }
    double sb = 0.5 * (lo + hi);
    /* monotonicity of the law below s_b (note §5 N12) */
    double prev = 0.0;
    for (int i = 1; i <= 400; ++i) {
        double e = lub_normal_law_eta_s(L, sb * i / 400.0);
        if (!(e >= prev) || !isfinite(e)) {
            *why = "the normal viscosity law is not increasing in phi below the floor value";
            return -1;
        }
        prev = e;
    }
    out->work = work;
    out->shields = shields;
    out->inventory = inventory;
    out->s_bottom = sb;
    out->phi_bottom = L->phi_m * sb / (1.0 + sb);
    out->m = 2;
    if (L->kind == LUB_NLAW_POWER && L->n < 1.5) {
        double m = ceil(1.0 / (L->n - 1.0)); /* integrand ~ v^{m(n-1)-1}, keep it >= v^0 */
        if (!(m <= 1e6)) {
            *why = "power law with n too close to 1 (n - 1 < 1e-6): the substitution exponent "
                   "ceil(1/(n-1)) of the quadrature is too large";
            return -1;
        }
        out->m = (int)m;
    }
    out->height = lub_resusp_y_of_s(L, out, 0.0);
    if (work && work->status) {
        *why = work->status == LUB_RESUSP_STOPPED
                   ? "stopped by a request before the height was computed"
                   : "the quadrature of the height gave up at its bound of panels";
        return -1;
    }
    if (!isfinite(out->height)) {
        *why = "the resuspended height is not finite";
        return -1;
    }
    return 0;
}

double lub_resusp_y_of_s(const lub_normal_law *L, const lub_resusp *r, double s)
{
    double sb = r->s_bottom;
    if (s >= sb)
        return 0.0;
    double first = r->inventory / r->phi_bottom, second = 0.0;
    if (s > 0.0) {
        double phi = L->phi_m * s / (1.0 + s);
        second = r->shields * lub_normal_law_eta_s(L, s) / phi;
    }
    double v1 = s > 0.0 ? pow(s / sb, 1.0 / r->m) : 0.0;
    double I = integral_v(L, sb, r->m, v1, 1.0, r->work);
    return first - second + r->shields / L->phi_m * I;
}

double lub_resusp_phi_at(const lub_normal_law *L, const lub_resusp *r, double y)
{
    if (y <= 0.0)
        return r->phi_bottom;
    if (y >= r->height)
        return 0.0;
    double lo = 0.0, hi = r->s_bottom; /* y(lo) = height > y > y(hi) = 0 */
    for (int it = 0; it < 200 && hi - lo > 1e-15 * r->s_bottom; ++it) {
        double mid = 0.5 * (lo + hi);
        if (lub_resusp_y_of_s(L, r, mid) > y)
            lo = mid;
        else
            hi = mid;
    }
    double s = 0.5 * (lo + hi);
    return L->phi_m * s / (1.0 + s);
}

void lub_resusp_profile(const lub_normal_law *L, const lub_resusp *r, int n, double *y, double *phi)
{
    if (n < 2)
        return;
    /* running integral from v = 1 down to v_k: O(n) for the whole profile */
    double I = 0.0, v_prev = 1.0, first = r->inventory / r->phi_bottom;
    for (int k = 0; k < n; ++k) {
        double v = 1.0 - (double)k / (double)(n - 1);
        double s = r->s_bottom * pow(v, r->m);
        phi[k] = L->phi_m * s / (1.0 + s);
        if (k == 0) {
            y[k] = 0.0;
            continue;
        }
        double w = gl5(L, r->s_bottom, r->m, v, v_prev, r->work);
        I += adapt(L, r->s_bottom, r->m, v, v_prev, w, 1e-14 * fabs(w) + 1e-300, 24, r->work);
        v_prev = v;
        double second = s > 0.0 ? r->shields * lub_normal_law_eta_s(L, s) / phi[k] : 0.0;
        y[k] = (k == n - 1) ? r->height : first - second + r->shields / L->phi_m * I;
    }
}

double lub_resusp_height_n2(double lambda, double phi_m, double shields, double inventory)
{
    double s0 = sqrt(inventory / (shields * lambda));
    return 2.0 * lambda * shields / phi_m * (s0 + 0.5 * s0 * s0);
}
