/* test_list_completeness.c — the Verlet list of a running system against a brute-force search
 * over all periodic images, after every step.
 *
 * A small packing is sheared (L_xy = 1) through a cell flip while L_yy oscillates (the cell
 * breathes: an imposed-volume oscillation of amplitude LYY_AMP), so the list ages under both
 * affine parts the skin rule must cover (shear and compression/extension) and under the
 * non-affine motion they drive. After each step (and lub_shear_complete_list, which makes the
 * list what the next step uses) every pair i < j is checked:
 *   - inside the cut-off (u_n <= cutoff a_ij at its nearest image): it is in the pair list,
 *     with the nearest image's shift, and no other image of it is inside the cut-off;
 *   - inside the list's guaranteed reach, centre distance < (2 + cutoff) a_ij + skin -
 *     skin_used (shear_system.h, skin rule): it is listed with the nearest image.
 * The first is what the physics needs; the second is the engine's own claim, a finer probe
 * of the skin rule (a rule that under-counts the skin consumed breaks it before it loses a
 * pair inside the cut-off). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "packing.h"
#include "shear_fixture.h"
#include "shear_test.h"

enum { N = 100, STEPS = 1500, PERIOD = 200 };
static const double PHI = 0.5, CUTOFF = 0.75, SKIN = 0.5, LYY_AMP = 5.0;

typedef struct {
    long inside;    /* pair-steps inside the cut-off */
    long missing;   /* ... not in the list */
    long wrong_img; /* ... listed with another image than the nearest */
    long two_img;   /* pairs with two images inside the cut-off */
    long reach_bad; /* pairs inside the guaranteed reach, not listed (or wrong image) */
} tally;

/* nearest image of j seen from i: returns the centre distance and the shift in k; also the
 * number of images with u_n <= cutoff a_ij (searched +-2 around the rounded fractional
 * difference: the cell is wider than twice the listing distance) */
static double nearest(const lub_shear_system *s, int i, int j, int k[3], int *n_in)
{
    const lub_cell *c = &s->cell;
    const vec3 f = lub_cell_to_frac(c, v3_sub(s->x[j], s->x[i]));
    const int k0[3] = {-(int)lround(f.x), -(int)lround(f.y), -(int)lround(f.z)};
    const double lim = s->r[i] + s->r[j] + 0.5 * CUTOFF * (s->r[i] + s->r[j]);
    double best = INFINITY;
    *n_in = 0;
    for (int a = -2; a <= 2; ++a)
        for (int b = -2; b <= 2; ++b)
            for (int e = -2; e <= 2; ++e) {
                const int kk[3] = {k0[0] + a, k0[1] + b, k0[2] + e};
                const double l = v3_norm(v3_sub(v3_add(s->x[j], lub_cell_shift(c, kk)), s->x[i]));
                *n_in += l <= lim;
                if (l < best) {
                    best = l;
                    memcpy(k, kk, sizeof kk);
                }
            }
    return best;
}

/* idx[i n + j] (i < j): the pair's index in s->pairs or -1 */
static void check(const lub_shear_system *s, int *idx, tally *t, long step)
{
    const lub_pairs *ps = &s->pairs;
    for (size_t p = 0; p < ps->n; ++p) {
        const int i = ps->i[p] < ps->j[p] ? ps->i[p] : ps->j[p];
        const int j = ps->i[p] < ps->j[p] ? ps->j[p] : ps->i[p];
        idx[i * N + j] = (int)p;
    }
    for (int i = 0; i < N; ++i)
        for (int j = i + 1; j < N; ++j) {
            int k[3] = {0, 0, 0}, n_in = 0;
            const double l = nearest(s, i, j, k, &n_in);
            const double rr = s->r[i] + s->r[j];
            const double reach = rr * (1.0 + 0.5 * CUTOFF) + SKIN - s->skin_used - 1e-9;
            const int in_cut = l - rr <= CUTOFF * 0.5 * rr;
            if (!in_cut && !(l < reach))
                continue;
            int listed = 0, same = 0;
            const int p = idx[i * N + j];
            if (p >= 0) {
                listed = 1;
                const int32_t *c = &ps->c[3 * p];
                const int sg = ps->i[p] == i ? 1 : -1; /* j seen from i */
                same = sg * c[0] == k[0] && sg * c[1] == k[1] && sg * c[2] == k[2];
            }
            if (in_cut) {
                t->inside++;
                t->missing += !listed;
                t->wrong_img += listed && !same;
                t->two_img += n_in > 1;
                if ((!listed || !same || n_in > 1) && t->missing + t->wrong_img + t->two_img <= 5)
                    fprintf(stderr,
                            "step %ld: pair %d %d u_n/a %.4f inside the cut-off: listed %d, "
                            "nearest image %d, images inside %d\n",
                            step, i, j, 2.0 * (l - rr) / rr, listed, same, n_in);
            }
            if (l < reach && !(listed && same) && ++t->reach_bad <= 5)
                fprintf(stderr,
                        "step %ld: pair %d %d at distance %.4f inside the reach %.4f (skin used "
                        "%.4f): listed %d, nearest image %d\n",
                        step, i, j, l, reach, s->skin_used, listed, same);
        }
    for (size_t p = 0; p < ps->n; ++p) {
        const int i = ps->i[p] < ps->j[p] ? ps->i[p] : ps->j[p];
        const int j = ps->i[p] < ps->j[p] ? ps->j[p] : ps->i[p];
        idx[i * N + j] = -1;
    }
}

int main(void)
{
    const lub_law_params law = shear_fixture_law(1e3);
    lub_shear_system s;
    int rc = shear_fixture_make(&s, N, PHI, &law, CUTOFF, 1, 3, 0.01);
    ST_CHECK(rc == 0, "setup rc %d", rc);
    if (rc)
        ST_DONE();
    ST_CHECK(s.nl.skin == SKIN, "fixture skin %g", s.nl.skin);
    int *idx = malloc((size_t)N * N * sizeof *idx);
    for (int k = 0; k < N * N; ++k)
        idx[k] = -1;
    tally t = {0};
    long worst_step = -1;
    for (int st = 0; st < STEPS; ++st) {
        double G[3][3];
        memcpy(G, s.cell.L, sizeof G);
        G[1][1] = LYY_AMP * sin(2.0 * acos(-1.0) * st / PERIOD);
        lub_shear_set_gradient(&s, G);
        rc = lub_shear_step(&s, 0, NULL);
        if (rc == 0)
            rc = lub_shear_complete_list(&s);
        ST_CHECK(rc == 0, "step %d rc %d: %s", st, rc, s.fail_msg);
        if (rc)
            break;
        const long bad = t.missing + t.wrong_img + t.two_img + t.reach_bad;
        check(&s, idx, &t, s.step);
        if (worst_step < 0 && t.missing + t.wrong_img + t.two_img + t.reach_bad > bad)
            worst_step = s.step;
    }
    printf("%ld steps, strain %.3f, %ld rebuilds, %ld flips, lost_pairs %ld; pair-steps inside "
           "the cut-off %ld: missing %ld, wrong image %ld, two images %ld; inside the reach, not "
           "listed %ld (first at step %ld)\n",
           s.step, s.time, s.rebuilds, s.flips, s.lost_pairs, t.inside, t.missing, t.wrong_img,
           t.two_img, t.reach_bad, worst_step);
    ST_CHECK(s.flips >= 1, "no flip in %ld steps (strain %.3f)", s.step, s.time);
    ST_CHECK(t.inside > 100L * STEPS, "only %ld pair-steps inside the cut-off", t.inside);
    ST_CHECK(t.missing == 0, "%ld pair-steps inside the cut-off missing from the list", t.missing);
    ST_CHECK(t.wrong_img == 0, "%ld pair-steps inside the cut-off listed with a far image",
             t.wrong_img);
    ST_CHECK(t.two_img == 0, "%ld pair-steps with two images inside the cut-off", t.two_img);
    ST_CHECK(t.reach_bad == 0, "%ld pair-steps inside the list's guaranteed reach not listed",
             t.reach_bad);
    ST_CHECK(s.lost_pairs == 0, "lost_pairs %ld", s.lost_pairs);
    free(idx);
    lub_shear_free(&s);
    ST_DONE();
}
