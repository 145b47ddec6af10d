/* step_stiffness.c — incremental pair stiffnesses and the Gershgorin bound of the explicit
 * step (step_stiffness.h). */
#include "step_stiffness.h"

#include <math.h>

void lub_pair_step_stiffness(const lub_law_params *p, double a, double delta, double dt,
                             double *k_normal, double *k_tangential)
{
    const double g = p->k_bulk;
    const double eta = p->eta > 0.0 ? p->eta : 0.0;
    const double e = p->eps > 0.0 ? p->eps : 0.0;
    const double x = exp(delta); /* 0 for a deeply compressed film: k_n -> g */
    const int normal_lub = (p->terms & LUB_TERM_NORMAL_LUB) && eta > 0.0;
    /* without normal lubrication a pair held at the static floor is in the hard core: the law
     * reports the whole g a (s - x) as a contact force (smooth spheres too) */
    const int hard_core = !normal_lub && delta <= LUB_DELTA_STATIC_FLOOR;
    const int contact = x < e || hard_core;
    const double alpha_c = contact ? p->alpha : 0.0;
    if (normal_lub) {
        const double hx = dt * g / (1.5 * LUB_PI * eta * a) * x;
        *k_normal = g * (1.0 + alpha_c * hx) / (1.0 + (1.0 + alpha_c) * hx);
    } else if (hard_core) {
        *k_normal = g; /* until 2026-12-07 g alpha/(1 + alpha) here, and 0 for eps = 0 */
    } else {
        *k_normal = g * alpha_c / (1.0 + alpha_c); /* quasi-static: springs in series */
    }
    const double kt = p->k_t > 0.0 ? p->k_t : 0.0;
    if ((p->terms & LUB_TERM_FRICTION) && contact) {
        *k_tangential = kt;
    } else if ((p->terms & LUB_TERM_SHEAR_LUB) && eta > 0.0 && kt > 0.0) {
        const double nu_t = lub_shear_viscosity(eta, a, delta);
        *k_tangential = kt * nu_t / (nu_t + kt * dt);
    } else {
        *k_tangential = 0.0;
    }
}

void lub_step_rows_add(double *trans, double *rot, int i, int j, const double *r,
                       const double *inv_m, const double *inv_i, double kn, double ks)
{
    const double ri = r[i], rj = r[j];
    const double mi = inv_m[i], mj = inv_m[j], ii = inv_i[i], ij = inv_i[j];
    const double mm = sqrt(mi * mj), im_i = sqrt(ii * mi), im_j = sqrt(ij * mj);
    const double k = kn + ks;
    /* translation rows */
    trans[i] += k * (mi + mm) + ks * (ri * im_i + rj * sqrt(mi * ij));
    trans[j] += k * (mj + mm) + ks * (rj * im_j + ri * sqrt(mj * ii));
    /* rotation rows */
    const double ii_jj = sqrt(ii * ij);
    rot[i] += ks * (ri * ri * ii + ri * rj * ii_jj + ri * im_i + ri * sqrt(ii * mj));
    rot[j] += ks * (rj * rj * ij + ri * rj * ii_jj + rj * im_j + rj * sqrt(ij * mi));
}

double lub_step_rows_max(const double *trans, const double *rot, int n, int *body)
{
    double best = 0.0;
    int at = -1;
    for (int p = 0; p < n; ++p) {
        const double v = trans[p] > rot[p] ? trans[p] : rot[p];
        if (v > best) {
            best = v;
            at = p;
        }
    }
    if (body)
        *body = at;
    return best;
}

double lub_pairs_stiffness_dt(const lub_pairs *ps, const lub_law_params *law, const double *r,
                              const double *inv_m, const double *inv_i, int n, double dt,
                              double *rows, int *body)
{
    double *trans = rows, *rot = rows + n;
    for (int p = 0; p < n; ++p)
        trans[p] = rot[p] = 0.0;
    for (size_t k = 0; k < ps->n; ++k) {
        if (!ps->active[k] || !ps->allow[k] || lub_pair_state_is_new(&ps->state[k]))
            continue;
        const int i = ps->i[k], j = ps->j[k];
        double kn, ks;
        lub_pair_step_stiffness(law, 0.5 * (r[i] + r[j]), ps->state[k].delta, dt, &kn, &ks);
        lub_step_rows_add(trans, rot, i, j, r, inv_m, inv_i, kn, ks);
    }
    const double w2 = lub_step_rows_max(trans, rot, n, body);
    return w2 > 0.0 ? 2.0 / sqrt(w2) : INFINITY;
}

double lub_pairs_stable_dt(const lub_pairs *ps, const lub_law_params *law, const double *r,
                           const double *inv_m, const double *inv_i, int n, double dt_max,
                           double safety, double *rows)
{
    /* dt / bound(dt) grows with dt (the films soften as dt grows, but slower than dt), so
     * dt_{k+1} = safety * bound(dt_k) decreases to the largest admissible step */
    double dt = dt_max;
    for (int it = 0; it < 50; ++it) {
        const double next =
            safety * lub_pairs_stiffness_dt(ps, law, r, inv_m, inv_i, n, dt, rows, NULL);
        if (next >= dt)
            return dt;
        if (next >= 0.99 * dt)
            return next;
        dt = next;
    }
    return dt;
}

void lub_step_control_init(lub_step_control *c, double dt_base, double safety)
{
    *c = (lub_step_control){.dt = dt_base, .dt_base = dt_base, .safety = safety, .dt_min = dt_base};
}

int lub_step_control_at_rebuild(lub_step_control *c, long rebuilds, const lub_pairs *ps,
                                const lub_law_params *law, const double *r, const double *inv_m,
                                const double *inv_i, int n, double *rows)
{
    if (rebuilds == c->rebuilds)
        return 0;
    c->rebuilds = rebuilds;
    double ratio;
    const double next = lub_pairs_adapted_dt(ps, law, r, inv_m, inv_i, n, c->dt, c->dt_base,
                                             c->safety, rows, &ratio);
    c->ratio_max = fmax(c->ratio_max, ratio);
    if (next == c->dt)
        return 0;
    c->dt = next;
    c->dt_min = fmin(c->dt_min, next);
    c->changes++;
    return 1;
}

double lub_pairs_adapted_dt(const lub_pairs *ps, const lub_law_params *law, const double *r,
                            const double *inv_m, const double *inv_i, int n, double dt,
                            double dt_base, double safety, double *rows, double *ratio)
{
    const double now = dt / lub_pairs_stiffness_dt(ps, law, r, inv_m, inv_i, n, dt, rows, NULL);
    double next = dt;
    if (safety > 0.0 && now > safety) {
        next = 0.9 * lub_pairs_stable_dt(ps, law, r, inv_m, inv_i, n, dt, safety, rows);
    } else if (safety > 0.0 && dt < dt_base && now < safety / 1.25) {
        /* dt / bound(dt) grows at most linearly in dt, so 1.25 dt is admissible */
        const double up = lub_pairs_stable_dt(ps, law, r, inv_m, inv_i, n, dt_base, safety, rows);
        next = up >= dt_base ? dt_base : fmax(dt, 0.9 * up);
    }
    if (ratio)
        *ratio = next == dt
                     ? now
                     : next / lub_pairs_stiffness_dt(ps, law, r, inv_m, inv_i, n, next, rows, NULL);
    return next;
}
