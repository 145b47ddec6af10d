/* test_cell.c — deforming periodic cell: image velocity, wrap with the mean-flow jump,
 * flips with consistent image shifts. */
#include <math.h>

#include "periodic_cell.h"
#include "shear_test.h"

static double dist3(vec3 a, vec3 b) { return v3_norm(v3_sub(a, b)); }

int main(void)
{
    lub_cell c;
    lub_cell_init_box(&c, 10, 8, 6);
    const double gd = 1.5;
    c.L[0][1] = gd;
    /* image velocity of a shift across the gradient boundary: L H (0,1,0) = (gd Ly, 0, 0) */
    int k[3] = {0, 1, 0};
    vec3 iv = lub_cell_image_velocity(&c, k);
    ST_CHECK(fabs(iv.x - gd * 8) < 1e-14 && iv.y == 0 && iv.z == 0, "image velocity %g", iv.x);
    int kx[3] = {1, 0, 1};
    iv = lub_cell_image_velocity(&c, kx);
    ST_CHECK(v3_norm(iv) == 0.0, "flow/vorticity shifts carry no velocity");

    /* shear the cell to strain 0.3 in steps */
    for (int s = 0; s < 300; ++s)
        ST_CHECK(lub_cell_update(&c, 0.001 / gd * 1.0) == 0, "update");
    ST_CHECK(fabs(c.h[0][1] - 0.3 * 8 * 1.0) < 1e-9 * 8, "tilt after strain 0.3: %g", c.h[0][1]);
    ST_CHECK(fabs(c.volume - 480) < 1e-9, "volume conserved %g", c.volume);

    /* a particle just above the top boundary moving with the mean flow */
    vec3 x = v3(3.0, 8.2, 1.0);
    vec3 v = lub_cell_mean_velocity(&c, x);
    vec3 xo = x, vo = v;
    int kw[3];
    lub_cell_wrap(&c, &x, &v, kw);
    ST_CHECK(kw[1] == 1, "wrap shift in y %d", kw[1]);
    vec3 s = lub_cell_to_frac(&c, x);
    ST_CHECK(s.x >= 0 && s.x < 1 && s.y >= 0 && s.y < 1 && s.z >= 0 && s.z < 1, "wrapped");
    /* velocity stays the mean flow at its new position (jump -L H k) */
    vec3 vm = lub_cell_mean_velocity(&c, x);
    ST_CHECK(dist3(v, vm) < 1e-12, "velocity after wrap is not the mean flow (%g)", dist3(v, vm));
    ST_CHECK(fabs((vo.x - v.x) - gd * 8) < 1e-12, "jump %g", vo.x - v.x);
    /* relative position and velocity to a neighbour are unchanged when its shift is updated */
    vec3 xn = v3(3.5, 7.9, 1.2), vn = v3(0.1, 0.2, 0.3);
    int cpair[3] = {0, 0, 0}; /* branch from particle (x) to neighbour */
    vec3 d0 = v3_sub(v3_add(xn, lub_cell_shift(&c, cpair)), xo);
    vec3 w0 = v3_sub(v3_add(vn, lub_cell_image_velocity(&c, cpair)), vo);
    int cnew[3] = {cpair[0] - kw[0], cpair[1] - kw[1], cpair[2] - kw[2]};
    vec3 d1 = v3_sub(v3_add(xn, lub_cell_shift(&c, cnew)), x);
    vec3 w1 = v3_sub(v3_add(vn, lub_cell_image_velocity(&c, cnew)), v);
    ST_CHECK(dist3(d0, d1) < 1e-12, "branch changed by the wrap %g", dist3(d0, d1));
    ST_CHECK(dist3(w0, w1) < 1e-12, "relative velocity changed by the wrap %g", dist3(w0, w1));

    /* flip: shear past tilt 1/2 and flip; every lattice vector H c keeps its value */
    for (int st = 0; st < 400; ++st)
        lub_cell_update(&c, 0.001 / gd);
    double tilt_before = c.h[0][1] / c.h[0][0];
    ST_CHECK(tilt_before > 0.5, "tilt %g", tilt_before);
    lub_cell before = c;
    int m[3];
    int f = lub_cell_flip(&c, m);
    ST_CHECK(f == 1 && m[1] == 1, "flip %d m1=%d", f, m[1]);
    ST_CHECK(fabs(c.h[0][1] / c.h[0][0]) <= 0.5, "tilt after flip %g", c.h[0][1] / c.h[0][0]);
    ST_CHECK(fabs(c.volume - before.volume) < 1e-9, "flip changed the volume");
    for (int a = -2; a <= 2; ++a)
        for (int b = -2; b <= 2; ++b) {
            int sh[3] = {a, b, 1};
            vec3 old = lub_cell_shift(&before, sh);
            vec3 oldv = lub_cell_image_velocity(&before, sh);
            lub_cell_flip_shift(m, sh);
            vec3 nw = lub_cell_shift(&c, sh);
            vec3 nwv = lub_cell_image_velocity(&c, sh);
            ST_CHECK(dist3(old, nw) < 1e-12 && dist3(oldv, nwv) < 1e-12,
                     "flip changed an image (%d,%d)", a, b);
        }
    double w[3];
    lub_cell_widths(&c, w);
    ST_CHECK(fabs(w[1] - 8) < 1e-12 && fabs(w[2] - 6) < 1e-12 && w[0] < 10 && w[0] > 8.5,
             "widths %g %g %g", w[0], w[1], w[2]);
    ST_DONE();
}
