/* few_body.c — leap-frog for a few lubricated spheres with exact Stokes drag (few_body.h). */
#include "few_body.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

#include "velocity_gradient.h"

vec3 lub_fb_flow_velocity(const lub_fb_env *e, vec3 x) { return lub_mat_vec(e->L, x); }

vec3 lub_fb_flow_spin(const lub_fb_env *e) { return lub_flow_spin(e->L); }

double lub_fb_critical_dt(const lub_fb_system *s)
{
    double w2max = 0.0;
    for (int k = 0; k < s->np; ++k) {
        const lub_fb_body *bi = &s->b[s->p[k].i], *bj = &s->b[s->p[k].j];
        double im = bi->inv_m + bj->inv_m;
        if (im <= 0.0)
            continue;
        double w2 = s->law.k_bulk * im;
        if (s->law.k_t > 0.0) {
            double it = im;
            if (s->env.rotation)
                it += bi->r * bi->r * bi->inv_I + bj->r * bj->r * bj->inv_I;
            double wt = s->law.k_t * it;
            if (wt > w2)
                w2 = wt;
        }
        if (w2 > w2max)
            w2max = w2;
    }
    return w2max > 0.0 ? 2.0 / sqrt(w2max) : INFINITY;
}

/* e^{-k} and phi = (1 - e^{-k})/k without cancellation (k >= 0). */
static void decay_factors(double k, double *ek, double *phi)
{
    if (k < 1e-8) {
        *phi = 1.0 - 0.5 * k;
        *ek = 1.0 - k * (*phi);
    } else {
        *ek = exp(-k);
        *phi = -expm1(-k) / k;
    }
}

/* v+ = target + (v - target) e^{-k} + impulse * phi,  k = zeta dt * inv_mass */
static vec3 drag_update(vec3 v, vec3 target, vec3 impulse, double zeta, double dt, double inv_mass)
{
    if (zeta <= 0.0)
        return v3_add(v, impulse);
    double ek, phi;
    decay_factors(zeta * dt * inv_mass, &ek, &phi);
    return v3_add(v3_add(target, v3_scale(v3_sub(v, target), ek)), v3_scale(impulse, phi));
}

int lub_fb_step(lub_fb_system *s, double dt, char *diag, size_t diag_size)
{
    for (int k = 0; k < s->nb; ++k) {
        s->b[k].f = v3(0, 0, 0);
        s->b[k].t = v3(0, 0, 0);
    }
    for (int k = 0; k < s->np; ++k) {
        lub_fb_pair *p = &s->p[k];
        lub_fb_body *b1 = &s->b[p->i], *b2 = &s->b[p->j];
        vec3 d = v3_sub(b2->x, b1->x);
        double a = 0.5 * (b1->r + b2->r);
        double un = v3_norm(d) - b1->r - b2->r;
        if (!(un <= p->cutoff * a)) {
            p->active = 0;
            continue;
        }
        if (!p->active) {
            p->active = 1;
            lub_pair_state_reset(&p->state);
        }
        lub_pair_input in = {
            .branch = d,
            .v1 = b1->v,
            .v2 = b2->v,
            .w1 = b1->w,
            .w2 = b2->w,
            .r1 = b1->r,
            .r2 = b2->r,
            .inv_inertia1 = s->env.rotation ? b1->inv_I : 0.0,
            .inv_inertia2 = s->env.rotation ? b2->inv_I : 0.0,
            .dt = dt,
        };
        int rc = lub_pair_step(&s->law, &in, &p->state, &p->out);
        if (rc != 0 || !v3_isfinite(p->out.force1) || !v3_isfinite(p->out.torque1) ||
            !v3_isfinite(p->out.torque2)) {
            snprintf(diag, diag_size,
                     "contact law returned a non-finite result for pair (%d,%d) at step %lld, "
                     "t = %.17g, u_n = %.17g, delta = %.17g",
                     p->i, p->j, (long long)s->step, s->t, un, p->out.delta);
            return -1;
        }
        b1->f = v3_add(b1->f, p->out.force1);
        b2->f = v3_sub(b2->f, p->out.force1);
        b1->t = v3_add(b1->t, p->out.torque1);
        b2->t = v3_add(b2->t, p->out.torque2);
    }
    vec3 spin_f = lub_fb_flow_spin(&s->env);
    for (int k = 0; k < s->nb; ++k) {
        lub_fb_body *b = &s->b[k];
        if (b->inv_m <= 0.0)
            continue;
        vec3 imp = v3_add(v3_scale(b->f, dt * b->inv_m), v3_scale(s->env.gravity, dt));
        b->v = drag_update(b->v, lub_fb_flow_velocity(&s->env, b->x), imp, s->env.zeta_t, dt,
                           b->inv_m);
        if (s->env.rotation && b->inv_I > 0.0)
            b->w = drag_update(b->w, spin_f, v3_scale(b->t, dt * b->inv_I), s->env.zeta_r, dt,
                               b->inv_I);
        b->x = v3_axpy(b->x, dt, b->v);
        if (!v3_isfinite(b->x) || !v3_isfinite(b->v) || !v3_isfinite(b->w)) {
            snprintf(diag, diag_size, "body %d: non-finite state at step %lld, t = %.17g", k,
                     (long long)s->step, s->t);
            return -1;
        }
    }
    if (dt != s->dt_seg) { /* a new step length: count its steps from here */
        s->t_seg = s->t;
        s->step_seg = s->step;
        s->dt_seg = dt;
    }
    s->step++;
    s->t = s->t_seg + (double)(s->step - s->step_seg) * dt;
    return 0;
}
