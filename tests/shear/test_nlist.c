/* test_nlist.c — neighbour list against brute force in a sheared cell (serial and with the
 * 2- and 3-thread pair search, which must give the identical list), and persistence of pair
 * states across rebuilds (with wraps and flips in between). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "neighbor_list.h"
#include "pair_store.h"
#include "rng.h"
#include "shear_test.h"

/* brute force: all pairs within the listing distance, nearest image among -2..2 shifts
 * (positions span at most 1.5 cells, so the nearest image is always among them) */
static int brute_has(const lub_cell *c, const vec3 *x, const double *r, int i, int j, double range,
                     double skin, int out_c[3])
{
    double lim = (r[i] + r[j]) * (1 + 0.5 * range) + skin;
    double best = INFINITY;
    for (int a = -2; a <= 2; ++a)
        for (int b = -2; b <= 2; ++b)
            for (int e = -2; e <= 2; ++e) {
                int k[3] = {a, b, e};
                vec3 d = v3_sub(v3_add(x[j], lub_cell_shift(c, k)), x[i]);
                double l = v3_norm(d);
                if (l < best) {
                    best = l;
                    memcpy(out_c, k, sizeof k);
                }
            }
    return best < lim;
}

static int check_against_brute(const lub_nlist *nl, const lub_cell *c, const vec3 *x,
                               const double *r, int n)
{
    int bad = 0;
    size_t found = 0;
    size_t k = 0;
    for (int i = 0; i < n; ++i)
        for (int j = i + 1; j < n; ++j) {
            int cb[3];
            int has = brute_has(c, x, r, i, j, nl->range, nl->skin, cb);
            /* listed pairs are sorted: advance */
            int listed = (k < nl->npairs && nl->pi[k] == i && nl->pj[k] == j);
            if (has != listed)
                bad++;
            if (listed) {
                if (memcmp(cb, &nl->pc[3 * k], sizeof cb) != 0)
                    bad++;
                ++k;
                ++found;
            }
        }
    if (k != nl->npairs)
        bad++;
    return bad;
}

int main(void)
{
    const int n = 600;
    lub_rng rng;
    lub_rng_seed(&rng, 42);
    vec3 *x = malloc(n * sizeof *x);
    double *r = malloc(n * sizeof *r);
    lub_cell c;
    lub_cell_init_box(&c, 22, 20, 21);
    c.L[0][1] = 1.0;
    for (int i = 0; i < n; ++i) {
        r[i] = 0.85 + 0.3 * lub_rng_uniform(&rng);
        /* positions deliberately outside the primary cell too */
        x[i] = v3(-5 + 32 * lub_rng_uniform(&rng), 20 * lub_rng_uniform(&rng) - 3,
                  21 * lub_rng_uniform(&rng));
    }
    lub_nlist nl;
    lub_nlist_init(&nl, 2.0, 0.4);
    lub_pairs ps;
    lub_pairs_init(&ps);
    const double tilts[4] = {0.0, 0.3, 0.49, -0.45};
    for (int t = 0; t < 4; ++t) {
        c.h[0][1] = tilts[t] * c.h[0][0];
        lub_cell_refresh(&c);
        int rc = lub_nlist_build(&nl, &c, x, r, n);
        ST_CHECK(rc == LUB_NLIST_OK, "build rc %d", rc);
        int bad = check_against_brute(&nl, &c, x, r, n);
        ST_CHECK(bad == 0, "tilt %g: %d mismatches vs brute force (%zu pairs)", tilts[t], bad,
                 nl.npairs);
        printf("nlist tilt=%.2f pairs=%zu mismatches=%d\n", tilts[t], nl.npairs, bad);
        /* the threaded search gives the same list, in the same order, at its first build
         * (equal ranges of i) and at a second one (ranges balanced by the first's pairs) */
        for (int th = 2; th <= 3; ++th) {
            lub_nlist par;
            lub_nlist_init(&par, 2.0, 0.4);
            par.threads = th;
            for (int build = 0; build < 2; ++build) {
                ST_CHECK(lub_nlist_build(&par, &c, x, r, n) == LUB_NLIST_OK, "threaded build");
                int same = par.npairs == nl.npairs;
                for (size_t k = 0; same && k < nl.npairs; ++k)
                    same = par.pi[k] == nl.pi[k] && par.pj[k] == nl.pj[k] &&
                           par.pc[3 * k] == nl.pc[3 * k] && par.pc[3 * k + 1] == nl.pc[3 * k + 1] &&
                           par.pc[3 * k + 2] == nl.pc[3 * k + 2];
                for (int i = 0; same && i <= n; ++i)
                    same = par.first[i] == nl.first[i];
                ST_CHECK(same, "tilt %g: %d-thread list (build %d) differs from the serial one",
                         tilts[t], th, build + 1);
            }
            /* second build: each range holds npairs/th pairs to within one i's pairs (equal
             * ranges of i fail this: i lists j > i only, so in this random order the first
             * half of i holds about 3/4 of the pairs) */
            ST_CHECK(par.split[0] == 0 && par.split[th] == n, "split ends");
            size_t most = 0;
            for (int i = 0; i < n; ++i)
                if (nl.first[i + 1] - nl.first[i] > most)
                    most = nl.first[i + 1] - nl.first[i];
            for (int k = 0; k < th && par.split[th] == n; ++k) {
                const double held = (double)(nl.first[par.split[k + 1]] - nl.first[par.split[k]]);
                ST_CHECK(fabs(held - (double)nl.npairs / th) <= (double)most + 1.0,
                         "tilt %g, %d threads: range %d holds %.0f of %zu pairs", tilts[t], th, k,
                         held, nl.npairs);
                if (t == 0 && th == 2)
                    printf("nlist 2-thread range %d: %.0f of %zu pairs (equal ranges of i: "
                           "%zu)\n",
                           k, held, nl.npairs,
                           k == 0 ? nl.first[n / 2] : nl.npairs - nl.first[n / 2]);
            }
            lub_nlist_free(&par);
        }
    }

    /* small and mid-size boxes: 4 to 7 bins per direction (bins half a listing distance wide,
     * engine/neighbor_list.c), i.e. the every-bin stencil (fewer than 5 bins) and the 5-wide
     * one, sheared and not, against brute force */
    {
        const double sides[4] = {10.2, 11.5, 13.0, 17.8};
        for (int b = 0; b < 4; ++b) {
            lub_cell sc;
            lub_cell_init_box(&sc, sides[b], sides[b] * 1.02, sides[b] * 0.99);
            const int m = (int)(0.09 * sides[b] * sides[b] * sides[b]);
            for (int tilt = 0; tilt < 2; ++tilt) {
                sc.h[0][1] = tilt ? 0.45 * sc.h[0][0] : 0.0;
                lub_cell_refresh(&sc);
                vec3 *y = malloc((size_t)m * sizeof *y);
                for (int i = 0; i < m; ++i)
                    y[i] = lub_mat_vec(sc.h, v3(1.2 * lub_rng_uniform(&rng) - 0.1,
                                                lub_rng_uniform(&rng), lub_rng_uniform(&rng)));
                lub_nlist sn;
                lub_nlist_init(&sn, 2.0, 0.4);
                int rc = lub_nlist_build(&sn, &sc, y, r, m);
                ST_CHECK(rc == LUB_NLIST_OK || rc == LUB_NLIST_CELL_TOO_SMALL, "small rc %d", rc);
                if (rc == LUB_NLIST_OK) {
                    int bad = check_against_brute(&sn, &sc, y, r, m);
                    ST_CHECK(bad == 0, "side %g tilt %d: %d mismatches (%d bins in x)", sides[b],
                             tilt, bad, sn.ncell[0]);
                    printf("nlist small box side=%.1f tilt=%d bins=%dx%dx%d pairs=%zu "
                           "mismatches=%d\n",
                           sides[b], tilt, sn.ncell[0], sn.ncell[1], sn.ncell[2], sn.npairs, bad);
                }
                lub_nlist_free(&sn);
                free(y);
            }
        }
    }

    /* persistence: mark each pair's state with a key, move, wrap, shear+flip, rebuild */
    c.h[0][1] = 0.0;
    lub_cell_refresh(&c);
    lub_nlist_build(&nl, &c, x, r, n);
    lub_pairs_adopt(&ps, &nl, n);
    ST_CHECK(ps.carried == 0, "first adopt carried %zu", ps.carried);
    vec3 *branch = malloc(nl.npairs * sizeof *branch);
    for (size_t k = 0; k < ps.n; ++k) {
        ps.state[k].delta = ps.i[k] * 10000.0 + ps.j[k];
        ps.state[k].x = 1.0; /* evaluated (not new) */
        ps.active[k] = (k % 3) != 0;
        branch[k] = v3_sub(v3_add(x[ps.j[k]], lub_cell_shift(&c, &ps.c[3 * k])), x[ps.i[k]]);
    }
    size_t n_old = ps.n;
    int32_t *oi = malloc(n_old * sizeof *oi), *oj = malloc(n_old * sizeof *oj);
    memcpy(oi, ps.i, n_old * sizeof *oi);
    memcpy(oj, ps.j, n_old * sizeof *oj);
    /* shear affinely by strain 0.7 (x += 0.7 y), flip, wrap everything, rebuild */
    for (int i = 0; i < n; ++i)
        x[i].x += 0.7 * x[i].y;
    c.h[0][1] = 0.7 * c.h[1][1];
    lub_cell_refresh(&c);
    int m[3];
    ST_CHECK(lub_cell_flip(&c, m) == 1, "flip expected");
    for (int i = 0; i < n; ++i)
        lub_cell_wrap(&c, &x[i], NULL, NULL);
    lub_nlist_build(&nl, &c, x, r, n);
    ST_CHECK(check_against_brute(&nl, &c, x, r, n) == 0, "after flip: brute force mismatch");
    lub_pairs_adopt(&ps, &nl, n);
    size_t carried = 0, fresh = 0, wrong = 0, branch_bad = 0, carried_active = 0;
    size_t o = 0;
    for (size_t k = 0; k < ps.n; ++k) {
        while (o < n_old && (oi[o] < ps.i[k] || (oi[o] == ps.i[k] && oj[o] < ps.j[k])))
            ++o;
        int existed = o < n_old && oi[o] == ps.i[k] && oj[o] == ps.j[k];
        if (existed) {
            carried++;
            carried_active += (o % 3) != 0;
            if (ps.state[k].delta != ps.i[k] * 10000.0 + ps.j[k])
                wrong++;
            if (ps.active[k] != ((o % 3) != 0))
                wrong++;
            /* the branch vector of a persisting pair is the sheared old one */
            vec3 b = v3_sub(v3_add(x[ps.j[k]], lub_cell_shift(&c, &ps.c[3 * k])), x[ps.i[k]]);
            vec3 bo = branch[o];
            vec3 bexp = v3(bo.x + 0.7 * bo.y, bo.y, bo.z);
            if (v3_norm(v3_sub(b, bexp)) > 1e-9)
                branch_bad++;
        } else {
            fresh++;
            if (!lub_pair_state_is_new(&ps.state[k]) || ps.active[k])
                wrong++;
        }
    }
    printf("persist carried=%zu new=%zu wrong=%zu branch_mismatch=%zu\n", carried, fresh, wrong,
           branch_bad);
    ST_CHECK(carried > 100, "too few carried pairs %zu", carried);
    /* lost: the old active states (o % 3 != 0) whose pair the new list lacks (here many: the
     * affine shift by 0.7 strain moves pairs out of the listing distance) */
    size_t old_active = 0;
    for (size_t q = 0; q < n_old; ++q)
        old_active += (q % 3) != 0;
    printf("persist lost=%zu of %zu active\n", ps.lost, old_active);
    ST_CHECK(ps.lost == old_active - carried_active && ps.lost > 0, "lost %zu, expected %zu",
             ps.lost, old_active - carried_active);
    ST_CHECK(wrong == 0, "%zu pair states not carried correctly", wrong);
    ST_CHECK(branch_bad == 0, "%zu branch vectors inconsistent after wrap+flip", branch_bad);
    /* cost-balanced split: stale after adopt (count split), then contiguous ranges covering
     * the list whose costs differ by less than two pairs' costs (a pair costs at most 6:
     * candidate 1, active 4, near 1); flags skewed towards the end of the list */
    {
        long k0, k1;
        lub_pairs_range(&ps, 1, 2, &k0, &k1);
        ST_CHECK(ps.nbounds == 0 && k0 == (long)ps.n / 2 && k1 == (long)ps.n,
                 "stale split must fall back to equal counts");
        for (size_t k = 0; k < ps.n; ++k) {
            ps.active[k] = k > ps.n / 3 || k % 5 == 0;
            ps.near[k] = ps.active[k] && k % 2 == 0;
        }
        for (int parts = 1; parts <= 5; ++parts) {
            lub_pairs_balance(&ps, parts);
            long lo = 1L << 60, hi = 0, prev = 0, cover = 0;
            for (int t = 0; t < parts; ++t) {
                lub_pairs_range(&ps, t, parts, &k0, &k1);
                ST_CHECK(k0 == prev && k1 >= k0, "parts=%d: range %d not contiguous", parts, t);
                long cost = 0;
                for (long k = k0; k < k1; ++k)
                    cost += 1 + 4 * ps.active[k] + ps.near[k];
                lo = cost < lo ? cost : lo;
                hi = cost > hi ? cost : hi;
                cover += k1 - k0;
                prev = k1;
            }
            printf("balance parts=%d cost_spread=%ld\n", parts, hi - lo);
            ST_CHECK(cover == (long)ps.n && prev == (long)ps.n, "parts=%d: ranges do not cover",
                     parts);
            ST_CHECK(hi - lo < 12, "parts=%d: cost spread %ld >= two pairs", parts, hi - lo);
        }
        lub_pairs_adopt(&ps, &nl, n);
        ST_CHECK(ps.nbounds == 0, "adopt must mark the split stale");
    }
    /* lost states: none when the same list is adopted again; exactly one when the new list
     * lacks one active pair */
    {
        for (size_t k = 0; k < ps.n; ++k)
            ps.active[k] = k % 2;
        lub_pairs_adopt(&ps, &nl, n);
        ST_CHECK(ps.lost == 0, "same list: %zu states lost", ps.lost);
        const size_t drop = 2 * (ps.n / 4) + 1; /* an odd index: active */
        for (size_t k = drop; k + 1 < nl.npairs; ++k) {
            nl.pi[k] = nl.pi[k + 1];
            nl.pj[k] = nl.pj[k + 1];
            for (int d = 0; d < 3; ++d)
                nl.pc[3 * k + d] = nl.pc[3 * (k + 1) + d];
        }
        nl.npairs--;
        lub_pairs_adopt(&ps, &nl, n);
        ST_CHECK(ps.lost == 1, "one active pair dropped: %zu states lost", ps.lost);
    }
    /* too small cell is reported */
    lub_cell small;
    lub_cell_init_box(&small, 8, 8, 8);
    ST_CHECK(lub_nlist_build(&nl, &small, x, r, 10) == LUB_NLIST_CELL_TOO_SMALL, "small cell");
    free(branch);
    free(oi);
    free(oj);
    free(x);
    free(r);
    lub_nlist_free(&nl);
    lub_pairs_free(&ps);
    ST_DONE();
}
