/* test_law_pair.c — full per-pair law (lub_pair_step): conservation, frame invariance,
 * decomposition, switches, torques, new pairs, shear viscosity, error returns, the
 * unfloored decay of a heavily compressed pair (delta far below -700, notes §11 P5), and, on
 * unequal spheres (a != 1), each torque arm, the shear increment and the a^3 of the roll/twist
 * coefficients against their formulas.
 * Prints name=value lines; exits non-zero on failure. */
#include "contact_law.h"
#include "contact_shear.h"
#include "law_check.h"
#include "law_rng.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

static lub_law_params base_params(void)
{
    lub_law_params p = {.eta = 1.0,
                        .k_bulk = 1e4,
                        .alpha = 1.0,
                        .k_t = 5e3,
                        .eps = 0.01,
                        .mu = 0.5,
                        .terms = LUB_TERM_ALL};
    return p;
}

/* Random realistic pair: radii ~1, gap in [-0.05, 1.5] a, random history. */
static void random_pair(law_rng *r, lub_law_params *p, lub_pair_input *in, lub_pair_state *st)
{
    *p = base_params();
    p->eta = law_rng_logrange(r, 1e-6, 1e3);
    p->alpha = law_rng_logrange(r, 1e-3, 1e3);
    p->eps = (law_rng_uniform(r) < 0.2) ? 0.0 : law_rng_range(r, 0.0, 0.1);
    p->mu = law_rng_range(r, 0.0, 1.0);
    memset(in, 0, sizeof *in);
    in->r1 = law_rng_range(r, 0.8, 1.2);
    in->r2 = law_rng_range(r, 0.8, 1.2);
    const double a = 0.5 * (in->r1 + in->r2);
    vec3 n = unit(rand_vec(r, 1.0));
    double un = a * law_rng_range(r, -0.05, 1.5);
    in->branch = v3_scale(n, in->r1 + in->r2 + un);
    in->v1 = rand_vec(r, 1.0);
    in->v2 = rand_vec(r, 1.0);
    in->w1 = rand_vec(r, 1.0);
    in->w2 = rand_vec(r, 1.0);
    in->inv_inertia1 = 1.0 / law_rng_range(r, 0.3, 0.5);
    in->inv_inertia2 = 1.0 / law_rng_range(r, 0.3, 0.5);
    in->dt = 1e-3;
    memset(st, 0, sizeof *st);
    const int fresh = (law_rng_uniform(r) < 0.1);
    /* 5 %: deep history (x_prev subnormal or 0 in double, no floor on delta) */
    lub_pair_state_set_gap(st, (law_rng_uniform(r) < 0.05) ? -law_rng_logrange(r, 700.0, 1e5)
                                                           : log(law_rng_logrange(r, 1e-12, 1.5)));
    if (fresh)
        st->x = LUB_PAIR_STATE_NEW;
    vec3 np = unit(v3_add(n, rand_vec(r, 0.01)));
    st->n_prev = np;
    vec3 f = rand_vec(r, 50.0);
    st->fs = v3_axpy(f, -v3_dot(f, np), np);
}

static void test_random_conservation_and_split(void)
{
    law_rng r = {99};
    const int N = 200000;
    double max_L = 0.0, max_split = 0.0, max_tan = 0.0;
    long n_contact = 0, n_slip = 0, n_stick = 0, n_torque = 0;
    for (int i = 0; i < N; ++i) {
        lub_law_params p;
        lub_pair_input in;
        lub_pair_state st;
        random_pair(&r, &p, &in, &st);
        lub_pair_output o;
        int rc = lub_pair_step(&p, &in, &st, &o);
        CHECK(rc == 0, "rc=%d", rc);
        /* angular momentum about the origin with x1 = 0, x2' = d: d x (-F1) + C1 + C2 = 0 */
        vec3 L = v3_add(v3_cross(in.branch, v3_neg(o.force1)), v3_add(o.torque1, o.torque2));
        double scale = v3_norm(in.branch) * v3_norm(o.force1) + v3_norm(o.torque1) +
                       v3_norm(o.torque2) + 1e-300;
        double eL = v3_norm(L) / scale;
        if (eL > max_L)
            max_L = eL;
        /* contact + lubrication parts sum to the total, normal and tangential */
        vec3 parts = v3_add(v3_scale(o.n, o.fn_contact + o.fn_lub), v3_add(o.fs_contact, o.fs_lub));
        double sc2 = fabs(o.fn_contact) + fabs(o.fn_lub) + v3_norm(o.fs_contact) +
                     v3_norm(o.fs_lub) + 1e-300;
        double es = v3_norm(v3_sub(parts, o.force1)) / sc2;
        if (es > max_split)
            max_split = es;
        /* stored shear force is tangential */
        double et = fabs(v3_dot(st.fs, o.n)) / (v3_norm(st.fs) + 1e-300);
        if (et > max_tan)
            max_tan = et;
        CHECK(o.delta >= LUB_DELTA_MIN && o.delta <= LUB_DELTA_MAX, "delta %g", o.delta);
        CHECK(o.fn_contact <= 0.0, "tensile contact force %g", o.fn_contact);
        CHECK(!o.contact || p.eps > 0.0, "contact with eps = 0");
        if (o.contact) {
            ++n_contact;
            CHECK(v3_norm(o.fs_contact) <= p.mu * fabs(o.fn_contact) * (1 + 1e-12) + 1e-300,
                  "Coulomb violated");
            if (o.slip)
                ++n_slip;
            else
                ++n_stick;
        } else {
            CHECK(v3_norm(o.fs_contact) == 0.0 && o.fn_contact == 0.0, "contact part w/o contact");
        }
        if (v3_norm(o.torque_roll1) > 0.0) {
            ++n_torque;
            CHECK(o.delta < 0.0, "roll torque beyond u = a");
            /* dissipative: torque on 1 along Omega_r = (w2 - w1)_t */
            CHECK(v3_dot(o.torque_roll1, v3_sub(in.w2, in.w1)) >= 0.0, "anti-dissipative roll");
        }
    }
    CHECK(max_L < 1e-12, "angular momentum %g", max_L);
    CHECK(max_split < 1e-12, "split %g", max_split);
    CHECK(max_tan < 1e-12, "shear not tangential %g", max_tan);
    CHECK(n_slip > 1000 && n_stick > 1000 && n_torque > 1000,
          "coverage slip %ld stick %ld torque %ld", n_slip, n_stick, n_torque);
    printf("pair_random_cases=%d\n", N);
    printf("pair_max_rel_angular_momentum_defect=%.3e\n", max_L);
    printf("pair_max_rel_split_defect=%.3e\n", max_split);
    printf("pair_max_shear_normal_component=%.3e\n", max_tan);
    printf("pair_cases_contact=%ld\npair_cases_slip=%ld\npair_cases_stick=%ld\npair_cases_torque=%"
           "ld\n",
           n_contact, n_slip, n_stick, n_torque);
}

/* Rotation matrix application (Rodrigues) about unit axis k by angle t. */
static vec3 rotate(vec3 v, vec3 k, double t)
{
    double c = cos(t), s = sin(t);
    return v3_add(v3_add(v3_scale(v, c), v3_scale(v3_cross(k, v), s)),
                  v3_scale(k, v3_dot(k, v) * (1 - c)));
}

/* Rigid motion (translation + rotation) of a pair: no force at all for a fresh pair at
 * rest relative to each other; for a sticking contact |F_s| is invariant and F_s co-rotates;
 * out of contact |F_s| follows exactly the Maxwell decay. */
static void test_rigid_motion(void)
{
    const vec3 k = unit(v3(0.3, -0.5, 0.8));
    const double Om = 0.7, dt = 1e-2;
    const vec3 Omega = v3_scale(k, Om), V = v3(0.2, 0.1, -0.3);
    struct {
        const char *name;
        double s;   /* u_n / a */
        double fs0; /* initial |F_s| */
        int stick;
    } cases[] = {{"free", 0.3, 0.0, 0}, {"stick", -0.005, 0.002, 1}, {"maxwell", 0.3, 0.002, 0}};
    for (int c = 0; c < 3; ++c) {
        lub_law_params p = {.eta = 0.01,
                            .k_bulk = 1.0,
                            .alpha = 1.0,
                            .k_t = 0.5,
                            .eps = 0.01,
                            .mu = 0.5,
                            .terms = LUB_TERM_ALL};
        const double r1 = 1.0, r2 = 1.0, a = 1.0;
        vec3 x1_0 = v3(0.1, 0.2, 0.3), n0 = unit(v3(1.0, 0.2, -0.1));
        vec3 x2_0 = v3_axpy(x1_0, r1 + r2 + cases[c].s * a, n0);
        lub_pair_state st;
        lub_pair_state_reset(&st);
        lub_pair_output o;
        double max_force = 0.0, max_dev = 0.0, max_dir = 0.0;
        vec3 f0 = v3(0, 0, 0);
        double nu_t = 0.0;
        const int NSTEP = 10000;
        for (int it = 0; it <= NSTEP; ++it) {
            double t = it * dt;
            vec3 x1 = v3_add(rotate(x1_0, k, Om * t), v3_scale(V, t));
            vec3 x2 = v3_add(rotate(x2_0, k, Om * t), v3_scale(V, t));
            lub_pair_input in = {.branch = v3_sub(x2, x1),
                                 .v1 = v3_add(V, v3_cross(Omega, v3_sub(x1, v3_scale(V, t)))),
                                 .v2 = v3_add(V, v3_cross(Omega, v3_sub(x2, v3_scale(V, t)))),
                                 .w1 = Omega,
                                 .w2 = Omega,
                                 .r1 = r1,
                                 .r2 = r2,
                                 .inv_inertia1 = 2.5,
                                 .inv_inertia2 = 2.5,
                                 .dt = dt};
            if (it == 1 && cases[c].fs0 > 0.0) {
                /* inject a tangential force once the pair is at its (static) state */
                vec3 tdir = unit(v3_cross(st.n_prev, v3(0, 0, 1)));
                st.fs = v3_scale(tdir, cases[c].fs0);
                f0 = st.fs;
            }
            int rc = lub_pair_step(&p, &in, &st, &o);
            CHECK(rc == 0, "rigid rc");
            if (it == 1)
                nu_t = lub_shear_viscosity(p.eta, a, o.delta);
            if (cases[c].fs0 == 0.0) {
                double f = v3_norm(o.force1) + v3_norm(o.torque1) + v3_norm(o.torque2);
                if (f > max_force)
                    max_force = f;
            } else if (it >= 1 && (cases[c].stick || it <= 100)) { /* Maxwell: 100 steps ~ 1e-5 */
                double expect = cases[c].fs0;
                if (!cases[c].stick)
                    expect *= pow(nu_t / (nu_t + p.k_t * dt), it);
                double dev = fabs(v3_norm(st.fs) - expect) / cases[c].fs0;
                if (dev > max_dev)
                    max_dev = dev;
                /* direction: the injected force co-rotates with the pair */
                vec3 fr = unit(rotate(f0, k, Om * t));
                double dir = v3_norm(v3_sub(unit(st.fs), fr));
                if (dir > max_dir)
                    max_dir = dir;
                if (cases[c].stick)
                    CHECK(o.contact && !o.slip, "stick case lost contact/stick");
            }
        }
        if (cases[c].fs0 == 0.0) {
            CHECK(max_force < 1e-12, "rigid free pair force %g", max_force);
            printf("rigid_%s_max_force=%.3e\n", cases[c].name, max_force);
        } else {
            CHECK(max_dev < 1e-9, "rigid %s |F_s| deviation %g", cases[c].name, max_dev);
            CHECK(max_dir < 1e-4, "rigid %s direction deviation %g", cases[c].name, max_dir);
            printf("rigid_%s_max_dev_abs_fs_over_fs0=%.3e\n", cases[c].name, max_dev);
            printf("rigid_%s_max_direction_error=%.3e\n", cases[c].name, max_dir);
        }
    }
}

static lub_pair_input simple_input(double un, vec3 w1, vec3 w2)
{
    lub_pair_input in = {.branch = v3(2.0 + un, 0, 0),
                         .v1 = v3(0, 0.1, 0),
                         .v2 = v3(0, -0.1, 0.05),
                         .w1 = w1,
                         .w2 = w2,
                         .r1 = 1,
                         .r2 = 1,
                         .inv_inertia1 = 2.5,
                         .inv_inertia2 = 2.5,
                         .dt = 1e-3};
    return in;
}

static void test_switches_and_torques(void)
{
    lub_law_params p = base_params();
    lub_pair_state st;
    lub_pair_output o;
    const vec3 w1 = v3(0.3, 0.2, -0.1), w2 = v3(-0.4, 0.1, 0.5);

    /* shear lubrication off, no contact: no shear force at all */
    p.terms = LUB_TERM_ALL & ~LUB_TERM_SHEAR_LUB;
    memset(&st, 0, sizeof st);
    st.delta = log(0.2);
    st.fs = v3(0, 1, 0);
    st.n_prev = v3(1, 0, 0);
    lub_pair_input in = simple_input(0.2, w1, w2);
    CHECK(lub_pair_step(&p, &in, &st, &o) == 0, "rc");
    CHECK(v3_norm(v3_axpy(o.force1, -v3_dot(o.force1, o.n), o.n)) == 0.0,
          "shear w/o lub, no contact");

    /* friction off, in contact: no tangential contact force, no slip */
    p.terms = LUB_TERM_ALL & ~LUB_TERM_FRICTION;
    memset(&st, 0, sizeof st);
    st.delta = log(0.002);
    st.fs = v3(0, 100, 0);
    st.n_prev = v3(1, 0, 0);
    in = simple_input(-0.01, w1, w2);
    CHECK(lub_pair_step(&p, &in, &st, &o) == 0, "rc");
    CHECK(o.contact && v3_norm(o.fs_contact) == 0.0 && !o.slip && v3_norm(o.fs_lub) > 0.0,
          "friction off: contact %d fs_c %g", o.contact, v3_norm(o.fs_contact));

    /* same with friction on: slip (100 >> mu |F_c|) and a non-zero contact part */
    p.terms = LUB_TERM_ALL;
    memset(&st, 0, sizeof st);
    st.delta = log(0.002);
    st.fs = v3(0, 100, 0);
    st.n_prev = v3(1, 0, 0);
    CHECK(lub_pair_step(&p, &in, &st, &o) == 0, "rc");
    CHECK(o.contact && o.slip && v3_norm(o.fs_contact) > 0.0, "friction on: slip expected");
    CHECK(fabs(v3_norm(o.fs_contact) - p.mu * fabs(o.fn_contact)) <= 1e-12 * fabs(o.fn_contact),
          "slider force != mu |F_c|");
    /* the asperity share by its formula, not by its own output (notes §2.9, §3.2.5): with
     * alpha = 0.1, F_c = -alpha g a (eps - x), F_l = g a (s - x) + alpha g a (eps - x) and the
     * slider mu alpha g a (eps - x), x = gap/a after the step (a = 1 here) */
    p.alpha = 0.1;
    memset(&st, 0, sizeof st);
    st.delta = log(0.002);
    st.fs = v3(0, 100, 0);
    st.n_prev = v3(1, 0, 0);
    CHECK(lub_pair_step(&p, &in, &st, &o) == 0, "rc");
    {
        const double x = o.gap, s = -0.01, asp = p.alpha * p.k_bulk * (p.eps - x);
        CHECK(o.contact && o.slip && asp > 0.0, "alpha 0.1: contact %d slip %d", o.contact, o.slip);
        CHECK(fabs(o.fn_contact + asp) <= 1e-12 * asp, "alpha 0.1: F_c %.17g, formula %.17g",
              o.fn_contact, -asp);
        CHECK(fabs(o.fn_lub - (p.k_bulk * (s - x) + asp)) <= 1e-9 * p.k_bulk * fabs(s - x),
              "alpha 0.1: F_l %.17g, formula %.17g", o.fn_lub, p.k_bulk * (s - x) + asp);
        CHECK(fabs(v3_norm(o.fs_contact) - p.mu * asp) <= 1e-12 * asp,
              "alpha 0.1: slider %.17g, mu alpha g a (eps - x) %.17g", v3_norm(o.fs_contact),
              p.mu * asp);
    }
    p.alpha = 1.0;

    /* normal lubrication off: fn_lub = 0, contact part = total */
    p.terms = LUB_TERM_ALL & ~LUB_TERM_NORMAL_LUB;
    lub_pair_state_reset(&st);
    CHECK(lub_pair_step(&p, &in, &st, &o) == 0, "rc");
    CHECK(o.fn_lub == 0.0 && o.contact && o.fn_contact < 0.0 &&
              fabs(o.fn_contact - v3_dot(o.force1, o.n)) < 1e-9 * fabs(o.fn_contact),
          "normal lub off");
    /* smooth spheres, no normal lubrication, overlapping: hard-core floor, repulsive g a s */
    p.eps = 0.0;
    lub_pair_state_reset(&st);
    CHECK(lub_pair_step(&p, &in, &st, &o) == 0, "rc");
    CHECK(o.contact && o.delta == LUB_DELTA_STATIC_FLOOR &&
              fabs(o.fn_contact - p.k_bulk * (-0.01)) < 1e-9 * p.k_bulk,
          "hard-core floor fn=%g", o.fn_contact);
    p = base_params();

    /* roll / twist: present for u < a, zero beyond, zero when switched off, and the exact
     * explicit coefficients when k = c dt / I_eff is small */
    for (int sw = 0; sw < 4; ++sw) {
        p.terms = LUB_TERM_ALL & ~(sw & 1 ? LUB_TERM_ROLL : 0u) & ~(sw & 2 ? LUB_TERM_TWIST : 0u);
        p.eta = 1e-3;
        lub_pair_state_reset(&st);
        in = simple_input(0.05, w1, w2);
        CHECK(lub_pair_step(&p, &in, &st, &o) == 0, "rc");
        const double x = exp(o.delta), L = -o.delta;
        const vec3 Om = v3_sub(w2, w1);
        const vec3 Omt = v3_scale(o.n, v3_dot(Om, o.n)), Omr = v3_sub(Om, Omt);
        /* exponential integration factor (1 - e^-k)/k, k = c dt (1/I1 + 1/I2) */
        const double cr = LUB_PI * p.eta * (1.5 + 0.126 * x) * L, ct = LUB_PI * p.eta * x * L;
        const double kr = cr * in.dt * 5.0, kt = ct * in.dt * 5.0;
        const vec3 Tr = v3_scale(Omr, cr * (-expm1(-kr) / kr));
        const vec3 Tt = v3_scale(Omt, ct * (-expm1(-kt) / kt));
        if (sw & 1)
            CHECK(v3_norm(o.torque_roll1) == 0.0, "roll off");
        else
            CHECK(v3_norm(v3_sub(o.torque_roll1, Tr)) < 1e-12 * v3_norm(Tr), "roll coefficient");
        if (sw & 2)
            CHECK(v3_norm(o.torque_twist1) == 0.0, "twist off");
        else
            CHECK(v3_norm(v3_sub(o.torque_twist1, Tt)) < 1e-12 * v3_norm(Tt), "twist coefficient");
    }
    p = base_params();
    lub_pair_state_reset(&st);
    in = simple_input(1.2, w1, w2); /* u > a */
    CHECK(lub_pair_step(&p, &in, &st, &o) == 0, "rc");
    CHECK(v3_norm(o.torque_roll1) == 0.0 && v3_norm(o.torque_twist1) == 0.0, "torque for u > a");

    /* stiff torque: exponential integration never reverses the relative spin */
    double worst = 0.0;
    for (int i = 0; i < 40; ++i) {
        p.eta = pow(10.0, -6 + 0.4 * i); /* 1e-6 ... 1e10 */
        lub_pair_state_reset(&st);
        in = simple_input(1e-9, w1, w2);
        CHECK(lub_pair_step(&p, &in, &st, &o) == 0, "rc");
        vec3 T = v3_add(o.torque_roll1, o.torque_twist1);
        vec3 Om = v3_sub(w2, w1);
        vec3 Om_new = v3_sub(v3_axpy(w2, -in.dt * in.inv_inertia2, T),
                             v3_axpy(w1, in.dt * in.inv_inertia1, T));
        /* per component along n and transverse: ratio in [0, 1] */
        double r_t = v3_dot(Om_new, o.n) / v3_dot(Om, o.n);
        vec3 Omr = v3_axpy(Om, -v3_dot(Om, o.n), o.n),
             Omr_new = v3_axpy(Om_new, -v3_dot(Om_new, o.n), o.n);
        double r_r = v3_dot(Omr_new, Omr) / v3_norm2(Omr);
        CHECK(r_t >= -1e-12 && r_t <= 1 + 1e-12 && r_r >= -1e-12 && r_r <= 1 + 1e-12,
              "spin reversal eta=%g r_t=%g r_r=%g", p.eta, r_t, r_r);
        if (r_r < worst || i == 0)
            worst = r_r;
    }
    printf("torque_stiff_min_relative_spin_ratio=%.3e\n", worst);
}

static void test_new_pairs_and_errors(void)
{
    lub_law_params p = base_params();
    lub_pair_state st;
    lub_pair_output o;
    /* created overlapping (rough): static solution, no lubrication force at rest */
    lub_pair_state_reset(&st);
    lub_pair_input in = simple_input(-0.004, v3(0, 0, 0), v3(0, 0, 0));
    in.v1 = in.v2 = v3(0, 0, 0);
    CHECK(lub_pair_step(&p, &in, &st, &o) == 0, "rc");
    CHECK(o.contact && fabs(exp(o.delta) - (-0.004 + 0.01) / 2.0) < 1e-12 &&
              fabs(o.fn_lub) < 1e-9 * fabs(o.fn_contact),
          "overlap creation x=%g fl=%g", exp(o.delta), o.fn_lub);
    /* created overlapping (smooth, lubricated): starts at the static floor, then the first
     * step already decays below it (no floor with lubrication); finite, all lubrication */
    p.eps = 0.0;
    lub_pair_state_reset(&st);
    CHECK(lub_pair_step(&p, &in, &st, &o) == 0, "rc");
    {
        const double h = in.dt * p.k_bulk / (1.5 * LUB_PI * p.eta * 1.0);
        const double want = LUB_DELTA_STATIC_FLOOR - log1p(h * 0.004); /* s = -0.004 */
        CHECK(!o.contact && fabs(o.delta - want) < 1e-11 && o.fn_lub < 0.0 && o.gap >= 0.0,
              "smooth overlap creation delta=%.17g want %.17g", o.delta, want);
    }
    /* a brand-new pair at u_n = 1e-320 a (subnormal) is finite */
    lub_pair_state_reset(&st);
    in.branch = v3(2.0 + 1e-320, 0, 0);
    CHECK(lub_pair_step(&p, &in, &st, &o) == 0 && isfinite(o.delta), "tiny gap creation");
    /* errors */
    in.branch = v3(0, 0, 0);
    CHECK(lub_pair_step(&p, &in, &st, &o) == 2, "zero branch must fail");
    in = simple_input(0.1, v3(0, 0, 0), v3(0, 0, 0));
    in.v1.x = NAN;
    lub_pair_state_reset(&st);
    CHECK(lub_pair_step(&p, &in, &st, &o) != 0, "NaN velocity must be reported");
    /* names */
    const char *names[8];
    CHECK(lub_terms_names(LUB_TERM_ALL, names, 8) == 5, "names all");
    CHECK(lub_terms_names(LUB_TERM_ROLL | LUB_TERM_FRICTION, names, 8) == 2 &&
              strcmp(names[1], "friction") == 0,
          "names subset");
}

static void test_shear_viscosity(void)
{
    const double eta = 2.0, a = 1.5;
    double xs[] = {1e-300,   1e-12, 1e-3, 0.1,     0.999999, 1.0,
                   1.000001, 3.0,   50.0, 99999.0, 100001.0, 1e8};
    double max_err = 0.0;
    for (unsigned i = 0; i < sizeof xs / sizeof xs[0]; ++i) {
        double x = xs[i], d = log(x);
        double nu = lub_shear_viscosity(eta, a, d);
        CHECK(nu > 0.0 && isfinite(nu), "nu_t(%g) = %g", x, nu);
        /* reference in long double, direct formula */
        long double X = x, ref = 0.5L * 3.14159265358979323846L * eta * a *
                                 (-2.0L + (2.0L + X) * logl((2.0L + X) / X));
        if (x < 1e4) {
            double err = fabs((double)((nu - ref) / ref));
            if (err > max_err)
                max_err = err;
        }
        if (x > 1e4) /* ~ pi eta a^2 / u = pi eta a / x */
            CHECK(fabs(nu / (LUB_PI * eta * a / x) - 1.0) < 1e-4, "large-gap limit x=%g", x);
    }
    CHECK(max_err < 1e-11, "nu_t error %g", max_err);
    printf("shear_viscosity_max_rel_err=%.3e\n", max_err);
}

/* (a) A heavily compressed pair (u_n fixed, s < -alpha e: asperities crushed; and smooth
 * s < 0) under shear and spins: over many steps delta strictly decreases, with exactly the
 * model's decrement -ln(1 - h (s + alpha_c e)) once x << |s|, goes far below -700 (x
 * subnormal, then 0), and every output stays finite: the normal force is carried by the
 * persistent lubrication g a (s + alpha e) (contact part -alpha g a e), nu_t = pi eta a
 * (ln 2 - 1 - delta) grows like -delta, the roll torque grows like -delta up to the
 * exponential-integration bound I_eff |Omega_r| / dt, the twist torque -> 0 with x. */
static void test_compressed_decay(void)
{
    const struct {
        double un, eps;
    } cases[] = {{-0.05, 0.01}, {-0.02, 0.0}};
    for (unsigned k = 0; k < 2; ++k) {
        lub_law_params p = base_params(); /* eta 1, g 1e4, alpha 1, k_t 5e3, mu 0.5 */
        p.eps = cases[k].eps;
        const vec3 w1 = v3(0.3, 0.2, -0.1), w2 = v3(-0.4, 0.1, 0.5);
        lub_pair_input in = simple_input(cases[k].un, w1, w2); /* a = 1, dt = 1e-3 */
        const double a = 1.0, ga = p.k_bulk * a, s = cases[k].un / a;
        const double h = in.dt * p.k_bulk / (1.5 * LUB_PI * p.eta * a);
        const double se = s + p.alpha * p.eps; /* < 0 */
        const double dec = log1p(-h * se);
        const double ieff_dt = 1.0 / ((in.inv_inertia1 + in.inv_inertia2) * in.dt);
        const vec3 Om = v3_sub(w2, w1);
        const double om_r = v3_norm(v3_axpy(Om, -Om.x, v3(1, 0, 0))); /* n = x */
        lub_pair_state st;
        lub_pair_state_reset(&st);
        lub_pair_output o;
        double prev = INFINITY, max_dev = 0.0, max_flub = 0.0, max_nut = 0.0;
        double troll_prev = 0.0;
        int monotone = 1, finite = 1, flags = 1, troll_ok = 1;
        long nsub = 0, nzero = 0;
        const int NSTEP = 120000;
        for (int it = 0; it < NSTEP; ++it) {
            const int rc = lub_pair_step(&p, &in, &st, &o);
            if (rc != 0 || !isfinite(o.delta) || !v3_isfinite(o.force1) ||
                !v3_isfinite(o.torque1) || !v3_isfinite(o.torque2) || !isfinite(o.fn_lub) ||
                !isfinite(o.fn_contact) || !v3_isfinite(o.fs_lub) || !(o.gap >= 0.0))
                finite = 0;
            if (!(o.delta < prev))
                monotone = 0;
            if (o.contact != (p.eps > 0.0))
                flags = 0;
            if (prev < -60.0) { /* x < 1e-26: decrement = ln(1 - h (s + alpha e)) */
                const double dev = fabs((prev - o.delta) - dec) / (1e-13 + 4e-16 * fabs(o.delta));
                if (dev > max_dev)
                    max_dev = dev;
                /* persistent lubrication force carries the load: F_l = g a (s + alpha e) */
                const double fl = fabs(o.fn_lub - ga * se) / (ga * fabs(se));
                if (fl > max_flub)
                    max_flub = fl;
                const double nut = lub_shear_viscosity(p.eta, a, o.delta);
                const double nut_ref = LUB_PI * p.eta * a * (log(2.0) - 1.0 - o.delta);
                if (fabs(nut / nut_ref - 1.0) > max_nut)
                    max_nut = fabs(nut / nut_ref - 1.0);
                const double tr = v3_norm(o.torque_roll1);
                /* grows with -delta (non-decreasing), bounded by I_eff |Omega_r| / dt */
                if (!(tr >= troll_prev * (1.0 - 1e-12)) || !(tr <= ieff_dt * om_r * (1.0 + 1e-12)))
                    troll_ok = 0;
                troll_prev = tr;
            }
            nsub += (o.gap > 0.0 && o.gap < 2.2250738585072014e-308);
            nzero += (o.gap == 0.0);
            prev = o.delta;
        }
        CHECK(finite, "compressed case %u: non-finite output", k);
        CHECK(monotone, "compressed case %u: delta not strictly decreasing", k);
        CHECK(flags, "compressed case %u: contact flag", k);
        CHECK(o.delta < -5000.0 && o.delta > LUB_DELTA_MIN, "compressed case %u: delta %g", k,
              o.delta);
        CHECK(nsub > 0 && nzero > 0, "compressed case %u: subnormal %ld / zero %ld steps", k, nsub,
              nzero);
        CHECK(max_dev <= 1.0, "compressed case %u: decrement off by %g (units of tol)", k, max_dev);
        CHECK(max_flub < 1e-12, "compressed case %u: F_l vs g a (s + alpha e): %g", k, max_flub);
        CHECK(p.eps == 0.0 || fabs(o.fn_contact + p.alpha * ga * p.eps) < 1e-12 * ga,
              "compressed case %u: contact force %g", k, o.fn_contact);
        CHECK(max_nut < 1e-12, "compressed case %u: nu_t vs pi eta a (ln 2 - 1 - delta): %g", k,
              max_nut);
        CHECK(troll_ok && troll_prev > 0.0, "compressed case %u: roll torque", k);
        CHECK(v3_norm(o.torque_twist1) == 0.0, "compressed case %u: twist %g", k,
              v3_norm(o.torque_twist1));
        printf("pair_compressed_case%u_final_delta=%.6g\n", k, o.delta);
        printf("pair_compressed_case%u_subnormal_steps=%ld_zero_gap_steps=%ld\n", k, nsub, nzero);
        printf("pair_compressed_case%u_final_nu_t=%.6g\n", k,
               lub_shear_viscosity(p.eta, a, o.delta));
        printf("pair_compressed_case%u_final_roll_torque=%.6g\n", k, troll_prev);
    }
}

/* ---- unequal radii: r1 = 0.8, r2 = 1.3, a = (r1 + r2)/2 = 1.05 (notes §0.2, §1.4) ----
 * The checks above cannot tell r1 from r2 or a^3 from a^2: the angular-momentum check sees only
 * the sum of the two torque arms, a rigid motion gives a zero shear increment for any split of
 * r1 w1 + r2 w2, and the torque coefficients are checked at a = 1. Here each quantity is
 * compared with its formula written out in the test. */
static const double UR1 = 0.8, UR2 = 1.3;

static vec3 tangential(vec3 f, vec3 n) { return v3_axpy(f, -v3_dot(f, n), n); }

/* a pair state at gap x0 a with normal n (no stored shear force) */
static lub_pair_state unequal_state(double x0, vec3 n)
{
    lub_pair_state st;
    memset(&st, 0, sizeof st);
    lub_pair_state_set_gap(&st, log(x0));
    st.n_prev = n;
    return st;
}

/* Shear-force torque arms (notes §4.6): the arm of body i is r_i + u_n/2, the distance from its
 * centre to the mid-gap point, and both bodies get (r_i + u_n/2) n x F_s (body 2: arm -n, force
 * -F_s), F_s = the tangential part of the force on body 1. Lubricated gap (with roll/twist
 * torques), near the roughness (Maxwell element), contact in stick and in slip, with the
 * roll/twist terms on (their own outputs are subtracted) and off. */
static void test_unequal_torque_arms(void)
{
    const double r1 = UR1, r2 = UR2, a = 0.5 * (r1 + r2);
    const vec3 n = unit(v3(0.3, -0.5, 0.8));
    const unsigned masks[2] = {LUB_TERM_ALL, LUB_TERM_ALL & ~(LUB_TERM_ROLL | LUB_TERM_TWIST)};
    const struct {
        double s, x0, fs0; /* u_n / a, stored u/a, stored |F_s| */
    } cases[] = {{0.3, 0.3, 1.0}, {0.02, 0.02, 1.0}, {-0.004, 0.003, 1.0}, {-0.004, 0.003, 100.0}};
    double max1 = 0.0, max2 = 0.0;
    int n_slip = 0;
    for (int m = 0; m < 2; ++m)
        for (unsigned k = 0; k < sizeof cases / sizeof cases[0]; ++k) {
            lub_law_params p = base_params();
            p.terms = masks[m];
            const double un = cases[k].s * a;
            const lub_pair_input in = {.branch = v3_scale(n, r1 + r2 + un),
                                       .v1 = v3(0.1, -0.2, 0.3),
                                       .v2 = v3(-0.3, 0.2, 0.1),
                                       .w1 = v3(0.5, -0.3, 0.2),
                                       .w2 = v3(-0.2, 0.6, 0.4),
                                       .r1 = r1,
                                       .r2 = r2,
                                       .inv_inertia1 = 2.5 / (r1 * r1),
                                       .inv_inertia2 = 2.5 / (r2 * r2),
                                       .dt = 1e-3};
            lub_pair_state st = unequal_state(cases[k].x0, n);
            st.fs = v3_scale(unit(tangential(v3(3.0, -1.0, 2.0), n)), cases[k].fs0);
            lub_pair_output o;
            CHECK(lub_pair_step(&p, &in, &st, &o) == 0, "unequal arms rc");
            n_slip += o.slip;
            const vec3 nn = unit(in.branch);
            const double u = v3_norm(in.branch) - r1 - r2;
            const vec3 fs = tangential(o.force1, nn);
            const vec3 nxf = v3_cross(nn, fs);
            const vec3 tl = v3_add(o.torque_roll1, o.torque_twist1);
            const vec3 c1 = v3_add(v3_scale(nxf, r1 + 0.5 * u), tl);
            const vec3 c2 = v3_sub(v3_scale(nxf, r2 + 0.5 * u), tl);
            const double scale = (r2 + fabs(u)) * v3_norm(fs) + v3_norm(tl);
            CHECK(v3_norm(fs) > 1e-3, "unequal arms case %u: no shear force", k);
            const double e1 = v3_norm(v3_sub(o.torque1, c1)) / scale;
            const double e2 = v3_norm(v3_sub(o.torque2, c2)) / scale;
            CHECK(e1 < 1e-12, "unequal radii mask %u s %g: torque1 != (r1 + u_n/2) n x F_s: %.3e",
                  p.terms, cases[k].s, e1);
            CHECK(e2 < 1e-12, "unequal radii mask %u s %g: torque2 != (r2 + u_n/2) n x F_s: %.3e",
                  p.terms, cases[k].s, e2);
            max1 = fmax(max1, e1);
            max2 = fmax(max2, e2);
        }
    CHECK(n_slip == 2, "unequal arms: %d slipping cases, expected 2", n_slip);
    printf("unequal_radii_torque1_arm_max_rel_err=%.3e\n", max1);
    printf("unequal_radii_torque2_arm_max_rel_err=%.3e\n", max2);
}

/* Objective shear increment (notes §1.7) on unequal spheres, against the relative velocity of
 * the two material points facing each other, body 1's at r1 n and body 2's at -r2 n from their
 * centres, with the translation scaled by alpha_r = (r1 + r2)/(r1 + r2 + u_n):
 *   du_s = dt P[alpha_r (v2 - v1) + w2 x (-r2 n) - w1 x (r1 n)],  P = I - n n.
 *  - rolling without sliding (r1 w1_t = -r2 w2_t, any spins about n, any approach velocity):
 *    zero;
 *  - worked cases with n = e_x, u_n = 0.1 (hand values) and random motions: the formula;
 *  - the same through lub_pair_step: a sticking contact with no stored force has
 *    F_s = k_t du_s exactly. */
static void test_unequal_shear_increment(void)
{
    const double r1 = UR1, r2 = UR2, a = 0.5 * (r1 + r2), dt = 1e-3;
    law_rng r = {2024};
    double max_roll = 0.0, max_ref = 0.0;
    for (int i = 0; i < 400; ++i) {
        const vec3 n = unit(rand_vec(&r, 1.0));
        const double un = a * law_rng_range(&r, -0.05, 1.0);
        const vec3 wt = tangential(rand_vec(&r, 1.0), n);
        const vec3 v1 = rand_vec(&r, 1.0);
        if (i % 2 == 0) { /* rolling without sliding */
            const vec3 w1 = v3_axpy(wt, law_rng_range(&r, -1.0, 1.0), n);
            const vec3 w2 = v3_axpy(v3_scale(wt, -r1 / r2), law_rng_range(&r, -1.0, 1.0), n);
            const vec3 v2 = v3_axpy(v1, law_rng_range(&r, -1.0, 1.0), n);
            const vec3 du = lub_shear_increment(v1, v2, w1, w2, r1, r2, un, n, dt);
            const double scale = dt * (r1 * v3_norm(wt) + v3_norm(v3_sub(v2, v1)) +
                                       r1 * v3_norm(w1) + r2 * v3_norm(w2));
            max_roll = fmax(max_roll, v3_norm(du) / scale);
        } else {
            const vec3 w1 = rand_vec(&r, 1.0), w2 = rand_vec(&r, 1.0), v2 = rand_vec(&r, 1.0);
            const double alpha_r = (r1 + r2) / (r1 + r2 + un);
            const vec3 vc1 = v3_cross(w1, v3_scale(n, r1));  /* body 1's point at r1 n */
            const vec3 vc2 = v3_cross(w2, v3_scale(n, -r2)); /* body 2's point at -r2 n */
            const vec3 ref = v3_scale(
                tangential(v3_add(v3_scale(v3_sub(v2, v1), alpha_r), v3_sub(vc2, vc1)), n), dt);
            const vec3 du = lub_shear_increment(v1, v2, w1, w2, r1, r2, un, n, dt);
            const double scale =
                dt * (alpha_r * v3_norm(v3_sub(v2, v1)) + r1 * v3_norm(w1) + r2 * v3_norm(w2));
            max_ref = fmax(max_ref, v3_norm(v3_sub(du, ref)) / scale);
        }
    }
    CHECK(max_roll < 1e-14, "unequal radii: rolling without sliding gives du_s = %.3e (rel)",
          max_roll);
    CHECK(max_ref < 1e-13, "unequal radii: du_s vs contact-point velocities: %.3e", max_ref);
    /* hand values: n = e_x, u_n = 0.1, v2 - v1 = (0.5, 0.2, 0), alpha_r = 2.1/2.2;
     * e_z x e_x = e_y, e_y x e_x = -e_z */
    const double ar = 2.1 / 2.2;
    const struct {
        vec3 w1, w2, rate; /* du_s / dt */
    } hand[] = {{v3(0, 0, 1), v3(0, 0, 0), v3(0, 0.2 * ar - 0.8, 0)},
                {v3(0, 0, 0), v3(0, 0, 1), v3(0, 0.2 * ar - 1.3, 0)},
                {v3(0.7, 2, 0.3), v3(0, 0, 0), v3(0, 0.2 * ar - 0.24, 1.6)},
                {v3(0, 0, 1), v3(0, 0, -0.8 / 1.3), v3(0, 0.2 * ar, 0)}};
    double max_hand = 0.0;
    for (unsigned k = 0; k < sizeof hand / sizeof hand[0]; ++k) {
        const vec3 du = lub_shear_increment(v3(0.1, 0.1, 0.1), v3(0.6, 0.3, 0.1), hand[k].w1,
                                            hand[k].w2, r1, r2, 0.1, v3(1, 0, 0), dt);
        const double e = v3_norm(v3_sub(du, v3_scale(hand[k].rate, dt))) / (dt * 1.3);
        CHECK(e < 1e-14, "unequal radii hand case %u: du_s/dt = (%.17g, %.17g, %.17g)", k,
              du.x / dt, du.y / dt, du.z / dt);
        max_hand = fmax(max_hand, e);
    }
    /* through the full law: sticking contact, F_s(prev) = 0, so F_s = k_t du_s */
    lub_law_params p = base_params();
    const vec3 n = unit(v3(0.3, -0.5, 0.8));
    const vec3 wt = tangential(v3(0.7, 0.2, -0.4), n);
    const vec3 v1 = v3(0.1, -0.2, 0.3), v2 = v3_axpy(v1, 0.25, n);
    const struct {
        vec3 w1, w2;
    } pc[] = {{v3_axpy(wt, 0.9, n), v3_axpy(v3_scale(wt, -r1 / r2), -0.4, n)}, /* rolling */
              {wt, v3(0, 0, 0)},
              {v3(0, 0, 0), wt},
              {v3(0.5, -0.3, 0.2), v3(-0.2, 0.6, 0.4)}};
    double max_law = 0.0;
    for (unsigned k = 0; k < sizeof pc / sizeof pc[0]; ++k) {
        const double un = -0.004 * a;
        const lub_pair_input in = {.branch = v3_scale(n, r1 + r2 + un),
                                   .v1 = v1,
                                   .v2 = v2,
                                   .w1 = pc[k].w1,
                                   .w2 = pc[k].w2,
                                   .r1 = r1,
                                   .r2 = r2,
                                   .inv_inertia1 = 2.5 / (r1 * r1),
                                   .inv_inertia2 = 2.5 / (r2 * r2),
                                   .dt = dt};
        lub_pair_state st = unequal_state(0.003, n);
        lub_pair_output o;
        CHECK(lub_pair_step(&p, &in, &st, &o) == 0, "unequal stick rc");
        CHECK(o.contact && !o.slip, "unequal stick case %u: contact %d slip %d", k, o.contact,
              o.slip);
        const vec3 vc1 = v3_cross(pc[k].w1, v3_scale(n, r1));
        const vec3 vc2 = v3_cross(pc[k].w2, v3_scale(n, -r2));
        const vec3 ref = v3_scale(tangential(v3_sub(vc2, vc1), n), p.k_t * dt); /* v2 - v1 || n */
        const vec3 fs = tangential(o.force1, n);
        const double e = v3_norm(v3_sub(fs, ref)) / (p.k_t * dt * r1 * v3_norm(wt));
        CHECK(e < 1e-12, "unequal radii stick case %u: F_s vs k_t du_s: %.3e (|F_s| %.3e)", k, e,
              v3_norm(fs));
        max_law = fmax(max_law, e);
    }
    printf("unequal_radii_rolling_increment_max_rel=%.3e\n", max_roll);
    printf("unequal_radii_increment_vs_contact_points_max_rel_err=%.3e\n", max_ref);
    printf("unequal_radii_increment_hand_cases_max_rel_err=%.3e\n", max_hand);
    printf("unequal_radii_stick_fs_vs_kt_du_max_rel_err=%.3e\n", max_law);
}

/* Roll and twist coefficients with a != 1 (notes §4.1-4.2, a = (r1 + r2)/2):
 *   c_r = pi eta a^3 (3/2 + 63/500 x) ln(1/x),  c_t = pi eta a^3 x ln(1/x),  x = u/a,
 * applied as c (1 - e^-k)/k, k = c dt (1/I1 + 1/I2) (c itself for fixed bodies). Radii
 * (0.8, 1.3) and (2, 3.5) (a = 1.05, 2.75), fixed and free bodies; with the shear terms off the
 * total torques are the lubrication torques alone (body 2: minus). */
static void test_unequal_spin_coefficients(void)
{
    const double radii[2][2] = {{UR1, UR2}, {2.0, 3.5}};
    const double inv[2][2] = {{0.0, 0.0}, {2.5, 1.7}};
    const vec3 n = unit(v3(0.3, -0.5, 0.8));
    const vec3 w1 = v3(0.3, 0.2, -0.1), w2 = v3(-0.4, 0.1, 0.5);
    double max_r = 0.0, max_t = 0.0, max_tot = 0.0;
    for (int ir = 0; ir < 2; ++ir)
        for (int ii = 0; ii < 2; ++ii) {
            lub_law_params p = base_params();
            p.terms = LUB_TERM_NORMAL_LUB | LUB_TERM_ROLL | LUB_TERM_TWIST;
            const double r1 = radii[ir][0], r2 = radii[ir][1], a = 0.5 * (r1 + r2);
            const lub_pair_input in = {.branch = v3_scale(n, r1 + r2 + 0.05 * a),
                                       .v1 = v3(0.1, -0.2, 0.3),
                                       .v2 = v3(-0.3, 0.2, 0.1),
                                       .w1 = w1,
                                       .w2 = w2,
                                       .r1 = r1,
                                       .r2 = r2,
                                       .inv_inertia1 = inv[ii][0],
                                       .inv_inertia2 = inv[ii][1],
                                       .dt = 1e-3};
            lub_pair_state st = unequal_state(0.05, n);
            lub_pair_output o;
            CHECK(lub_pair_step(&p, &in, &st, &o) == 0, "unequal spin rc");
            CHECK(o.delta < 0.0, "unequal spin: u > a");
            const double x = exp(o.delta), L = -o.delta, inv_sum = inv[ii][0] + inv[ii][1];
            const double a3 = a * a * a;
            const double cr = LUB_PI * p.eta * a3 * (1.5 + 63.0 / 500.0 * x) * L;
            const double ct = LUB_PI * p.eta * a3 * x * L;
            const double kr = cr * in.dt * inv_sum, kt = ct * in.dt * inv_sum;
            const double fr = kr > 0.0 ? -expm1(-kr) / kr : 1.0;
            const double ft = kt > 0.0 ? -expm1(-kt) / kt : 1.0;
            const vec3 Om = v3_sub(w2, w1);
            const vec3 Omt = v3_scale(n, v3_dot(Om, n)), Omr = v3_sub(Om, Omt);
            const vec3 Tr = v3_scale(Omr, cr * fr), Tt = v3_scale(Omt, ct * ft);
            const double er = v3_norm(v3_sub(o.torque_roll1, Tr)) / v3_norm(Tr);
            const double et = v3_norm(v3_sub(o.torque_twist1, Tt)) / v3_norm(Tt);
            const vec3 T = v3_add(Tr, Tt);
            const double e1 = v3_norm(v3_sub(o.torque1, T)) / v3_norm(T);
            const double e2 = v3_norm(v3_add(o.torque2, T)) / v3_norm(T);
            CHECK(er < 1e-12,
                  "unequal radii a = %g, 1/I %g: roll torque vs pi eta a^3 (3/2 + 63x/500) "
                  "ln(1/x): %.3e",
                  a, inv_sum, er);
            CHECK(et < 1e-12,
                  "unequal radii a = %g, 1/I %g: twist torque vs pi eta a^3 x ln(1/x): %.3e", a,
                  inv_sum, et);
            CHECK(e1 < 1e-12 && e2 < 1e-12,
                  "unequal radii a = %g, 1/I %g: total torques %.3e / %.3e", a, inv_sum, e1, e2);
            max_r = fmax(max_r, er);
            max_t = fmax(max_t, et);
            max_tot = fmax(max_tot, fmax(e1, e2));
        }
    printf("unequal_radii_roll_coefficient_max_rel_err=%.3e\n", max_r);
    printf("unequal_radii_twist_coefficient_max_rel_err=%.3e\n", max_t);
    printf("unequal_radii_spin_total_torque_max_rel_err=%.3e\n", max_tot);
}

int main(void)
{
    test_random_conservation_and_split();
    test_rigid_motion();
    test_switches_and_torques();
    test_new_pairs_and_errors();
    test_shear_viscosity();
    test_compressed_decay();
    test_unequal_torque_arms();
    test_unequal_shear_increment();
    test_unequal_spin_coefficients();
    printf("pair_failures=%d\n", failures);
    return failures ? 1 : 0;
}
