/* law_sim.c — see law_sim.h. */
#include "law_sim.h"

#include <math.h>
#include <string.h>

void law_sim_prepare(law_sim *s)
{
    memset(s->exists, 0, sizeof s->exists);
    s->steps = 0;
    s->work_ext = 0.0;
    s->work_abs = 0.0;
    s->bad = 0;
    s->min_delta = INFINITY;
    s->max_delta = -INFINITY;
    s->contact_steps = s->slip_steps = s->enter_events = s->leave_events = 0;
    s->create_events = s->erase_events = s->skip_band_events = 0;
    if (s->create <= 0.0)
        s->create = 2.0;
    if (s->cutoff <= 0.0)
        s->cutoff = 2.0;
}

int law_sim_step(law_sim *s)
{
    vec3 F[LAW_SIM_MAX], T[LAW_SIM_MAX];
    int npairs[LAW_SIM_MAX];
    const int n = s->n;
    /* pair list update (creation / erasure at the cut-off) */
    for (int i = 0; i < n; ++i)
        npairs[i] = 0;
    for (int i = 0; i < n; ++i)
        for (int j = i + 1; j < n; ++j) {
            const double a = 0.5 * (s->r[i] + s->r[j]);
            const double un = v3_norm(v3_sub(s->x[j], s->x[i])) - s->r[i] - s->r[j];
            if (s->exists[i][j] && un > s->cutoff * a) {
                s->exists[i][j] = 0;
                ++s->erase_events;
            } else if (!s->exists[i][j] && un < s->create * a) {
                s->exists[i][j] = 1;
                lub_pair_state_reset(&s->st[i][j]);
                ++s->create_events;
            }
            if (s->exists[i][j]) {
                ++npairs[i];
                ++npairs[j];
            }
        }
    for (int i = 0; i < n; ++i) {
        F[i] = s->fext[i];
        T[i] = v3(0, 0, 0);
    }
    int rc = 0;
    for (int i = 0; i < n; ++i)
        for (int j = i + 1; j < n; ++j) {
            if (!s->exists[i][j])
                continue;
            const double shi = s->share_torque_budget ? npairs[i] : 1.0;
            const double shj = s->share_torque_budget ? npairs[j] : 1.0;
            lub_pair_input in = {.branch = v3_sub(s->x[j], s->x[i]),
                                 .v1 = s->v[i],
                                 .v2 = s->v[j],
                                 .w1 = s->w[i],
                                 .w2 = s->w[j],
                                 .r1 = s->r[i],
                                 .r2 = s->r[j],
                                 .inv_inertia1 = s->fixed[i] ? 0.0 : shi / s->I[i],
                                 .inv_inertia2 = s->fixed[j] ? 0.0 : shj / s->I[j],
                                 .dt = s->dt};
            const double e = s->p.eps;
            const int was_new = lub_pair_state_is_new(&s->st[i][j]);
            const double x_prev = exp(s->st[i][j].delta);
            const int was_contact = !was_new && s->out[i][j].contact;
            lub_pair_output *o = &s->out[i][j];
            if (lub_pair_step(&s->p, &in, &s->st[i][j], o) != 0) {
                rc = 1;
                s->bad = 1;
            }
            if (o->delta < s->min_delta)
                s->min_delta = o->delta;
            if (o->delta > s->max_delta)
                s->max_delta = o->delta;
            s->contact_steps += o->contact;
            s->slip_steps += o->slip;
            if (!was_new) {
                s->enter_events += (!was_contact && o->contact);
                s->leave_events += (was_contact && !o->contact);
                const double x = o->gap / (0.5 * (s->r[i] + s->r[j]));
                if (e > 0.0 && ((x_prev >= e && x < 0.5 * e) || (x_prev < 0.5 * e && x >= e)))
                    ++s->skip_band_events;
            }
            F[i] = v3_add(F[i], o->force1);
            F[j] = v3_sub(F[j], o->force1);
            T[i] = v3_add(T[i], o->torque1);
            T[j] = v3_add(T[j], o->torque2);
        }
    for (int i = 0; i < n; ++i) {
        s->v_old[i] = s->v[i];
        s->w_old[i] = s->w[i];
        if (s->fixed[i])
            continue;
        s->v[i] = v3_axpy(s->v[i], s->dt / s->m[i], F[i]);
        s->w[i] = v3_axpy(s->w[i], s->dt / s->I[i], T[i]);
        const double dw = s->dt * v3_dot(s->fext[i], s->v[i]);
        s->work_ext += dw;
        s->work_abs += fabs(dw);
        s->x[i] = v3_axpy(s->x[i], s->dt, s->v[i]);
    }
    ++s->steps;
    return rc;
}

double law_sim_kinetic(const law_sim *s)
{
    double k = 0.0;
    for (int i = 0; i < s->n; ++i)
        if (!s->fixed[i])
            k += 0.5 * s->m[i] * v3_norm2(s->v[i]) + 0.5 * s->I[i] * v3_norm2(s->w[i]);
    return k;
}

double law_sim_kinetic_mid(const law_sim *s)
{
    double k = 0.0;
    for (int i = 0; i < s->n; ++i)
        if (!s->fixed[i]) {
            const vec3 v = v3_scale(v3_add(s->v[i], s->v_old[i]), 0.5);
            const vec3 w = v3_scale(v3_add(s->w[i], s->w_old[i]), 0.5);
            k += 0.5 * s->m[i] * v3_norm2(v) + 0.5 * s->I[i] * v3_norm2(w);
        }
    return k;
}

double law_sim_elastic(const law_sim *s)
{
    double E = 0.0;
    const double g = s->p.k_bulk, kn = s->p.alpha * g, kt = s->p.k_t;
    for (int i = 0; i < s->n; ++i)
        for (int j = i + 1; j < s->n; ++j) {
            if (!s->exists[i][j] || lub_pair_state_is_new(&s->st[i][j]))
                continue;
            const lub_pair_output *o = &s->out[i][j];
            const double a = 0.5 * (s->r[i] + s->r[j]);
            const double fn = v3_dot(o->force1, o->n);
            E += 0.5 * fn * fn / g;
            if (o->contact && kn > 0.0) {
                /* asperity spring: deflection e a - u, saturated at e a (hard-core regime) */
                const double def = fmax(0.0, s->p.eps * a - o->gap);
                E += 0.5 * kn * def * def;
            }
            if (kt > 0.0) {
                const vec3 fs = v3_axpy(o->force1, -fn, o->n);
                E += 0.5 * v3_norm2(fs) / kt;
            }
        }
    return E;
}
