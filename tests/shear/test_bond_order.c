/* test_bond_order.c — the global bond order Q6 (engine/bond_order.h): lattice values against an
 * independent evaluation with scipy's spherical harmonics, rotation/reversal invariance, the
 * random-direction level; and lub_shear_bond_order_q6 on a system (pair list and image shifts)
 * against a brute-force minimum-image pass over all pairs, on a sheared random packing and on
 * an fcc crystal in a periodic box, and after every step of sheared runs whose pair list does
 * not reach the bonds (small cut-off and skin; a cell too small for a bond list). */
#include <math.h>
#include <stdlib.h>

#include "bond_order.h"
#include "rng.h"
#include "shear_fixture.h"
#include "shear_test.h"

/* Q6 of the n bonds b[] (kernel under test) */
static double q6_of(const vec3 *b, int n)
{
    lub_q6_accum a;
    lub_q6_zero(&a);
    for (int k = 0; k < n; ++k)
        lub_q6_add(&a, b[k]);
    return lub_q6_value(&a);
}

/* rotation by angle t about the unit axis u (Rodrigues) */
static vec3 rotate(vec3 v, vec3 u, double t)
{
    const double c = cos(t), s = sin(t), d = u.x * v.x + u.y * v.y + u.z * v.z;
    const vec3 cr = v3(u.y * v.z - u.z * v.y, u.z * v.x - u.x * v.z, u.x * v.y - u.y * v.x);
    return v3(v.x * c + cr.x * s + u.x * d * (1 - c), v.y * c + cr.y * s + u.y * d * (1 - c),
              v.z * c + cr.z * s + u.z * d * (1 - c));
}

/* Q6 over all pairs closer than factor (r_i + r_j), minimum image through fractional
 * coordinates (exact for distances below half the cell's smallest width): independent of the
 * pair list and of its stored image shifts */
static double q6_brute(const lub_shear_system *s, double factor, long *bonds)
{
    lub_q6_accum a;
    lub_q6_zero(&a);
    for (int i = 0; i < s->n; ++i)
        for (int j = i + 1; j < s->n; ++j) {
            vec3 f = lub_cell_to_frac(&s->cell, v3_sub(s->x[j], s->x[i]));
            f = v3(f.x - round(f.x), f.y - round(f.y), f.z - round(f.z));
            const vec3 d = lub_cell_to_cart(&s->cell, f);
            const double reach = factor * (s->r[i] + s->r[j]);
            if (v3_norm2(d) < reach * reach)
                lub_q6_add(&a, d);
        }
    if (bonds)
        *bonds = a.n;
    return lub_q6_value(&a);
}

/* n spheres at phi 0.5 (packing seed 3, radius std 5 %), sheared at L_xy = 1 with cut-off and
 * skin as given, stepped `steps` times; after every step Q6 and its bond count against
 * q6_brute. Returns the steps where they differ; *bonds_sum: the bonds summed over the steps;
 * *listed_own: the system built its own bond list; *too_small: steps where a bond list
 * (range 0.4, no skin) does not fit the cell (the system's O(n^2) fallback). */
static int q6_run(int n, double cutoff, double skin, int steps, long *bonds_sum, int *listed_own,
                  int *too_small)
{
    double *r = malloc(n * sizeof *r);
    vec3 *x = malloc(n * sizeof *x);
    lub_cell c;
    lub_packing_params pp = {
        .n = n, .phi = 0.5, .radius_std = 0.05, .seed = 3, .margin = 0.01, .max_sweeps = 2000000};
    int rc = lub_packing_generate(&pp, r, x, &c, NULL);
    ST_CHECK(rc == 0, "packing n %d: %d", n, rc);
    const lub_law_params law = shear_fixture_law(1e3);
    lub_shear_system s;
    c.L[0][1] = 1.0;
    if (rc == 0)
        rc = lub_shear_init(&s, n, r, x, &c, &law, 0.01, cutoff, skin, 1.0, 1, 0, 0);
    ST_CHECK(rc == 0, "init n %d cut-off %g skin %g: %d", n, cutoff, skin, rc);
    free(r);
    free(x);
    if (rc)
        return -1;
    s.dt = 0.3 * lub_shear_elastic_dt(&s);
    int bad = 0;
    *bonds_sum = 0;
    *too_small = 0;
    lub_nlist probe;
    lub_nlist_init(&probe, 0.4, 0.0);
    for (int step = 0; step < steps; ++step) {
        rc = lub_shear_step(&s, 0, NULL);
        ST_CHECK(rc == 0, "step %d: %d %s", step, rc, s.fail_msg);
        if (rc)
            break;
        long b_sys = 0, b_all = 0;
        const double q_sys = lub_shear_bond_order_q6(&s, 1.2, &b_sys);
        const double q_all = q6_brute(&s, 1.2, &b_all);
        *bonds_sum += b_all;
        *too_small += lub_nlist_build(&probe, &s.cell, s.x, s.r, n) == LUB_NLIST_CELL_TOO_SMALL;
        if (b_sys != b_all || !(fabs(q_sys - q_all) <= 1e-12 * q_all)) {
            if (++bad <= 3)
                fprintf(stderr,
                        "n %d cut-off %g skin %g step %ld (skin used %.3f): %ld bonds, Q6 %.12f; "
                        "brute force %ld, %.12f\n",
                        n, cutoff, skin, s.step, s.skin_used, b_sys, q_sys, b_all, q_all);
        }
    }
    *listed_own = s.bond_nl.pair_cap > 0;
    lub_nlist_free(&probe);
    lub_shear_free(&s);
    return bad;
}

int main(void)
{
    /* ---- kernel ---- */
    vec3 fcc[12], sc[6], bcc[8];
    int nf = 0, ns = 0, nb = 0;
    for (int i = -1; i <= 1; ++i)
        for (int j = -1; j <= 1; ++j)
            for (int k = -1; k <= 1; ++k) {
                const int l1 = abs(i) + abs(j) + abs(k);
                if (l1 == 2)
                    fcc[nf++] = v3(i, j, k);
                if (l1 == 1)
                    sc[ns++] = v3(i, j, k);
                if (l1 == 3)
                    bcc[nb++] = v3(i, j, k);
            }
    /* reference values: numpy/scipy, sqrt(4 pi/13 sum_m |mean sph_harm(m, 6, phi, theta)|^2) */
    const double q_fcc = 0.5745242597140697, q_sc = 0.35355339059327373, q_bcc = 0.6285393610547086,
                 q_three = 0.612603060946092;
    ST_CHECK(fabs(q6_of(fcc, nf) - q_fcc) < 1e-12, "fcc %.15f", q6_of(fcc, nf));
    ST_CHECK(fabs(q6_of(sc, ns) - q_sc) < 1e-12, "sc %.15f", q6_of(sc, ns));
    ST_CHECK(fabs(q6_of(bcc, nb) - q_bcc) < 1e-12, "bcc %.15f", q6_of(bcc, nb));
    const vec3 three[3] = {v3(1, 2, 3), v3(0.3, -1, 0.2), v3(-2, 0.5, 0.7)};
    ST_CHECK(fabs(q6_of(three, 3) - q_three) < 1e-12, "three bonds %.15f", q6_of(three, 3));
    const vec3 one = v3(0.0, 0.0, 2.5);
    ST_CHECK(fabs(q6_of(&one, 1) - 1.0) < 1e-14, "one bond %.15f", q6_of(&one, 1));
    /* invariance: a rotation of every bond, and reversing some of them */
    vec3 rot[12];
    const vec3 axis = v3(0.48, -0.6, 0.64); /* unit */
    for (int k = 0; k < nf; ++k) {
        rot[k] = rotate(fcc[k], axis, 0.7314);
        if (k % 3 == 0)
            rot[k] = v3_scale(rot[k], -3.0);
    }
    ST_CHECK(fabs(q6_of(rot, nf) - q_fcc) < 1e-12, "rotated fcc %.15f", q6_of(rot, nf));
    /* zero and non-finite bonds are ignored; none -> NaN */
    lub_q6_accum a, b;
    lub_q6_zero(&a);
    for (int k = 0; k < nf; ++k)
        lub_q6_add(&a, fcc[k]);
    lub_q6_add(&a, v3(0, 0, 0));
    lub_q6_add(&a, v3(NAN, 1, 0));
    ST_CHECK(a.n == nf && fabs(lub_q6_value(&a) - q_fcc) < 1e-12, "n %ld q %.15f", a.n,
             lub_q6_value(&a));
    lub_q6_zero(&b);
    ST_CHECK(isnan(lub_q6_value(&b)), "empty accumulator");
    /* isotropic random directions: E[Q6^2] = 1/n */
    lub_rng rng;
    lub_rng_seed(&rng, 7);
    lub_q6_zero(&a);
    const int nr = 20000;
    for (int k = 0; k < nr; ++k)
        lub_q6_add(&a, v3(lub_rng_gauss(&rng), lub_rng_gauss(&rng), lub_rng_gauss(&rng)));
    const double qr = lub_q6_value(&a) * sqrt((double)nr);
    ST_CHECK(qr > 0.2 && qr < 3.0, "random directions: Q6 sqrt(n) = %g", qr);

    /* ---- system: pair list and image shifts against brute force ---- */
    lub_law_params law = shear_fixture_law(1e4);
    lub_shear_system s;
    int rc = shear_fixture_make(&s, 300, 0.5, &law, 1.0, 1, 3, 0.01);
    ST_CHECK(rc == 0, "fixture %d", rc);
    if (rc == 0) {
        /* shear to a tilted cell (through at least one flip) */
        for (int step = 0; step < 4000 && rc == 0; ++step)
            rc = lub_shear_step(&s, 0, NULL);
        ST_CHECK(rc == 0, "steps %d", rc);
        const double tilt = s.cell.h[0][1] / s.cell.h[1][1];
        const double q_list = lub_shear_bond_order_q6(&s, 1.2, NULL),
                     q_all = q6_brute(&s, 1.2, NULL);
        ST_CHECK(fabs(q_list - q_all) < 1e-12 * q_all, "list %.15f brute %.15f (tilt %.3f)", q_list,
                 q_all, tilt);
        ST_CHECK(q_list < 0.15, "random packing Q6 %.4f", q_list);
        printf("bond_order_random_q6=%.6f\nbond_order_random_tilt=%.4f\nbond_order_flips=%ld\n",
               q_list, tilt, s.flips);
        /* cut-off 1 reaches the bonds: the pair list is read, no list of its own */
        ST_CHECK(s.bond_nl.pair_cap == 0, "a bond list was built at cut-off 1");
        lub_shear_free(&s);
    }
    /* every bond counts where the pair list does not reach 1.2 (r_i + r_j): until 2026-12-07
     * only listed pairs were bonds (cut-off 0.1, skin 0.05: about 3/4 of them at every step;
     * at the default skin 0.5 a few steps where the skin was nearly used up); in a cell
     * too small for the bond list's 2.4 r_max at some steps (24 spheres) the O(n^2) fallback */
    {
        const struct {
            int n;
            double cutoff, skin;
            int steps, own;
        } cases[] = {{300, 0.1, 0.05, 400, 1}, {300, 0.1, 0.5, 700, 1}, {24, 0.1, 0.05, 400, -1}};
        for (size_t k = 0; k < sizeof cases / sizeof cases[0]; ++k) {
            long bonds_sum = 0;
            int own = 0, too_small = 0;
            const int bad = q6_run(cases[k].n, cases[k].cutoff, cases[k].skin, cases[k].steps,
                                   &bonds_sum, &own, &too_small);
            ST_CHECK(bad == 0,
                     "n %d cut-off %g skin %g: Q6 or bonds differ from the brute force at "
                     "%d of %d steps",
                     cases[k].n, cases[k].cutoff, cases[k].skin, bad, cases[k].steps);
            ST_CHECK(bonds_sum > 2L * cases[k].n * cases[k].steps, "n %d: only %ld bonds",
                     cases[k].n, bonds_sum);
            ST_CHECK(cases[k].own < 0 || own == cases[k].own,
                     "n %d cut-off %g skin %g: bond list built %d, expected %d", cases[k].n,
                     cases[k].cutoff, cases[k].skin, own, cases[k].own);
            ST_CHECK(cases[k].own >= 0 || (too_small > 0 && too_small < cases[k].steps),
                     "n %d: the bond list does not fit at %d of %d steps (both paths wanted)",
                     cases[k].n, too_small, cases[k].steps);
            printf("bond_order_small_cutoff n=%d skin=%g steps=%d bonds=%ld bond_list_misfit=%d\n",
                   cases[k].n, cases[k].skin, cases[k].steps, bonds_sum, too_small);
        }
    }
    /* fcc crystal, 4 x 4 x 4 cubic cells, nearest distance 2.1 (gap 0.1 a), at rest */
    {
        const int nc = 4, n = 4 * nc * nc * nc;
        const double al = 2.1 * sqrt(2.0), side = nc * al;
        const vec3 basis[4] = {v3(0, 0, 0), v3(0.5, 0.5, 0), v3(0.5, 0, 0.5), v3(0, 0.5, 0.5)};
        double *r = malloc(n * sizeof *r);
        vec3 *x = malloc(n * sizeof *x);
        int m = 0;
        for (int i = 0; i < nc; ++i)
            for (int j = 0; j < nc; ++j)
                for (int k = 0; k < nc; ++k)
                    for (int q = 0; q < 4; ++q) {
                        r[m] = 1.0;
                        x[m++] = v3((i + basis[q].x + 0.25) * al, (j + basis[q].y + 0.25) * al,
                                    (k + basis[q].z + 0.25) * al);
                    }
        lub_cell c;
        lub_cell_init_box(&c, side, side, side);
        rc = lub_shear_init(&s, n, r, x, &c, &law, 0.01, 1.0, 0.5, 1e-3, 1, 0, 0);
        ST_CHECK(rc == 0, "fcc init %d", rc);
        if (rc == 0) {
            rc = lub_shear_step(&s, 0, NULL);
            ST_CHECK(rc == 0, "fcc step %d", rc);
            long bonds = 0;
            const double q = lub_shear_bond_order_q6(&s, 1.2, &bonds);
            ST_CHECK(bonds == 6 * n, "fcc: %ld bonds, 12 per sphere expected", bonds);
            ST_CHECK(fabs(q - q_fcc) < 1e-9, "fcc crystal Q6 %.12f", q);
            ST_CHECK(fabs(q6_brute(&s, 1.2, NULL) - q) < 1e-12, "fcc brute %.12f",
                     q6_brute(&s, 1.2, NULL));
            lub_shear_free(&s);
        }
        free(r);
        free(x);
    }
    ST_DONE();
}
