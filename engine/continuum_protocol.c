/* continuum_protocol.c — piecewise shear protocols for the texture model
 * (see continuum_protocol.h). */
#include "continuum_protocol.h"

#include <math.h>
#include <stdio.h>

/* 5-point Gauss–Legendre nodes and weights on [-1, 1] */
static const double GL_X[5] = {-0.9061798459386640, -0.5384693101056831, 0.0, 0.5384693101056831,
                               0.9061798459386640};
static const double GL_W[5] = {0.2369268850561891, 0.4786286704993665, 0.5688888888888889,
                               0.4786286704993665, 0.2369268850561891};

/* Transient considered decayed beyond delta1 * gamma > DECAYED (e^-40 ~ 4e-18). */
#define DECAYED 40.0
/* At most this many panels are integrated one by one; longer stretches by panel doubling. */
#define MAX_DIRECT 4096

/* Panel length: a tenth of the solution's shortest strain scale 1/max(delta1, sqrt(1 - a^2))
 * (decay rate and oscillation frequency of the linear system). Until 2026-12-07 it was
 * 0.1/max(1, delta1), so that a small delta1 meant 400/delta1 panels before the transient had
 * decayed (25 s for alpha = 1e-6, strain 1e7, and no stop request honoured meanwhile). */
static double sub_step(const lub_texture_params *p)
{
    return 0.1 / fmax(p->delta1, sqrt((1.0 - p->a) * (1.0 + p->a)));
}

static double eta_at(const lub_texture_params *p, int s, lub_texture_state g0, double gamma)
{
    return lub_texture_stress_of(p, s, lub_texture_advance(p, s, g0, gamma)).eta_app;
}

/* int_{g1}^{g2} eta_app dgamma / sigma_abs by one GL5 panel; -1 if eta_app <= 0 at a node */
static int panel(const lub_texture_params *p, int s, lub_texture_state g0, double sigma_abs,
                 double g1, double g2, double *out, double *gamma_bad)
{
    double c = 0.5 * (g1 + g2), h = 0.5 * (g2 - g1), acc = 0.0;
    for (int k = 0; k < 5; ++k) {
        double gk = c + h * GL_X[k];
        double e = eta_at(p, s, g0, gk);
        if (!(e > 0.0)) {
            *gamma_bad = gk;
            return -1;
        }
        acc += GL_W[k] * e;
    }
    *out = acc * h / sigma_abs;
    return 0;
}

/* acc += int_{0}^{G} eta_app/sigma_abs from state g0, panel by panel (G <= MAX_DIRECT panels) */
static int direct(const lub_texture_params *p, int s, lub_texture_state g0, double sigma_abs,
                  double G, double *acc, double *gamma_bad)
{
    const double h = sub_step(p);
    for (double g = 0.0; g < G;) {
        double g2 = fmin(G, g + h), dt;
        if (panel(p, s, g0, sigma_abs, g, g2, &dt, gamma_bad))
            return -1;
        *acc += dt;
        g = g2;
    }
    return 0;
}

/* Panel doubling. The deviation d = g - g_ss from the steady state of sign s obeys the free
 * (homogeneous) system, d(gamma) = M(gamma) d0, and eta_app = eta_ss + l.d + d^T Q d with l, Q
 * constant. The GL5 integral of eta_app over a run of 2^j panels of length h starting from d is
 * then eta_ss 2^j h + L_j.d + d^T R_j d, and the run maps d to T_j d; (T, L, R) of 2^(j+1) panels
 * follow from those of 2^j (the run twice), so n panels cost O(log n) 3 x 3 products. Used only
 * where the transient outlives MAX_DIRECT panels, i.e. sqrt(1 - a^2) > 10 delta1 (slowly
 * damped oscillation), where g_ss (<= 1/(1 - a^2)) is moderate. */
typedef struct {
    double T[3][3], L[3], R[3][3];
} tm_block;

typedef struct {
    const lub_texture_params *p;
    int s;
    double sigma_abs, h, eta_ss, gss[3], l[3], Q[3][3];
    tm_block b0; /* one panel */
} tm_ctx;

static void to_arr(lub_texture_state g, double x[3])
{
    x[0] = g.xx;
    x[1] = g.yy;
    x[2] = g.xy;
}

/* free propagator over dgamma as a matrix (columns: images of the unit vectors) */
static void free_matrix(const lub_texture_params *p, int s, double dgamma, double M[3][3])
{
    for (int i = 0; i < 3; ++i) {
        double e[3] = {0.0, 0.0, 0.0}, c[3];
        e[i] = 1.0;
        to_arr(lub_texture_free(p, s, (lub_texture_state){e[0], e[1], e[2]}, dgamma), c);
        for (int r = 0; r < 3; ++r)
            M[r][i] = c[r];
    }
}

/* out = A^T B A (3 x 3) */
static void congruence(double A[3][3], double B[3][3], double out[3][3])
{
    double BA[3][3];
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j)
            BA[i][j] = B[i][0] * A[0][j] + B[i][1] * A[1][j] + B[i][2] * A[2][j];
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j)
            out[i][j] = A[0][i] * BA[0][j] + A[1][i] * BA[1][j] + A[2][i] * BA[2][j];
}

static void tm_init(tm_ctx *c, const lub_texture_params *p, int s, double sigma_abs)
{
    const double ee = p->eta_e, sg = s >= 0 ? 1.0 : -1.0;
    c->p = p;
    c->s = s;
    c->sigma_abs = sigma_abs;
    c->h = sub_step(p);
    lub_texture_state gs = lub_texture_steady_state(p, s);
    to_arr(gs, c->gss);
    c->eta_ss = lub_texture_stress_of(p, s, gs).eta_app;
    /* (4.5c) of lub_texture_stress_of as eta + ee (l0.x + x^T Q x) in x = (xx, yy, xy) */
    const double l0[3] = {0.5 * p->delta2, 0.5 * p->delta2, p->delta1 * sg};
    const double qd = 0.5 * p->beta2, qx = 0.5 * p->beta3 * sg;
    const double Q[3][3] = {{qd, 0.0, qx}, {0.0, qd, qx}, {qx, qx, p->beta1 + p->beta2}};
    for (int i = 0; i < 3; ++i) {
        double lp = l0[i];
        for (int j = 0; j < 3; ++j) {
            c->Q[i][j] = ee * Q[i][j];
            lp += 2.0 * Q[i][j] * c->gss[j];
        }
        c->l[i] = ee * lp; /* gradient at g_ss */
    }
    tm_block *b = &c->b0;
    for (int i = 0; i < 3; ++i) {
        b->L[i] = 0.0;
        for (int j = 0; j < 3; ++j)
            b->R[i][j] = 0.0;
    }
    for (int k = 0; k < 5; ++k) {
        double M[3][3], MQM[3][3], w = 0.5 * c->h * GL_W[k];
        free_matrix(p, s, 0.5 * c->h * (1.0 + GL_X[k]), M);
        congruence(M, c->Q, MQM);
        for (int i = 0; i < 3; ++i) {
            b->L[i] += w * (M[0][i] * c->l[0] + M[1][i] * c->l[1] + M[2][i] * c->l[2]);
            for (int j = 0; j < 3; ++j)
                b->R[i][j] += w * MQM[i][j];
        }
    }
    free_matrix(p, s, c->h, b->T);
}

/* the run of 2^(j+1) panels (strain 2H) from that of 2^j panels (strain H): the run twice. Its
 * propagator is evaluated directly at 2H rather than squared, so that rounding does not grow
 * with the number of doublings (squaring a rotation 2^j times drifts its norm by 2^j eps) */
static tm_block tm_double(const tm_ctx *c, const tm_block *a, double H)
{
    tm_block r;
    double Ta[3][3], Ra[3][3], RT[3][3];
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) {
            Ta[i][j] = a->T[i][j];
            Ra[i][j] = a->R[i][j];
        }
    congruence(Ta, Ra, RT);
    for (int i = 0; i < 3; ++i) {
        r.L[i] = a->L[i] + Ta[0][i] * a->L[0] + Ta[1][i] * a->L[1] + Ta[2][i] * a->L[2];
        for (int j = 0; j < 3; ++j)
            r.R[i][j] = a->R[i][j] + RT[i][j];
    }
    free_matrix(c->p, c->s, 2.0 * H, r.T);
    return r;
}

/* time spent over the block of strain H from deviation d */
static double tm_time(const tm_ctx *c, const tm_block *b, double H, const double d[3])
{
    double q = 0.0;
    for (int i = 0; i < 3; ++i)
        q += d[i] * (b->L[i] + b->R[i][0] * d[0] + b->R[i][1] * d[1] + b->R[i][2] * d[2]);
    return (c->eta_ss * H + q) / c->sigma_abs;
}

static void tm_move(const tm_block *b, double d[3])
{
    double n[3];
    for (int i = 0; i < 3; ++i)
        n[i] = b->T[i][0] * d[0] + b->T[i][1] * d[1] + b->T[i][2] * d[2];
    for (int i = 0; i < 3; ++i)
        d[i] = n[i];
}

/* eta_app > 0 on [0, G] in the doubling regime. The free system is periodic with period
 * P = 2 pi/sqrt(1 - a^2) up to the factor e^{-delta1 gamma}, so at the phase of a node gamma_k of
 * the first period eta_app = f(e) = eta_ss + e l.d_k + e^2 d_k^T Q d_k, e = e^{-delta1 (gamma -
 * gamma_k)}: checked at the GL nodes of the first period (those panel-by-panel integration would
 * check there) for every e in [e^{-delta1 (G - gamma_k)}, 1]. On failure *gamma_bad is the
 * smallest strain where one of these phases reaches eta_app <= 0. */
static int tm_check(const tm_ctx *c, lub_texture_state g0, double G, double *gamma_bad)
{
    const lub_texture_params *p = c->p;
    const double P = 2.0 * 3.14159265358979323846 / sqrt((1.0 - p->a) * (1.0 + p->a));
    double first = INFINITY;
    for (double g = 0.0; g < fmin(P, G); g += c->h)
        for (int k = 0; k < 5; ++k) {
            const double gk = g + 0.5 * c->h * (1.0 + GL_X[k]);
            if (gk > G)
                continue;
            double x[3], d[3], lin = 0.0, qua = 0.0;
            to_arr(lub_texture_advance(p, c->s, g0, gk), x);
            for (int i = 0; i < 3; ++i)
                d[i] = x[i] - c->gss[i];
            for (int i = 0; i < 3; ++i) {
                lin += c->l[i] * d[i];
                qua += d[i] * (c->Q[i][0] * d[0] + c->Q[i][1] * d[1] + c->Q[i][2] * d[2]);
            }
#define F_OF(e) (c->eta_ss + (e)*lin + (e) * (e)*qua)
            if (!(F_OF(1.0) > 0.0)) {
                first = fmin(first, gk);
                continue;
            }
            const double elo = exp(-p->delta1 * (G - gk));
            double e_bad = elo; /* the minimum of f on [elo, 1] */
            if (qua > 0.0 && -lin / (2.0 * qua) > elo && -lin / (2.0 * qua) < 1.0)
                e_bad = -lin / (2.0 * qua);
            if (F_OF(e_bad) > 0.0)
                continue;
            double lo = e_bad, hi = 1.0; /* f(lo) <= 0 < f(hi): the crossing nearest e = 1 */
            for (int it = 0; it < 80; ++it) {
                const double mid = 0.5 * (lo + hi);
                if (F_OF(mid) > 0.0)
                    hi = mid;
                else
                    lo = mid;
            }
            first = fmin(first, lo > 0.0 ? gk - log(lo) / p->delta1 : G);
#undef F_OF
        }
    if (first <= G) {
        *gamma_bad = first;
        return -1;
    }
    return 0;
}

int lub_rheo_time_for_strain(const lub_texture_params *p, int s, lub_texture_state g0,
                             double sigma_abs, double dgamma, double *t, double *gamma_bad)
{
    const double h = sub_step(p), G = fmin(dgamma, DECAYED / p->delta1);
    double acc = 0.0, done = 0.0;
    lub_texture_state gm = g0; /* state at strain done */
    if (G / h > MAX_DIRECT) {
        tm_ctx c;
        tm_init(&c, p, s, sigma_abs);
        if (tm_check(&c, g0, G, gamma_bad))
            return -1;
        double d[3], x[3], H = h, n = floor(G / h);
        to_arr(g0, x);
        for (int i = 0; i < 3; ++i)
            d[i] = x[i] - c.gss[i];
        /* the binary digits of n, lowest first: the panels are identical, so runs of 2^j panels
         * may be taken in any order */
        tm_block b = c.b0;
        while (n > 0.0) {
            if (fmod(n, 2.0) == 1.0) {
                acc += tm_time(&c, &b, H, d);
                tm_move(&b, d);
                done += H;
            }
            n = floor(0.5 * n);
            if (n > 0.0) {
                b = tm_double(&c, &b, H);
                H *= 2.0;
            }
        }
        gm = (lub_texture_state){c.gss[0] + d[0], c.gss[1] + d[1], c.gss[2] + d[2]};
    }
    if (direct(p, s, gm, sigma_abs, fmax(0.0, G - done), &acc, gamma_bad)) {
        *gamma_bad += done;
        return -1;
    }
    if (dgamma > G) { /* steady: eta_app constant from here on */
        double e = eta_at(p, s, gm, fmax(0.0, G - done));
        if (!(e > 0.0)) {
            *gamma_bad = G;
            return -1;
        }
        acc += (dgamma - G) * e / sigma_abs;
    }
    *t = acc;
    return 0;
}

int lub_rheo_strain_for_time(const lub_texture_params *p, int s, lub_texture_state g0,
                             double sigma_abs, double t, double *dgamma, double *gamma_bad)
{
    const double h = sub_step(p), Gd = DECAYED / p->delta1;
    double acc = 0.0, base = 0.0;
    lub_texture_state gb = g0; /* state at strain base */
    if (!(t > 0.0)) {
        *dgamma = 0.0;
        return 0;
    }
    if (Gd / h > MAX_DIRECT) {
        /* binary lifting on runs of 2^j panels, largest first, while the time stays below t and
         * the strain within the transient (the run of 2^j panels is rebuilt for each j: O(J^2)
         * products, J = log2(Gd/h), and no storage) */
        tm_ctx c;
        tm_init(&c, p, s, sigma_abs);
        if (tm_check(&c, g0, Gd, gamma_bad))
            return -1;
        double d[3], x[3];
        to_arr(g0, x);
        for (int i = 0; i < 3; ++i)
            d[i] = x[i] - c.gss[i];
        int J = 0;
        while (ldexp(h, J) <= Gd && J < 2000)
            ++J;
        for (int j = J - 1; j >= 0; --j) {
            const double H = ldexp(h, j);
            if (base + H > Gd)
                continue;
            tm_block b = c.b0;
            for (int i = 0; i < j; ++i)
                b = tm_double(&c, &b, ldexp(h, i));
            const double dt = tm_time(&c, &b, H, d);
            if (acc + dt < t) {
                acc += dt;
                tm_move(&b, d);
                base += H;
            }
        }
        gb = (lub_texture_state){c.gss[0] + d[0], c.gss[1] + d[1], c.gss[2] + d[2]};
    }
    for (double g = 0.0, n = 0.0;; n += 1.0) {
        /* steady: eta_app constant from here on. Also where a panel no longer adds to the time
         * acc (t - acc below its rounding, only after the doubling of an immense transient) and,
         * as a guard on the work, after MAX_DIRECT panels (the doubling leaves at most one) */
        if (p->delta1 * (base + g) > DECAYED || n > MAX_DIRECT) {
            double e = eta_at(p, s, gb, g);
            if (!(e > 0.0)) {
                *gamma_bad = base + g;
                return -1;
            }
            *dgamma = base + g + (t - acc) * sigma_abs / e;
            return 0;
        }
        double dt;
        if (panel(p, s, gb, sigma_abs, g, g + h, &dt, gamma_bad)) {
            *gamma_bad += base;
            return -1;
        }
        if (acc + dt == acc) {
            n = 2.0 * MAX_DIRECT;
            continue;
        }
        if (acc + dt >= t) {
            /* Newton on d in [0, h]: int_g^{g+d} eta/|sigma| = t - acc (monotone, eta > 0) */
            double target = t - acc, d = h * target / dt, lo = 0.0, hi = h;
            for (int it = 0; it < 60; ++it) {
                double f;
                if (panel(p, s, gb, sigma_abs, g, g + d, &f, gamma_bad)) {
                    *gamma_bad += base;
                    return -1;
                }
                f -= target;
                if (f > 0.0)
                    hi = d;
                else
                    lo = d;
                double e = eta_at(p, s, gb, g + d);
                double dn = d - f * sigma_abs / e;
                if (!(dn > lo && dn < hi))
                    dn = 0.5 * (lo + hi); /* safeguard: bisection */
                if (fabs(dn - d) <= 1e-15 * (g + h)) {
                    d = dn;
                    break;
                }
                d = dn;
            }
            *dgamma = base + g + d;
            return 0;
        }
        acc += dt;
        g += h;
    }
}

static int emit(const lub_texture_params *p, int seg, double time, double strain, double gd,
                int s_report, lub_texture_state g, lub_rheo_sink sink, void *user,
                lub_rheo_error *err, int *stopped)
{
    lub_rheo_sample S;
    lub_texture_stress st = lub_texture_stress_of(p, s_report, g);
    S.segment = seg;
    S.time = time;
    S.strain = strain;
    S.gd = gd;
    S.eta_app = st.eta_app;
    S.sigma_xy = gd * st.eta_app;
    S.n1 = fabs(gd) * st.n1;
    S.n2 = fabs(gd) * st.n2;
    S.pp = fabs(gd) * st.pp;
    S.g = g;
    S.micro = lub_texture_micro_of(p, g);
    const double chk[10] = {S.eta_app, S.sigma_xy, S.n1, S.n2, S.pp,
                            g.xx,      g.yy,       g.xy, time, strain};
    for (int i = 0; i < 10; ++i)
        if (!isfinite(chk[i])) {
            err->segment = seg;
            err->strain = strain;
            snprintf(err->message, sizeof err->message,
                     "non-finite stress, state, time or strain at strain %.6g, time %.6g", strain,
                     time);
            return -1;
        }
    if (!(S.micro.b_min > 0.0)) {
        err->segment = seg;
        err->strain = strain;
        snprintf(err->message, sizeof err->message,
                 "b_e lost positive definiteness (min eigenvalue %.3g) at strain %.6g",
                 S.micro.b_min, strain);
        return -1;
    }
    if (sink(user, &S)) {
        *stopped = 1;
        return 1;
    }
    return 0;
}

int lub_rheo_run(const lub_texture_params *p, lub_texture_state g0, int s0, const lub_segment *segs,
                 int nseg, int samples, lub_rheo_sink sink, void *user, lub_rheo_error *err)
{
    lub_texture_state g = g0;
    int s_last = s0 >= 0 ? 1 : -1, stopped = 0, rc;
    double t = 0.0, strain = 0.0;
    if (samples < 2)
        samples = 2;
    for (int k = 0; k < nseg; ++k) {
        const lub_segment *sg = &segs[k];
        int moving = (sg->mode == LUB_SEG_RATE) || (sg->mode == LUB_SEG_OSCILLATION) ||
                     (sg->mode == LUB_SEG_STRESS && sg->value != 0.0);
        if (!moving) { /* pause (or zero stress): gamma_e frozen, stresses 0 */
            for (int i = 0; i < samples; ++i) {
                double ti = t + sg->duration * (double)i / (double)(samples - 1);
                rc = emit(p, k, ti, strain, 0.0, s_last, g, sink, user, err, &stopped);
                if (rc)
                    return rc < 0 ? -1 : 1;
            }
            t += sg->duration;
            continue;
        }
        if (sg->mode == LUB_SEG_OSCILLATION) {
            const double A = sg->value, om = 2.0 * 3.14159265358979323846 * sg->frequency;
            const double Th = 0.5 / sg->frequency, Gh = 2.0 * A / om; /* half period, its strain */
            long kcur = 0;
            lub_texture_state gstart = g, gs = g;
            double gl = 0.0;
            int s = 1;
            for (int i = 0; i < samples; ++i) {
                double ti = sg->duration * (double)i / (double)(samples - 1);
                long hk = (long)floor(ti / Th);
                if (i == samples - 1 && hk > 0 && ti - hk * Th <= 0.0)
                    hk -= 1; /* the end instant belongs to the half period that ends there */
                while (kcur < hk) {
                    gstart = lub_texture_advance(p, (kcur % 2 == 0) ? 1 : -1, gstart, Gh);
                    ++kcur;
                }
                s = (hk % 2 == 0) ? 1 : -1;
                double tau = fmin(ti - hk * Th, Th);
                gl = (A / om) * (1.0 - cos(om * tau));
                gs = lub_texture_advance(p, s, gstart, gl);
                rc = emit(p, k, t + ti, strain + hk * Gh + gl, A * sin(om * ti), s, gs, sink, user,
                          err, &stopped);
                if (rc)
                    return rc < 0 ? -1 : 1;
            }
            g = gs;
            strain += kcur * Gh + gl;
            t += sg->duration;
            s_last = s;
            continue;
        }
        int s = sg->value > 0.0 ? 1 : -1;
        double total, gamma_bad = 0.0;
        if (sg->mode == LUB_SEG_RATE) {
            total = sg->strain > 0.0 ? sg->strain : fabs(sg->value) * sg->duration;
        } else if (sg->strain > 0.0) {
            total = sg->strain;
        } else if (lub_rheo_strain_for_time(p, s, g, fabs(sg->value), sg->duration, &total,
                                            &gamma_bad)) {
            goto eta_fail;
        }
        double t_prev_local = 0.0, g_prev = 0.0;
        for (int i = 0; i < samples; ++i) {
            double gi = total * (double)i / (double)(samples - 1);
            double ti;
            lub_texture_state gs = lub_texture_advance(p, s, g, gi);
            double gd;
            if (sg->mode == LUB_SEG_RATE) {
                gd = sg->value;
                ti = gi / fabs(gd);
            } else {
                double dt = 0.0;
                if (gi > g_prev) {
                    /* time between samples: restart the map at the previous sample's state */
                    lub_texture_state gp = lub_texture_advance(p, s, g, g_prev);
                    if (lub_rheo_time_for_strain(p, s, gp, fabs(sg->value), gi - g_prev, &dt,
                                                 &gamma_bad)) {
                        gamma_bad += g_prev;
                        goto eta_fail;
                    }
                }
                ti = t_prev_local + dt;
                double e = lub_texture_stress_of(p, s, gs).eta_app;
                if (!(e > 0.0)) {
                    gamma_bad = gi;
                    goto eta_fail;
                }
                gd = sg->value / e;
            }
            if (sg->mode == LUB_SEG_STRESS && sg->strain == 0.0 && i == samples - 1)
                ti = sg->duration; /* exact end of a duration segment */
            rc = emit(p, k, t + ti, strain + gi, gd, s, gs, sink, user, err, &stopped);
            if (rc)
                return rc < 0 ? -1 : 1;
            t_prev_local = ti;
            g_prev = gi;
        }
        g = lub_texture_advance(p, s, g, total);
        t += t_prev_local;
        strain += total;
        s_last = s;
        continue;
    eta_fail:
        err->segment = k;
        err->strain = strain + gamma_bad;
        snprintf(err->message, sizeof err->message,
                 "imposed stress with apparent viscosity <= 0 at strain %.6g of segment %d: "
                 "sgn(gd) = sgn(sigma) no longer holds (model outside its domain)",
                 gamma_bad, k);
        return -1;
    }
    (void)stopped;
    return 0;
}
