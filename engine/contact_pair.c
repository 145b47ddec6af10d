/* contact_pair.c — one step of the full lubricated contact law for one pair (notes §12):
 * geometry, normal backward-Euler solve, tangential update, roll/twist torques, torque arms.
 * The building blocks live in contact_normal.c, contact_shear.c and contact_torque.c. */
#include "contact_law.h"
#include "contact_normal.h"
#include "contact_shear.h"
#include "contact_torque.h"

#include <math.h>
#include <string.h>

int lub_pair_step(const lub_law_params *p, const lub_pair_input *in, lub_pair_state *state,
                  lub_pair_output *out)
{
    const unsigned terms = p->terms;
    const double dist = v3_norm(in->branch);
    if (!(dist > 0.0) || !isfinite(dist)) {
        memset(out, 0, sizeof *out);
        return 2; /* coincident or non-finite centres: the normal is undefined */
    }
    /* ---- geometry (notes §1) ---- */
    const vec3 n = v3_scale(in->branch, 1.0 / dist);
    const double r1 = in->r1, r2 = in->r2, dt = in->dt;
    const double un = dist - r1 - r2;
    const double a = 0.5 * (r1 + r2);
    const double s = un / a;
    const double g = p->k_bulk;
    const double alpha = p->alpha;
    const double eta = (p->eta > 0.0) ? p->eta : 0.0;
    const double e = (p->eps > 0.0) ? p->eps : 0.0;
    const double mu = (p->mu > 0.0) ? p->mu : 0.0; /* notes §11 P6: mu < 0 -> 0 */

    /* h = dt g a / nu_n, nu_n = 3/2 pi eta a^2 (notes §2.2); +inf without normal lubrication. */
    const int normal_lub = (terms & LUB_TERM_NORMAL_LUB) && eta > 0.0;
    const double h = normal_lub ? dt * g / (1.5 * LUB_PI * eta * a) : INFINITY;

    /* ---- new pair (notes §2.10, §11 P3) ---- */
    if (lub_pair_state_is_new(state)) {
        if (s > 0.0) {
            state->delta = log(s); /* >= -745 even for a subnormal s: no floor needed */
        } else {
            /* created overlapping: start at the static (quasi-static) solution, or at its
             * fixed floor LUB_DELTA_STATIC_FLOOR when there is none; with lubrication the
             * step below then lets the gap decay from there without any floor */
            int c0;
            state->delta = lub_normal_solve(0.0, s, INFINITY, e, alpha, &c0);
        }
        state->fs = v3(0.0, 0.0, 0.0);
        state->n_prev = n;
    }

    /* ---- normal part (notes §2.6, §2.9) ----
     * delta is never floored (notes §11 P5): x = e^delta may be subnormal or 0 in a
     * compressed contact. x is used only where x -> 0 is harmless (F_n, F_c, R+, gap); nu_t
     * and the torques take delta. */
    int contact = 0;
    double x;
    const double delta = lub_normal_solve_ex(state->delta, s, h, e, alpha, &contact, &x);
    const double ga = g * a;
    const double fn = ga * (s - x); /* total normal force on 1 along n (< 0: repulsion) */
    double fn_c, fn_l;
    if (!normal_lub) {
        /* quasi-static: F_n is carried by the contact alone (0 out of contact since x = s) */
        fn_c = contact ? fn : 0.0;
        fn_l = 0.0;
    } else if (contact) {
        /* R+ = (s - x) + alpha (e - x): the same product alpha g a (e - x) appears in F_c and
         * F_l, so F_c + F_l = F_n to round-off even when both are large and opposite. */
        const double p_asp = alpha * ga * (e - x); /* > 0: contact means x < e */
        fn_c = -p_asp;
        fn_l = ga * (s - x) + p_asp; /* g a R+ (notes §2.9), not F_n - F_c of separate solves */
    } else {
        fn_c = 0.0;
        fn_l = fn; /* = g a R+ exactly: R+ = s - x */
    }

    /* ---- tangential part (notes §3) ---- */
    const vec3 fr = lub_shear_rotate(state->fs, state->n_prev, n, in->w1, in->w2, dt);
    const vec3 dus = lub_shear_increment(in->v1, in->v2, in->w1, in->w2, r1, r2, un, n, dt);
    const double kt_dt = p->k_t * dt;
    const vec3 f_trial = v3_axpy(fr, p->k_t, dus);
    const double nu_t =
        ((terms & LUB_TERM_SHEAR_LUB) && eta > 0.0) ? lub_shear_viscosity_x(eta, a, delta, x) : 0.0;
    const int friction = (terms & LUB_TERM_FRICTION) && contact;
    lub_shear_result sh;
    lub_shear_update(f_trial, nu_t, kt_dt, friction, mu * fabs(fn_c), &sh);

    /* ---- roll / twist lubrication torques (notes §4), u < a only ---- */
    vec3 t_roll, t_twist;
    lub_spin_torques(eta, a, delta, x, n, v3_sub(in->w2, in->w1), in->inv_inertia1,
                     in->inv_inertia2, dt, (terms & LUB_TERM_ROLL) != 0,
                     (terms & LUB_TERM_TWIST) != 0, &t_roll, &t_twist);

    /* ---- assemble (notes §4.6-4.7) ---- */
    const vec3 nxf = v3_cross(n, sh.fs);
    const vec3 t_lub = v3_add(t_roll, t_twist);
    out->force1 = v3_axpy(sh.fs, fn, n);
    out->torque1 = v3_add(v3_scale(nxf, r1 + 0.5 * un), t_lub);
    out->torque2 = v3_sub(v3_scale(nxf, r2 + 0.5 * un), t_lub);
    out->n = n;
    out->un = un;
    out->gap = a * x;
    out->delta = delta;
    out->fn_contact = fn_c;
    out->fn_lub = fn_l;
    out->fs_contact = sh.fs_contact;
    out->fs_lub = sh.fs_lub;
    out->torque_roll1 = t_roll;
    out->torque_twist1 = t_twist;
    out->contact = contact;
    out->slip = sh.slip;

    state->delta = delta;
    state->fs = sh.fs;
    state->n_prev = n;
    state->x = x;

    const int finite = v3_isfinite(out->force1) && v3_isfinite(out->torque1) &&
                       v3_isfinite(out->torque2) && isfinite(delta) && isfinite(fn_c) &&
                       isfinite(fn_l) && isfinite(out->gap);
    return finite ? 0 : 1;
}

void lub_pair_state_set_gap(lub_pair_state *s, double delta)
{
    s->delta = delta;
    s->x = exp(delta);
}

int lub_terms_names(unsigned terms, const char **names, int max)
{
    static const struct {
        unsigned bit;
        const char *name;
    } table[] = {{LUB_TERM_NORMAL_LUB, "normal_lubrication"},
                 {LUB_TERM_SHEAR_LUB, "shear_lubrication"},
                 {LUB_TERM_ROLL, "roll_lubrication"},
                 {LUB_TERM_TWIST, "twist_lubrication"},
                 {LUB_TERM_FRICTION, "friction"}};
    int k = 0;
    for (unsigned i = 0; i < sizeof table / sizeof table[0]; ++i)
        if ((terms & table[i].bit) && k < max && names)
            names[k++] = table[i].name;
    return k;
}
