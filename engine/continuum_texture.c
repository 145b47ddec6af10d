/* continuum_texture.c — texture-tensor model kernel (see continuum_texture.h). */
#include "continuum_texture.h"

#include <math.h>
#include <stddef.h>

const char *lub_texture_check(const lub_texture_params *p)
{
    const double v[8] = {p->a,     p->delta1, p->delta2, p->beta1,
                         p->beta2, p->beta3,  p->eta,    p->eta_e};
    for (int i = 0; i < 8; ++i)
        if (!isfinite(v[i]))
            return "every parameter must be finite";
    /* b_e = I/a + gamma_e stays SPD only for a in ]0,1] (thesis Remark 4.1; note §5 N1) */
    if (!(p->a > 0.0 && p->a <= 1.0))
        return "a must be in ]0,1] (Gordon-Schowalter parameter; a = 0 is singular)";
    if (!(p->delta1 > 0.0))
        return "delta1 (alpha) must be > 0";
    if (!(p->eta > 0.0))
        return "eta must be > 0";
    if (!(p->eta_e >= 0.0))
        return "eta_e must be >= 0";
    return NULL;
}

lub_texture_params lub_texture_m3(double alpha, double beta, double eta_e, double eta)
{
    lub_texture_params p = {.a = 1.0,
                            .delta1 = alpha,
                            .delta2 = 0.0,
                            .beta1 = beta,
                            .beta2 = 0.0,
                            .beta3 = 0.0,
                            .eta = eta,
                            .eta_e = eta_e};
    return p;
}

/* r = delta1/Delta and q = 1/Delta, Delta = 1 - a^2 + delta1^2 of (4.6) with 1 - a^2 formed
 * without cancellation; without forming delta1^2 (it overflows for delta1 > 1.3e154,
 * and then r = delta1/inf = 0 lost the steady shear component and every stress with it) */
static void inv_delta(const lub_texture_params *p, double *r, double *q)
{
    const double w = (1.0 - p->a) * (1.0 + p->a), d1 = p->delta1;
    if (d1 > 1.0) {
        *r = 1.0 / (d1 + w / d1);
        *q = *r / d1;
    } else {
        const double D = w + d1 * d1;
        *r = d1 / D;
        *q = 1.0 / D;
    }
}

lub_texture_state lub_texture_steady_state(const lub_texture_params *p, int s)
{
    double r, q;
    inv_delta(p, &r, &q);
    lub_texture_state g = {(1.0 + p->a) * q, -(1.0 - p->a) * q, (s >= 0 ? 1.0 : -1.0) * r};
    return g;
}

lub_texture_stress lub_texture_steady_stress(const lub_texture_params *p)
{
    /* (4.7a-d); (3.8) when a = 1 and beta2 = beta3 = delta2 = 0. Written with r = delta1/Delta
     * and q = 1/Delta (delta1^2/Delta = delta1 r, delta1^2/Delta^2 = r^2, delta1/Delta^2 = r q),
     * so that no product overflows where the result does not */
    const double a = p->a, d1 = p->delta1, d2 = p->delta2;
    const double b1 = p->beta1, b2 = p->beta2, b3 = p->beta3, ee = p->eta_e;
    lub_texture_stress res = {p->eta, 0.0, 0.0, 0.0};
    if (ee == 0.0) /* no elastic stress (0 x an overflowed bracket would be NaN) */
        return res;
    double r, q;
    inv_delta(p, &r, &q);
    const double rr = r * r, rq = r * q, qq = q * q;
    res.eta_app = p->eta + ee * (d1 * r + a * d2 * q + b1 * rr + b2 * ((1.0 + a * a) * qq + rr) +
                                 2.0 * a * b3 * rq);
    res.n1 = 2.0 * ee * (r + b1 * rq + 2.0 * a * b3 * qq);
    res.n2 = ee * (r * (-1.0 + a + d2) - (1.0 - a) * b1 * rq + 2.0 * a * b2 * rq +
                   b3 * ((1.0 - a) * (1.0 - a) * qq + rr));
    res.pp = -2.0 * ee / 3.0 *
             (r * (a + d2) + a * (b1 + 2.0 * b2) * rq + b3 * ((1.0 + a * a) * qq + rr));
    return res;
}

lub_texture_state lub_texture_rhs(const lub_texture_params *p, int s, lub_texture_state g)
{
    const double a = p->a, d1 = p->delta1, sg = s >= 0 ? 1.0 : -1.0;
    lub_texture_state r;
    r.xx = (1.0 + a) * sg * g.xy - d1 * g.xx;         /* (4.4a) */
    r.yy = -(1.0 - a) * sg * g.xy - d1 * g.yy;        /* (4.4b) */
    r.xy = sg - 0.5 * (1.0 - a) * sg * g.xx           /* (4.4c), sign of the   */
           + 0.5 * (1.0 + a) * sg * g.yy - d1 * g.xy; /* g_xx term per E5      */
    return r;
}

/* sin(x)/x without cancellation near 0 */
static double sinc(double x)
{
    if (fabs(x) < 1e-4)
        return 1.0 - x * x / 6.0;
    return sin(x) / x;
}

/* The forced response of the linear system to a unit g_xy source from g = 0 (s = +1):
 *   *ic = int_0^gamma e^{-delta1 t} cos(w t) dt,  *is = int_0^gamma e^{-delta1 t} sin(w t)/w dt,
 * w = sqrt(1 - a^2) (so that g_xy = ic, g_xx = (1 + a) is, g_yy = -(1 - a) is). Both are computed
 * without cancellation for every delta1 > 0, w in [0, 1), gamma > 0: by the power series of
 * (1 - e^{-z gamma})/z, z = delta1 - i w, when |z| gamma <= 1, and otherwise by the closed form
 * with 1 - e^{-x} cos y written as -expm1(-x) cos y + 2 sin^2(y/2). (Until 2026-12-07 the solution
 * was the steady state plus a decaying deviation, which at a = 1 subtracts numbers of size
 * 2/delta1^2 to get an O(gamma^2) g_xx: at delta1 = 1e-8 g_xx came out 0 instead of 0.25.) */
static void forced(const lub_texture_params *p, double gamma, double *ic, double *is)
{
    const double w = sqrt((1.0 - p->a) * (1.0 + p->a)), x = p->delta1 * gamma, y = w * gamma;
    if (hypot(x, y) <= 1.0) {
        /* (-x + i y)^k = C_k + i y S_k; ic = gamma sum C_k/(k+1)!, is = gamma^2 sum S_k/(k+1)! */
        double C = 1.0, S = 0.0, f = 1.0, sc = 0.0, ss = 0.0;
        for (int k = 0; k < 24; ++k) {
            f /= (double)(k + 1);
            sc += C * f;
            ss += S * f;
            const double Cn = -x * C - y * y * S;
            S = C - x * S;
            C = Cn;
        }
        *ic = gamma * sc;
        *is = gamma * gamma * ss;
        return;
    }
    double r, q;
    inv_delta(p, &r, &q); /* r = delta1/(w^2 + delta1^2), q = 1/(w^2 + delta1^2) */
    const double E = exp(-x), h = sin(0.5 * y);
    const double N = -expm1(-x) * cos(y) + 2.0 * h * h; /* 1 - E cos y */
    *ic = r * N + (E > 0.0 ? q * w * E * sin(y) : 0.0);
    *is = q * (N - (E > 0.0 ? x * E * sinc(y) : 0.0));
}

lub_texture_state lub_texture_free(const lub_texture_params *p, int s, lub_texture_state d0,
                                   double dgamma)
{
    if (!(dgamma > 0.0))
        return d0;
    const double a = p->a, sg = s >= 0 ? 1.0 : -1.0, e = exp(-p->delta1 * dgamma);
    lub_texture_state d = {0.0, 0.0, 0.0};
    if (e == 0.0)
        return d;
    /* mirror map (xx, yy, xy) -> (xx, yy, -xy) turns s = -1 into s = +1 */
    const double X0 = d0.xx, Y0 = d0.yy, Z0 = sg * d0.xy;
    const double w = sqrt((1.0 - a) * (1.0 + a)), u = w * dgamma;
    const double Bw = -0.5 * (1.0 - a) * X0 + 0.5 * (1.0 + a) * Y0;
    const double sc = sinc(u), sh = sinc(0.5 * u);
    /* S = Z0 sin(u)/w + Bw (1 - cos u)/w^2, written with sinc so that w -> 0 is exact */
    const double hs = dgamma * sh; /* (not dgamma^2 sh^2: inf x 0 for a huge dgamma) */
    const double S = Z0 * dgamma * sc + Bw * 0.5 * hs * hs;
    const double Zh = Z0 * cos(u) + Bw * dgamma * sc;
    d.xx = e * (X0 + (1.0 + a) * S);
    d.yy = e * (Y0 - (1.0 - a) * S);
    d.xy = sg * e * Zh;
    return d;
}

lub_texture_state lub_texture_advance(const lub_texture_params *p, int s, lub_texture_state g0,
                                      double dgamma)
{
    if (!(dgamma > 0.0))
        return g0;
    const double a = p->a, sg = s >= 0 ? 1.0 : -1.0;
    /* the free decay of g0 plus the forced response from 0, each without cancellation */
    double ic, is;
    forced(p, dgamma, &ic, &is);
    lub_texture_state f = lub_texture_free(p, s, g0, dgamma);
    lub_texture_state g = {f.xx + (1.0 + a) * is, f.yy - (1.0 - a) * is, f.xy + sg * ic};
    return g;
}

lub_texture_stress lub_texture_stress_of(const lub_texture_params *p, int s, lub_texture_state g)
{
    const double sg = s >= 0 ? 1.0 : -1.0, ee = p->eta_e;
    const double d1 = p->delta1, d2 = p->delta2, b1 = p->beta1, b2 = p->beta2, b3 = p->beta3;
    const double xx = g.xx, yy = g.yy, xy = g.xy;
    /* (4.5a,b,d) divided by |gd| (gd/|gd| = sg), tau_zz = 0 */
    double txx = ee * ((d1 + b1 * sg * xy) * xx + b2 * sg * (xx + yy) * xy +
                       b3 * (xx * xx + xy * xy) + d2 * sg * xy);
    double tyy = ee * ((d1 + b1 * sg * xy) * yy + b2 * sg * (xx + yy) * xy +
                       b3 * (xy * xy + yy * yy) + d2 * sg * xy);
    /* (4.5c) divided by gd */
    double exy =
        p->eta + ee * ((d1 * sg + b1 * xy) * xy + 0.5 * b2 * (xx * xx + yy * yy + 2.0 * xy * xy) +
                       b3 * sg * (xx + yy) * xy + 0.5 * d2 * (xx + yy));
    lub_texture_stress r = {exy, txx - tyy, tyy, -(txx + tyy) / 3.0};
    return r;
}

lub_texture_micro lub_texture_micro_of(const lub_texture_params *p, lub_texture_state g)
{
    lub_texture_micro m;
    /* E2: principal direction of gamma_e; equals atan((-gxx + sqrt(gxx^2 + 4 gxy^2))/(2 gxy))
     * when gyy = 0 (M3), and atan(delta1)/2 at steady state (Prop. 4.2). */
    m.theta_e = 0.5 * atan2(2.0 * g.xy, g.xx - g.yy);
    double c0 = 1.0 / p->a;
    double bxx = c0 + g.xx, byy = c0 + g.yy, bxy = g.xy;
    double mean = 0.5 * (bxx + byy), rad = hypot(0.5 * (bxx - byy), bxy);
    m.b_min = fmin(mean - rad, c0);
    /* eigenvalues of b^{-1}/tr(b^{-1}) are lambda_j/(lambda_1+lambda_2): gap = 2 rad/(bxx+byy) */
    m.fabric_gap = mean > 0.0 ? rad / mean : 0.0;
    return m;
}
