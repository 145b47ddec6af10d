/* test_system.c — the sheared system as a whole:
 *  1. affine flow without interactions: the particle stress stays exactly zero (convective
 *     term, wraps across the gradient boundary with the mean-flow velocity jump, flips);
 *     with the drag towards the affine flow, the non-affine velocity decays exactly as the
 *     implicit update says;
 *  2. a dense robustness run (phi = 0.55, all terms) finishes without NaN, with contacts,
 *     compressive pressure and positive shear stress;
 *  3. two 2-thread runs give the identical trajectory (each thread's pair sums follow the
 *     pair order), and 1 and 2 threads agree to round-off over 300 steps (the per-particle
 *     sums are added in a different order, and the dynamics amplifies round-off);
 *  4. on the evolved dense configuration, the batched pair evaluation of force-only steps
 *     (lub_pair_eval_range, contact_batch.h) gives the per-particle forces and torques, the
 *     states and the sigma_yy sum of the scalar law (lub_pair_eval for every pair) to 1e-10 of
 *     the largest pair force, and the image-shift fallback of that evaluation gives the very
 *     sums of its 27-entry shift table:
 *     round-off only (the kernel's own test, tests/law/test_contact_batch.c, covers every
 *     regime); a scalar-only run and a batched run of the same system agree in their stresses
 *     to within the statistics of the chaotic dynamics (checked in the physics suite, not
 *     here: trajectories separate by round-off). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "pair_eval.h"
#include "shear_system.h"
#include "shear_fixture.h"
#include "shear_test.h"

/* 64 unit spheres on a cubic lattice of spacing 3 a in a 12 a box, sheared (L_xy = 1), cut-off
 * 0.2 a, dt 2e-3: no two spheres ever interact under the affine flow */
static int make_lattice(lub_shear_system *s)
{
    const lub_law_params law = shear_fixture_law(1e4);
    const int nl = 4, n = nl * nl * nl;
    double r[64];
    vec3 x[64];
    for (int i = 0; i < n; ++i) {
        r[i] = 1.0;
        x[i] = v3(1.5 + 3.0 * (i % nl), 1.5 + 3.0 * ((i / nl) % nl), 1.5 + 3.0 * (i / (nl * nl)));
    }
    lub_cell c;
    lub_cell_init_box(&c, 12, 12, 12);
    c.L[0][1] = 1.0;
    return lub_shear_init(s, n, r, x, &c, &law, 1e-2, 0.2, 0.5, 2e-3, 1, 0, 0);
}

/* The bodies of the system as the pair kernel reads them. */
static lub_pair_bodies system_bodies(const lub_shear_system *s)
{
    return (lub_pair_bodies){
        .x = s->x, .v = s->v, .w = s->w, .r = s->r, .inv_i_share = s->inv_i_share};
}

/* Every pair of s through the batched law (lub_pair_eval_range) into *acc; returns its result
 * (the first failing pair or -1) and its sums in *sums. */
static long eval_batched(lub_shear_system *s, lub_pair_accum *acc, lub_pair_range_sums *sums)
{
    const lub_pair_bodies bodies = system_bodies(s);
    lub_pair_batch batch[2];
    double un = 0.0;
    *sums = (lub_pair_range_sums){0.0, 0, 0};
    return lub_pair_eval_range(&s->pairs, 0, (long)s->pairs.n, &s->cell, &bodies, &s->law,
                               s->cutoff, s->dt, s->n, acc, batch, sums, &un);
}

/* The batched evaluation with every pair's image code set to LUB_PAIR_IMG_OTHER (the shift
 * H c and its velocity L H c computed per pair instead of read from the 27-entry table) gives
 * the very sums *ref of the table path, from the same states st0/act0/near0: the table holds
 * the same products. Restores the codes; leaves the states as evaluated. */
static void check_image_fallback(lub_shear_system *s, const lub_pair_state *st0,
                                 const unsigned char *act0, const unsigned char *near0,
                                 const lub_pair_accum *ref)
{
    lub_pairs *ps = &s->pairs;
    const size_t np = ps->n;
    unsigned char *img0 = malloc(np);
    lub_pair_accum acc;
    const int acc_rc = lub_pair_accum_init(&acc, s->n);
    ST_CHECK(img0 && acc_rc == 0, "no memory");
    if (!img0 || acc_rc)
        return;
    memcpy(img0, ps->img, np);
    long shifted = 0;
    for (size_t k = 0; k < np; ++k) {
        shifted += ps->img[k] != 13; /* 13: c = (0, 0, 0) */
        ps->img[k] = LUB_PAIR_IMG_OTHER;
    }
    memcpy(ps->state, st0, np * sizeof *st0);
    memcpy(ps->active, act0, np);
    memcpy(ps->near, near0, np);
    lub_pair_range_sums sums;
    const long kf = eval_batched(s, &acc, &sums);
    const size_t nv = (size_t)s->n * sizeof(vec3), ni = (size_t)s->n * sizeof(int);
    const int same = memcmp(acc.f, ref->f, nv) == 0 && memcmp(acc.t, ref->t, nv) == 0 &&
                     memcmp(acc.n_active, ref->n_active, ni) == 0;
    printf("image_fallback shifted_pairs=%ld of %zu identical=%d\n", shifted, np, same);
    ST_CHECK(kf < 0, "fallback evaluation failed at pair %ld", kf);
    ST_CHECK(shifted > 100, "too few pairs across the cell boundary (%ld)", shifted);
    ST_CHECK(same, "image-shift fallback and table give different sums");
    memcpy(ps->img, img0, np);
    free(img0);
    lub_pair_accum_free(&acc);
}

static void compare_batched_with_scalar(lub_shear_system *s)
{
    lub_pairs *ps = &s->pairs;
    const size_t np = ps->n;
    lub_pair_state *st0 = malloc(np * sizeof *st0), *stb = malloc(np * sizeof *stb);
    unsigned char *act0 = malloc(np), *near0 = malloc(np), *nearb = malloc(np);
    lub_pair_accum accb, accs;
    const int acc_rc = lub_pair_accum_init(&accb, s->n) | lub_pair_accum_init(&accs, s->n);
    ST_CHECK(st0 && stb && act0 && near0 && nearb && acc_rc == 0, "no memory");
    if (!(st0 && stb && act0 && near0 && nearb) || acc_rc)
        return;
    memcpy(st0, ps->state, np * sizeof *st0);
    memcpy(act0, ps->active, np);
    memcpy(near0, ps->near, np);
    const lub_pair_bodies bodies = system_bodies(s);
    double un = 0.0;
    lub_pair_range_sums sums;
    const long kf = eval_batched(s, &accb, &sums);
    const double syy_b = sums.syy;
    const long nc_b = sums.contacts;
    ST_CHECK(kf < 0, "batched evaluation failed at pair %ld", kf);
    memcpy(stb, ps->state, np * sizeof *stb);
    memcpy(nearb, ps->near, np);
    check_image_fallback(s, st0, act0, near0, &accb);
    memcpy(ps->state, st0, np * sizeof *st0);
    memcpy(ps->active, act0, np);
    memcpy(ps->near, near0, np);
    double syy_s = 0.0, fmax_s = 0.0, tmax_s = 0.0, ef = 0.0, et = 0.0, ed = 0.0;
    long nc_s = 0, nact = 0, near_diff = 0, count_diff = 0;
    for (size_t k = 0; k < np; ++k) {
        lub_pair_output o;
        vec3 d;
        const int rc =
            lub_pair_eval(ps, k, &s->cell, &bodies, &s->law, s->cutoff, s->dt, &accs, &o, &d, &un);
        ST_CHECK(rc != LUB_PAIR_NONFINITE, "scalar law failed at pair %zu", k);
        if (rc != LUB_PAIR_OK)
            continue;
        nact++;
        syy_s += o.force1.y * d.y;
        nc_s += o.contact;
        fmax_s = fmax(fmax_s, v3_norm(o.force1));
        tmax_s = fmax(tmax_s, fmax(v3_norm(o.torque1), v3_norm(o.torque2)));
        ed = fmax(ed, fabs(stb[k].delta - ps->state[k].delta));
        near_diff += nearb[k] != ps->near[k];
    }
    for (int p = 0; p < s->n; ++p) {
        ef = fmax(ef, v3_norm(v3_sub(accb.f[p], accs.f[p])));
        et = fmax(et, v3_norm(v3_sub(accb.t[p], accs.t[p])));
        count_diff += accb.n_active[p] != accs.n_active[p];
    }
    ef /= fmax_s;
    et /= tmax_s;
    const double esyy = fabs(syy_b - syy_s) / fabs(syy_s);
    printf("batch_vs_scalar active_pairs=%ld contacts=%ld/%ld max_force_err=%.3g "
           "max_torque_err=%.3g max_delta_err=%.3g syy_rel_err=%.3g near_flag_diffs=%ld "
           "active_count_diffs=%ld\n",
           nact, nc_b, nc_s, ef, et, ed, esyy, near_diff, count_diff);
    ST_CHECK(nact > 1000 && nc_s > 50, "configuration too sparse (%ld pairs)", nact);
    ST_CHECK(ef < 1e-10 && et < 1e-10, "batched forces/torques differ: %g %g", ef, et);
    ST_CHECK(ed < 1e-10, "batched gap state differs by %g", ed);
    ST_CHECK(esyy < 1e-10, "batched sigma_yy sum differs by %g", esyy);
    ST_CHECK(labs(nc_b - nc_s) <= 1 && near_diff <= 1, "flags differ: contacts %ld/%ld near %ld",
             nc_b, nc_s, near_diff);
    ST_CHECK(count_diff == 0, "%ld particles with different active-pair counts", count_diff);
    free(st0), free(stb), free(act0), free(near0), free(nearb);
    lub_pair_accum_free(&accb);
    lub_pair_accum_free(&accs);
}

/* Mean fraction of the contacts that slide (law output slip) over the stress samples of a
 * short dense run (N = 300, phi = 0.55) with friction coefficient mu and term mask terms. */
static double sliding_fraction(double mu, unsigned terms, double *zc)
{
    lub_law_params law = shear_fixture_law(1e4);
    law.mu = mu;
    law.terms = terms;
    lub_shear_system s;
    int rc = shear_fixture_make(&s, 300, 0.55, &law, 2.0, 1, 7, 1e-2);
    ST_CHECK(rc == 0, "init");
    double slide = 0.0, contacts = 0.0;
    int samples = 0;
    for (int step = 0; step < 600 && rc == 0; ++step) {
        lub_shear_sample smp;
        const unsigned fl = (step >= 200 && step % 10 == 0) ? LUB_SAMPLE_STRESS : 0u;
        rc = lub_shear_step(&s, fl, &smp);
        if (fl && rc == 0) {
            ST_CHECK(smp.n_sliding <= smp.n_contacts, "more sliding pairs than contacts");
            slide += (double)smp.n_sliding;
            contacts += (double)smp.n_contacts;
            samples++;
        }
    }
    ST_CHECK(rc == 0, "sliding run rc %d", rc);
    *zc = samples ? 2.0 * contacts / ((double)samples * s.n) : 0.0;
    lub_shear_free(&s);
    return contacts > 0 ? slide / contacts : NAN;
}

int main(void)
{
    /* 1. no interactions: spheres on a lattice with gradient-direction spacing 3 a: the affine
     * flow (plus a uniform drift along y, so that spheres cross the gradient boundary and get
     * the mean-flow velocity jump) never brings two spheres within the cut-off 0.2 a */
    {
        lub_shear_system s;
        int rc = make_lattice(&s);
        ST_CHECK(rc == 0, "init %d", rc);
        const double u = 2.0;
        for (int i = 0; i < s.n; ++i)
            s.v[i].y += u;
        double max_xy = 0, max_dev_yy = 0, yy_exp = 0, max_pair = 0;
        size_t max_active = 0;
        for (int i = 0; i < s.n; ++i)
            yy_exp -= s.m[i] * u * u;
        yy_exp /= s.cell.volume;
        double max_dev_syy = 0;
        for (int step = 0; step < 1500 && rc == 0; ++step) {
            lub_shear_sample smp;
            /* with the servo's sigma_yy too, and alone every third step: smp.syy (what the
             * servo holds) is the stress's yy, kinetic part included */
            const unsigned want =
                step % 3 == 2 ? LUB_SAMPLE_SYY : LUB_SAMPLE_STRESS | LUB_SAMPLE_SYY;
            rc = lub_shear_step(&s, want, &smp);
            if (fabs(smp.syy - yy_exp) > max_dev_syy)
                max_dev_syy = fabs(smp.syy - yy_exp);
            if (want == LUB_SAMPLE_SYY)
                continue;
            double tot[9];
            lub_stress_total(&smp.stress, tot);
            for (int part = 0; part < LUB_SP_KIN; ++part)
                for (int k = 0; k < 9; ++k)
                    if (fabs(smp.stress.part[part][k]) > max_pair)
                        max_pair = fabs(smp.stress.part[part][k]);
            if (smp.n_active > max_active)
                max_active = smp.n_active;
            if (fabs(tot[1]) > max_xy)
                max_xy = fabs(tot[1]);
            if (fabs(tot[4] - yy_exp) > max_dev_yy)
                max_dev_yy = fabs(tot[4] - yy_exp);
        }
        ST_CHECK(rc == 0, "step rc %d", rc);
        printf(
            "affine strain=%.2f flips=%ld rebuilds=%ld active_pairs_max=%zu max|pair stress|=%.3g "
            "max|sigma_xy|=%.3g max|dsigma_yy|=%.3g (kinetic sigma_yy = %.4g)\n",
            s.time, s.flips, s.rebuilds, max_active, max_pair, max_xy, max_dev_yy, yy_exp);
        ST_CHECK(s.flips >= 2, "flips %ld", s.flips);
        ST_CHECK(max_active == 0 && max_pair == 0.0, "interactions in the affine test");
        ST_CHECK(max_xy < 1e-9 * fabs(yy_exp), "kinetic sigma_xy not zero: %g", max_xy);
        ST_CHECK(max_dev_yy < 1e-9 * fabs(yy_exp), "kinetic sigma_yy drift %g", max_dev_yy);
        ST_CHECK(max_dev_syy < 1e-9 * fabs(yy_exp), "servo sigma_yy off by %g (kinetic %g)",
                 max_dev_syy, yy_exp);
        lub_shear_free(&s);
    }
    /* 1b. the drag towards the affine flow (drag_viscosity): without interactions the
     * non-affine velocity d = v - L x of every sphere decays as d0 / (1 + c)^steps exactly
     * (c = 6 pi eta_d r dt / m; the implicit update is exact for the discrete leap-frog with
     * the convective term, and wraps and flips leave d unchanged) */
    {
        lub_shear_system s;
        int rc = make_lattice(&s);
        ST_CHECK(rc == 0, "init %d", rc);
        s.drag_viscosity = 1.5e-3;
        const vec3 d0 = v3(0.3, 2.0, -0.5);
        for (int i = 0; i < s.n; ++i)
            s.v[i] = v3_add(s.v[i], d0);
        const int steps = 1500;
        for (int step = 0; step < steps && rc == 0; ++step)
            rc = lub_shear_step(&s, 0, NULL);
        ST_CHECK(rc == 0, "step rc %d", rc);
        const double cdt = 6.0 * 3.14159265358979323846 * s.drag_viscosity * s.dt / s.m[0];
        const double decay = pow(1.0 + cdt, -steps);
        double worst = 0.0;
        for (int i = 0; i < s.n; ++i) {
            vec3 d = v3_sub(s.v[i], lub_cell_mean_velocity(&s.cell, s.x[i]));
            double e = v3_norm(v3_sub(d, v3_scale(d0, decay)));
            worst = e > worst ? e : worst;
        }
        printf("affine drag: decay factor %.4f after %d steps, flips=%ld, max |d - d0 decay| = "
               "%.3g\n",
               decay, steps, s.flips, worst);
        ST_CHECK(decay < 0.3 && decay > 0.01, "decay factor %g out of the tested range", decay);
        ST_CHECK(s.flips >= 2, "flips %ld", s.flips);
        ST_CHECK(worst < 1e-10 * v3_norm(d0), "non-affine velocity %g off the exact decay", worst);
        lub_shear_free(&s);
    }
    /* 2. dense robustness run + 3. thread equivalence */
    {
        lub_law_params law = shear_fixture_law(1e4);
        lub_shear_system a, b, b2;
        int rc = shear_fixture_make(&a, 400, 0.55, &law, 2.0, 1, 5, 1e-2);
        rc |= shear_fixture_make(&b, 400, 0.55, &law, 2.0, 2, 5, 1e-2);
        rc |= shear_fixture_make(&b2, 400, 0.55, &law, 2.0, 2, 5, 1e-2);
        ST_CHECK(rc == 0, "init");
        const int nsteps = 1200;
        double sxy = 0, P = 0, zc = 0, z = 0;
        int ns = 0;
        double maxdiff = 0, maxsdiff = 0, maxdiff22 = 0;
        int momentum_bad = 0;
        for (int step = 0; step < nsteps && rc == 0; ++step) {
            lub_shear_sample sa, sb;
            unsigned fl = (step % 10 == 0) ? LUB_SAMPLE_STRESS : 0u;
            rc = lub_shear_step(&a, fl, &sa);
            if (rc) {
                fprintf(stderr, "%s\n", a.fail_msg);
                break;
            }
            if (step < 300) {
                lub_shear_sample sb2;
                rc = lub_shear_step(&b, fl, &sb);
                rc |= lub_shear_step(&b2, fl, &sb2);
                for (int i = 0; i < a.n; ++i) {
                    maxdiff = fmax(maxdiff, v3_norm(v3_sub(a.x[i], b.x[i])));
                    maxdiff22 = fmax(maxdiff22, v3_norm(v3_sub(b2.x[i], b.x[i])));
                }
                if (fl) {
                    double ta[9], tb[9];
                    lub_stress_total(&sa.stress, ta);
                    lub_stress_total(&sb.stress, tb);
                    for (int k = 0; k < 9; ++k) {
                        double d = fabs(ta[k] - tb[k]) / (fabs(ta[k]) + 1e-300);
                        if (fabs(ta[k]) > 1e-8 && d > maxsdiff)
                            maxsdiff = d;
                    }
                }
            }
            {
                /* pair forces are equal and opposite: the total force vanishes */
                vec3 sum = v3(0, 0, 0);
                double mag = 0;
                for (int i = 0; i < a.n; ++i) {
                    sum = v3_add(sum, a.f[i]);
                    mag += v3_norm(a.f[i]);
                }
                if (v3_norm(sum) > 1e-9 * (mag + 1e-300))
                    momentum_bad++;
            }
            if (fl && step * a.dt > 0.2) {
                double t[9];
                lub_stress_total(&sa.stress, t);
                sxy += t[1];
                P += -t[4];
                z += 2.0 * sa.n_active / a.n;
                zc += 2.0 * sa.n_contacts / a.n;
                ns++;
                ST_CHECK(isfinite(t[1]) && isfinite(t[4]), "non-finite stress");
            }
        }
        ST_CHECK(rc == 0, "dense run failed rc=%d", rc);
        ST_CHECK(ns > 10, "samples %d", ns);
        ST_CHECK(momentum_bad == 0, "%d steps with a non-zero total force", momentum_bad);
        sxy /= ns;
        P /= ns;
        z /= ns;
        zc /= ns;
        printf("dense n=400 phi=0.55 strain=%.2f dt=%.3g sigma_xy=%.4g P=%.4g mu=%.3f Z=%.2f "
               "Zc=%.2f rebuilds=%ld flips=%ld\n",
               a.time, a.dt, sxy, P, sxy / P, z, zc, a.rebuilds, a.flips);
        printf("threads max_position_diff_1_vs_2=%.3g max_stress_reldiff=%.3g "
               "max_position_diff_2_vs_2=%.3g\n",
               maxdiff, maxsdiff, maxdiff22);
        ST_CHECK(sxy > 0 && P > 0, "sheared suspension must resist: sxy %g P %g", sxy, P);
        ST_CHECK(z > 2 && zc > 0.1, "coordination Z %g Zc %g", z, zc);
        ST_CHECK(maxdiff22 == 0.0, "two 2-thread runs: positions differ by %g", maxdiff22);
        ST_CHECK(maxdiff < 1e-11, "1 vs 2 threads: positions differ by %g a", maxdiff);
        ST_CHECK(maxsdiff < 1e-9, "1 vs 2 threads: stresses differ by %g", maxsdiff);
        if (rc == 0)
            compare_batched_with_scalar(&a);
        lub_shear_free(&a);
        lub_shear_free(&b);
        lub_shear_free(&b2);
    }
    /* 4. the sliding-contact count follows the Coulomb limit: almost every contact slides
     * when mu is tiny, almost none when it is huge, none at all without friction */
    {
        double zc_lo, zc_mid, zc_hi, zc_off;
        const double lo = sliding_fraction(1e-4, LUB_TERM_ALL, &zc_lo);
        const double mid = sliding_fraction(0.5, LUB_TERM_ALL, &zc_mid);
        const double hi = sliding_fraction(1e3, LUB_TERM_ALL, &zc_hi);
        const double off = sliding_fraction(0.5, LUB_TERM_ALL & ~LUB_TERM_FRICTION, &zc_off);
        printf("sliding fraction mu=1e-4: %.3f (Zc %.2f)  mu=0.5: %.3f (Zc %.2f)  mu=1e3: %.3f "
               "(Zc %.2f)  friction off: %.3f (Zc %.2f)\n",
               lo, zc_lo, mid, zc_mid, hi, zc_hi, off, zc_off);
        ST_CHECK(zc_lo > 0.5 && zc_mid > 0.5 && zc_hi > 0.5 && zc_off > 0.5, "too few contacts");
        ST_CHECK(lo > 0.9, "mu = 1e-4: only %.3f of the contacts slide", lo);
        ST_CHECK(hi < 0.1, "mu = 1e3: %.3f of the contacts slide", hi);
        ST_CHECK(mid > hi && mid < lo, "mu = 0.5: %.3f not between %.3f and %.3f", mid, hi, lo);
        ST_CHECK(off == 0.0, "friction off: %.3f of the contacts slide", off);
    }
    ST_DONE();
}
