/* test_step_stiffness.c — the pairs' incremental stiffness and the many-partner step bound
 * (engine/step_stiffness.h; lub_shear_step_control of shear_system.h).
 *
 *  1. k_n of lub_pair_step_stiffness is the law's own dF_n/du_n: a central finite difference of
 *     the backward-Euler normal solve (lub_normal_solve) at a stationary film, in and out of
 *     contact, from a film much softer than g (h x >> 1) to one as stiff as g (h x << 1), within
 *     1e-5 relative (difference step 1e-7 of the gap);
 *  2. the limits: no normal lubrication gives 0 out of contact and g alpha/(1 + alpha) in
 *     contact, and g in the hard core (asperities crushed, or smooth spheres overlapping: the
 *     law's own dF_n/du_n there, by a finite difference, with eps 0.02 and with eps 0, where
 *     the pair is a frictional contact all the same); the tangential element is k_t in a frictional
 * contact, the Maxwell value k_t nu_t/(nu_t + k_t dt) outside, 0 without shear lubrication;
 *  3. the Gershgorin rows bound the true largest eigenvalue of M^-1/2 K M^-1/2 (from above,
 *     and within a factor 3: 2.5 at most in these clusters), assembled
 *     here independently from the pairs' relative normal and tangential displacements (with the
 *     lever arms of contact_shear.h) for 40 random clusters of 2-7 bodies, and equal it for a
 *     single pair of equal spheres with normal stiffness only (2 g/m: the single-pair bound
 *     sqrt(2 m/g));
 *  4. on a sheared 200-particle packing: lub_pairs_stable_dt returns dt_max when the pairs allow
 *     it, and otherwise a step whose ratio to lub_pairs_stiffness_dt is the requested safety to
 *     within 1 %; light, soft spheres with a 3 a cut-off need less than the single-pair step;
 *     lub_pairs_adapted_dt lowers a step beyond the bound to 0.9 of the admissible one, raises
 *     one below 1/1.25 of the safety back to it (or to dt_base), keeps one in between or any
 *     with safety 0, and reports the ratio at the step it returns; lub_shear_step_control
 *     applies it once per rebuild and keeps the summary's record.
 */
#include "step_stiffness.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "contact_shear.h"
#include "rng.h"
#include "shear_fixture.h"
#include "shear_test.h"
#include "step_count.h"

/* the fixture's law (g = 1e4, k_t = g/2, eps 0.02, mu 0.5) with the given terms */
static lub_law_params law_with(unsigned terms)
{
    lub_law_params p = shear_fixture_law(1e4);
    p.terms = terms;
    return p;
}

/* F_n (force per g a) after one step from a film at x_prev when the centre gap is s */
static double normal_force(double x_prev, double s, double h, double e, double alpha)
{
    const double delta = lub_normal_solve(log(x_prev), s, h, e, alpha, NULL);
    return s - exp(delta);
}

static void check_normal_against_law(void)
{
    const lub_law_params p = law_with(LUB_TERM_ALL);
    const double a = 1.0, g = p.k_bulk;
    const double xs[] = {0.5, 0.05, 0.01, 0.005, 1e-4};
    const double dts[] = {1e-6, 1e-4, 1e-2};
    for (size_t ix = 0; ix < sizeof xs / sizeof xs[0]; ++ix)
        for (size_t id = 0; id < sizeof dts / sizeof dts[0]; ++id) {
            const double x = xs[ix], dt = dts[id];
            const double h = dt * g / (1.5 * LUB_PI * p.eta * a);
            const int contact = x < p.eps;
            const double ac = contact ? p.alpha : 0.0;
            /* stationary film: R = s + ac e - (1 + ac) x = 0 */
            const double s = (1.0 + ac) * x - ac * p.eps;
            const double ds = 1e-7 * x;
            const double fd = g *
                              (normal_force(x, s + ds, h, p.eps, p.alpha) -
                               normal_force(x, s - ds, h, p.eps, p.alpha)) /
                              (2.0 * ds);
            double kn, ks;
            lub_pair_step_stiffness(&p, a, log(x), dt, &kn, &ks);
            ST_CHECK(fabs(kn - fd) <= 1e-5 * g, "x=%g dt=%g: k_n %.9g, law %.9g (h x = %g)", x, dt,
                     kn, fd, h * x);
        }
    /* the two ends: a film far softer than g and one as stiff as g */
    double kn, ks;
    lub_pair_step_stiffness(&p, a, log(0.5), 1.0, &kn, &ks);
    ST_CHECK(kn < 0.01 * p.k_bulk, "soft film k_n %g", kn);
    lub_pair_step_stiffness(&p, a, log(0.5), 1e-9, &kn, &ks);
    ST_CHECK(kn > 0.999 * p.k_bulk, "stiff film k_n %g", kn);
}

static void check_limits(void)
{
    const double a = 1.0, dt = 1e-4;
    double kn, ks;
    lub_law_params p = law_with(LUB_TERM_ALL & ~LUB_TERM_NORMAL_LUB);
    lub_pair_step_stiffness(&p, a, log(0.5), dt, &kn, &ks);
    ST_CHECK(kn == 0.0, "no normal lubrication, out of contact: k_n %g", kn);
    lub_pair_step_stiffness(&p, a, log(0.01), dt, &kn, &ks);
    ST_CHECK(fabs(kn - 0.5 * p.k_bulk) <= 1e-12 * p.k_bulk,
             "no normal lubrication, contact: k_n %g (springs in series: g/2)", kn);
    ST_CHECK(ks == p.k_t, "frictional contact: k_s %g", ks);
    /* the hard core (until 2026-12-07 g alpha/(1 + alpha) with eps > 0, and 0 for eps = 0) */
    for (int smooth = 0; smooth <= 1; ++smooth) {
        lub_law_params q = p;
        q.eps = smooth ? 0.0 : q.eps;
        const double s = smooth ? -0.005 : -0.05, ds = 1e-7;
        const double fd = q.k_bulk *
                          (normal_force(1e-3, s + ds, INFINITY, q.eps, q.alpha) -
                           normal_force(1e-3, s - ds, INFINITY, q.eps, q.alpha)) /
                          (2.0 * ds);
        int contact = 0;
        const double delta = lub_normal_solve(log(1e-3), s, INFINITY, q.eps, q.alpha, &contact);
        lub_pair_step_stiffness(&q, a, delta, dt, &kn, &ks);
        ST_CHECK(delta == LUB_DELTA_STATIC_FLOOR && contact &&
                     fabs(fd - q.k_bulk) <= 1e-6 * q.k_bulk && fabs(kn - fd) <= 1e-6 * q.k_bulk &&
                     ks == q.k_t,
                 "hard core, eps %g: delta %g contact %d, k_n %g against the law's %g, k_s %g",
                 q.eps, delta, contact, kn, fd, ks);
    }

    p = law_with(LUB_TERM_ALL);
    lub_pair_step_stiffness(&p, a, log(0.3), dt, &kn, &ks);
    const double nu_t = lub_shear_viscosity(p.eta, a, log(0.3));
    const double maxwell = p.k_t * nu_t / (nu_t + p.k_t * dt);
    ST_CHECK(fabs(ks - maxwell) <= 1e-12 * p.k_t, "Maxwell element: k_s %g, expected %g", ks,
             maxwell);
    p = law_with(LUB_TERM_ALL & ~LUB_TERM_FRICTION);
    lub_pair_step_stiffness(&p, a, log(0.01), dt, &kn, &ks);
    const double nu_c = lub_shear_viscosity(p.eta, a, log(0.01));
    ST_CHECK(fabs(ks - p.k_t * nu_c / (nu_c + p.k_t * dt)) <= 1e-12 * p.k_t,
             "frictionless contact is a Maxwell element: k_s %g", ks);
    p = law_with(LUB_TERM_ALL & ~LUB_TERM_SHEAR_LUB);
    lub_pair_step_stiffness(&p, a, log(0.3), dt, &kn, &ks);
    ST_CHECK(ks == 0.0, "no shear lubrication, out of contact: k_s %g", ks);
    /* a film compressed below the smallest double: finite, k_n -> g */
    p = law_with(LUB_TERM_ALL);
    lub_pair_step_stiffness(&p, a, -1e5, dt, &kn, &ks);
    ST_CHECK(isfinite(kn) && isfinite(ks) && fabs(kn - p.k_bulk) <= 1e-12 * p.k_bulk,
             "deep film: k_n %g k_s %g", kn, ks);
}

/* ---- 3: Gershgorin rows against an independently assembled stiffness matrix ---- */
enum { MAXB = 7, DOF = 6 * MAXB };

static void add_outer(double K[DOF][DOF], const int *idx, const double *b, int len, double k)
{
    for (int p = 0; p < len; ++p)
        for (int q = 0; q < len; ++q)
            K[idx[p]][idx[q]] += k * b[p] * b[q];
}

/* largest eigenvalue of a symmetric positive semi-definite matrix (power iteration) */
static double largest_eigenvalue(double K[DOF][DOF], int n)
{
    double v[DOF], w[DOF], lam = 0.0;
    for (int i = 0; i < n; ++i)
        v[i] = 1.0 + 0.1 * i;
    for (int it = 0; it < 20000; ++it) {
        double norm = 0.0;
        for (int i = 0; i < n; ++i) {
            w[i] = 0.0;
            for (int j = 0; j < n; ++j)
                w[i] += K[i][j] * v[j];
            norm += w[i] * w[i];
        }
        norm = sqrt(norm);
        if (norm == 0.0)
            return 0.0;
        for (int i = 0; i < n; ++i)
            v[i] = w[i] / norm;
        if (fabs(norm - lam) <= 1e-13 * norm)
            return norm;
        lam = norm;
    }
    return lam;
}

static void check_gershgorin(void)
{
    lub_rng rng;
    lub_rng_seed(&rng, 12345);
    for (int trial = 0; trial < 40; ++trial) {
        const int nb = 2 + (int)(lub_rng_uniform(&rng) * (MAXB - 1));
        double r[MAXB], inv_m[MAXB], inv_i[MAXB], trans[MAXB] = {0}, rot[MAXB] = {0};
        double K[DOF][DOF];
        memset(K, 0, sizeof K);
        for (int b = 0; b < nb; ++b) {
            r[b] = 0.8 + 0.4 * lub_rng_uniform(&rng);
            const double m = (0.5 + lub_rng_uniform(&rng)) * r[b] * r[b] * r[b];
            inv_m[b] = 1.0 / m;
            inv_i[b] = 1.0 / (0.4 * m * r[b] * r[b]);
        }
        for (int i = 0; i < nb; ++i)
            for (int j = i + 1; j < nb; ++j) {
                if (lub_rng_uniform(&rng) < 0.3)
                    continue;
                const double kn = lub_rng_uniform(&rng), ks = 0.7 * lub_rng_uniform(&rng);
                double n[3] = {lub_rng_uniform(&rng) - 0.5, lub_rng_uniform(&rng) - 0.5,
                               lub_rng_uniform(&rng) - 0.5};
                const double nn = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
                for (int c = 0; c < 3; ++c)
                    n[c] /= nn;
                lub_step_rows_add(trans, rot, i, j, r, inv_m, inv_i, kn, ks);
                /* q = (x_i, th_i, x_j, th_j), mass-scaled: q_k = sqrt(M_k) * displacement */
                int idx[12];
                double scale[12];
                for (int c = 0; c < 3; ++c) {
                    idx[c] = 6 * i + c;
                    idx[3 + c] = 6 * i + 3 + c;
                    idx[6 + c] = 6 * j + c;
                    idx[9 + c] = 6 * j + 3 + c;
                    scale[c] = sqrt(inv_m[i]);
                    scale[3 + c] = sqrt(inv_i[i]);
                    scale[6 + c] = sqrt(inv_m[j]);
                    scale[9 + c] = sqrt(inv_i[j]);
                }
                /* normal: n.(x_j - x_i) */
                double bn[12] = {0};
                for (int c = 0; c < 3; ++c) {
                    bn[c] = -n[c];
                    bn[6 + c] = n[c];
                }
                for (int c = 0; c < 12; ++c)
                    bn[c] *= scale[c];
                add_outer(K, idx, bn, 12, kn);
                /* tangential: (I - n n)(x_j - x_i) + r_i n x th_i + r_j n x th_j, component e */
                for (int e = 0; e < 3; ++e) {
                    double bt[12] = {0};
                    for (int c = 0; c < 3; ++c) {
                        const double pc = (e == c ? 1.0 : 0.0) - n[e] * n[c];
                        bt[c] = -pc;
                        bt[6 + c] = pc;
                    }
                    /* (n x th)_e = sum_c eps_{e k c} n_k th_c */
                    const int e1 = (e + 1) % 3, e2 = (e + 2) % 3;
                    double cross[3] = {0};
                    cross[e2] = n[e1];  /* eps_{e e1 e2} = +1 */
                    cross[e1] = -n[e2]; /* eps_{e e2 e1} = -1 */
                    for (int c = 0; c < 3; ++c) {
                        bt[3 + c] = r[i] * cross[c];
                        bt[9 + c] = r[j] * cross[c];
                    }
                    for (int c = 0; c < 12; ++c)
                        bt[c] *= scale[c];
                    add_outer(K, idx, bt, 12, ks);
                }
            }
        const double bound = lub_step_rows_max(trans, rot, nb, NULL);
        const double lam = largest_eigenvalue(K, 6 * nb);
        ST_CHECK(lam <= bound * (1.0 + 1e-9),
                 "trial %d (%d bodies): omega_max^2 %.9g above the "
                 "row bound %.9g",
                 trial, nb, lam, bound);
        /* and not so loose that it would cut the step for nothing (2.5 at most here) */
        ST_CHECK(bound <= 3.0 * lam, "trial %d: row bound %.9g, omega_max^2 %.9g", trial, bound,
                 lam);
    }
    /* one pair of equal spheres, normal stiffness only: the bound is exact, 2 g/m */
    const double r[2] = {1.0, 1.0}, inv_m[2] = {0.25, 0.25}, inv_i[2] = {1.0, 1.0};
    double trans[2] = {0}, rot[2] = {0};
    lub_step_rows_add(trans, rot, 0, 1, r, inv_m, inv_i, 3.0, 0.0);
    int body = -2;
    const double w2 = lub_step_rows_max(trans, rot, 2, &body);
    ST_CHECK(fabs(w2 - 2.0 * 3.0 * 0.25) <= 1e-15 && body == 0, "single pair: %g (body %d)", w2,
             body);
    ST_CHECK(lub_step_rows_max(trans, rot, 0, &body) == 0.0 && body == -1, "no bodies");
}

/* ---- 4: on a packing ---- */
static double bound_of(lub_shear_system *s, double dt)
{
    return lub_pairs_stiffness_dt(&s->pairs, &s->law, s->r, s->inv_m, s->inv_i, s->n, dt,
                                  s->row_scratch, NULL);
}

static double stable_of(lub_shear_system *s, double dt_max, double safety)
{
    return lub_pairs_stable_dt(&s->pairs, &s->law, s->r, s->inv_m, s->inv_i, s->n, dt_max, safety,
                               s->row_scratch);
}

static double adapted_of(lub_shear_system *s, double dt, double dt_base, double safety,
                         double *ratio)
{
    return lub_pairs_adapted_dt(&s->pairs, &s->law, s->r, s->inv_m, s->inv_i, s->n, dt, dt_base,
                                safety, s->row_scratch, ratio);
}

static void check_system(void)
{
    /* light, soft spheres with a 3 a cut-off: St * stiffness = 1 (runs at 0.3 of the
     * single-pair step blew up) */
    lub_law_params law = shear_fixture_law(1e2);
    lub_shear_system s;
    ST_CHECK(shear_fixture_make(&s, 200, 0.3, &law, 3.0, 1, 7u, 0.01) == 0, "fixture");
    ST_CHECK(lub_shear_step(&s, 0, NULL) == 0, "first step");
    const double dt_pair = s.dt; /* 0.3 of the single-pair step */
    double no_rows[2];
    lub_shear_system empty = {.n = 0, .row_scratch = no_rows};
    ST_CHECK(isinf(bound_of(&empty, dt_pair)), "no pairs: no bound");
    const double bound = bound_of(&s, dt_pair);
    ST_CHECK(dt_pair / bound > 1.0, "dt/bound %g: this configuration needs a smaller step",
             dt_pair / bound);
    const double stable = stable_of(&s, dt_pair, 0.9);
    const double ratio = stable / bound_of(&s, stable);
    ST_CHECK(stable < dt_pair && ratio <= 0.9 * 1.01 && ratio >= 0.9 * 0.98,
             "stable step %g (single-pair %g): ratio %g", stable, dt_pair, ratio);
    ST_CHECK(stable_of(&s, 0.5 * stable, 0.9) == 0.5 * stable,
             "an admissible dt_max is returned unchanged");
    /* the scene's rule: lowered to 0.9 of the admissible step, raised back from far below it,
     * kept in between, and dt_base restored when the pairs allow it */
    double down_ratio;
    const double down = adapted_of(&s, dt_pair, dt_pair, 0.9, &down_ratio);
    ST_CHECK(fabs(down - 0.9 * stable) <= 1e-12 * stable, "lowered to %g, expected %g", down,
             0.9 * stable);
    ST_CHECK(down_ratio == down / bound_of(&s, down), "ratio %g at the returned step", down_ratio);
    double kept_ratio;
    ST_CHECK(adapted_of(&s, dt_pair, dt_pair, 0.0, &kept_ratio) == dt_pair &&
                 kept_ratio == dt_pair / bound,
             "safety 0 keeps the step (ratio %g)", kept_ratio);
    const double up = adapted_of(&s, 0.3 * stable, dt_pair, 0.9, NULL);
    ST_CHECK(fabs(up - 0.9 * stable) <= 1e-12 * stable, "raised to %g, expected %g", up,
             0.9 * stable);
    ST_CHECK(adapted_of(&s, 0.85 * stable, dt_pair, 0.9, NULL) == 0.85 * stable,
             "a step within the margins is kept");
    ST_CHECK(adapted_of(&s, 0.3 * stable, 0.5 * stable, 0.9, NULL) == 0.5 * stable,
             "raised back to dt_base when the pairs allow it");
    /* the system's control: nothing between rebuilds, one change at a rebuild, its record */
    lub_step_control ctl;
    lub_step_control_init(&ctl, dt_pair, 0.9);
    ctl.rebuilds = s.rebuilds;
    ST_CHECK(lub_shear_step_control(&s, &ctl) == 0 && ctl.dt == dt_pair && ctl.ratio_max == 0.0,
             "no rebuild since: no change");
    ctl.rebuilds = s.rebuilds - 1;
    ST_CHECK(lub_shear_step_control(&s, &ctl) == 1 && ctl.dt == down && ctl.dt_min == down &&
                 ctl.changes == 1 && ctl.ratio_max == down_ratio,
             "a rebuild: dt %g, min %g, changes %ld, ratio %g", ctl.dt, ctl.dt_min, ctl.changes,
             ctl.ratio_max);
    lub_shear_free(&s);
}

/* the diagnostic of a step that fell so far that the run would pass the step-count limit
 * (step_count.h; both many-particle scenes give it) */
static void check_fell_message(void)
{
    char text[600];
    lub_step_count_fell(text, sizeof text, 2.5e-9, 3.25, 0.9, 4, 2e12);
    ST_CHECK(strstr(text, "the automatic step fell to 2.5e-09 at strain 3.2500") &&
                 strstr(text, "/dt_stiffness_safety 0.9; 4 changes") &&
                 strstr(text, "take the run to 2e+12 steps, more than the 1e+12") &&
                 strstr(text, "; lower /strain or /stiffness"),
             "%s", text);
}

int main(void)
{
    check_fell_message();
    check_normal_against_law();
    check_limits();
    check_gershgorin();
    check_system();
    ST_DONE();
}
