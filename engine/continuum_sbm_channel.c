/* continuum_sbm_channel.c — steady pipe/channel migration with a congested plug
 * (see continuum_sbm_channel.h). */
#include "continuum_sbm_channel.h"

#include <math.h>

double lub_closure_phi_m(const lub_closure *c)
{
    switch (c->kind) {
    case LUB_CLOSURE_M4: return c->m4_phi_m;
    case LUB_CLOSURE_MM: return c->mm.phi_m;
    case LUB_CLOSURE_DEM: return c->dem_phi_m;
    }
    return NAN;
}

void lub_closure_eval(const lub_closure *c, double psi, double *A_r, double *A_th, double *eta_rel)
{
    switch (c->kind) {
    case LUB_CLOSURE_M4: {
        lub_texture_params p;
        const char *why;
        if (lub_m4_from_laws(&c->m4, psi, c->m4_phi_m, 1.0, &p, &why)) {
            *A_r = *A_th = 0.0;
            *eta_rel = 1.0;
            return;
        }
        lub_texture_stress st = lub_texture_steady_stress(&p);
        *A_r = st.n2 / st.eta_app; /* tau_rr = N2 since tau_thth = tau_zz(vorticity) = 0 */
        *A_th = 0.0;
        *eta_rel = st.eta_app;
        return;
    }
    case LUB_CLOSURE_MM: {
        double ep = lub_mm_eta_p(&c->mm, psi), en = lub_mm_eta_n(&c->mm, psi);
        *eta_rel = 1.0 + ep;
        *A_r = -c->mm.lambda_grad * en / (*eta_rel);
        *A_th = -c->mm.lambda_vort * en / (*eta_rel);
        return;
    }
    case LUB_CLOSURE_DEM: {
        double phi = psi * c->dem_phi_m;
        double er = lub_dem_eta_r(phi, c->dem_phi_m), e22 = lub_dem_eta22(psi);
        *eta_rel = er;
        *A_r = -e22 / er;
        *A_th = -lub_dem_lambda33(phi, c->dem_phi_rcp) * e22 / er;
        return;
    }
    }
}

static double abs_Ar(const lub_closure *c, double psi)
{
    double ar, ath, er;
    if (!(psi > 0.0))
        return 0.0;
    lub_closure_eval(c, psi, &ar, &ath, &er);
    return -ar;
}

/* psi with |A_r(psi)| = A, capped at psi*: Illinois regula falsi on the monotone bracket
 * [0, psi*] (|A_r| increases, checked by lub_channel_solve), ~10 evaluations */
static double psi_of_A(const lub_closure *c, double A, double psi_star, double A_star)
{
    if (A >= A_star)
        return psi_star;
    if (!(A > 0.0))
        return 0.0;
    double a = 0.0, b = psi_star, fa = -A, fb = A_star - A;
    int side = 0;
    for (int it = 0; it < 200 && b - a > 1e-15; ++it) {
        double x = (a * fb - b * fa) / (fb - fa);
        if (!(x > a && x < b))
            x = 0.5 * (a + b);
        double fx = abs_Ar(c, x) - A;
        if (fx == 0.0)
            return x;
        if ((fx > 0.0) == (fb > 0.0)) {
            b = x;
            fb = fx;
            if (side == -1)
                fa *= 0.5;
            side = -1;
        } else {
            a = x;
            fa = fx;
            if (side == +1)
                fb *= 0.5;
            side = +1;
        }
        if (fabs(fx) <= 1e-15 * A)
            return x;
    }
    return 0.5 * (a + b);
}

/* A_th/A_r at psi (0 for M4; constant for MM) */
static double kappa(const lub_closure *c, double psi)
{
    double ar, ath, er;
    if (!(psi > 0.0)) {
        if (c->kind == LUB_CLOSURE_MM)
            return c->mm.lambda_vort / c->mm.lambda_grad;
        if (c->kind == LUB_CLOSURE_M4)
            return 0.0;
        psi = 1e-6;
    }
    lub_closure_eval(c, psi, &ar, &ath, &er);
    return ar != 0.0 ? ath / ar : 0.0;
}

/* pipe: d lnQ / d ln r = kappa(psi(|Q|/r^2)) */
static double pipe_rhs(const lub_closure *c, double lnr, double lnQ, double ps, double As)
{
    return kappa(c, psi_of_A(c, exp(lnQ - 2.0 * lnr), ps, As));
}

static double rk4_step(const lub_closure *c, double x0, double y0, double x1, double ps, double As)
{
    double h = x1 - x0;
    double k1 = pipe_rhs(c, x0, y0, ps, As);
    double k2 = pipe_rhs(c, x0 + 0.5 * h, y0 + 0.5 * h * k1, ps, As);
    double k3 = pipe_rhs(c, x0 + 0.5 * h, y0 + 0.5 * h * k2, ps, As);
    double k4 = pipe_rhs(c, x1, y0 + h * k3, ps, As);
    return y0 + h / 6.0 * (k1 + 2.0 * k2 + 2.0 * k3 + k4);
}

/* psi on the midpoints for the wall constant q; returns the plug edge */
static double fill_psi(const lub_closure *c, const lub_channel_setup *S, double q, double As,
                       double *x, double *psi)
{
    const int n = S->n;
    const double ps = S->psi_star;
    if (S->geom == LUB_GEOM_CHANNEL) {
        for (int i = 0; i < n; ++i)
            psi[i] = psi_of_A(c, q / x[i], ps, As);
        return fmin(1.0, q / As);
    }
    if (c->kind != LUB_CLOSURE_DEM) { /* constant kappa: |Q| = q r^kappa exactly */
        double k = kappa(c, 0.0);
        for (int i = 0; i < n; ++i)
            psi[i] = psi_of_A(c, q * pow(x[i], k - 2.0), ps, As);
        return fmin(1.0, pow(q / As, 1.0 / (2.0 - k)));
    }
    /* DEM: kappa = lambda_33(psi) varies; RK4 in ln r from the wall inward */
    if (q >= As) {
        for (int i = 0; i < n; ++i)
            psi[i] = ps;
        return 1.0;
    }
    double lr = 0.0, lq = log(q), edge = 0.0;
    int i = n - 1;
    for (; i >= 0; --i) {
        double lr1 = log(x[i]);
        double lq1 = rk4_step(c, lr, lq, lr1, ps, As);
        if (exp(lq1 - 2.0 * lr1) >= As) { /* entered the plug in ]x_i, previous]: locate */
            double a = lr1, b = lr;
            for (int it = 0; it < 60; ++it) {
                double m = 0.5 * (a + b);
                double lm = rk4_step(c, lr, lq, m, ps, As);
                if (exp(lm - 2.0 * m) >= As)
                    a = m;
                else
                    b = m;
            }
            edge = exp(0.5 * (a + b));
            break;
        }
        psi[i] = psi_of_A(c, exp(lq1 - 2.0 * lr1), ps, As);
        lr = lr1;
        lq = lq1;
    }
    for (; i >= 0; --i)
        psi[i] = ps;
    return edge;
}

/* velocity (mean 1), pressure gradient, means */
static void flow(const lub_closure *c, const lub_channel_setup *S, const double *x,
                 const double *psi, double *u, double *eta_rel, double *G, double *area,
                 double *flux)
{
    const int n = S->n;
    const int pipe = S->geom == LUB_GEOM_PIPE;
    double acc = 0.0, w_sum = 0.0, mean = 0.0, wpsi = 0.0, upsi = 0.0, uw = 0.0;
    for (int i = n - 1; i >= 0; --i) {
        double ar, ath, er;
        lub_closure_eval(c, psi[i], &ar, &ath, &er);
        eta_rel[i] = er;
        double gd = (pipe ? 0.5 : 1.0) * x[i] / er; /* for G = 1 */
        u[i] = acc + 0.5 * gd / n;
        acc += gd / n;
    }
    for (int i = 0; i < n; ++i) {
        double w = pipe ? 2.0 * x[i] : 1.0; /* area weight per unit dx */
        w_sum += w;
        mean += w * u[i];
        wpsi += w * psi[i];
        upsi += w * u[i] * psi[i];
        uw += w * u[i];
    }
    mean /= w_sum;
    *G = 1.0 / mean;
    for (int i = 0; i < n; ++i)
        u[i] *= *G;
    *area = wpsi / w_sum;
    *flux = upsi / uw;
}

int lub_channel_solve(const lub_closure *c, const lub_channel_setup *S, double *x, double *psi,
                      double *u, double *pc, double *eta_rel, lub_channel_result *res,
                      const char **why)
{
    const int n = S->n;
    if (n < 4) {
        *why = "at least 4 cells";
        return -1;
    }
    if (!(S->psi_star > 0.0 && S->psi_star < 1.0)) {
        *why = "psi_star must be in ]0,1[";
        return -1;
    }
    if (!(S->psi_mean > 0.0 && S->psi_mean < S->psi_star)) {
        *why = "psi_mean must be in ]0, psi_star[";
        return -1;
    }
    /* |A_r| must increase with psi (note §5 N13) */
    double prev = 0.0;
    for (int i = 1; i <= 400; ++i) {
        double a = abs_Ar(c, S->psi_star * i / 400.0);
        if (!(a > prev) || !isfinite(a)) {
            *why = "|A_r(psi)| of the closure is not increasing up to psi_star";
            return -1;
        }
        prev = a;
    }
    const double As = abs_Ar(c, S->psi_star);
    for (int i = 0; i < n; ++i)
        x[i] = (i + 0.5) / n;
    /* ln q in ]ln As - 60, ln As]: the measure increases with q; Illinois regula falsi on the
     * bracket (bisection safeguard), about 10 profile evaluations */
    double lo = log(As) - 60.0, hi = log(As), G = 0.0, area = 0.0, flux = 0.0;
    double flo = -S->psi_mean, fhi = S->psi_star - S->psi_mean, xq = hi;
    int side = 0;
    for (int it = 0; it < 200 && hi - lo > 1e-14; ++it) {
        if (S->stop && *S->stop) {
            *why = "stopped by a request";
            return -2;
        }
        double mid = (lo * fhi - hi * flo) / (fhi - flo);
        if (!(mid > lo && mid < hi) || it % 8 == 7)
            mid = 0.5 * (lo + hi);
        fill_psi(c, S, exp(mid), As, x, psi);
        flow(c, S, x, psi, u, eta_rel, &G, &area, &flux);
        double f = (S->flux_weighted ? flux : area) - S->psi_mean;
        xq = mid;
        if (fabs(f) <= 1e-14)
            break;
        if (f < 0.0) {
            lo = mid;
            flo = f;
            if (side == -1)
                fhi *= 0.5;
            side = -1;
        } else {
            hi = mid;
            fhi = f;
            if (side == +1)
                flo *= 0.5;
            side = +1;
        }
    }
    double q = exp(xq);
    double edge = fill_psi(c, S, q, As, x, psi);
    flow(c, S, x, psi, u, eta_rel, &G, &area, &flux);
    double ar, ath, er;
    lub_closure_eval(c, S->psi_star, &ar, &ath, &er);
    double slope = S->geom == LUB_GEOM_PIPE ? G * (ar - 0.5 * ath) : G * ar; /* dp_c/dx < 0 */
    for (int i = 0; i < n; ++i)
        pc[i] = x[i] < edge ? slope * (x[i] - edge) : 0.0;
    res->q = q;
    res->x_plug = edge;
    res->psi_wall = psi_of_A(c, q, S->psi_star, As);
    res->psi_centre = edge > 0.0 ? S->psi_star : psi[0];
    res->G = G;
    res->G_newtonian = S->geom == LUB_GEOM_PIPE ? 8.0 : 3.0;
    res->psi_area = area;
    res->psi_flux = flux;
    res->pc_centre = edge > 0.0 ? -slope * edge : 0.0;
    /* the root finder ends on its bracket too: the measure jumps (no root) where |A_r| stops
     * increasing towards the axis (DEM: lambda_33 > 2 in the pipe) */
    if (!(fabs((S->flux_weighted ? flux : area) - S->psi_mean) <= LUB_CHANNEL_INVENTORY_TOL)) {
        *why = "the inventory is not met";
        return -3;
    }
    return 0;
}
