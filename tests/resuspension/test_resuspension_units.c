/* Unit tests of the resuspension building blocks (issue 4):
 *  1. exact sphere–slab volume (resuspension_profile.c) against closed forms and a fine
 *     numerical integration of pi (r^2 - y^2), partition of unity over bins;
 *  2. floor impermeability (floor_wall.c + resuspension_system.c): the bound on the passing
 *     radius holds for the built floor (brute-force search of the largest hole), and a
 *     particle of the smallest allowed radius pushed by a huge weight into a hole, and a bed
 *     pressed by a huge weight, stay above the floor;
 *  3. drag hooks: an isolated particle relaxes to the mean flow u at the exact implicit rate
 *     of the shear drag (gradient) or the dilute drag; no shear drag in the vorticity
 *     orientation; the dilute drag is switched off for a particle with >= 3 interactions.
 *  4. 1 and 2 threads: a sheared, settling bed of 343 particles (above the 256 at which the
 *     neighbour search goes parallel; 200 steps, 5 rebuilds) stepped on 1 and on 2
 *     threads keeps its positions within 1e-10 a of each other (only the order of the pair
 *     sums differs), two 2-thread runs agree bit for bit, and the 2-thread system's teams
 *     really had 2 threads (team_min); skipped on 1 processor or an OpenMP thread limit of 1.
 *     Summing only thread 0's pair sums (the other thread's forces lost) fails it.
 * Each check fails on a wrong formula (cap volume, factor 6 pi r, gating, sign). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "floor_wall.h"
#include "processors.h"
#include "resuspension_profile.h"
#include "resuspension_system.h"

static int failures = 0;
#define CHECK(cond, ...)                                                                           \
    do {                                                                                           \
        if (!(cond)) {                                                                             \
            fprintf(stderr, "%s:%d: ", __FILE__, __LINE__);                                        \
            fprintf(stderr, __VA_ARGS__);                                                          \
            fprintf(stderr, "\n");                                                                 \
            ++failures;                                                                            \
        }                                                                                          \
    } while (0)

static const double PI = 3.14159265358979323846;

/* fine midpoint integration of the disc area pi (r^2 - (y - yc)^2) over [y1, y2] */
static double slab_numeric(double yc, double r, double y1, double y2)
{
    const int m = 200000;
    double lo = fmax(y1, yc - r), hi = fmin(y2, yc + r), s = 0.0;
    if (hi <= lo)
        return 0.0;
    double h = (hi - lo) / m;
    for (int k = 0; k < m; ++k) {
        double y = lo + (k + 0.5) * h - yc;
        s += PI * (r * r - y * y);
    }
    return s * h;
}

static void test_slab(void)
{
    const double r = 1.3, yc = 2.0, V = 4.0 / 3.0 * PI * r * r * r;
    CHECK(fabs(lub_sphere_slab_volume(yc, r, -10, 10) - V) < 1e-12 * V, "whole sphere");
    CHECK(fabs(lub_sphere_slab_volume(yc, r, yc, 10) - 0.5 * V) < 1e-12 * V, "hemisphere");
    CHECK(lub_sphere_slab_volume(yc, r, yc + r, yc + 5) == 0.0, "above");
    CHECK(lub_sphere_slab_volume(yc, r, -5, yc - r) == 0.0, "below");
    CHECK(lub_sphere_slab_volume(yc, r, 3.0, 1.0) == 0.0, "reversed slab");
    /* a cap of height h: pi h^2 (3r - h)/3 */
    double h = 0.4;
    CHECK(fabs(lub_sphere_slab_volume(yc, r, yc - r - 1, yc - r + h) -
               PI * h * h * (3 * r - h) / 3) < 1e-13,
          "cap");
    double worst = 0.0;
    for (int k = 0; k < 40; ++k) {
        double y1 = yc - 1.6 + 0.071 * k, y2 = y1 + 0.013 + 0.05 * (k % 7);
        double e = fabs(lub_sphere_slab_volume(yc, r, y1, y2) - slab_numeric(yc, r, y1, y2));
        worst = fmax(worst, e);
    }
    CHECK(worst < 1e-9, "slab volume vs numerical integration: worst error %.3g", worst);
    printf("slab_volume_max_error=%.3g\n", worst);

    /* partition: bins covering the sphere sum to its volume; a sphere cut by the profile
     * range contributes only its inside part */
    enum { NB = 37 };
    double vol[NB];
    memset(vol, 0, sizeof vol);
    lub_profile_add_sphere(vol, NB, 0.0, 0.17, 3.05, 0.97);
    double s = 0;
    for (int i = 0; i < NB; ++i)
        s += vol[i];
    const double V2 = 4.0 / 3.0 * PI * pow(0.97, 3);
    CHECK(fabs(s - V2) < 1e-12 * V2, "partition of unity: %.17g vs %.17g", s, V2);
    memset(vol, 0, sizeof vol);
    lub_profile_add_sphere(vol, NB, 0.0, 0.17, 0.3, 0.97); /* cut by y0 = 0 */
    s = 0;
    for (int i = 0; i < NB; ++i)
        s += vol[i];
    CHECK(fabs(s - lub_sphere_slab_volume(0.3, 0.97, 0.0, 100.0)) < 1e-12, "cut at y0");
    /* weighted version carries value * volume */
    double v2[NB], w2[NB];
    memset(v2, 0, sizeof v2);
    memset(w2, 0, sizeof w2);
    lub_profile_add_sphere_weighted(v2, w2, NB, 0.0, 0.17, 3.05, 0.97, -2.5);
    double sw = 0;
    for (int i = 0; i < NB; ++i)
        sw += w2[i];
    CHECK(fabs(sw + 2.5 * V2) < 1e-11, "weighted sum");
    /* a simple cubic lattice of spheres of radius 0.5 in cells of side 1 has phi = pi/6 when
     * averaged over one period */
    double phi[4], vl[4] = {0, 0, 0, 0};
    for (int j = -1; j <= 4; ++j)
        lub_profile_add_sphere(vl, 4, 0.0, 1.0, j + 0.5, 0.5);
    lub_profile_normalise(vl, 4, 1.0, 1.0, phi);
    for (int i = 0; i < 4; ++i)
        CHECK(fabs(phi[i] - PI / 6) < 1e-13, "lattice phi[%d] = %.17g", i, phi[i]);
}

/* ---- a small system helper ---- */
typedef struct {
    lub_rs_params p;
    lub_law_params law;
} sys_setup;

static sys_setup default_setup(void)
{
    sys_setup s;
    memset(&s, 0, sizeof s);
    s.p.orientation = LUB_RS_GRADIENT;
    s.p.shear_rate = 1.0;
    s.p.gravity = 0.0;
    s.p.drho = 1.0;
    s.p.rho = 1.0;
    s.p.eta_shear = 0.0;
    s.p.eta_dilute = 0.0;
    s.p.dilute_max_interactions = 2;
    s.p.y_floor = 2.0;
    s.p.y_lid = 40.0;
    s.p.cutoff = 2.0;
    s.p.skin = 0.3;
    s.p.dt = 1e-3;
    s.p.threads = 1;
    s.law.eta = 1.0;
    s.law.k_bulk = 1e4;
    s.law.alpha = 1.0;
    s.law.k_t = 5e3;
    s.law.eps = 2e-3;
    s.law.mu = 0.5;
    s.law.terms = LUB_TERM_ALL;
    return s;
}

enum { NSIDE = 8 };
static const double CELL = 2.0 * NSIDE; /* floor of radius 1 */

static int make_system(lub_rs_system *S, const sys_setup *st, int n, const double *r, const vec3 *x,
                       double jitter)
{
    double fr[NSIDE * NSIDE];
    vec3 fp[NSIDE * NSIDE];
    for (int i = 0; i < NSIDE * NSIDE; ++i)
        fr[i] = 1.0;
    lub_floor_build(NSIDE, 1.0, st->p.y_floor, jitter, 42, fp);
    return lub_rs_init(S, &st->p, &st->law, n, r, x, NSIDE * NSIDE, fr, fp, CELL, 60.0, CELL);
}

/* largest sphere that fits between the floor spheres at the hole (x, z), found by bisection
 * on the radius of a probe whose centre slides down the vertical line through (x, z): it
 * passes if at some height its clearance to every floor sphere is >= its radius all the
 * way down to below the floor. Conservative: returns the largest radius whose lowest-point
 * clearance (over heights) is positive. */
static double hole_radius(const vec3 *fp, int nf, double x, double z)
{
    double best = INFINITY; /* min over heights of the min distance to floor surfaces */
    for (double y = 0.0; y <= 4.0; y += 0.002) {
        double m = INFINITY;
        for (int i = 0; i < nf; ++i)
            for (int sx = -1; sx <= 1; ++sx)
                for (int sz = -1; sz <= 1; ++sz) {
                    double dx = fp[i].x + sx * CELL - x, dz = fp[i].z + sz * CELL - z;
                    if (fabs(dx) > 3.5 || fabs(dz) > 3.5)
                        continue;
                    vec3 d = v3(dx, fp[i].y - y, dz);
                    m = fmin(m, v3_norm(d) - 1.0);
                }
        best = fmin(best, m);
    }
    return best; /* a probe of radius > best cannot go through this line */
}

static void test_floor(void)
{
    const double jitter = 0.3;
    vec3 fp[NSIDE * NSIDE];
    lub_floor_build(NSIDE, 1.0, 2.0, jitter, 42, fp);
    double ymin = INFINITY, ymax = -INFINITY;
    for (int i = 0; i < NSIDE * NSIDE; ++i) {
        ymin = fmin(ymin, fp[i].y);
        ymax = fmax(ymax, fp[i].y);
    }
    CHECK(ymin >= 2.0 - 0.3 - 1e-12 && ymax <= 2.0 + 0.3 + 1e-12, "jitter range");
    CHECK(ymax - ymin > 0.3, "jitter applied (spread %.3g)", ymax - ymin);
    /* every hole centre (corners of the lattice cells) */
    double worst = 0.0;
    for (int i = 0; i < NSIDE; ++i)
        for (int k = 0; k < NSIDE; ++k)
            worst = fmax(worst, hole_radius(fp, NSIDE * NSIDE, 2.0 * i, 2.0 * k));
    const double bound = lub_floor_max_passing_radius(1.0, jitter);
    printf("floor_largest_hole_radius=%.4f bound=%.4f\n", worst, bound);
    CHECK(worst <= bound, "hole radius %.4f exceeds the documented bound %.4f", worst, bound);
    CHECK(worst > sqrt(2.0) - 1.0 - 0.01, "hole search broken (%.4f)", worst);

    /* dynamic: the smallest allowed particle (radius 0.7) above a hole under a huge weight */
    sys_setup st = default_setup();
    st.p.gravity = 1e3; /* weight = 4/3 pi 0.343 * 1e3 ~ 1.4e3 k_bulk-scale forces */
    st.p.rho = 1.0;
    st.p.eta_dilute = 1.0;
    double r = 0.7;
    vec3 x = v3(2.0 * 3, 2.0 + 1.0 + 0.3 + 1.5, 2.0 * 3); /* above the hole at (6, 6) */
    lub_rs_system S;
    CHECK(make_system(&S, &st, 1, &r, &x, jitter) == LUB_RS_OK, "init");
    int rc = 0;
    double ylow = INFINITY;
    for (int k = 0; k < 20000 && rc == 0; ++k) {
        rc = lub_rs_step(&S);
        ylow = fmin(ylow, S.x[0].y);
    }
    CHECK(rc == LUB_RS_OK, "heavy particle on the floor: rc %d (%s)", rc, S.fail_msg);
    CHECK(ylow > 2.0, "particle sank to y = %.4f (floor plane 2.0)", ylow);
    printf("floor_heavy_particle_lowest_centre=%.4f\n", ylow);
    lub_rs_free(&S);

    /* a bed of 3 layers pressed by a large weight (Sh ~ 1e-2) */
    enum { NB = 3 * 49 };
    double rb[NB];
    vec3 xb[NB];
    for (int l = 0, q = 0; l < 3; ++l)
        for (int i = 0; i < 7; ++i)
            for (int k = 0; k < 7; ++k, ++q) {
                rb[q] = 0.85 + 0.05 * ((q * 7) % 5);
                xb[q] = v3(1.0 + 2.28 * i + 0.3 * (l % 2), 5.0 + 2.4 * l, 1.0 + 2.28 * k);
            }
    st = default_setup();
    st.p.gravity = 100.0; /* bottom particles carry ~ 0.2 k_bulk a: Sh ~ 1e-2 */
    st.p.eta_dilute = 1.0;
    st.p.dt = 3e-4;
    CHECK(make_system(&S, &st, NB, rb, xb, 0.15) == LUB_RS_OK, "init bed");
    rc = 0;
    for (int k = 0; k < 4000 && rc == 0; ++k)
        rc = lub_rs_step(&S);
    int below = -1;
    double low = lub_rs_lowest(&S, &below);
    CHECK(rc == LUB_RS_OK, "heavy bed: rc %d (%s)", rc, S.fail_msg);
    CHECK(below == 0, "%d particles below the floor plane", below);
    printf("floor_heavy_bed_lowest_bottom=%.4f below=%d\n", low, below);
    lub_rs_free(&S);
}

/* isolated particle: v relaxes to u at the implicit rate (1 + dt c/m)^-n */
static double relax_error(int orientation, double eta_shear, double eta_dilute, int dmax,
                          double expect_visc)
{
    sys_setup st = default_setup();
    st.p.orientation = orientation;
    st.p.eta_shear = eta_shear;
    st.p.eta_dilute = eta_dilute;
    st.p.dilute_max_interactions = dmax;
    double r = 1.1;
    vec3 x = v3(5.0, 20.0, 7.0);
    lub_rs_system S;
    if (make_system(&S, &st, 1, &r, &x, 0.0) != LUB_RS_OK)
        return INFINITY;
    const vec3 u0 = lub_rs_mean_velocity(&S, S.x[0]);
    const vec3 dv0 = v3(0.7, 0.0, 0.25); /* v_y = 0: the particle stays at its height */
    S.v[0] = v3_add(u0, dv0);
    const double m = S.m[0];
    const double c = 6.0 * PI * r * expect_visc;
    const int nsteps = 500;
    for (int k = 0; k < nsteps; ++k)
        if (lub_rs_step(&S) != LUB_RS_OK) {
            lub_rs_free(&S);
            return INFINITY;
        }
    const vec3 u = lub_rs_mean_velocity(&S, S.x[0]);
    vec3 dv = v3_sub(S.v[0], u);
    const double f = pow(1.0 + st.p.dt * c / m, -nsteps);
    /* vorticity orientation: the convective term dt L v = dt gd v_z e_x couples v'_z into
     * v'_x, so only y and z follow the pure decay there; in the gradient orientation the
     * particle keeps its height (v_y = 0), u at its centre is constant and x decays purely */
    double e = fabs(dv.y - f * dv0.y) + fabs(dv.z - f * dv0.z);
    if (orientation == LUB_RS_GRADIENT)
        e += fabs(dv.x - f * dv0.x);
    lub_rs_free(&S);
    return e;
}

static void test_drag(void)
{
    double e1 = relax_error(LUB_RS_GRADIENT, 1.0 / 30.0, 0.0, 2, 1.0 / 30.0);
    double e2 = relax_error(LUB_RS_GRADIENT, 0.0, 1.0, 2, 1.0);
    double e3 = relax_error(LUB_RS_GRADIENT, 0.5, 1.0, 2, 1.5);
    double e4 = relax_error(LUB_RS_VORTICITY, 5.0, 0.0, 2, 0.0); /* no shear drag there */
    double e5 = relax_error(LUB_RS_VORTICITY, 0.0, 2.0, 2, 2.0);
    double e6 = relax_error(LUB_RS_GRADIENT, 0.0, 1.0, -1, 0.0); /* dilute drag disabled */
    printf("drag_errors=%.2g,%.2g,%.2g,%.2g,%.2g,%.2g\n", e1, e2, e3, e4, e5, e6);
    CHECK(e1 < 1e-10, "shear drag rate (err %.3g)", e1);
    CHECK(e2 < 1e-10, "dilute drag rate (err %.3g)", e2);
    CHECK(e3 < 1e-10, "shear + dilute drag rate (err %.3g)", e3);
    CHECK(e4 < 1e-10, "vorticity orientation must have no shear drag (err %.3g)", e4);
    CHECK(e5 < 1e-10, "dilute drag in vorticity orientation (err %.3g)", e5);
    CHECK(e6 < 1e-10, "max_interactions = -1 disables the dilute drag (err %.3g)", e6);
    /* a wrong expectation must be detected (the check can fail) */
    CHECK(relax_error(LUB_RS_GRADIENT, 0.0, 1.0, 2, 0.5) > 1e-3, "drag test insensitive");

    /* gating: a particle resting in a floor hole has >= 3 interactions, so a huge dilute drag
     * must not change its trajectory; an isolated one is changed */
    double traj[2][3];
    for (int pass = 0; pass < 2; ++pass) {
        sys_setup st = default_setup();
        st.p.orientation = LUB_RS_VORTICITY; /* floor rides with u: no mean-flow mismatch */
        st.p.gravity = 1.0;
        st.p.eta_dilute = 1e3;
        st.p.dilute_max_interactions = pass == 0 ? 2 : -1;
        double r[2] = {1.0, 1.0};
        vec3 x[2] = {v3(6.0, 2.0 + 1.5, 6.0), v3(9.0, 30.0, 9.0)}; /* gap 0.05 to 4 floor spheres */
        lub_rs_system S;
        CHECK(make_system(&S, &st, 2, r, x, 0.0) == LUB_RS_OK, "init gating");
        S.v[0] = v3_add(S.v[0], v3(0.1, 0.0, 0.05));
        for (int k = 0; k < 300; ++k)
            CHECK(lub_rs_step(&S) == LUB_RS_OK, "gating step");
        CHECK(S.nint[0] >= 3, "resting particle has %d interactions", S.nint[0]);
        CHECK(S.nint[1] == 0, "isolated particle has %d interactions", S.nint[1]);
        traj[pass][0] = S.v[0].x;
        traj[pass][1] = S.v[0].y;
        traj[pass][2] = S.v[1].y;
        lub_rs_free(&S);
    }
    CHECK(traj[0][0] == traj[1][0] && traj[0][1] == traj[1][1],
          "dilute drag acted on a particle with >= 3 interactions");
    CHECK(fabs(traj[0][2] - traj[1][2]) > 1e-6, "dilute drag did not act on a lone particle");
}

/* 7 layers of 7 x 7 spheres (radii 0.85-1.05) above the floor, settling under gravity while
 * sheared, on 1 thread and twice on 2 */
static void test_threads(void)
{
    if (lub_processors_available() < 2 || lub_omp_thread_limit() < 2) {
        printf("threads_1_vs_2=skipped (%d processor(s), OpenMP thread limit %d)\n",
               lub_processors_available(), lub_omp_thread_limit());
        return;
    }
    enum { NL = 7, NB = NL * 49, STEPS = 200 };
    double rb[NB];
    vec3 xb[NB];
    for (int l = 0, q = 0; l < NL; ++l)
        for (int i = 0; i < 7; ++i)
            for (int k = 0; k < 7; ++k, ++q) {
                rb[q] = 0.85 + 0.05 * ((q * 7) % 5);
                xb[q] = v3(1.0 + 2.28 * i + 0.3 * (l % 2), 5.0 + 2.3 * l, 1.0 + 2.28 * k);
            }
    lub_rs_system S[3]; /* 1 thread, 2 threads, 2 threads again */
    const int threads[3] = {1, 2, 2};
    int rc = 0;
    for (int m = 0; m < 3; ++m) {
        sys_setup st = default_setup();
        st.p.gravity = 10.0;
        st.p.eta_dilute = 1.0;
        st.p.dt = 1e-3;
        st.p.threads = threads[m];
        rc |= make_system(&S[m], &st, NB, rb, xb, 0.15);
    }
    CHECK(rc == LUB_RS_OK, "init of the thread systems: rc %d", rc);
    CHECK(S[0].n > 256, "%d bodies: the neighbour search stays serial", S[0].n);
    double diff12 = 0.0, diff22 = 0.0;
    for (int k = 0; k < STEPS && rc == LUB_RS_OK; ++k) {
        for (int m = 0; m < 3 && rc == LUB_RS_OK; ++m)
            if ((rc = lub_rs_step(&S[m])) != LUB_RS_OK)
                fprintf(stderr, "threads %d: %s\n", threads[m], S[m].fail_msg);
        for (int i = 0; i < S[0].n && rc == LUB_RS_OK; ++i) {
            diff12 = fmax(diff12, v3_norm(v3_sub(S[0].x[i], S[1].x[i])));
            diff22 = fmax(diff22, v3_norm(v3_sub(S[1].x[i], S[2].x[i])));
        }
    }
    printf("threads_1_vs_2_max_position_diff=%.3g threads_2_vs_2=%.3g rebuilds=%ld "
           "pairs=%ld team_min=%d,%d\n",
           diff12, diff22, S[1].rebuilds, (long)S[1].pairs.n, S[0].team_min, S[1].team_min);
    CHECK(rc == LUB_RS_OK, "thread runs failed: rc %d", rc);
    CHECK(S[1].team_min == 2 && S[2].team_min == 2, "2-thread systems ran teams of %d, %d",
          S[1].team_min, S[2].team_min);
    CHECK(S[0].team_min == 1, "1-thread system ran a team of %d", S[0].team_min);
    CHECK(S[1].rebuilds >= 2, "%ld neighbour-list rebuilds: the parallel search is untested",
          S[1].rebuilds);
    CHECK(S[1].pairs.n > NB, "%ld pairs: the pair forces are hardly tested", (long)S[1].pairs.n);
    CHECK(diff22 == 0.0, "two 2-thread runs: positions differ by %g", diff22);
    CHECK(diff12 < 1e-10, "1 vs 2 threads: positions differ by %g a", diff12);
    for (int m = 0; m < 3; ++m)
        lub_rs_free(&S[m]);
}

int main(void)
{
    test_slab();
    test_floor();
    test_drag();
    test_threads();
    if (failures) {
        fprintf(stderr, "%d failure(s)\n", failures);
        return 1;
    }
    printf("resuspension_units=ok\n");
    return 0;
}
