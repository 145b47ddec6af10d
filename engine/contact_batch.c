/* contact_batch.c — vector (4- or 8-lane) evaluation of the lubricated contact law (see
 * contact_batch.h).
 *
 * Every line mirrors a line of contact_pair.c / contact_normal.c / contact_shear.c /
 * contact_torque.c for the regular case; branches of the scalar law become lane masks and
 * both sides are computed. Differences from the scalar code, all at round-off level:
 *  - exp/log from simd_math.h instead of libm;
 *  - the normal solve starts from the state's x (u/a as the last step computed it) where the
 *    scalar law recomputes e^delta: one exp fewer per pair, the same value to round-off;
 *  - nu_t for u > a uses ln(2 + x) - delta instead of log1p(2/x) (same value, x <= 8 here);
 *  - reciprocals shared between quantities (1/|d| and 1/a; 1/c1, 1/(1 + q) and 1/|F_s|^2 of
 *    the shear-force rotation) and the branch test of the normal root multiplied through by e;
 *    divisions and square roots that only some lanes need run only when one of the group does;
 *  - the stable damping factor (1 - e^-k)/k uses its Taylor series up to k = 0.35 (truncation
 *    3e-19) and 1 - e^-k above, instead of the 4-term series up to k = 1e-3 and expm1.
 * Compiled for AVX-512 (8 lanes) or AVX2+FMA (4 lanes) when the build machine has them (CMake
 * LUBDEM_SIMD), with floating-point contraction allowed in this file only. */
#include "contact_batch.h"

#include "simd_math.h"

#include <float.h>
#include <math.h>
#include <stddef.h>

typedef struct {
    lub_vd x, y, z;
} vvec3;

static inline vvec3 w_add(vvec3 a, vvec3 b) { return (vvec3){a.x + b.x, a.y + b.y, a.z + b.z}; }
static inline vvec3 w_sub(vvec3 a, vvec3 b) { return (vvec3){a.x - b.x, a.y - b.y, a.z - b.z}; }
static inline vvec3 w_scale(vvec3 a, lub_vd s) { return (vvec3){a.x * s, a.y * s, a.z * s}; }
static inline vvec3 w_axpy(vvec3 a, lub_vd s, vvec3 b)
{
    return (vvec3){a.x + s * b.x, a.y + s * b.y, a.z + s * b.z};
}
static inline lub_vd w_dot(vvec3 a, vvec3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
static inline vvec3 w_cross(vvec3 a, vvec3 b)
{
    return (vvec3){a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
static inline vvec3 w_sel(lub_vi m, vvec3 a, vvec3 b)
{
    return (vvec3){lub_v_sel(m, a.x, b.x), lub_v_sel(m, a.y, b.y), lub_v_sel(m, a.z, b.z)};
}
static inline lub_vi w_isfinite(vvec3 a)
{
    return lub_v_isfinite(a.x) & lub_v_isfinite(a.y) & lub_v_isfinite(a.z);
}
static inline vvec3 w_load(const double *x, const double *y, const double *z, int g)
{
    return (vvec3){lub_v_load(x + g), lub_v_load(y + g), lub_v_load(z + g)};
}

#if LUB_VW == 4
/* lanes of (a, b) picked by index, 0-3 from a and 4-7 from b (one shuffle instruction) */
#if defined(__clang__)
#define LUB_SHUF(a, b, i0, i1, i2, i3) __builtin_shufflevector(a, b, i0, i1, i2, i3)
#else
#define LUB_SHUF(a, b, i0, i1, i2, i3) __builtin_shuffle(a, b, (lub_vi){i0, i1, i2, i3})
#endif
/* 4 x 4 transpose: rows r0..r3 in, columns out (c_k[l] = r_l[k]). Moves data only. */
static inline void transpose4(lub_vd r0, lub_vd r1, lub_vd r2, lub_vd r3, lub_vd *c0, lub_vd *c1,
                              lub_vd *c2, lub_vd *c3)
{
    const lub_vd t0 = LUB_SHUF(r0, r1, 0, 4, 2, 6), t1 = LUB_SHUF(r0, r1, 1, 5, 3, 7);
    const lub_vd t2 = LUB_SHUF(r2, r3, 0, 4, 2, 6), t3 = LUB_SHUF(r2, r3, 1, 5, 3, 7);
    *c0 = LUB_SHUF(t0, t2, 0, 1, 4, 5);
    *c1 = LUB_SHUF(t1, t3, 0, 1, 4, 5);
    *c2 = LUB_SHUF(t0, t2, 2, 3, 6, 7);
    *c3 = LUB_SHUF(t1, t3, 2, 3, 6, 7);
}
/* The pair state as two rows of 4 doubles: (delta, x, fs.x, fs.y) at byte 0 and
 * (fs.z, n_prev.x, n_prev.y, n_prev.z) at byte 32, read or written through the struct's bytes. */
_Static_assert(offsetof(lub_pair_state, delta) == 0 && offsetof(lub_pair_state, x) == 8 &&
                   offsetof(lub_pair_state, fs.x) == 16 && offsetof(lub_pair_state, fs.z) == 32 &&
                   offsetof(lub_pair_state, n_prev.x) == 40 &&
                   offsetof(lub_pair_state, n_prev.z) == 56,
               "lub_pair_state: the rows of transpose4");
static inline lub_vd state_row(const lub_pair_state *s, size_t byte)
{
    lub_vd v;
    memcpy(&v, (const unsigned char *)s + byte, sizeof v);
    return v;
}
static inline void state_row_store(lub_pair_state *s, size_t byte, lub_vd v)
{
    memcpy((unsigned char *)s + byte, &v, sizeof v);
}
#endif

/* The stable damping coefficient of contact_torque.c (lub_stable_damping):
 * D = c (1 - e^-k)/k, k = c dt inv_sum (D = c for k = 0). */
__attribute__((always_inline)) static inline lub_vd stable_damping(lub_vd c, double dt,
                                                                   lub_vd inv_sum)
{
    const lub_vd k = c * dt * inv_sum;
    /* (1 - e^-k)/k = sum_n (-k)^n/(n+1)!, n <= 14: truncation k^15/16! < 3e-19 at k = 0.35 */
    lub_vd ps = lub_v_set1(1.0 / 1307674368000.0); /* 1/15! */
    ps = ps * (-k) + 1.0 / 87178291200.0;
    ps = ps * (-k) + 1.0 / 6227020800.0;
    ps = ps * (-k) + 1.0 / 479001600.0;
    ps = ps * (-k) + 1.0 / 39916800.0;
    ps = ps * (-k) + 1.0 / 3628800.0;
    ps = ps * (-k) + 1.0 / 362880.0;
    ps = ps * (-k) + 1.0 / 40320.0;
    ps = ps * (-k) + 1.0 / 5040.0;
    ps = ps * (-k) + 1.0 / 720.0;
    ps = ps * (-k) + 1.0 / 120.0;
    ps = ps * (-k) + 1.0 / 24.0;
    ps = ps * (-k) + 1.0 / 6.0;
    ps = ps * (-k) + 0.5;
    ps = ps * (-k) + 1.0;
    const lub_vi small = k <= 0.35;
    if (!lub_v_any(~small))
        return c * ps;
    /* large k: (1 - e^-k)/(dt inv_sum), inv_sum > 0 there; the denominator of unused lanes is
     * made 1 so that nothing divides by 0 */
    const lub_vd den = lub_v_sel(small, lub_v_set1(1.0), inv_sum * dt);
    const lub_vd big = (1.0 - lub_v_exp(-lub_v_min(k, lub_v_set1(700.0)))) / den;
    return lub_v_sel(small, c * ps, big);
}

int lub_pair_batch_width(void) { return LUB_VW; }

int lub_pair_batch_accelerated(void)
{
#if defined(__AVX2__) && defined(__FMA__)
    return 1;
#else
    return 0; /* SSE2 pairs: measured slower than the scalar law (README "Batched evaluation") */
#endif
}
void lub_pair_batch_exp(const double *x, double *y) { lub_v_store(y, lub_v_exp(lub_v_load(x))); }
void lub_pair_batch_log(const double *x, double *y) { lub_v_store(y, lub_v_log(lub_v_load(x))); }

const char *lub_pair_batch_isa(void)
{
#if defined(__AVX512F__) && defined(__AVX512DQ__) && defined(__AVX512VL__)
    return "avx512";
#elif defined(__AVX2__) && defined(__FMA__)
    return "avx2+fma";
#elif defined(__AVX__)
    return "avx";
#else
    return "sse2";
#endif
}

int lub_pair_step_batch(const lub_law_params *p, double dt, lub_pair_batch *b)
{
    const int n = b->n;
    const unsigned terms = p->terms;
    const double eta = (p->eta > 0.0) ? p->eta : 0.0;
    if (n <= 0 || !(terms & LUB_TERM_NORMAL_LUB) || !(eta > 0.0) || !(dt > 0.0)) {
        for (int l = 0; l < n; ++l)
            b->done[l] = 0;
        return 0;
    }
    const double e = (p->eps > 0.0) ? p->eps : 0.0;
    const double mu = (p->mu > 0.0) ? p->mu : 0.0;
    const double alpha = (p->alpha >= 0.0) ? p->alpha : 0.0;
    const double g = p->k_bulk, k_t = p->k_t;
    const double kt_dt = k_t * dt;
    const double h_a = dt * g / (1.5 * LUB_PI * eta); /* h = dt g a / nu_n = h_a / a */
    const int shear_lub = (terms & LUB_TERM_SHEAR_LUB) != 0;
    const int with_friction = (terms & LUB_TERM_FRICTION) != 0;
    const int with_roll = (terms & LUB_TERM_ROLL) != 0, with_twist = (terms & LUB_TERM_TWIST) != 0;
    const lub_vd zero = lub_v_set1(0.0), one = lub_v_set1(1.0);
    const lub_vi none = {0};
    const double x_lo = exp(-700.0), x_hi = exp(700.0); /* the delta guard, as gaps u/a */

    /* pad the last group with copies of lane 0 (read only, never stored) */
    const int ng = (n + LUB_VW - 1) / LUB_VW * LUB_VW;
    for (int l = n; l < ng; ++l) {
        b->bx[l] = b->bx[0], b->by[l] = b->by[0], b->bz[l] = b->bz[0];
        b->v1x[l] = b->v1x[0], b->v1y[l] = b->v1y[0], b->v1z[l] = b->v1z[0];
        b->v2x[l] = b->v2x[0], b->v2y[l] = b->v2y[0], b->v2z[l] = b->v2z[0];
        b->w1x[l] = b->w1x[0], b->w1y[l] = b->w1y[0], b->w1z[l] = b->w1z[0];
        b->w2x[l] = b->w2x[0], b->w2y[l] = b->w2y[0], b->w2z[l] = b->w2z[0];
        b->r1[l] = b->r1[0], b->r2[l] = b->r2[0];
        b->inv_i1[l] = b->inv_i1[0], b->inv_i2[l] = b->inv_i2[0];
        b->state[l] = b->state[0];
    }

    int accepted = 0;
    for (int g0 = 0; g0 < ng; g0 += LUB_VW) {
        /* ---- state (from the per-pair structs straight into registers; each state was
         * written a step ago, so its loads do not wait on store forwarding) ---- */
        lub_pair_state *const *st = &b->state[g0];
#if LUB_VW == 4
        /* four lanes: two 32-byte loads per state (delta, x, fs.x, fs.y | fs.z, n_prev) and a
         * 4 x 4 transpose, instead of 28 scalar loads and inserts */
        lub_vd x_prev;
        vvec3 fs_prev, n_prev;
        {
            lub_vd unused_delta;
            transpose4(state_row(st[0], 0), state_row(st[1], 0), state_row(st[2], 0),
                       state_row(st[3], 0), &unused_delta, &x_prev, &fs_prev.x, &fs_prev.y);
            transpose4(state_row(st[0], 32), state_row(st[1], 32), state_row(st[2], 32),
                       state_row(st[3], 32), &fs_prev.z, &n_prev.x, &n_prev.y, &n_prev.z);
        }
#else
#define SX(l) st[l]->x
#define SFX(l) st[l]->fs.x
#define SFY(l) st[l]->fs.y
#define SFZ(l) st[l]->fs.z
#define SNX(l) st[l]->n_prev.x
#define SNY(l) st[l]->n_prev.y
#define SNZ(l) st[l]->n_prev.z
        const lub_vd x_prev = {LUB_LANES(SX)};
        const vvec3 fs_prev = {{LUB_LANES(SFX)}, {LUB_LANES(SFY)}, {LUB_LANES(SFZ)}};
        const vvec3 n_prev = {{LUB_LANES(SNX)}, {LUB_LANES(SNY)}, {LUB_LANES(SNZ)}};
#undef SX
#undef SFX
#undef SFY
#undef SFZ
#undef SNX
#undef SNY
#undef SNZ
#endif
        /* the stored gap within the guard, e^-700 <= x <= e^700 (delta in [-700, 700]); a new
         * pair has x < 0 and is declined here too */
        lub_vi ok = (x_prev >= x_lo) & (x_prev <= x_hi);

        /* ---- geometry (contact_pair.c) ---- */
        const vvec3 br = w_load(b->bx, b->by, b->bz, g0);
        const vvec3 v1 = w_load(b->v1x, b->v1y, b->v1z, g0);
        const vvec3 v2 = w_load(b->v2x, b->v2y, b->v2z, g0);
        const vvec3 w1 = w_load(b->w1x, b->w1y, b->w1z, g0);
        const vvec3 w2 = w_load(b->w2x, b->w2y, b->w2z, g0);
        const lub_vd r1 = lub_v_load(b->r1 + g0), r2 = lub_v_load(b->r2 + g0);
        const lub_vd ii1 = lub_v_load(b->inv_i1 + g0), ii2 = lub_v_load(b->inv_i2 + g0);
        const lub_vd dist = lub_v_sqrt(w_dot(br, br));
        ok &= (dist > 0.0) & lub_v_isfinite(dist);
        const lub_vd dist_safe = lub_v_sel(ok, dist, one);
        const lub_vd un = dist - r1 - r2;
        const lub_vd a = 0.5 * (r1 + r2);
        /* 1/dist and 1/a from one division (a division costs as much as ~10 multiplies) */
        const lub_vd inv_da = 1.0 / (dist_safe * a);
        const lub_vd inv_dist = a * inv_da, inv_a = dist_safe * inv_da;
        const vvec3 nrm = w_scale(br, inv_dist);
        const lub_vd s = un * inv_a;
        const lub_vd h = h_a * inv_a;

        /* ---- normal part (contact_normal.c, closed form) ---- */
        /* x_prev = e^delta as the law left it: no exp here (one of the three transcendental
         * functions per pair); delta itself is not read */
        const lub_vd xp = lub_v_sel(ok, x_prev, one);
        lub_vi c = none;
        if (e > 0.0)
            c = ((h * (s - e) - 1.0) * e + xp) < 0.0; /* h (s - e) - 1 + xp/e < 0, times e */
        const lub_vd ac = lub_v_sel(c, lub_v_set1(alpha), zero);
        const lub_vd A = 1.0 + ac;
        const lub_vd bq = 1.0 - h * (s + ac * e);
        const lub_vd q = 4.0 * A * h * xp;
        ok &= lub_v_isfinite(bq) & lub_v_isfinite(q) & ((lub_v_abs(bq) >= 1e-140) | (q >= 1e-290));
        const lub_vd sq = lub_v_sqrt(bq * bq + q);
        const lub_vi bpos = bq > 0.0;
        /* the root in its cancellation-free form: 2 xp/(bq + sq) for bq > 0, (sq - bq)/(2 A h)
         * otherwise (one division for both) */
        lub_vd x = lub_v_sel(bpos, 2.0 * xp, sq - bq) / lub_v_sel(bpos, bq + sq, 2.0 * A * h);
        ok &= (x >= DBL_MIN) & (x <= 1e304); /* normal, and ln x <= 700 (the guard) */
        x = lub_v_sel(ok, x, one);
        const lub_vd delta = lub_v_log(x);
        const lub_vi contact = (e > 0.0) ? (x < e) : none;

        const lub_vd ga = g * a;
        const lub_vd fn = ga * (s - x);
        const lub_vd fn_c = lub_v_sel(contact, -(alpha * ga * (e - x)), zero);

        /* ---- tangential part (contact_shear.c) ---- */
        /* rotation of the stored shear force: tilt n_prev -> n, then twist about n */
        const lub_vd m0 = w_dot(fs_prev, fs_prev);
        const vvec3 wt = w_cross(n_prev, nrm);
        const lub_vd c1 = 1.0 + w_dot(n_prev, nrm);
        const lub_vd tau = 0.5 * dt * w_dot(w_add(w1, w2), nrm);
        const lub_vd qt = 0.25 * tau * tau;
        const lub_vi m0_zero = m0 == 0.0;
        ok &= (c1 > 1e-12) | m0_zero;
        /* 1/c1, 1/(1 + qt) and 1/m0 from one division of their product; the ranges asked
         * here keep the product a normal double (other lanes go to the scalar law) */
        ok &= m0_zero | ((m0 >= 1e-200) & (m0 <= 1e200));
        ok &= qt <= 1e50;
        const lub_vd c1s = lub_v_sel(ok, c1, one), qt1 = lub_v_sel(ok, 1.0 + qt, one);
        const lub_vd m0s = lub_v_sel(ok & ~m0_zero, m0, one);
        const lub_vd inv3 = 1.0 / (c1s * qt1 * m0s);
        const lub_vd inv_c1 = qt1 * m0s * inv3, inv_qt1 = c1s * m0s * inv3,
                     inv_m0 = c1s * qt1 * inv3;
        const vvec3 wf = w_cross(wt, fs_prev);
        vvec3 f = w_add(fs_prev, w_axpy(wf, inv_c1, w_cross(wt, wf)));
        f = w_scale(w_axpy(w_scale(f, 1.0 - qt), tau, w_cross(nrm, f)), inv_qt1);
        f = w_axpy(f, -w_dot(f, nrm), nrm);
        const lub_vd m1 = w_dot(f, f);
        const lub_vd ratio = m1 * inv_m0;
        const lub_vi near_one = lub_v_abs(ratio - 1.0) < 1e-8;
        /* the magnitude is restored to first order where the rotation kept it to 1e-8 (nearly
         * always); the square root and its division only when a lane needs them */
        lub_vd fscale = 1.5 - 0.5 * ratio;
        const lub_vi exact_scale = ~near_one & (m1 > 0.0) & ~m0_zero;
        if (lub_v_any(exact_scale))
            fscale = lub_v_sel(exact_scale, 1.0 / lub_v_sqrt(lub_v_sel(exact_scale, ratio, one)),
                               fscale);
        vvec3 fr = w_scale(f, fscale);
        fr = w_sel(m1 > 0.0, fr, (vvec3){zero, zero, zero});
        fr = w_sel(m0_zero, fs_prev, fr);
        /* increment of the tangential displacement */
        const lub_vd alpha_r = (r1 + r2) * inv_dist; /* (r1 + r2)/(r1 + r2 + u_n) */
        vvec3 du = w_scale(w_sub(v2, v1), alpha_r);
        du = w_sub(du, w_cross(w_axpy(w_scale(w1, r1), r2, w2), nrm));
        du = w_axpy(du, -w_dot(du, nrm), nrm);
        du = w_scale(du, lub_v_set1(dt));
        const vvec3 f_trial = w_axpy(fr, lub_v_set1(k_t), du);
        /* nu_t (lub_shear_viscosity_x) */
        lub_vd nu_t = zero;
        const lub_vi dneg = delta < 0.0;
        if (shear_lub) {
            const lub_vi small = x < 1e-3;
            ok &= dneg | (x <= 8.0);
            /* ln((2 + x)/x) = ln(2 + x) - delta: no division (the scalar law's log1p(2/x) for
             * u > a, ln(2 + x) - delta below) */
            const lub_vd l2x = 0.69314718055994530942 + x * (0.5 - x * (0.125 - x * (1.0 / 24.0)));
            const lub_vd L = lub_v_log(2.0 + x);
            const lub_vd lg = lub_v_sel(small, l2x, L) - delta;
            nu_t = 0.5 * LUB_PI * eta * a * ((2.0 + x) * lg - 2.0);
        }
        /* Maxwell element / stick / slip (lub_shear_update), in one form:
         * fs = f_sl + (f_trial - f_sl) nu_t/den, f_sl = 0 (no friction), f_trial (stick),
         * f_trial lim/|f_trial| (slip) */
        const lub_vi friction = with_friction ? contact : none;
        const lub_vd lim = mu * lub_v_abs(fn_c);
        const lub_vd den = nu_t + kt_dt;
        const lub_vd visc = lub_v_sel(den > 0.0, nu_t / lub_v_sel(den > 0.0, den, one), zero);
        const lub_vd ft2 = w_dot(f_trial, f_trial);
        const lub_vi slip = friction & (ft2 > lim * lim);
        lub_vd csl = lub_v_sel(friction, one, zero);
        if (lub_v_any(slip))
            csl = lub_v_sel(slip, lim / lub_v_sqrt(lub_v_sel(slip, ft2, one)), csl);
        const vvec3 f_sl = w_scale(f_trial, csl);
        const vvec3 fs = w_add(f_sl, w_scale(w_sub(f_trial, f_sl), visc));

        /* ---- roll / twist torques (contact_torque.c), u < a only ---- */
        vvec3 t_lub = {zero, zero, zero};
        if ((with_roll || with_twist) && lub_v_any(dneg)) {
            const lub_vd base = LUB_PI * eta * a * a * a * (-delta);
            const lub_vd inv_sum = ii1 + ii2;
            const vvec3 om = w_sub(w2, w1);
            const lub_vd wn = w_dot(om, nrm);
            if (with_roll) {
                const vvec3 om_r = w_axpy(om, -wn, nrm);
                const lub_vd cr = base * (1.5 + 0.126 * x);
                t_lub = w_add(t_lub, w_scale(om_r, stable_damping(cr, dt, inv_sum)));
            }
            if (with_twist) {
                const lub_vd ct = base * x;
                t_lub = w_add(t_lub, w_scale(nrm, wn * stable_damping(ct, dt, inv_sum)));
            }
            t_lub = w_sel(dneg, t_lub, (vvec3){zero, zero, zero});
        }

        /* ---- assemble ---- */
        const vvec3 nxf = w_cross(nrm, fs);
        const vvec3 force1 = w_axpy(fs, fn, nrm);
        const vvec3 torque1 = w_add(w_scale(nxf, r1 + 0.5 * un), t_lub);
        const vvec3 torque2 = w_sub(w_scale(nxf, r2 + 0.5 * un), t_lub);
        ok &= w_isfinite(force1) & w_isfinite(torque1) & w_isfinite(torque2) &
              lub_v_isfinite(delta) & w_isfinite(fs);

        /* ---- store: forces and torques of the whole group straight into the output arrays
         * (ng <= LUB_BATCH; lanes that are padding or declined hold values nobody reads), the
         * per-pair state of the accepted lanes one by one ---- */
        lub_v_store(b->f1x + g0, force1.x), lub_v_store(b->f1y + g0, force1.y);
        lub_v_store(b->f1z + g0, force1.z);
        lub_v_store(b->t1x + g0, torque1.x), lub_v_store(b->t1y + g0, torque1.y);
        lub_v_store(b->t1z + g0, torque1.z);
        lub_v_store(b->t2x + g0, torque2.x), lub_v_store(b->t2y + g0, torque2.y);
        lub_v_store(b->t2z + g0, torque2.z);
        int64_t okl[LUB_VW], cl[LUB_VW];
        memcpy(okl, &ok, sizeof okl);
        memcpy(cl, &contact, sizeof cl);
#if LUB_VW == 4
        /* the states as rows (delta, x, fs.x, fs.y | fs.z, n): two 32-byte stores per lane */
        lub_vd ra[4], rb[4];
        transpose4(delta, x, fs.x, fs.y, &ra[0], &ra[1], &ra[2], &ra[3]);
        transpose4(fs.z, nrm.x, nrm.y, nrm.z, &rb[0], &rb[1], &rb[2], &rb[3]);
#else
        double o[7][LUB_VW];
        lub_v_store(o[0], fs.x), lub_v_store(o[1], fs.y), lub_v_store(o[2], fs.z);
        lub_v_store(o[3], nrm.x), lub_v_store(o[4], nrm.y), lub_v_store(o[5], nrm.z);
        lub_v_store(o[6], x);
#endif
        double dl[LUB_VW];
        lub_v_store(dl, delta);
        for (int l = 0; l < LUB_VW && g0 + l < n; ++l) {
            const int q = g0 + l;
            if (!okl[l]) {
                b->done[q] = 0;
                continue;
            }
            b->contact[q] = cl[l] != 0;
            b->near[q] = dl[l] < 0.0;
            b->done[q] = 1;
            lub_pair_state *out_state = b->state[q];
#if LUB_VW == 4
            state_row_store(out_state, 0, ra[l]);
            state_row_store(out_state, 32, rb[l]);
#else
            out_state->delta = dl[l];
            out_state->x = o[6][l];
            out_state->fs = v3(o[0][l], o[1][l], o[2][l]);
            out_state->n_prev = v3(o[3][l], o[4][l], o[5][l]);
#endif
            accepted++;
        }
    }
    return accepted;
}
