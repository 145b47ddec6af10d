/* test_microstructure.c — pair distribution on the unit sphere: normalisation (integral of the
 * interaction density over the hemisphere = Z/2), central symmetry, isotropy, edge bins; the
 * axis convention on single normals (theta = arccos(n_y), phi = atan2(n_x, n_z)); the velocity
 * maps' sign flip for the pairs counted as -n (per bin: an isotropic constant velocity averages
 * to ~0, a separating velocity w = n to +n of the bin); empty bins' mean gap and velocities NaN
 * (not 0, a touching pair at rest). The maps against an independent recomputation from a run's
 * interaction network: shear.microstructure_cli (tests/shear/test_microstructure_cli.py). */
#include <math.h>
#include <string.h>

#include "microstructure.h"
#include "rng.h"
#include "shear_test.h"

int main(void)
{
    lub_pdf p;
    ST_CHECK(lub_pdf_init(&p, 13, 9) == 0, "init");
    lub_rng rng;
    lub_rng_seed(&rng, 11);
    const int n_particles = 1000, npairs = 200000;
    for (int k = 0; k < npairs; ++k) {
        /* isotropic normals */
        double z = 2 * lub_rng_uniform(&rng) - 1, ph = 6.283185307179586 * lub_rng_uniform(&rng);
        double s = sqrt(1 - z * z);
        lub_pair_output o;
        memset(&o, 0, sizeof o);
        o.n = v3(s * cos(ph), s * sin(ph), z);
        o.un = 0.5;
        o.contact = (k % 4) == 0;
        o.fn_contact = -1.0;
        /* contact-point velocity: constant +x; centre-of-mass velocity: w = n (separating) */
        lub_pdf_add_pair(&p, &o, v3_scale(o.n, 2.5), v3(1, 0, 0), o.n, 1.0, n_particles, 100.0);
    }
    p.snapshots = 1;
    lub_pdf_finish(&p);
    double integral = 0, cint = 0, dmin = 1e300, dmax = 0, area = 0;
    for (int b = 0; b < p.nt * p.np; ++b) {
        double ds = lub_pdf_solid_angle(&p, b);
        area += ds;
        integral += p.density[b] * ds;
        cint += p.contact_density[b] * ds;
        double iso = p.density[b];
        if (iso < dmin)
            dmin = iso;
        if (iso > dmax)
            dmax = iso;
        ST_CHECK(fabs(p.gap_sum[b] - 0.5) < 1e-12, "mean gap");
    }
    /* the bins tile the hemisphere exactly (the midpoint solid angles summed to 1.0024 of it
     * at 13 bins in theta, and every density read that much low) */
    ST_CHECK(fabs(area / (2 * 3.14159265358979323846) - 1) < 1e-12, "bins cover %.15g of 2 pi",
             area / (2 * 3.14159265358979323846));
    /* Z/2 = npairs / N */
    double zhalf = (double)npairs / n_particles;
    printf("pdf integral=%.4f (Z/2=%.4f) contact_integral=%.4f density_min=%.3f max=%.3f "
           "(isotropic %.3f)\n",
           integral, zhalf, cint, dmin, dmax, zhalf / (2 * 3.14159265358979));
    ST_CHECK(fabs(integral / zhalf - 1) < 0.01, "normalisation %g vs %g", integral, zhalf);
    ST_CHECK(fabs(cint / (zhalf / 4) - 1) < 0.03, "contact normalisation %g", cint);
    /* midpoint solid angles: isotropic density flat within sampling noise + midpoint error */
    double iso = zhalf / (2 * 3.14159265358979);
    ST_CHECK(dmin > 0.85 * iso && dmax < 1.15 * iso, "isotropy %g..%g vs %g", dmin, dmax, iso);
    /* central symmetry: n and -n fall in the same bin, the second one inversed */
    int inv1, inv2;
    vec3 n = v3(0.3, 0.5, -0.81);
    n = v3_scale(n, 1 / v3_norm(n));
    int b1 = lub_pdf_bin(&p, n, &inv1), b2 = lub_pdf_bin(&p, v3_neg(n), &inv2);
    ST_CHECK(b1 == b2 && inv1 != inv2, "central symmetry %d %d %d %d", b1, b2, inv1, inv2);
    /* theta = pi exactly (n = -y) stays inside the grid (notes P15) */
    int bb = lub_pdf_bin(&p, v3(0, -1, 0), &inv1);
    ST_CHECK(bb >= 0 && bb < p.nt * p.np, "edge bin %d", bb);
    /* mean relative velocity flips sign for inversed pairs: the isotropic constant +x input
     * averages to ~0 in every bin (within 5/sqrt(pairs in the bin); without the flip 1),
     * and the separating w = n to the bin's own direction (without the flip ~0) */
    const double pi = 3.14159265358979323846;
    double vmax = 0, align_min = 1;
    for (int b = 0; b < p.nt * p.np; ++b) {
        const double *v = p.vel_sum + 3 * b, *vc = p.vel_com_sum + 3 * b;
        /* in units of the bin's noise 1/sqrt(count) */
        const double mv = sqrt((v[0] * v[0] + v[1] * v[1] + v[2] * v[2]) * p.count[b]);
        vmax = mv > vmax ? mv : vmax;
        const double th = (b / p.np + 0.5) * pi / p.nt, ph = (b % p.np + 0.5) * pi / p.np;
        const double al = vc[0] * sin(th) * sin(ph) + vc[1] * cos(th) + vc[2] * sin(th) * cos(ph);
        align_min = al < align_min ? al : align_min;
    }
    printf("isotropic constant velocity: largest |mean| sqrt(count) in a bin %.3f; separating "
           "velocity: "
           "smallest projection on the bin's direction %.3f\n",
           vmax, align_min);
    ST_CHECK(vmax < 5.0, "constant velocity averages to %.3g/sqrt(count) in a bin, not ~0", vmax);
    ST_CHECK(align_min > 0.9, "separating velocity along its bin's direction only %.3g", align_min);
    lub_pdf_free(&p);

    /* single normals, 13 x 9 bins: n = x (theta = pi/2, phi = pi/2): bin (6, 4); n = z
     * (theta = pi/2, phi = 0): (6, 0); n = y (theta = 0): (0, 0); n = -x (phi = -pi/2 < 0):
     * counted as +x, inversed; n = -y tilted to -x (theta = pi, phi = -pi/2)
     * as +y tilted to +x (theta = 0, phi = pi/2), inversed */
    ST_CHECK(lub_pdf_init(&p, 13, 9) == 0, "init");
    const struct {
        vec3 n;
        int it, ip, inv;
    } unit[] = {{{1, 0, 0}, 6, 4, 0},        {{0, 0, 1}, 6, 0, 0},
                {{0, 1, 0}, 0, 0, 0},        {{-1, 0, 0}, 6, 4, 1},
                {{-1e-300, -1, 0}, 0, 4, 1}, {{0.5, 0.5 * sqrt(2.0), 0.5}, 3, 2, 0}};
    for (size_t u = 0; u < sizeof unit / sizeof unit[0]; ++u) {
        int inv;
        const int b = lub_pdf_bin(&p, unit[u].n, &inv);
        ST_CHECK(b == unit[u].it * p.np + unit[u].ip && inv == unit[u].inv,
                 "normal %zu: bin (%d, %d) inversed %d, expected (%d, %d) %d", u, b / p.np,
                 b % p.np, inv, unit[u].it, unit[u].ip, unit[u].inv);
    }
    /* one pair along +x and one along -x, both moving (2, 3, 4) (the second one's velocity
     * enters as -(2, 3, 4)): the bin's means are 0; one pair along +z: its velocity itself;
     * every other bin is empty: NaN mean gap and velocities, zero densities */
    lub_pair_output o;
    memset(&o, 0, sizeof o);
    o.un = 0.25;
    o.n = v3(1, 0, 0);
    lub_pdf_add_pair(&p, &o, o.n, v3(2, 3, 4), v3(2, 3, 4), 1.0, 10, 100.0);
    o.n = v3(-1, 0, 0);
    lub_pdf_add_pair(&p, &o, o.n, v3(2, 3, 4), v3(2, 3, 4), 1.0, 10, 100.0);
    o.n = v3(0, 0, 1);
    o.un = 0.5;
    lub_pdf_add_pair(&p, &o, o.n, v3(2, 3, 4), v3(-2, 1, 5), 2.0, 10, 100.0);
    p.snapshots = 1;
    lub_pdf_finish(&p);
    const int bx = 6 * p.np + 4, bz = 6 * p.np;
    ST_CHECK(p.count[bx] == 2 && p.count[bz] == 1, "pair counts %g %g", p.count[bx], p.count[bz]);
    ST_CHECK(fabs(p.vel_sum[3 * bx]) + fabs(p.vel_sum[3 * bx + 1]) + fabs(p.vel_sum[3 * bx + 2]) ==
                 0,
             "+x and -x pairs of one velocity: mean %g %g %g", p.vel_sum[3 * bx],
             p.vel_sum[3 * bx + 1], p.vel_sum[3 * bx + 2]);
    ST_CHECK(p.vel_sum[3 * bz] == 2 && p.vel_sum[3 * bz + 1] == 3 && p.vel_sum[3 * bz + 2] == 4 &&
                 p.vel_com_sum[3 * bz] == -2 && p.vel_com_sum[3 * bz + 1] == 1 &&
                 p.vel_com_sum[3 * bz + 2] == 5 && p.gap_sum[bz] == 0.25,
             "+z pair: velocity %g %g %g, centre velocity %g %g %g, gap %g", p.vel_sum[3 * bz],
             p.vel_sum[3 * bz + 1], p.vel_sum[3 * bz + 2], p.vel_com_sum[3 * bz],
             p.vel_com_sum[3 * bz + 1], p.vel_com_sum[3 * bz + 2], p.gap_sum[bz]);
    int empty_ok = 1, filled = 0;
    for (int b = 0; b < p.nt * p.np; ++b) {
        if (p.density[b] != 0) {
            filled++;
            continue;
        }
        empty_ok &= isnan(p.gap_sum[b]) && p.count[b] == 0;
        for (int d = 0; d < 3; ++d)
            empty_ok &= isnan(p.vel_sum[3 * b + d]) && isnan(p.vel_com_sum[3 * b + d]);
    }
    ST_CHECK(filled == 2 && empty_ok, "empty bins: %d filled, mean gap and velocities NaN: %d",
             filled, empty_ok);
    lub_pdf_free(&p);
    ST_DONE();
}
