/* test_power_faces.c — faces of the power diagram (engine/power_faces.h), the interaction set
 * "delaunay" of simple_shear:
 *   1. simple cubic lattice: the 6 face neighbours have area (2r)^2, the 12 edge and 8 corner
 *      neighbours (degenerate faces) area ~0, nothing open;
 *   2. random polydisperse spheres: the neighbours with a face of positive area are exactly the
 *      edges of the regular triangulation found by brute force (empty orthosphere of some
 *      tetrahedron), and the area seen from either sphere agrees;
 *   3. periodic random packing: the cells (pyramids over the faces) tile the box, sum of
 *      volumes = box volume to round-off;
 *   4. certification: lub_power_certified_radius bounds what a sphere outside the known set
 *      can cut, and a face beyond R is reported open.
 */
#include "power_faces.h"
#include "rng.h"
#include "shear_test.h"

#include <math.h>
#include <stdlib.h>

enum { MAXS = 2048 };

static lub_power_site sites[MAXS];

static void cubic_lattice(void)
{
    int n = 0;
    for (int a = -3; a <= 3; ++a)
        for (int b = -3; b <= 3; ++b)
            for (int c = -3; c <= 3; ++c)
                if (a || b || c)
                    sites[n++] = (lub_power_site){v3(2.0 * a, 2.0 * b, 2.0 * c), 1.0, 0};
    lub_power_sort(sites, n);
    int faces = 0, open_any = 0;
    for (int j = 0; j < n; ++j) {
        const vec3 d = sites[j].d;
        const double l2 = v3_norm2(d);
        if (l2 > 12.5)
            continue;
        int open = 0;
        const double A = lub_power_face_area(1.0, sites, n, j, 20.0, 1.0, &open);
        open_any |= open;
        if (fabs(l2 - 4.0) < 1e-12) {
            ST_CHECK(fabs(A - 4.0) < 1e-12, "face neighbour (%g %g %g): area %.17g, expected 4",
                     d.x, d.y, d.z, A);
            faces++;
        } else {
            ST_CHECK(A < 1e-12, "edge/corner neighbour (%g %g %g): area %.3g, expected 0", d.x, d.y,
                     d.z, A);
        }
    }
    ST_CHECK(faces == 6, "%d face neighbours", faces);
    ST_CHECK(!open_any, "a face of the bounded cube cell is reported open");
}

/* orthocentre c of spheres (0, p, q, s): equal power to all four; returns 0 if degenerate */
static int orthocentre(double r0, lub_power_site P, lub_power_site Q, lub_power_site S, vec3 *c)
{
    /* 2 c.d = |d|^2 + r0^2 - r^2 for d in {P, Q, S} */
    const vec3 a = P.d, b = Q.d, e = S.d;
    const double ra = v3_norm2(a) + r0 * r0 - P.r * P.r, rb = v3_norm2(b) + r0 * r0 - Q.r * Q.r,
                 re = v3_norm2(e) + r0 * r0 - S.r * S.r;
    const vec3 bc = v3_cross(b, e), ca = v3_cross(e, a), ab = v3_cross(a, b);
    const double det = 2.0 * v3_dot(a, bc);
    if (fabs(det) < 1e-12)
        return 0;
    *c = v3_scale(v3_add(v3_add(v3_scale(bc, ra), v3_scale(ca, rb)), v3_scale(ab, re)), 1.0 / det);
    return 1;
}

static int brute_force_neighbour(double r0, const lub_power_site *s, int n, int j)
{
    for (int k = 0; k < n; ++k)
        for (int l = k + 1; l < n; ++l) {
            if (k == j || l == j)
                continue;
            vec3 c;
            if (!orthocentre(r0, s[j], s[k], s[l], &c))
                continue;
            const double w = v3_norm2(c) - r0 * r0;
            int empty = 1;
            for (int m = 0; m < n && empty; ++m)
                if (m != j && m != k && m != l)
                    empty = v3_norm2(v3_sub(c, s[m].d)) - s[m].r * s[m].r > w;
            if (empty)
                return 1;
        }
    return 0;
}

/* spheres at random non-overlapping positions in a cube of side L centred on sphere 0 */
static int random_spheres(lub_rng *g, int want, double L, double *r0, lub_power_site *s)
{
    *r0 = 1.0 + 0.05 * lub_rng_gauss(g);
    int n = 0;
    for (int tries = 0; n < want && tries < 100000; ++tries) {
        const vec3 d = v3(L * (lub_rng_uniform(g) - 0.5), L * (lub_rng_uniform(g) - 0.5),
                          L * (lub_rng_uniform(g) - 0.5));
        const double r = 1.0 + 0.05 * lub_rng_gauss(g);
        int ok = v3_norm(d) > r + *r0;
        for (int m = 0; m < n && ok; ++m)
            ok = v3_norm(v3_sub(d, s[m].d)) > r + s[m].r;
        if (ok)
            s[n++] = (lub_power_site){d, r, 0};
    }
    return n;
}

static void random_against_brute_force(void)
{
    lub_rng g;
    lub_rng_seed(&g, 12345);
    int checked = 0, neighbours = 0;
    for (int trial = 0; trial < 6; ++trial) {
        double r0;
        lub_power_site s[80];
        const int n = random_spheres(&g, 70, 9.0, &r0, s);
        lub_power_sort(s, n);
        for (int j = 0; j < n; ++j) {
            if (v3_norm(s[j].d) > 4.0) /* the cell of sphere 0 is well inside the cloud */
                continue;
            int open = 0;
            const double A = lub_power_face_area(r0, s, n, j, 50.0, 1.3, &open);
            const int bf = brute_force_neighbour(r0, s, n, j);
            ST_CHECK((A > 1e-9) == bf, "trial %d site %d: area %.3g, brute force %d", trial, j, A,
                     bf);
            ST_CHECK(!(A > 1e-9 && open), "trial %d site %d: face open", trial, j);
            neighbours += bf;
            checked++;
            /* the same face seen from sphere j */
            lub_power_site t[80];
            int m = 0;
            t[m++] = (lub_power_site){v3_neg(s[j].d), r0, 1};
            for (int k = 0; k < n; ++k)
                if (k != j)
                    t[m++] = (lub_power_site){v3_sub(s[k].d, s[j].d), s[k].r, 0};
            lub_power_sort(t, m);
            int back = -1;
            for (int k = 0; k < m; ++k)
                if (t[k].tag == 1)
                    back = k;
            const double Aj = lub_power_face_area(s[j].r, t, m, back, 50.0, 1.3, NULL);
            ST_CHECK(fabs(A - Aj) < 1e-9 * (1.0 + A), "trial %d site %d: area %.15g vs %.15g",
                     trial, j, A, Aj);
        }
    }
    ST_CHECK(checked > 100 && neighbours > 40, "only %d sites checked, %d neighbours", checked,
             neighbours);
    printf("brute_force_sites=%d brute_force_neighbours=%d\n", checked, neighbours);
}

static void periodic_tiling(void)
{
    lub_rng g;
    lub_rng_seed(&g, 777);
    const double L = 9.0;
    enum { N = 60 };
    vec3 x[N];
    double r[N];
    int n = 0;
    for (int tries = 0; n < N && tries < 100000; ++tries) {
        const vec3 p =
            v3(L * lub_rng_uniform(&g), L * lub_rng_uniform(&g), L * lub_rng_uniform(&g));
        const double rr = 1.0 + 0.05 * lub_rng_gauss(&g);
        int ok = 1;
        for (int m = 0; m < n && ok; ++m) {
            vec3 d = v3_sub(p, x[m]);
            d.x -= L * round(d.x / L), d.y -= L * round(d.y / L), d.z -= L * round(d.z / L);
            ok = v3_norm(d) > rr + r[m];
        }
        if (ok)
            x[n] = p, r[n++] = rr;
    }
    double rmax = 0.0;
    for (int i = 0; i < n; ++i)
        rmax = r[i] > rmax ? r[i] : rmax;
    double volume = 0.0;
    for (int i = 0; i < n; ++i) {
        int m = 0;
        for (int k = 0; k < n; ++k)
            for (int a = -1; a <= 1; ++a)
                for (int b = -1; b <= 1; ++b)
                    for (int c = -1; c <= 1; ++c) {
                        const vec3 d = v3_add(v3_sub(x[k], x[i]), v3(a * L, b * L, c * L));
                        if (k == i && !a && !b && !c)
                            continue;
                        if (v3_norm(d) < 1.2 * L)
                            sites[m++] = (lub_power_site){d, r[k], 0};
                    }
        lub_power_sort(sites, m);
        for (int j = 0; j < m; ++j) {
            const double lj = v3_norm(sites[j].d);
            const double h = (lj * lj + r[i] * r[i] - sites[j].r * sites[j].r) / (2.0 * lj);
            int open = 0;
            const double A = lub_power_face_area(r[i], sites, m, j, 0.55 * L, rmax, &open);
            ST_CHECK(!(A > 0.0 && open), "cell %d reaches the bounding ball", i);
            volume += A * h / 3.0;
        }
    }
    printf("periodic_tiling_n=%d volume=%.15g box=%.15g\n", n, volume, L * L * L);
    ST_CHECK(fabs(volume / (L * L * L) - 1.0) < 1e-10, "cells fill %.15g of the box",
             volume / (L * L * L));
}

static void certification(void)
{
    /* R + sqrt(R^2 + rmax^2 - r0^2) = known at the certified radius */
    const double known = 4.5, r0 = 0.9, rmax = 1.2;
    const double R = lub_power_certified_radius(known, r0, rmax);
    ST_CHECK(fabs(R + sqrt(R * R + rmax * rmax - r0 * r0) - known) < 1e-12, "R = %.15g", R);
    ST_CHECK(lub_power_certified_radius(0.0, 1.0, 1.0) == 0.0, "no known spheres");
    /* two spheres only: the face is unbounded, so it is open at any R */
    lub_power_site two[1] = {{v3(3.0, 0.0, 0.0), 1.0, 0}};
    int open = 0;
    const double A = lub_power_face_area(1.0, two, 1, 0, 2.0, 1.0, &open);
    ST_CHECK(open && fabs(A - 2.0 * sqrt(2.0) * (4.0 - 2.25)) < 1e-12,
             "lone pair: area %.15g open %d", A, open);
    /* plane beyond the ball */
    ST_CHECK(lub_power_face_area(1.0, two, 1, 0, 1.0, 1.0, &open) == 0.0 && open,
             "plane beyond R must give 0, open");
}

int main(void)
{
    cubic_lattice();
    random_against_brute_force();
    periodic_tiling();
    certification();
    ST_DONE();
}
