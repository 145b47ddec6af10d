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

lub_texture_state lub_texture_advance(const lub_texture_params *p, int s, lub_texture_state g0,
                                      double dgamma)
{
    if (!(dgamma > 0.0))
        return g0;
    const double a = p->a, sg = s >= 0 ? 1.0 : -1.0;
    /* mirror map (xx, yy, xy) -> (xx, yy, -xy) turns s = -1 into s = +1 */
    lub_texture_state bar = lub_texture_steady_state(p, +1);
    double X0 = g0.xx - bar.xx, Y0 = g0.yy - bar.yy, Z0 = sg * g0.xy - bar.xy;
    double e = exp(-p->delta1 * dgamma);
    if (e == 0.0) {
        bar.xy *= sg;
        return bar;
    }
    double w = sqrt((1.0 - a) * (1.0 + a));
    double u = w * dgamma;
    double Bw = -0.5 * (1.0 - a) * X0 + 0.5 * (1.0 + a) * Y0;
    double sc = sinc(u), sh = sinc(0.5 * u);
    /* S = Z0 sin(u)/w + Bw (1 - cos u)/w^2, written with sinc so that w -> 0 is exact */
    double S = Z0 * dgamma * sc + Bw * 0.5 * dgamma * dgamma * sh * sh;
    double Zh = Z0 * cos(u) + Bw * dgamma * sc;
    lub_texture_state g;
    g.xx = bar.xx + e * (X0 + (1.0 + a) * S);
    g.yy = bar.yy + e * (Y0 - (1.0 - a) * S);
    g.xy = sg * (bar.xy + e * Zh);
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
