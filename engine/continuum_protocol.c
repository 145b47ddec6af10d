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

static double sub_step(const lub_texture_params *p) { return 0.1 / fmax(1.0, p->delta1); }

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

int lub_rheo_time_for_strain(const lub_texture_params *p, int s, lub_texture_state g0,
                             double sigma_abs, double dgamma, double *t, double *gamma_bad)
{
    double h = sub_step(p), g = 0.0, acc = 0.0;
    while (g < dgamma) {
        if (p->delta1 * g > DECAYED) { /* steady: eta_app constant from here on */
            double e = eta_at(p, s, g0, g);
            if (!(e > 0.0)) {
                *gamma_bad = g;
                return -1;
            }
            acc += (dgamma - g) * e / sigma_abs;
            break;
        }
        double g2 = fmin(dgamma, g + h), dt;
        if (panel(p, s, g0, sigma_abs, g, g2, &dt, gamma_bad))
            return -1;
        acc += dt;
        g = g2;
    }
    *t = acc;
    return 0;
}

int lub_rheo_strain_for_time(const lub_texture_params *p, int s, lub_texture_state g0,
                             double sigma_abs, double t, double *dgamma, double *gamma_bad)
{
    double h = sub_step(p), g = 0.0, acc = 0.0;
    if (!(t > 0.0)) {
        *dgamma = 0.0;
        return 0;
    }
    for (;;) {
        if (p->delta1 * g > DECAYED) {
            double e = eta_at(p, s, g0, g);
            if (!(e > 0.0)) {
                *gamma_bad = g;
                return -1;
            }
            *dgamma = g + (t - acc) * sigma_abs / e;
            return 0;
        }
        double dt;
        if (panel(p, s, g0, sigma_abs, g, g + h, &dt, gamma_bad))
            return -1;
        if (acc + dt >= t) {
            /* Newton on d in [0, h]: int_g^{g+d} eta/|sigma| = t - acc (monotone, eta > 0) */
            double target = t - acc, d = h * target / dt, lo = 0.0, hi = h;
            for (int it = 0; it < 60; ++it) {
                double f;
                if (panel(p, s, g0, sigma_abs, g, g + d, &f, gamma_bad))
                    return -1;
                f -= target;
                if (f > 0.0)
                    hi = d;
                else
                    lo = d;
                double e = eta_at(p, s, g0, g + d);
                double dn = d - f * sigma_abs / e;
                if (!(dn > lo && dn < hi))
                    dn = 0.5 * (lo + hi); /* safeguard: bisection */
                if (fabs(dn - d) <= 1e-15 * (g + h)) {
                    d = dn;
                    break;
                }
                d = dn;
            }
            *dgamma = g + d;
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
