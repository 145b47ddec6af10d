/* test_microstructure.c — pair distribution on the unit sphere: normalisation (integral of the
 * interaction density over the hemisphere = Z/2), central symmetry, isotropy, edge bins. */
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
        lub_pdf_add_pair(&p, &o, v3_scale(o.n, 2.5), v3(1, 0, 0), 1.0, n_particles, 100.0);
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
    /* mean relative velocity flips sign for inversed pairs: isotropic +x input averages ~0 */
    double vx = 0;
    for (int b = 0; b < p.nt * p.np; ++b)
        vx += fabs(p.vel_sum[3 * b]) < 1.0 + 1e-12 ? 0 : 1;
    ST_CHECK(vx == 0, "velocity magnitude");
    lub_pdf_free(&p);
    ST_DONE();
}
