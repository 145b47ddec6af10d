/* test_contact_batch.c — the vector (4- or 8-lane) law (contact_batch.h) against the scalar law
 * (lub_pair_step) and the vector exp/log (simd_math.h) against libm.
 *
 * 1. exp/log: relative error over their domains (log: 2e5 points log-uniform over the normal
 *    doubles plus points next to 1; exp: uniform on [-707, 707]); bound 4e-16 (2 ulp).
 * 2. Batched law: random pairs over every regime the time step meets (far pairs u > a, near
 *    pairs with roll/twist torques, contacts in stick and in slip, smooth and rough spheres,
 *    h from 1e-4 to 1e4, rotated normals, fixed bodies) for several term masks. Each accepted
 *    lane is compared with lub_pair_step on a copy of the same state: forces, torques, the new
 *    state and the flags. Tolerances: torques and shear force 1e-11 of their size; the gap
 *    delta 1e-12; the force 1e-10 of g a (|s| + x), the scale of the round-off of
 *    F_n = g a (s - x). The closed form b = 1 - h (s + a_c e) loses digits when h s ~ 1, in
 *    both implementations alike (they differ by FMA contraction and 2-ulp exp/log), so x+ can
 *    differ by ~1e-13 relative; the largest differences seen are 2e-11 (force) and 1.3e-13
 *    (delta). A wrong branch or a missing term gives O(1) errors.
 * 3. Declined lanes (new pairs, delta outside [-700, 700], u/a > 8, a stored shear force
 *    outside [1e-100, 1e100], an absurd spin about the normal, quasi-static law) are
 *    reported as not done and their state is bit-for-bit untouched; a regular far pair is
 *    accepted.
 * 4. Unequal radii (a = 1.05, 2.75) against formulas written out in the test, not against the
 *    scalar law: each torque arm r_i + u_n/2, the shear increment (zero for rolling without
 *    sliding) and the a^3 of the roll/twist coefficients.
 * Prints name=value lines; exits non-zero on failure. */
#include "contact_batch.h"
#include "contact_law.h"
#include "law_check.h"
#include "law_rng.h"

#include <float.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

static void test_math(void)
{
    law_rng r = {12345};
    double max_log = 0.0, max_exp = 0.0;
    const int w = lub_pair_batch_width();
    for (int k = 0; k < 200000; ++k) {
        double x[8], y[8];
        for (int l = 0; l < w; ++l) {
            if (k % 4 == 0)
                x[l] = 1.0 + law_rng_range(&r, -1e-3, 1e-3) * pow(10.0, -(double)(k % 13));
            else
                x[l] = law_rng_logrange(&r, DBL_MIN, 1e307);
        }
        lub_pair_batch_log(x, y);
        for (int l = 0; l < w; ++l) {
            const double ref = log(x[l]);
            const double err = fabs(y[l] - ref) / fmax(fabs(ref), DBL_MIN);
            if (err > max_log)
                max_log = err;
        }
        for (int l = 0; l < w; ++l)
            x[l] = law_rng_range(&r, -707.0, 707.0);
        lub_pair_batch_exp(x, y);
        for (int l = 0; l < w; ++l) {
            const double err = fabs(y[l] - exp(x[l])) / exp(x[l]);
            if (err > max_exp)
                max_exp = err;
        }
    }
    printf("simd_log_max_rel_err=%.3g\nsimd_exp_max_rel_err=%.3g\n", max_log, max_exp);
    CHECK(max_log < 4e-16, "log relative error %.3g", max_log);
    CHECK(max_exp < 4e-16, "exp relative error %.3g", max_exp);
    /* exact points */
    double one[8] = {1.0, 2.0, 0.5, 1024.0, 1.0, 1.0, 1.0, 1.0}, out[8];
    lub_pair_batch_log(one, out);
    CHECK(out[0] == 0.0, "log(1) = %.17g", out[0]);
    CHECK(fabs(out[1] - log(2.0)) <= DBL_EPSILON * log(2.0), "log 2 = %.17g", out[1]);
    double z[8] = {0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0};
    lub_pair_batch_exp(z, out);
    CHECK(out[0] == 1.0, "exp(0) = %.17g", out[0]);
}

typedef struct {
    lub_pair_input in;
    lub_pair_state st;
} pair_case;

/* A pair in one of the regimes of a dense sheared suspension. */
static pair_case random_case(law_rng *r, int regime)
{
    pair_case c;
    memset(&c, 0, sizeof c);
    const double r1 = law_rng_range(r, 0.85, 1.15), r2 = law_rng_range(r, 0.85, 1.15);
    const double a = 0.5 * (r1 + r2);
    double s; /* u_n / a */
    switch (regime) {
    case 0: s = law_rng_range(r, 1.0, 2.2); break;      /* far: u > a */
    case 1: s = law_rng_logrange(r, 0.03, 1.0); break;  /* near, out of contact */
    case 2: s = law_rng_logrange(r, 1e-5, 0.03); break; /* around the roughness */
    default: s = law_rng_range(r, -0.03, 0.005); break; /* compressed contact */
    }
    const vec3 n = unit(rand_vec(r, 1.0));
    c.in.branch = v3_scale(n, (r1 + r2) + s * a);
    c.in.r1 = r1, c.in.r2 = r2;
    c.in.v1 = rand_vec(r, 1.0);
    c.in.v2 = rand_vec(r, 1.0);
    c.in.w1 = rand_vec(r, 1.0);
    c.in.w2 = rand_vec(r, 1.0);
    const int fixed = law_rng_uniform(r) < 0.1;
    c.in.inv_inertia1 = fixed ? 0.0 : law_rng_logrange(r, 0.1, 1e4);
    c.in.inv_inertia2 = law_rng_logrange(r, 0.1, 1e4);
    c.in.dt = law_rng_logrange(r, 1e-6, 1e-2);
    /* history: a gap near the current one (or a deep one for compressed contacts), a stored
     * shear force of any size, a slightly different previous normal */
    double dprev;
    if (regime == 3)
        dprev = law_rng_range(r, -30.0, log(0.02));
    else
        dprev = log(fabs(s) + 1e-12) + law_rng_range(r, -0.3, 0.3);
    lub_pair_state_set_gap(&c.st, dprev);
    const double fs_size = law_rng_uniform(r) < 0.05 ? law_rng_logrange(r, 1e-95, 1e95)
                                                     : law_rng_logrange(r, 1e-3, 1e3);
    c.st.fs = law_rng_uniform(r) < 0.1 ? v3(0, 0, 0) : rand_vec(r, fs_size);
    c.st.n_prev = unit(v3_axpy(n, law_rng_range(r, 0.0, 0.2), rand_vec(r, 1.0)));
    return c;
}

static double vdiff(vec3 a, vec3 b) { return v3_norm(v3_sub(a, b)); }

static void fill_lane(lub_pair_batch *b, int l, const pair_case *c, lub_pair_state *st)
{
    b->bx[l] = c->in.branch.x, b->by[l] = c->in.branch.y, b->bz[l] = c->in.branch.z;
    b->v1x[l] = c->in.v1.x, b->v1y[l] = c->in.v1.y, b->v1z[l] = c->in.v1.z;
    b->v2x[l] = c->in.v2.x, b->v2y[l] = c->in.v2.y, b->v2z[l] = c->in.v2.z;
    b->w1x[l] = c->in.w1.x, b->w1y[l] = c->in.w1.y, b->w1z[l] = c->in.w1.z;
    b->w2x[l] = c->in.w2.x, b->w2y[l] = c->in.w2.y, b->w2z[l] = c->in.w2.z;
    b->r1[l] = c->in.r1, b->r2[l] = c->in.r2;
    b->inv_i1[l] = c->in.inv_inertia1, b->inv_i2[l] = c->in.inv_inertia2;
    b->state[l] = st;
}

static void test_batch_against_scalar(void)
{
    const unsigned masks[] = {LUB_TERM_ALL, LUB_TERM_ALL & ~(LUB_TERM_ROLL | LUB_TERM_TWIST),
                              LUB_TERM_NORMAL_LUB | LUB_TERM_FRICTION | LUB_TERM_ROLL,
                              LUB_TERM_ALL & ~LUB_TERM_FRICTION};
    const double eps_values[] = {0.02, 0.0, 0.002};
    law_rng r = {777};
    double max_f = 0.0, max_t = 0.0, max_d = 0.0, max_fs = 0.0;
    long compared = 0, offered = 0, contacts = 0, slips = 0, nears = 0;
    for (int m = 0; m < 4; ++m)
        for (int ie = 0; ie < 3; ++ie)
            for (int rep = 0; rep < 300; ++rep) {
                /* alpha != 1 in two batches of three: the asperity share of the normal force
                 * (and so the Coulomb limit) differs from the total's only then */
                lub_law_params p = {.eta = 1.0,
                                    .k_bulk = law_rng_logrange(&r, 1e2, 1e6),
                                    .alpha = rep % 3 ? law_rng_logrange(&r, 0.05, 20.0) : 1.0,
                                    .k_t = 0.0,
                                    .eps = eps_values[ie],
                                    .mu = 0.5,
                                    .terms = masks[m]};
                p.k_t = 0.5 * p.k_bulk;
                /* one dt per batch (the batch takes a single dt) */
                pair_case cs[LUB_BATCH];
                lub_pair_state sb[LUB_BATCH];
                lub_pair_batch b;
                b.n = 1 + (int)(law_rng_uniform(&r) * LUB_BATCH) % LUB_BATCH;
                const double dt = law_rng_logrange(&r, 1e-6, 1e-2);
                for (int l = 0; l < b.n; ++l) {
                    cs[l] = random_case(&r, (int)(law_rng_uniform(&r) * 4.0));
                    cs[l].in.dt = dt;
                    sb[l] = cs[l].st;
                    fill_lane(&b, l, &cs[l], &sb[l]);
                }
                const int acc = lub_pair_step_batch(&p, dt, &b);
                int nd = 0;
                offered += b.n;
                for (int l = 0; l < b.n; ++l) {
                    lub_pair_state ss = cs[l].st;
                    lub_pair_output o;
                    const int rc = lub_pair_step(&p, &cs[l].in, &ss, &o);
                    if (!b.done[l]) {
                        CHECK(memcmp(&sb[l], &cs[l].st, sizeof sb[l]) == 0,
                              "declined lane %d state modified", l);
                        continue;
                    }
                    nd++;
                    CHECK(rc == 0, "scalar law failed (rc %d) on an accepted lane", rc);
                    /* the normal force g a (s - x) is computed from two nearly equal numbers
                     * near equilibrium: its round-off scale is g a (|s| + x), not |F| */
                    const double a = 0.5 * (cs[l].in.r1 + cs[l].in.r2);
                    const double fscale =
                        v3_norm(o.force1) + p.k_bulk * a * (fabs(o.un) / a + exp(o.delta));
                    const double tscale =
                        fmax(fmax(v3_norm(o.torque1), v3_norm(o.torque2)), 1e-300);
                    const double ef = vdiff(v3(b.f1x[l], b.f1y[l], b.f1z[l]), o.force1) / fscale;
                    const double et1 = vdiff(v3(b.t1x[l], b.t1y[l], b.t1z[l]), o.torque1) / tscale;
                    const double et2 = vdiff(v3(b.t2x[l], b.t2y[l], b.t2z[l]), o.torque2) / tscale;
                    const double ed = fabs(sb[l].delta - ss.delta) / fmax(1.0, fabs(ss.delta));
                    const double efs =
                        vdiff(sb[l].fs, ss.fs) / fmax(v3_norm(ss.fs), fmax(fscale, 1e-300));
                    const double en = vdiff(sb[l].n_prev, ss.n_prev);
                    max_f = fmax(max_f, ef);
                    max_t = fmax(max_t, fmax(et1, et2));
                    max_d = fmax(max_d, ed);
                    max_fs = fmax(max_fs, efs);
                    CHECK(ef < 1e-10 && et1 < 1e-11 && et2 < 1e-11,
                          "mask %u eps %g s %.3g: force err %.3g torque err %.3g/%.3g", masks[m],
                          p.eps, o.un / (0.5 * (cs[l].in.r1 + cs[l].in.r2)), ef, et1, et2);
                    CHECK(ed < 1e-12 && efs < 1e-11 && en < 1e-14,
                          "state: delta err %.3g fs err %.3g n err %.3g", ed, efs, en);
                    /* flags: identical unless the gap sits on the roughness to round-off */
                    const double x = exp(ss.delta);
                    if (fabs(x - p.eps) > 1e-9 * p.eps)
                        CHECK(b.contact[l] == o.contact, "contact flag %d vs %d (x %.17g)",
                              b.contact[l], o.contact, x);
                    if (fabs(ss.delta) > 1e-12)
                        CHECK(b.near[l] == (o.delta < 0.0), "near flag");
                    CHECK(!lub_pair_state_is_new(&ss) && !lub_pair_state_is_new(&sb[l]),
                          "new after the step");
                    /* the stored x is the solve's u/a: e^delta to round-off (delta = ln x is
                     * good to 4e-16 max(1, |delta|), simd_math.h), as the scalar's */
                    CHECK(fabs(sb[l].x - exp(sb[l].delta)) <=
                                  1e-15 * fmax(1.0, fabs(sb[l].delta)) * sb[l].x &&
                              fabs(sb[l].x - ss.x) <= 1e-9 * ss.x,
                          "stored x %.17g, e^delta %.17g, scalar x %.17g", sb[l].x,
                          exp(sb[l].delta), ss.x);
                    contacts += o.contact;
                    slips += o.slip;
                    nears += o.delta < 0.0;
                    compared++;
                }
                CHECK(acc == nd, "returned %d accepted, flags say %d", acc, nd);
            }
    printf("batch_lanes_offered=%ld\nbatch_lanes_compared=%ld\nbatch_contacts=%ld\n"
           "batch_slips=%ld\nbatch_near=%ld\n",
           offered, compared, contacts, slips, nears);
    printf("batch_max_force_rel_err=%.3g\nbatch_max_torque_rel_err=%.3g\n"
           "batch_max_delta_err=%.3g\nbatch_max_fs_rel_err=%.3g\n",
           max_f, max_t, max_d, max_fs);
    /* the random regimes must exercise every branch and most lanes must be accepted */
    CHECK(compared > offered * 9 / 10, "only %ld of %ld lanes accepted", compared, offered);
    CHECK(contacts > 100 && slips > 50 && nears > 1000, "regimes not all exercised");
}

static void test_declined(void)
{
    law_rng r = {99};
    lub_law_params p = {.eta = 1.0,
                        .k_bulk = 1e4,
                        .alpha = 1.0,
                        .k_t = 5e3,
                        .eps = 0.02,
                        .mu = 0.5,
                        .terms = LUB_TERM_ALL};
    enum { NL = 8 };
    pair_case cs[NL];
    lub_pair_state sb[NL];
    lub_pair_batch b;
    b.n = NL;
    for (int l = 0; l < NL; ++l)
        cs[l] = random_case(&r, 0);
    cs[0].st.x = LUB_PAIR_STATE_NEW;           /* new pair: created by the scalar law */
    lub_pair_state_set_gap(&cs[1].st, -800.0); /* deep gap */
    lub_pair_state_set_gap(&cs[2].st, 701.0);  /* beyond the guard */
    cs[3].in.branch = v3_scale(unit(cs[3].in.branch), cs[3].in.r1 + cs[3].in.r2 + 9.0); /* u/a>8 */
    lub_pair_state_set_gap(&cs[3].st, log(9.0 / (0.5 * (cs[3].in.r1 + cs[3].in.r2))));
    /* lane 4: regular. Outside the ranges of the kernel's shared division (1/c1, 1/(1 + qt),
     * 1/|F_s|^2 from one reciprocal): stored shear forces below 1e-100 and above 1e100, and a
     * spin about the normal so large that (dt (w1 + w2).n / 2)^2 / 4 > 1e50 */
    cs[5].st.fs = v3(1e-101, 0.0, 0.0);
    cs[7].st.fs = v3(0.0, 0.0, 1e101);
    cs[6].in.w1 = v3_scale(unit(cs[6].in.branch), 1e32);
    for (int l = 0; l < NL; ++l) {
        sb[l] = cs[l].st;
        fill_lane(&b, l, &cs[l], &sb[l]);
    }
    int acc = lub_pair_step_batch(&p, 1e-4, &b);
    CHECK(acc == 1 && b.done[4] == 1, "regular lane accepted (%d accepted)", acc);
    for (int l = 0; l < NL; ++l) {
        if (l == 4)
            continue;
        CHECK(b.done[l] == 0, "lane %d should be declined", l);
        CHECK(memcmp(&sb[l], &cs[l].st, sizeof sb[l]) == 0, "declined lane %d modified", l);
    }
    /* quasi-static law (no normal lubrication): the whole batch is declined */
    p.terms = LUB_TERM_ALL & ~LUB_TERM_NORMAL_LUB;
    for (int l = 0; l < NL; ++l)
        sb[l] = cs[l].st;
    acc = lub_pair_step_batch(&p, 1e-4, &b);
    CHECK(acc == 0, "quasi-static batch accepted %d lanes", acc);
    printf("batch_isa=%s\nbatch_width=%d\n", lub_pair_batch_isa(), lub_pair_batch_width());
}

static vec3 tangential(vec3 f, vec3 n) { return v3_axpy(f, -v3_dot(f, n), n); }

/* 4. Unequal radii (r1 = 0.8, r2 = 1.3, a = (r1 + r2)/2 = 1.05) against the formulas written out
 * here, not against lub_pair_step (an error shared by both laws passes section 2):
 *  - torque arms (notes §4.6): torque_i = (r_i + u_n/2) n x F_s, F_s = tangential part of the
 *    force on body 1, roll/twist off; lubricated gap, Maxwell element, stick and slip;
 *  - shear increment (notes §1.7): sticking contacts with no stored force, F_s = k_t du_s, du_s
 *    the tangential relative velocity of the facing material points (body 1's at r1 n, body
 *    2's at -r2 n) times dt: zero for rolling without sliding (r1 w1_t = -r2 w2_t);
 *  - roll/twist coefficients pi eta a^3 (3/2 + 63x/500) ln(1/x) and pi eta a^3 x ln(1/x),
 *    exponentially integrated, for a = 1.05 and a = 2.75, fixed and free bodies (shear
 *    terms off: the total torques are these alone). */
static void test_unequal_radii(void)
{
    const double dt = 1e-3;
    const vec3 n = unit(v3(0.3, -0.5, 0.8));
    const vec3 wt = tangential(v3(0.7, 0.2, -0.4), n);
    lub_law_params p = {.eta = 1.0,
                        .k_bulk = 1e4,
                        .alpha = 1.0,
                        .k_t = 5e3,
                        .eps = 0.01,
                        .mu = 0.5,
                        .terms = LUB_TERM_ALL & ~(LUB_TERM_ROLL | LUB_TERM_TWIST)};
    /* arms and increment: one batch */
    const struct {
        double s, x0, fs0; /* u_n / a, stored u/a, stored |F_s| */
        vec3 w1, w2;
        int stick; /* 1: sticking, F_s = k_t du_s */
    } cases[] = {
        {0.3, 0.3, 1.0, v3(0.5, -0.3, 0.2), v3(-0.2, 0.6, 0.4), 0},
        {0.02, 0.02, 1.0, v3(0.5, -0.3, 0.2), v3(-0.2, 0.6, 0.4), 0},
        {-0.004, 0.003, 1.0, v3(0.5, -0.3, 0.2), v3(-0.2, 0.6, 0.4), 0},
        {-0.004, 0.003, 100.0, v3(0.5, -0.3, 0.2), v3(-0.2, 0.6, 0.4), 0},
        {-0.004, 0.003, 0.0, v3_axpy(wt, 0.9, n), v3_axpy(v3_scale(wt, -0.8 / 1.3), -0.4, n), 1},
        {-0.004, 0.003, 0.0, wt, v3(0, 0, 0), 1},
        {-0.004, 0.003, 0.0, v3(0, 0, 0), wt, 1},
        {-0.004, 0.003, 0.0, v3(0.5, -0.3, 0.2), v3(-0.2, 0.6, 0.4), 1},
    };
    enum { NC = sizeof cases / sizeof cases[0] };
    pair_case cs[NC];
    lub_pair_state sb[NC];
    lub_pair_batch b;
    b.n = NC;
    for (int l = 0; l < NC; ++l) {
        const double r1 = 0.8, r2 = 1.3, a = 0.5 * (r1 + r2);
        memset(&cs[l], 0, sizeof cs[l]);
        cs[l].in.branch = v3_scale(n, r1 + r2 + cases[l].s * a);
        cs[l].in.r1 = r1, cs[l].in.r2 = r2;
        cs[l].in.v1 = v3(0.1, -0.2, 0.3);
        /* stick lanes: v2 - v1 along n, so du_s comes from the spins alone */
        cs[l].in.v2 = cases[l].stick ? v3_axpy(cs[l].in.v1, 0.25, n) : v3(-0.3, 0.2, 0.1);
        cs[l].in.w1 = cases[l].w1, cs[l].in.w2 = cases[l].w2;
        cs[l].in.inv_inertia1 = 2.5 / (r1 * r1), cs[l].in.inv_inertia2 = 2.5 / (r2 * r2);
        cs[l].in.dt = dt;
        lub_pair_state_set_gap(&cs[l].st, log(cases[l].x0));
        cs[l].st.fs = v3_scale(unit(tangential(v3(3.0, -1.0, 2.0), n)), cases[l].fs0);
        cs[l].st.n_prev = n;
        sb[l] = cs[l].st;
        fill_lane(&b, l, &cs[l], &sb[l]);
    }
    int acc = lub_pair_step_batch(&p, dt, &b);
    CHECK(acc == NC, "unequal radii: %d of %d lanes accepted", acc, NC);
    double max1 = 0.0, max2 = 0.0, max_roll = 0.0, max_fs = 0.0;
    for (int l = 0; l < NC; ++l) {
        if (!b.done[l])
            continue;
        const double r1 = cs[l].in.r1, r2 = cs[l].in.r2;
        const vec3 nn = unit(cs[l].in.branch);
        const double u = v3_norm(cs[l].in.branch) - r1 - r2;
        const vec3 fs = tangential(v3(b.f1x[l], b.f1y[l], b.f1z[l]), nn);
        const vec3 nxf = v3_cross(nn, fs);
        const double scale = (r2 + fabs(u)) * v3_norm(fs) + 1e-300;
        const double e1 =
            vdiff(v3(b.t1x[l], b.t1y[l], b.t1z[l]), v3_scale(nxf, r1 + 0.5 * u)) / scale;
        const double e2 =
            vdiff(v3(b.t2x[l], b.t2y[l], b.t2z[l]), v3_scale(nxf, r2 + 0.5 * u)) / scale;
        if (l != 4) { /* lane 4 (rolling) has F_s = 0 */
            CHECK(v3_norm(fs) > 1e-3, "unequal radii lane %d: no shear force", l);
            CHECK(e1 < 1e-12, "batch unequal radii lane %d: torque1 != (r1 + u_n/2) n x F_s: %.3e",
                  l, e1);
            CHECK(e2 < 1e-12, "batch unequal radii lane %d: torque2 != (r2 + u_n/2) n x F_s: %.3e",
                  l, e2);
            max1 = fmax(max1, e1);
            max2 = fmax(max2, e2);
        }
        if (cases[l].stick) {
            /* sticking: |k_t du_s| well inside mu alpha g a (eps - x) */
            const vec3 vc1 = v3_cross(cases[l].w1, v3_scale(nn, r1));
            const vec3 vc2 = v3_cross(cases[l].w2, v3_scale(nn, -r2));
            const vec3 ref = v3_scale(tangential(v3_sub(vc2, vc1), nn), p.k_t * dt);
            const double e = vdiff(fs, ref) / (p.k_t * dt * r1 * v3_norm(wt));
            CHECK(b.contact[l], "unequal radii lane %d: contact expected", l);
            CHECK(e < 1e-12, "batch unequal radii lane %d: F_s vs k_t du_s: %.3e (|F_s| %.3e)", l,
                  e, v3_norm(fs));
            if (l == 4)
                max_roll = fmax(max_roll, e);
            else
                max_fs = fmax(max_fs, e);
        }
    }
    /* roll / twist coefficients */
    const double radii[2][2] = {{0.8, 1.3}, {2.0, 3.5}};
    const double inv[2][2] = {{0.0, 0.0}, {2.5, 1.7}};
    const vec3 w1 = v3(0.3, 0.2, -0.1), w2 = v3(-0.4, 0.1, 0.5);
    p.terms = LUB_TERM_NORMAL_LUB | LUB_TERM_ROLL | LUB_TERM_TWIST;
    b.n = 4;
    for (int l = 0; l < 4; ++l) {
        const double r1 = radii[l / 2][0], r2 = radii[l / 2][1], a = 0.5 * (r1 + r2);
        memset(&cs[l], 0, sizeof cs[l]);
        cs[l].in.branch = v3_scale(n, r1 + r2 + 0.05 * a);
        cs[l].in.r1 = r1, cs[l].in.r2 = r2;
        cs[l].in.v1 = v3(0.1, -0.2, 0.3), cs[l].in.v2 = v3(-0.3, 0.2, 0.1);
        cs[l].in.w1 = w1, cs[l].in.w2 = w2;
        cs[l].in.inv_inertia1 = inv[l % 2][0], cs[l].in.inv_inertia2 = inv[l % 2][1];
        cs[l].in.dt = dt;
        lub_pair_state_set_gap(&cs[l].st, log(0.05));
        cs[l].st.n_prev = n;
        sb[l] = cs[l].st;
        fill_lane(&b, l, &cs[l], &sb[l]);
    }
    acc = lub_pair_step_batch(&p, dt, &b);
    CHECK(acc == 4, "unequal radii torques: %d of 4 lanes accepted", acc);
    double max_t = 0.0;
    for (int l = 0; l < 4; ++l) {
        if (!b.done[l])
            continue;
        const double a = 0.5 * (cs[l].in.r1 + cs[l].in.r2), a3 = a * a * a;
        const double inv_sum = cs[l].in.inv_inertia1 + cs[l].in.inv_inertia2;
        const double x = exp(sb[l].delta), L = -sb[l].delta;
        CHECK(sb[l].delta < 0.0, "unequal radii torques lane %d: u > a", l);
        const double cr = LUB_PI * p.eta * a3 * (1.5 + 63.0 / 500.0 * x) * L;
        const double ct = LUB_PI * p.eta * a3 * x * L;
        const double kr = cr * dt * inv_sum, kt = ct * dt * inv_sum;
        const double fr = kr > 0.0 ? -expm1(-kr) / kr : 1.0;
        const double ft = kt > 0.0 ? -expm1(-kt) / kt : 1.0;
        const vec3 Om = v3_sub(w2, w1);
        const vec3 Omt = v3_scale(n, v3_dot(Om, n)), Omr = v3_sub(Om, Omt);
        const vec3 T = v3_add(v3_scale(Omr, cr * fr), v3_scale(Omt, ct * ft));
        const double e1 = vdiff(v3(b.t1x[l], b.t1y[l], b.t1z[l]), T) / v3_norm(T);
        const double e2 = vdiff(v3(b.t2x[l], b.t2y[l], b.t2z[l]), v3_neg(T)) / v3_norm(T);
        CHECK(e1 < 1e-11 && e2 < 1e-11,
              "batch unequal radii a = %g, 1/I %g: roll+twist torques vs pi eta a^3 (...) ln(1/x): "
              "%.3e / %.3e",
              a, inv_sum, e1, e2);
        max_t = fmax(max_t, fmax(e1, e2));
    }
    printf("batch_unequal_radii_torque1_arm_max_rel_err=%.3e\n", max1);
    printf("batch_unequal_radii_torque2_arm_max_rel_err=%.3e\n", max2);
    printf("batch_unequal_radii_rolling_fs_rel=%.3e\n", max_roll);
    printf("batch_unequal_radii_stick_fs_vs_kt_du_max_rel_err=%.3e\n", max_fs);
    printf("batch_unequal_radii_spin_torque_max_rel_err=%.3e\n", max_t);
}

int main(void)
{
    test_math();
    test_batch_against_scalar();
    test_declined();
    test_unequal_radii();
    printf("failures=%d\n", failures);
    return failures ? 1 : 0;
}
