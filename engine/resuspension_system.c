/* resuspension_system.c — lubricated spheres under gravity above a rough floor
 * (resuspension_system.h). Reuses periodic_cell, neighbor_list and pair_store unchanged. */
#include "resuspension_system.h"

#include "floor_wall.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "pair_eval.h"
#include "velocity_gradient.h"

#ifdef _OPENMP
#include <omp.h>
#endif

static const double RS_PI = 3.14159265358979323846;

static double frob(const double m[3][3])
{
    double s = 0.0;
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j)
            s += m[i][j] * m[i][j];
    return sqrt(s);
}

vec3 lub_rs_mean_velocity(const lub_rs_system *s, vec3 x)
{
    return lub_mat_vec(s->L_flow, v3(x.x, x.y - s->p.y_floor, x.z));
}

void lub_rs_free(lub_rs_system *s)
{
    free(s->x);
    free(s->v);
    free(s->w);
    free(s->f);
    free(s->t);
    free(s->x_ref);
    free(s->r);
    free(s->m);
    free(s->inv_m);
    free(s->inv_i);
    free(s->weight);
    free(s->nint);
    free(s->inv_i_share);
    free(s->row_scratch);
    free(s->img);
    if (s->acc) {
        for (int k = 0; k < (s->p.threads > 0 ? s->p.threads : 1); ++k)
            lub_pair_accum_free(&s->acc[k]);
        free(s->acc);
    }
    lub_nlist_free(&s->nl);
    lub_pairs_free(&s->pairs);
    memset(s, 0, sizeof *s);
}

int lub_rs_init(lub_rs_system *s, const lub_rs_params *p, const lub_law_params *law, int n_mobile,
                const double *radius, const vec3 *pos, int n_floor, const double *floor_r,
                const vec3 *floor_pos, double lx, double ly, double lz)
{
    memset(s, 0, sizeof *s);
    const int n = n_mobile + n_floor;
    const size_t nn = (size_t)(n > 0 ? n : 1);
    s->n = n;
    s->n_mobile = n_mobile;
    s->p = *p;
    s->law = *law;
    s->fail_pair = -1;
    s->x = calloc(nn, sizeof *s->x);
    s->v = calloc(nn, sizeof *s->v);
    s->w = calloc(nn, sizeof *s->w);
    s->f = calloc(nn, sizeof *s->f);
    s->t = calloc(nn, sizeof *s->t);
    s->x_ref = calloc(nn, sizeof *s->x_ref);
    s->r = calloc(nn, sizeof *s->r);
    s->m = calloc(nn, sizeof *s->m);
    s->inv_m = calloc(nn, sizeof *s->inv_m);
    s->inv_i = calloc(nn, sizeof *s->inv_i);
    s->weight = calloc(nn, sizeof *s->weight);
    s->nint = calloc(nn, sizeof *s->nint);
    s->inv_i_share = calloc(nn, sizeof *s->inv_i_share);
    s->row_scratch = calloc(2 * nn, sizeof *s->row_scratch);
    s->img = calloc(3 * nn, sizeof *s->img);
    const int nthreads = p->threads > 0 ? p->threads : 1;
    s->acc = calloc((size_t)nthreads, sizeof *s->acc);
    lub_nlist_init(&s->nl, p->cutoff, p->skin);
    s->nl.threads = nthreads;
    lub_pairs_init(&s->pairs);
    if (!s->x || !s->v || !s->w || !s->f || !s->t || !s->x_ref || !s->r || !s->m || !s->inv_m ||
        !s->inv_i || !s->weight || !s->nint || !s->inv_i_share || !s->row_scratch || !s->img ||
        !s->acc) {
        lub_rs_free(s);
        return LUB_RS_NOMEM;
    }
    for (int k = 0; k < nthreads; ++k)
        if (lub_pair_accum_init(&s->acc[k], n)) {
            lub_rs_free(s);
            return LUB_RS_NOMEM;
        }
    lub_cell_init_box(&s->cell, lx, ly, lz);
    memset(s->L_flow, 0, sizeof s->L_flow);
    if (p->orientation == LUB_RS_VORTICITY) {
        s->L_flow[0][2] = p->shear_rate;
        s->cell.L[0][2] = p->shear_rate;
    } else {
        s->L_flow[0][1] = p->shear_rate;
    }
    const vec3 w0 = lub_flow_spin(s->L_flow);
    for (int i = 0; i < n; ++i) {
        const int mob = i < n_mobile;
        const double r = mob ? radius[i] : floor_r[i - n_mobile];
        const double vol = 4.0 / 3.0 * RS_PI * r * r * r;
        s->r[i] = r;
        s->x[i] = mob ? pos[i] : floor_pos[i - n_mobile];
        s->m[i] = p->rho * vol;
        s->inv_m[i] = mob ? 1.0 / s->m[i] : 0.0;
        s->inv_i[i] = mob ? 1.0 / (0.4 * s->m[i] * r * r) : 0.0;
        s->inv_i_share[i] = lub_inertia_share(s->inv_i[i], 0);
        s->weight[i] = mob ? p->drho * vol * p->gravity : 0.0;
        /* floor spheres in the gradient orientation sit where u ~ 0 and are held at rest;
         * in the vorticity orientation they ride with the sheared cell */
        s->v[i] = (mob || p->orientation == LUB_RS_VORTICITY) ? lub_rs_mean_velocity(s, s->x[i])
                                                              : v3(0, 0, 0);
        s->w[i] = mob ? w0 : v3(0, 0, 0);
    }
    s->need_rebuild = 1;
    return LUB_RS_OK;
}

static int rebuild(lub_rs_system *s)
{
    int m[3];
    const int flipped = lub_cell_flip(&s->cell, m);
    s->flips += flipped;
    for (int i = 0; i < s->n; ++i) {
        /* the images carried through flips too (until 2026-12-06 they were not, and x + H img
         * jumped by a cell width along x for a body that had crossed the tilted side) */
        const int mob = i < s->n_mobile;
        vec3 *vp = (mob || s->p.orientation == LUB_RS_VORTICITY) ? &s->v[i] : NULL;
        lub_cell_wrap_counted(&s->cell, m, flipped, &s->x[i], vp, &s->img[3 * i]);
    }
    int rc = lub_nlist_build(&s->nl, &s->cell, s->x, s->r, s->n);
    if (rc == LUB_NLIST_NOMEM)
        return LUB_RS_NOMEM;
    if (rc == LUB_NLIST_CELL_TOO_SMALL) {
        snprintf(s->fail_msg, sizeof s->fail_msg,
                 "cell narrower than twice the listing distance %.4g", s->nl.max_dist);
        return LUB_RS_CELL_TOO_SMALL;
    }
    if (lub_pairs_adopt(&s->pairs, &s->nl, s->n))
        return LUB_RS_NOMEM;
    memcpy(s->x_ref, s->x, (size_t)s->n * sizeof *s->x);
    s->t_ref = s->time;
    s->need_rebuild = 0;
    s->rebuilds++;
    return LUB_RS_OK;
}

/* A blown-up motion with finite numbers: the largest non-affine displacement since the last
 * rebuild (at most half the skin before this step) exceeds half the narrower periodic width, so
 * one step moved a particle past particles it never met. Writes fail_msg when it did. */
static int runaway(lub_rs_system *s, double umax2, double tau, int nmob)
{
    double w[3];
    lub_cell_widths(&s->cell, w);
    const double half_width = 0.5 * fmin(w[0], w[2]);
    if (umax2 <= half_width * half_width)
        return 0;
    int worst = 0;
    for (int p = 0; p < nmob; ++p) {
        const vec3 xr = s->x_ref[p];
        const vec3 aff =
            v3_axpy(xr, tau, lub_mat_vec(s->L_flow, v3(xr.x, xr.y - s->p.y_floor, xr.z)));
        if (v3_norm2(v3_sub(s->x[p], aff)) >= umax2)
            worst = p;
    }
    snprintf(s->fail_msg, sizeof s->fail_msg,
             "particle %d moved %.3g a in one step (speed %.3g against the flow), more than half "
             "the cell's narrower periodic width %.3g a: the motion is unstable at step %ld",
             worst, sqrt(umax2), v3_norm(v3_sub(s->v[worst], lub_rs_mean_velocity(s, s->x[worst]))),
             2.0 * half_width, s->step);
    return 1;
}

int lub_rs_complete_list(lub_rs_system *s) { return s->need_rebuild ? rebuild(s) : LUB_RS_OK; }

int lub_rs_step(lub_rs_system *s)
{
    if (s->need_rebuild) {
        int rc = rebuild(s);
        if (rc != LUB_RS_OK)
            return rc;
    }
    lub_pairs *ps = &s->pairs;
    const lub_cell *cell = &s->cell;
    const double dt = s->p.dt, cutoff = s->p.cutoff;
    const int nt = s->p.threads > 0 ? s->p.threads : 1;
    const int nmob = s->n_mobile;
    int failed = 0;
    (void)nt;

    /* N_i / I_i (contact_law.h recommendation), N_i = active pairs of body i; 1/I = 0 for floor
     * spheres */
    const lub_pair_bodies bodies = {
        .x = s->x, .v = s->v, .w = s->w, .r = s->r, .inv_i_share = s->inv_i_share};
    long ncon = 0, ncrush = 0;
    /* every step needs only forces, contact and crushed counts: the batched law
     * (lub_pair_eval_range) on a contiguous static partition of the pairs */
#pragma omp parallel num_threads(nt) reduction(| : failed) reduction(+ : ncon, ncrush)
    {
#ifdef _OPENMP
        const long tid = omp_get_thread_num(), nteam = omp_get_num_threads();
#else
        const long tid = 0, nteam = 1;
#endif
        long k0, k1; /* contiguous static partition of the pairs, balanced by cost */
        lub_pairs_range(ps, (int)tid, (int)nteam, &k0, &k1);
        lub_pair_accum *acc = &s->acc[tid];
        lub_pair_accum_zero(acc, 0, s->n);
        if (tid == 0)
            s->team = (int)nteam;
        lub_pair_batch batch[2];
        lub_pair_range_sums sums = {0.0, 0, 0};
        double un = 0.0;
        const long kf = lub_pair_eval_range(ps, k0, k1, cell, &bodies, &s->law, cutoff, dt, nmob,
                                            acc, batch, &sums, &un);
        ncon += sums.contacts;
        ncrush += sums.crushed;
        if (kf >= 0) {
            const int i = ps->i[kf], j = ps->j[kf];
            const double a = 0.5 * (s->r[i] + s->r[j]);
            failed = 1;
#pragma omp critical(lub_rs_fail)
            {
                if (s->fail_pair < 0) {
                    s->fail_pair = kf;
                    snprintf(s->fail_msg, sizeof s->fail_msg,
                             "pair law non-finite for pair %ld (bodies %d, %d; u_n/a=%.6g) at "
                             "step %ld, t=%.6g",
                             kf, i, j, un / a, s->step, s->time);
                }
            }
        }
    }
    if (s->team_min == 0 || s->team < s->team_min)
        s->team_min = s->team;
    if (failed)
        return LUB_RS_NONFINITE;
    /* once per neighbour list, from the flags of its first evaluation */
    if (nt > 1 && ps->nbounds != nt)
        lub_pairs_balance(ps, nt);
    s->n_contacts = ncon;
    s->n_crushed = ncrush;

    /* pair sums of the team (in thread order), integrate the free particles */
    const int team = s->team;
    const lub_pair_accum *all = s->acc;
    const double g_eta_s = s->p.orientation == LUB_RS_GRADIENT ? s->p.eta_shear : 0.0;
    const double eta_d = s->p.eta_dilute;
    const int ndil = s->p.dilute_max_interactions;
    const double y_lid = s->p.y_lid;
    double umax2 = 0.0, vmax2 = 0.0;
    long hits = 0;
    int bad = 0;
    const double tau = s->time + dt - s->t_ref;
#pragma omp parallel for num_threads(nt) schedule(static) reduction(max : umax2, vmax2) \
    reduction(+ : hits) reduction(| : bad)
    for (int p = 0; p < s->n; ++p) {
        vec3 F, T;
        int count, n_near;
        lub_pair_accum_sum(all, team, p, &F, &T, &count, &n_near);
        (void)n_near;
        s->nint[p] = count;
        s->inv_i_share[p] = lub_inertia_share(s->inv_i[p], count);
        if (p >= nmob) { /* floor sphere: prescribed velocity */
            s->f[p] = F;
            s->t[p] = T;
            s->x[p] = v3_axpy(s->x[p], dt, s->v[p]);
            continue;
        }
        F.y -= s->weight[p];
        s->f[p] = F;
        s->t[p] = T;
        const vec3 u = lub_rs_mean_velocity(s, s->x[p]);
        const double c = 6.0 * RS_PI * s->r[p] * (g_eta_s + (count <= ndil ? eta_d : 0.0));
        const double cm = dt * c * s->inv_m[p];
        vec3 v = v3_add(
            s->v[p], v3_scale(v3_add(v3_scale(F, s->inv_m[p]), lub_mat_vec(cell->L, s->v[p])), dt));
        v = v3_scale(v3_axpy(v, cm, u), 1.0 / (1.0 + cm));
        s->w[p] = v3_axpy(s->w[p], dt * s->inv_i[p], T);
        vec3 x = v3_axpy(s->x[p], dt, v);
        hits += lub_lid_reflect(x.y, s->r[p], y_lid, &v.y);
        s->v[p] = v;
        s->x[p] = x;
        if (!v3_isfinite(x) || !v3_isfinite(v) || !v3_isfinite(s->w[p]))
            bad = 1;
        const vec3 dv = v3_sub(v, lub_rs_mean_velocity(s, x));
        if (v3_norm2(dv) > vmax2)
            vmax2 = v3_norm2(dv);
        /* non-affine displacement since the last rebuild */
        const vec3 xr = s->x_ref[p];
        const vec3 aff =
            v3_axpy(xr, tau, lub_mat_vec(s->L_flow, v3(xr.x, xr.y - s->p.y_floor, xr.z)));
        const double u2 = v3_norm2(v3_sub(x, aff));
        if (u2 > umax2)
            umax2 = u2;
    }
    s->lid_hits += hits;
    s->max_speed = sqrt(vmax2);
    if (bad) {
        snprintf(s->fail_msg, sizeof s->fail_msg,
                 "a particle position or velocity became non-finite at step %ld, t=%.6g", s->step,
                 s->time);
        return LUB_RS_NONFINITE;
    }
    if (umax2 > s->p.skin * s->p.skin && runaway(s, umax2, tau, nmob))
        return LUB_RS_RUNAWAY;
    if (s->p.orientation == LUB_RS_VORTICITY && lub_cell_update(&s->cell, dt)) {
        snprintf(s->fail_msg, sizeof s->fail_msg, "cell degenerate at step %ld", s->step);
        return LUB_RS_NONFINITE;
    }
    s->time += dt;
    s->step++;
    double strain_term[3][3];
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j)
            strain_term[i][j] = tau * s->L_flow[i][j];
    if (2.0 * sqrt(umax2) + frob(strain_term) * s->nl.max_dist > s->p.skin)
        s->need_rebuild = 1;
    /* confinement check: a free particle below the floor centre plane or above the cell */
    const double ly = s->cell.h[1][1];
    for (int p = 0; p < nmob; ++p) {
        const double y = s->x[p].y;
        if (y < s->p.y_floor || y > ly) {
            s->escaped_below = y < s->p.y_floor;
            snprintf(s->fail_msg, sizeof s->fail_msg,
                     "particle %d escaped the cell (y = %.6g, floor plane %.6g, top %.6g) at "
                     "step %ld",
                     p, y, s->p.y_floor, ly, s->step);
            return LUB_RS_ESCAPED;
        }
    }
    return LUB_RS_OK;
}

void lub_rs_unwrapped(const lub_rs_system *s, int i, vec3 *x, vec3 *v)
{
    const vec3 shift = lub_cell_shift(&s->cell, &s->img[3 * i]);
    *x = v3_add(s->x[i], shift);
    *v = v3_add(s->v[i], lub_mat_vec(s->cell.L, shift));
}

double lub_rs_kinetic_energy(const lub_rs_system *s)
{
    double e = 0.0;
    for (int p = 0; p < s->n_mobile; ++p) {
        const vec3 dv = v3_sub(s->v[p], lub_rs_mean_velocity(s, s->x[p]));
        e += 0.5 * s->m[p] * v3_norm2(dv);
    }
    return e;
}

double lub_rs_area(const lub_rs_system *s) { return s->cell.volume / s->cell.h[1][1]; }

double lub_rs_lowest(const lub_rs_system *s, int *below_floor)
{
    double low = INFINITY;
    int below = 0;
    for (int p = 0; p < s->n_mobile; ++p) {
        const double b = s->x[p].y - s->r[p];
        if (b < low)
            low = b;
        below += s->x[p].y < s->p.y_floor;
    }
    if (below_floor)
        *below_floor = below;
    return low;
}

int lub_rs_step_control(lub_rs_system *s, lub_step_control *c)
{
    return lub_step_control_at_rebuild(c, s->rebuilds, &s->pairs, &s->law, s->r, s->inv_m, s->inv_i,
                                       s->n, s->row_scratch);
}
