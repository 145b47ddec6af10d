/* test_law_settling.c — dynamics validation of the normal part (notes §12 "validation
 * targets", §2.6 prototype check): a sphere settling under its weight W onto a fixed sphere,
 * integrated with the leap-frog of law_sim.c and the full law.
 *  - smooth (eps = 0), viscous limit: u(t) = u0 exp(-(8/9) t / tau_c), tau_c = eta/(a rho g_grav)
 *    (from W = nu_n u'/u with nu_n = 3/2 pi eta a^2); checked over t in [0.5, 6] tau_c to
 *    2e-4 relative (u0 taken at 0.5 tau_c, after the inertial transient);
 *  - rough (physical eps = 0.02, i.e. Yade eps_Y = 0.01), alpha = 1: the gap converges to the
 *    static value u_eq = eps a - W/k_n (notes §2.6: 2 eps_Y a - W/g).
 * Parameters of the notes' prototype: rho = 1000, a = 0.01, eta = 100, g_grav = 1,
 * g = k_n = E a = 1e4, dt = 1e-4 (elastic limit sqrt(m/g) = 6.5e-4).
 * Prints name=value lines; exits non-zero on failure. */
#include "law_sim.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

static int failures = 0;

static void setup(law_sim *s, double eps)
{
    const double rho = 1000.0, a = 0.01, eta = 100.0, grav = 1.0, E = 1e6;
    memset(s, 0, sizeof *s);
    s->n = 2;
    for (int i = 0; i < 2; ++i) {
        s->r[i] = a;
        s->m[i] = 4.0 / 3.0 * LUB_PI * rho * a * a * a;
        s->I[i] = 0.4 * s->m[i] * a * a;
    }
    s->fixed[0] = 1;
    s->x[0] = v3(0, 0, 0);
    s->x[1] = v3(0, 3.0 * a, 0); /* u_n = a */
    s->fext[1] = v3(0, -s->m[1] * grav, 0);
    s->p = (lub_law_params){.eta = eta,
                            .k_bulk = E * a,
                            .alpha = 1.0,
                            .k_t = 0.3 * E * a,
                            .eps = eps,
                            .mu = 0.5,
                            .terms = LUB_TERM_ALL};
    s->dt = 1e-4;
    s->create = 50.0;
    s->cutoff = 50.0;
    law_sim_prepare(s);
}

int main(void)
{
    static law_sim s;
    const double rho = 1000.0, a = 0.01, eta = 100.0, grav = 1.0;
    const double tau_c = eta / (a * rho * grav);
    const int nsteps = (int)(6.0 * tau_c / 1e-4);

    /* smooth: exponential settling */
    setup(&s, 0.0);
    double max_rel = 0.0, u0 = -1.0, t0 = 0.5 * tau_c;
    for (int k = 0; k < nsteps; ++k) {
        if (law_sim_step(&s) != 0) {
            ++failures;
            break;
        }
        const double u = s.out[0][1].gap; /* from the evaluation at step k (time k dt) */
        if (u0 < 0.0 && k * s.dt >= t0)
            u0 = u, t0 = k * s.dt;
        if (u0 > 0.0) {
            const double ref = u0 * exp(-(8.0 / 9.0) * (k * s.dt - t0) / tau_c);
            const double rel = fabs(u / ref - 1.0);
            if (rel > max_rel)
                max_rel = rel;
        }
    }
    const double u_end = s.out[0][1].gap;
    printf("settling_smooth_tau_c=%.6g\nsettling_smooth_final_gap_over_a=%.6e\n", tau_c, u_end / a);
    printf("settling_smooth_max_rel_err_vs_exp=%.3e\n", max_rel);
    if (!(max_rel < 2e-4)) {
        ++failures;
        fprintf(stderr, "FAIL smooth settling error %g\n", max_rel);
    }

    /* rough: static equilibrium gap eps a - W/k_n */
    const double eps = 0.02;
    setup(&s, eps);
    for (int k = 0; k < nsteps; ++k)
        if (law_sim_step(&s) != 0) {
            ++failures;
            break;
        }
    const double W = s.m[1] * grav, u_eq = eps * a - W / (s.p.alpha * s.p.k_bulk);
    const double u_r = s.out[0][1].gap;
    const double rel_eq = fabs(u_r / u_eq - 1.0);
    printf("settling_rough_gap=%.10e\nsettling_rough_expected=%.10e\nsettling_rough_rel_err=%.3e\n",
           u_r, u_eq, rel_eq);
    printf("settling_rough_contact=%d\n", s.out[0][1].contact);
    if (!(rel_eq < 1e-6) || !s.out[0][1].contact) {
        ++failures;
        fprintf(stderr, "FAIL rough equilibrium %g\n", rel_eq);
    }
    printf("settling_failures=%d\n", failures);
    return failures ? 1 : 0;
}
