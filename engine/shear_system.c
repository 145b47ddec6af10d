/* shear_system.c — leap-frog dynamics of a sheared periodic suspension (see shear_system.h). */
#include "shear_system.h"

#include "bond_order.h"
#include "pair_eval.h"
#include "packing.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#ifdef _OPENMP
#include <omp.h>
#endif

static const double PI = 3.14159265358979323846;

static int thread_id(void)
{
#ifdef _OPENMP
    return omp_get_thread_num();
#else
    return 0;
#endif
}

/* size of the current team (1 outside a parallel region or without OpenMP) */
static int team_size(void)
{
#ifdef _OPENMP
    return omp_get_num_threads();
#else
    return 1;
#endif
}

#define mat_vec lub_mat_vec

void lub_shear_free(lub_shear_system *s)
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
    free(s->inv_i_share);
    free(s->row_scratch);
    free(s->img);
    free(s->tstress);
    free(s->tsyy);
    free(s->tcount);
    if (s->acc) {
        for (int k = 0; k < s->threads; ++k)
            lub_pair_accum_free(&s->acc[k]);
        free(s->acc);
    }
    if (s->tpdf) {
        for (int k = 0; k < s->threads; ++k)
            lub_pdf_free(&s->tpdf[k]);
        free(s->tpdf);
    }
    lub_pdf_free(&s->pdf);
    lub_nlist_free(&s->nl);
    lub_nlist_free(&s->bond_nl);
    lub_pairs_free(&s->pairs);
    lub_topology_free(&s->topo);
    memset(s, 0, sizeof *s);
}

int lub_shear_init(lub_shear_system *s, int n, const double *radius, const vec3 *pos,
                   const lub_cell *cell, const lub_law_params *law, double rho, double cutoff,
                   double skin, double dt, int threads, int pdf_theta, int pdf_phi)
{
    memset(s, 0, sizeof *s);
    if (threads < 1)
        threads = 1;
    s->n = n;
    s->threads = threads;
    s->batch_law = 1;
    size_t un = (size_t)n;
    s->x = malloc(un * sizeof *s->x);
    s->v = malloc(un * sizeof *s->v);
    s->w = malloc(un * sizeof *s->w);
    s->f = calloc(un, sizeof *s->f);
    s->t = calloc(un, sizeof *s->t);
    s->x_ref = malloc(un * sizeof *s->x_ref);
    s->r = malloc(un * sizeof *s->r);
    s->m = malloc(un * sizeof *s->m);
    s->inv_m = malloc(un * sizeof *s->inv_m);
    s->inv_i = malloc(un * sizeof *s->inv_i);
    s->inv_i_share = malloc(un * sizeof *s->inv_i_share);
    s->row_scratch = malloc(2 * un * sizeof *s->row_scratch);
    s->img = calloc(3 * un, sizeof *s->img);
    s->tstress = calloc((size_t)threads, sizeof *s->tstress);
    s->tsyy = calloc((size_t)threads, sizeof *s->tsyy);
    s->tcount = calloc(LUB_COUNT_N * (size_t)threads, sizeof *s->tcount);
    s->acc = calloc((size_t)threads, sizeof *s->acc);
    if (!s->x || !s->v || !s->w || !s->f || !s->t || !s->x_ref || !s->r || !s->m || !s->inv_m ||
        !s->inv_i || !s->inv_i_share || !s->row_scratch || !s->img || !s->tstress || !s->tsyy ||
        !s->tcount || !s->acc) {
        lub_shear_free(s);
        return LUB_SHEAR_NOMEM;
    }
    for (int k = 0; k < threads; ++k)
        if (lub_pair_accum_init(&s->acc[k], n)) {
            lub_shear_free(s);
            return LUB_SHEAR_NOMEM;
        }
    if (pdf_theta > 0 && pdf_phi > 0) {
        s->tpdf = calloc((size_t)threads, sizeof *s->tpdf);
        if (!s->tpdf || lub_pdf_init(&s->pdf, pdf_theta, pdf_phi)) {
            lub_shear_free(s);
            return LUB_SHEAR_NOMEM;
        }
        for (int k = 0; k < threads; ++k)
            if (lub_pdf_init(&s->tpdf[k], pdf_theta, pdf_phi)) {
                lub_shear_free(s);
                return LUB_SHEAR_NOMEM;
            }
    }
    s->cell = *cell;
    vec3 spin = lub_flow_spin(cell->L);
    for (int i = 0; i < n; ++i) {
        double r = radius[i];
        s->r[i] = r;
        s->x[i] = pos[i];
        s->m[i] = 4.0 / 3.0 * PI * r * r * r * rho;
        s->inv_m[i] = 1.0 / s->m[i];
        s->inv_i[i] = 1.0 / (0.4 * s->m[i] * r * r);
        s->inv_i_share[i] = lub_inertia_share(s->inv_i[i], 0);
        s->v[i] = lub_cell_mean_velocity(cell, pos[i]);
        s->w[i] = spin;
    }
    s->law = *law;
    s->cutoff = cutoff;
    s->dt = dt;
    s->fail_pair = -1;
    lub_nlist_init(&s->nl, cutoff, skin);
    s->nl.threads = threads;
    lub_nlist_init(&s->bond_nl, 0.0, 0.0);
    lub_pairs_init(&s->pairs);
    s->need_rebuild = 1;
    return LUB_SHEAR_OK;
}

void lub_shear_set_gradient(lub_shear_system *s, const double Lnew[3][3])
{
    double dL[3][3];
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j)
            dL[i][j] = Lnew[i][j] - s->cell.L[i][j];
    vec3 dspin = lub_flow_spin(dL);
    for (int p = 0; p < s->n; ++p) {
        s->v[p] = v3_add(s->v[p], mat_vec(dL, s->x[p]));
        s->w[p] = v3_add(s->w[p], dspin);
    }
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j)
            s->cell.L[i][j] = Lnew[i][j];
}

double lub_shear_elastic_dt(const lub_shear_system *s)
{
    double best = INFINITY;
    for (int i = 0; i < s->n; ++i) {
        double t2 = s->m[i] / s->law.k_bulk;
        if (s->law.k_t > 0) {
            double tr = 1.0 / (s->inv_i[i] * s->law.k_t * s->r[i] * s->r[i]);
            if (tr < t2)
                t2 = tr;
        }
        if (t2 < best)
            best = t2;
    }
    return sqrt(best);
}

double lub_shear_phi(const lub_shear_system *s)
{
    double v = 0.0;
    for (int i = 0; i < s->n; ++i)
        v += s->r[i] * s->r[i] * s->r[i];
    return 4.0 / 3.0 * PI * v / s->cell.volume;
}

/* Q6 over the nearest-image pairs closer than bond_factor (r_i + r_j), O(n^2): the bond
 * list's fallback where it cannot be built (a cell narrower than twice its listing distance,
 * or no memory). The nearest image is searched among the 27 around the rounded fractional
 * difference. */
static double bond_order_brute(const lub_shear_system *s, double bond_factor, long *bonds)
{
    lub_q6_accum acc;
    lub_q6_zero(&acc);
    for (int i = 0; i < s->n; ++i)
        for (int j = i + 1; j < s->n; ++j) {
            const vec3 d0 = v3_sub(s->x[j], s->x[i]);
            const vec3 f = lub_cell_to_frac(&s->cell, d0);
            const int k0[3] = {-(int)lround(f.x), -(int)lround(f.y), -(int)lround(f.z)};
            vec3 best = d0;
            double best2 = INFINITY;
            for (int a = -1; a <= 1; ++a)
                for (int b = -1; b <= 1; ++b)
                    for (int c = -1; c <= 1; ++c) {
                        const int k[3] = {k0[0] + a, k0[1] + b, k0[2] + c};
                        const vec3 d = v3_add(d0, lub_cell_shift(&s->cell, k));
                        if (v3_norm2(d) < best2) {
                            best2 = v3_norm2(d);
                            best = d;
                        }
                    }
            const double reach = bond_factor * (s->r[i] + s->r[j]);
            if (best2 < reach * reach)
                lub_q6_add(&acc, best);
        }
    if (bonds)
        *bonds = acc.n;
    return lub_q6_value(&acc);
}

/* Whether the pair list holds every bond with skin_left of its skin unspent: it holds every
 * pair closer than (r_i + r_j)(1 + cutoff/2) + skin_left (skin rule; also right after a step
 * that found the skin used up), enough when that covers bond_factor (r_i + r_j) for the
 * largest pair. */
static int pair_list_holds_bonds(const lub_shear_system *s, double bond_factor, double skin_left)
{
    double rmax = 0.0;
    for (int i = 0; i < s->n; ++i)
        rmax = fmax(rmax, s->r[i]);
    return skin_left >= 2.0 * rmax * (bond_factor - 1.0 - 0.5 * s->nl.range);
}

/* The bond list from the current positions: every pair closer than bond_factor (r_i + r_j),
 * no skin. Returns lub_nlist_build's code. */
static int build_bond_list(lub_shear_system *s, double bond_factor)
{
    lub_nlist *bl = &s->bond_nl;
    bl->range = fmax(0.0, 2.0 * (bond_factor - 1.0));
    bl->skin = 0.0;
    return lub_nlist_build(bl, &s->cell, s->x, s->r, s->n);
}

int lub_shear_bond_order_prepare(lub_shear_system *s, double bond_factor)
{
    if (pair_list_holds_bonds(s, bond_factor, 0.0))
        return LUB_NLIST_OK;
    return build_bond_list(s, bond_factor);
}

double lub_shear_bond_order_q6(lub_shear_system *s, double bond_factor, long *bonds)
{
    const int32_t *pi = s->pairs.i, *pj = s->pairs.j, *pc = s->pairs.c;
    size_t np = s->pairs.n;
    if (!pair_list_holds_bonds(s, bond_factor, s->nl.skin - s->skin_used)) {
        const lub_nlist *bl = &s->bond_nl;
        if (build_bond_list(s, bond_factor) != LUB_NLIST_OK)
            return bond_order_brute(s, bond_factor, bonds);
        pi = bl->pi;
        pj = bl->pj;
        pc = bl->pc;
        np = bl->npairs;
    }
    lub_q6_accum acc;
    lub_q6_zero(&acc);
    for (size_t k = 0; k < np; ++k) {
        const int i = pi[k], j = pj[k];
        const vec3 d = v3_sub(v3_add(s->x[j], lub_cell_shift(&s->cell, &pc[3 * k])), s->x[i]);
        const double reach = bond_factor * (s->r[i] + s->r[j]);
        if (v3_norm2(d) < reach * reach)
            lub_q6_add(&acc, d);
    }
    if (bonds)
        *bonds = acc.n;
    return lub_q6_value(&acc);
}

int lub_shear_step_control(lub_shear_system *s, lub_step_control *c)
{
    return lub_step_control_at_rebuild(c, s->rebuilds, &s->pairs, &s->law, s->r, s->inv_m, s->inv_i,
                                       s->n, s->row_scratch);
}

/* Bytes of each array element, shared by lub_shear_memory_bytes and lub_shear_min_bytes. */
enum {
    PARTICLE_BYTES = 6 * sizeof(vec3) + 7 * sizeof(double) + 3 * sizeof(int), /* x v w f t
                                 x_ref; r m 1/m 1/I share, 2 scratch rows; images */
    THREAD_PARTICLE_BYTES = 2 * sizeof(vec3) + 2 * sizeof(int), /* per-thread pair sums */
    NLIST_PARTICLE_BYTES = sizeof(size_t) + 2 * sizeof(int) + sizeof(vec3),
    NLIST_PAIR_BYTES = 5 * sizeof(int32_t),                              /* i, j, image shift */
    STORE_PAIR_BYTES = 2 * sizeof(int32_t) + sizeof(lub_pair_state) + 1, /* i j state active;
                                                                            double-buffered */
    STORE_FLAT_PAIR_BYTES = 3 * sizeof(int32_t) + 3                      /* c, near, allow, img */
};

size_t lub_shear_memory_bytes(const lub_shear_system *s)
{
    size_t n = (size_t)s->n;
    size_t b = n * PARTICLE_BYTES;
    const lub_nlist *lists[2] = {&s->nl, &s->bond_nl}; /* the bond list: empty unless used */
    for (int l = 0; l < 2; ++l) {
        const lub_nlist *nl = lists[l];
        for (int t = 0; t < nl->nparts; ++t) /* per-thread buffers of the parallel search */
            b += nl->parts[t].cap * NLIST_PAIR_BYTES;
        b += nl->pair_cap * NLIST_PAIR_BYTES + nl->part_cap * NLIST_PARTICLE_BYTES +
             nl->bin_cap * sizeof(int);
    }
    const lub_pairs *ps = &s->pairs;
    b += (ps->cap + ps->ocap) * STORE_PAIR_BYTES + ps->fcap * STORE_FLAT_PAIR_BYTES;
    b += s->topo.site_cap * sizeof(lub_power_site) + (size_t)s->topo.n_cap * sizeof(size_t);
    b += (size_t)s->threads * (sizeof(lub_stress) + sizeof(double) + 3 * sizeof(size_t));
    b += (size_t)s->threads * n * THREAD_PARTICLE_BYTES;
    return b;
}

double lub_shear_listed_pairs_estimate(double phi, double radius_std, double cutoff, double skin)
{
    /* centres within d = (2 + cutoff) a + skin of a sphere, at number density
     * phi/(4/3 pi <a^3>) with <a^3> = 1 + 3 std^2, outside the excluded <(a_i + a_j)^3>; the
     * pair correlation is taken as 1 (a dense packing has more pairs near contact) */
    const double d = 2.0 + cutoff + skin, v2 = radius_std * radius_std;
    const double shell = d * d * d - 8.0 * (1.0 + 1.5 * v2);
    return shell > 0.0 ? 0.5 * phi / (1.0 + 3.0 * v2) * shell : 0.0;
}

double lub_shear_list_range(double cutoff, double radius_std, int delaunay)
{
    if (!delaunay)
        return cutoff;
    double r_lo, r_hi;
    lub_packing_radius_clip(radius_std, &r_lo, &r_hi);
    /* mean-size pairs (centre distance 2 + range) are listed to the reach */
    return fmax(cutoff, lub_topology_reach(r_lo, r_hi, cutoff) - 2.0);
}

double lub_shear_listing_distance(double cutoff, double radius_std, double skin, int delaunay)
{
    double r_lo, r_hi;
    lub_packing_radius_clip(radius_std, &r_lo, &r_hi);
    const double d = 2.0 * r_hi * (1.0 + 0.5 * cutoff);
    return (delaunay ? fmax(d, lub_topology_reach(r_lo, r_hi, cutoff)) : d) + skin;
}

double lub_shear_rebuild_strain(double cutoff, double skin) { return skin / (2.0 + cutoff + skin); }

double lub_shear_min_bytes(double n, double phi, double radius_std, double cutoff, double skin,
                           int threads, int rebuilt)
{
    const double pairs = 0.9 * n * lub_shear_listed_pairs_estimate(phi, radius_std, cutoff, skin);
    const double per_particle =
        PARTICLE_BYTES + NLIST_PARTICLE_BYTES + (threads > 1 ? threads : 1) * THREAD_PARTICLE_BYTES;
    const double per_pair =
        NLIST_PAIR_BYTES + (rebuilt ? 2 : 1) * STORE_PAIR_BYTES + STORE_FLAT_PAIR_BYTES;
    return n * per_particle + pairs * per_pair;
}

/* Delaunay flags from the current positions; the list holds every pair with u_n < nl.range
 * a_ij (the skin criterion), the range the topology certifies its faces with. */
static int update_topology(lub_shear_system *s)
{
    if (lub_topology_update(&s->topo, &s->pairs, &s->cell, s->x, s->r, s->n, s->cutoff))
        return 1;
    s->topology_step = s->step;
    return 0;
}

/* 1 when this step is one of the periodic updates of the triangulation and the set has not
 * been computed from these positions yet (lub_shear_complete_list may have done it) */
static int topology_update_due(const lub_shear_system *s)
{
    return s->topology_interval > 0 && s->step % s->topology_interval == 0 &&
           s->topology_step != s->step;
}

static int rebuild(lub_shear_system *s)
{
    int m[3];
    const int flipped = lub_cell_flip(&s->cell, m);
    s->flips += flipped;
    for (int i = 0; i < s->n; ++i)
        lub_cell_wrap_counted(&s->cell, m, flipped, &s->x[i], &s->v[i], &s->img[3 * i]);
    int rc = lub_nlist_build(&s->nl, &s->cell, s->x, s->r, s->n);
    if (rc == LUB_NLIST_CELL_TOO_SMALL) {
        snprintf(s->fail_msg, sizeof s->fail_msg,
                 "cell narrower than twice the neighbour listing distance %.3g (t=%.6g)",
                 s->nl.max_dist, s->time);
        return LUB_SHEAR_CELL_TOO_SMALL;
    }
    if (rc != LUB_NLIST_OK || lub_pairs_adopt(&s->pairs, &s->nl, s->n))
        return LUB_SHEAR_NOMEM;
    s->lost_pairs += (long)s->pairs.lost;
    s->skin_used = 0.0;
    if (s->topology_interval > 0 && update_topology(s))
        return LUB_SHEAR_NOMEM;
    memcpy(s->x_ref, s->x, (size_t)s->n * sizeof *s->x);
    memcpy(s->h_ref, s->cell.h, sizeof s->h_ref);
    s->rebuilds++;
    s->need_rebuild = 0;
    return LUB_SHEAR_OK;
}

/* A = H H_ref^-1 for the cell matrix H of `cell` */
static void affine_map(const lub_shear_system *s, const lub_cell *cell, double A[3][3])
{
    lub_cell ref;
    memcpy(ref.h, s->h_ref, sizeof ref.h);
    lub_cell_refresh(&ref);
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) {
            double v = 0.0;
            for (int k = 0; k < 3; ++k)
                v += cell->h[i][k] * ref.hinv[k][j];
            A[i][j] = v;
        }
}

/* A blown-up motion with finite numbers: the largest non-affine displacement since the last
 * rebuild (at most half the skin before this step) exceeds half the narrowest cell width, so
 * one step moved a particle past particles it never met. Writes fail_msg when it did. */
static int runaway(lub_shear_system *s, const double A[3][3], double umax2)
{
    double w[3];
    lub_cell_widths(&s->cell, w);
    const double half_width = 0.5 * fmin(w[0], fmin(w[1], w[2]));
    if (umax2 <= half_width * half_width)
        return 0;
    int worst = 0;
    for (int p = 0; p < s->n; ++p)
        if (v3_norm2(v3_sub(s->x[p], mat_vec(A, s->x_ref[p]))) >= umax2)
            worst = p;
    snprintf(s->fail_msg, sizeof s->fail_msg,
             "particle %d moved %.3g a in one step (speed %.3g against the flow), more than half "
             "the cell's narrowest width %.3g a: the motion is unstable",
             worst, sqrt(umax2), v3_norm(v3_sub(s->v[worst], mat_vec(s->cell.L, s->x[worst]))),
             2.0 * half_width);
    return 1;
}

void lub_shear_use_delaunay(lub_shear_system *s, int interval, double guard)
{
    s->topology_interval = interval < 1 ? 1 : interval;
    s->topology_step = -1;
    /* candidates listed to a reach beyond the cut-off, so that the faces are certified within a
     * ball that does not shrink as the skin is consumed (pair_topology.h) */
    double r_min = s->n > 0 ? s->r[0] : 1.0, r_max = r_min;
    for (int p = 1; p < s->n; ++p) {
        r_min = fmin(r_min, s->r[p]);
        r_max = fmax(r_max, s->r[p]);
    }
    s->nl.reach = lub_topology_reach(r_min, r_max, s->cutoff);
    lub_topology_init(&s->topo, s->cutoff, s->nl.reach, guard, s->r, s->n, s->threads);
    s->pairs.allow_guard = guard; /* between updates too (pair_eval) */
    s->need_rebuild = 1;
}

int lub_shear_complete_list(lub_shear_system *s)
{
    if (s->need_rebuild)
        return rebuild(s);
    /* the interaction set the next step will use: a due update of the triangulation is a
     * function of the positions, so the step's own update gives the same set again */
    if (topology_update_due(s) && update_topology(s))
        return LUB_SHEAR_NOMEM;
    return LUB_SHEAR_OK;
}

/* The microstructure of the configuration the step is about to evaluate into the threads'
 * s->tpdf: every interacting pair through the scalar law on a copy of its state (a pair
 * entering the cut-off on a fresh one), as lub_pair_eval would evaluate it, but changing no pair
 * state, flag or sum, so that the step that follows, batched or not, is bit for bit the one of
 * a run without microstructure (until 2026-12-07 a snapshot step took the scalar law for the
 * forces too, and a run with microstructure left the one without at round-off). A pair the law
 * fails on is left out; the step reports the failure. No allocation. */
static void pdf_snapshot(lub_shear_system *s)
{
    const int nt = s->threads;
    const lub_cell *cell = &s->cell;
    const lub_pairs *ps = &s->pairs;
    const lub_pair_bodies bodies = {
        .x = s->x, .v = s->v, .w = s->w, .r = s->r, .inv_i_share = s->inv_i_share};
    const long npairs = (long)ps->n;
    const int n = s->n;
    for (int k = 0; k < nt; ++k)
        lub_pdf_clear(&s->tpdf[k]);
#pragma omp parallel num_threads(nt)
    {
        lub_pdf *pdf = &s->tpdf[thread_id()];
#pragma omp for schedule(static)
        for (long k = 0; k < npairs; ++k) {
            lub_pair_input in;
            double un;
            if (lub_pair_input_of(ps, (size_t)k, cell, &bodies, s->cutoff, s->dt, &in, &un) !=
                LUB_PAIR_OK)
                continue;
            lub_pair_state st = ps->state[k];
            if (!ps->active[k])
                lub_pair_state_reset(&st); /* as lub_pairs_enter */
            lub_pair_output o;
            if (lub_pair_step(&s->law, &in, &st, &o) != 0 || !v3_isfinite(o.force1) ||
                !v3_isfinite(o.torque1) || !v3_isfinite(o.torque2))
                continue;
            const double h1 = in.r1 + 0.5 * un, h2 = in.r2 + 0.5 * un;
            const vec3 wc = v3_sub(in.v2, in.v1); /* centre-of-mass relative velocity */
            vec3 w = v3_sub(wc, v3_scale(v3_cross(in.w2, o.n), h2));
            w = v3_sub(w, v3_scale(v3_cross(in.w1, o.n), h1));
            lub_pdf_add_pair(pdf, &o, in.branch, w, wc, 0.5 * (in.r1 + in.r2), n, cell->volume);
        }
    }
}

int lub_shear_step(lub_shear_system *s, unsigned flags, lub_shear_sample *out)
{
    if (s->need_rebuild) {
        int rc = rebuild(s);
        if (rc)
            return rc;
    } else if (topology_update_due(s)) {
        /* the list is unchanged, so its buffers suffice: nothing is allocated */
        if (update_topology(s))
            return LUB_SHEAR_NOMEM;
    }
    const int nt = s->threads;
    const lub_cell *cell = &s->cell;
    lub_pairs *ps = &s->pairs;
    const double dt = s->dt;
    const double drag_c = 6.0 * 3.14159265358979323846 * s->drag_viscosity * dt; /* x r/m */
    const double cutoff = s->cutoff;
    const lub_law_params *law = &s->law;
    const int want_stress = (flags & LUB_SAMPLE_STRESS) != 0;
    const int want_syy = (flags & (LUB_SAMPLE_SYY | LUB_SAMPLE_STRESS)) != 0;
    const int want_pdf = (flags & LUB_SAMPLE_PDF) && s->tpdf;
    const long npairs = (long)ps->n;
    const int n = s->n;
    const double volume = s->cell.volume; /* stresses use the volume of the force evaluation */
    int failed = 0;

    for (int k = 0; k < nt; ++k) {
        if (want_stress)
            lub_stress_zero(&s->tstress[k]);
        s->tsyy[k] = 0.0;
        for (int c = 0; c < LUB_COUNT_N; ++c)
            s->tcount[LUB_COUNT_N * k + c] = 0;
    }
    if (want_pdf)
        pdf_snapshot(s);

    const lub_pair_bodies bodies = {
        .x = s->x, .v = s->v, .w = s->w, .r = s->r, .inv_i_share = s->inv_i_share};
    /* a microstructure snapshot reads the pairs on copies of their states (pdf_snapshot): the
     * step itself is the one taken without it, batched law included */
    const int batched = s->batch_law && !want_stress;
    /* the cell at the end of the step (a pure function of the current cell) and the affine
     * map since the last rebuild, so that the skin criterion is measured in the same pass as
     * the integration */
    lub_cell next = s->cell;
    const int cell_degenerate = lub_cell_update(&next, dt);
    double A[3][3];
    affine_map(s, &next, A);
    double umax2 = 0.0; /* largest squared non-affine displacement since the last rebuild */
    int bad_position = 0;
#pragma omp parallel num_threads(nt) reduction(| : failed, bad_position) reduction(max : umax2)
    {
        const int tid = thread_id();
        const int nteam = team_size();
        lub_stress *ts = &s->tstress[tid];
        lub_pair_accum *acc = &s->acc[tid];
        double syy = 0.0;
        size_t nact = 0, ncon = 0, ncrush = 0, nslide = 0;
        lub_pair_accum_zero(acc, 0, n);
        if (tid == 0)
            s->team = nteam; /* read after the barrier below */
        if (batched) {
            /* contiguous static partition of the pairs over the team, balanced by cost */
            long k0, k1;
            lub_pairs_range(ps, tid, nteam, &k0, &k1);
            lub_pair_batch batch[2];
            lub_pair_range_sums sums = {0.0, 0, 0};
            double un = 0.0;
            const long kf = lub_pair_eval_range(ps, k0, k1, cell, &bodies, law, cutoff, dt, n, acc,
                                                batch, &sums, &un);
            syy += want_syy ? sums.syy : 0.0;
            if (kf >= 0) {
                failed = 1;
#pragma omp critical(lub_shear_fail)
                {
                    if (s->fail_pair < 0) {
                        const int i = ps->i[kf], j = ps->j[kf];
                        s->fail_pair = kf;
                        snprintf(s->fail_msg, sizeof s->fail_msg,
                                 "pair law non-finite for pair %ld (particles %d, %d; u_n/a=%.6g) "
                                 "at step %ld, t=%.6g",
                                 kf, i, j, un / (0.5 * (s->r[i] + s->r[j])), s->step, s->time);
                    }
                }
            }
        }
        /* scalar path (stress or PDF samples); when batched this loop is empty and its
         * implicit barrier orders the pair evaluation before the sums below */
#pragma omp for schedule(static)
        for (long k = 0; k < (batched ? 0 : npairs); ++k) {
            const int i = ps->i[k], j = ps->j[k];
            lub_pair_output o;
            vec3 d;
            double un;
            const int rc =
                lub_pair_eval(ps, (size_t)k, cell, &bodies, law, cutoff, dt, acc, &o, &d, &un);
            if (rc == LUB_PAIR_OUT)
                continue;
            const double ri = s->r[i], rj = s->r[j];
            const double a = 0.5 * (ri + rj);
            if (rc == LUB_PAIR_NONFINITE) {
                failed = 1;
#pragma omp critical(lub_shear_fail)
                {
                    if (s->fail_pair < 0) {
                        s->fail_pair = k;
                        snprintf(s->fail_msg, sizeof s->fail_msg,
                                 "pair law non-finite for pair %ld (particles %d, %d; u_n/a=%.6g) "
                                 "at step %ld, t=%.6g",
                                 k, i, j, un / a, s->step, s->time);
                    }
                }
                continue;
            }
            if (want_syy)
                syy += o.force1.y * d.y;
            if (want_stress) {
                lub_stress_add_pair(ts, &o, d);
                nact++;
                ncon += o.contact ? 1 : 0;
                /* crushed contacts (a subset of the contacts, as the fraction's name says;
                 * until 2026-12-06 every pair this compressed, contact or not) */
                ncrush += (o.contact && un < -law->alpha * law->eps * a) ? 1 : 0;
                nslide += o.slip ? 1 : 0;
            }
        }
        /* pair sums of the team (in thread order) + kinetic stress + integrate: one pass per
         * particle */
        double kyy = 0.0;
        const int team = s->team;
        const lub_pair_accum *all = s->acc;
#pragma omp for schedule(static)
        for (int p = 0; p < n; ++p) {
            vec3 F, T;
            int n_active, near;
            lub_pair_accum_sum(all, team, p, &F, &T, &n_active, &near);
            (void)n_active;
            s->inv_i_share[p] = lub_inertia_share(s->inv_i[p], near);
            s->f[p] = F;
            s->t[p] = T;
            vec3 v = s->v[p];
            vec3 x = s->x[p];
            if (want_syy || want_stress) {
                vec3 vp = v3_sub(v, mat_vec(cell->L, x));
                if (want_stress)
                    lub_stress_add_kinetic(ts, s->m[p], vp);
                kyy -= s->m[p] * vp.y * vp.y;
            }
            vec3 acc = v3_add(v3_scale(F, s->inv_m[p]), mat_vec(cell->L, v));
            v = v3_axpy(v, dt, acc);
            if (drag_c > 0.0) {
                const double c = drag_c * s->r[p] * s->inv_m[p];
                v = v3_scale(v3_axpy(v, c, mat_vec(cell->L, x)), 1.0 / (1.0 + c));
            }
            s->v[p] = v;
            s->w[p] = v3_axpy(s->w[p], dt * s->inv_i[p], T);
            x = v3_axpy(x, dt, v);
            s->x[p] = x;
            const double u2 = v3_norm2(v3_sub(x, mat_vec(A, s->x_ref[p])));
            bad_position |= !(u2 < INFINITY);
            umax2 = u2 > umax2 ? u2 : umax2;
        }
        s->tsyy[tid] = syy + kyy;
        size_t *count = &s->tcount[LUB_COUNT_N * tid];
        count[LUB_COUNT_ACTIVE] = nact;
        count[LUB_COUNT_CONTACT] = ncon;
        count[LUB_COUNT_CRUSHED] = ncrush;
        count[LUB_COUNT_SLIDING] = nslide;
    }
    if (s->team_min == 0 || s->team < s->team_min)
        s->team_min = s->team;
    if (failed)
        return LUB_SHEAR_NONFINITE;
    /* once per neighbour list, from the flags of its first evaluation */
    if (nt > 1 && ps->nbounds != nt)
        lub_pairs_balance(ps, nt);

    if (cell_degenerate) {
        snprintf(s->fail_msg, sizeof s->fail_msg, "cell degenerate at step %ld", s->step);
        return LUB_SHEAR_DEGENERATE;
    }
    s->cell = next;
    s->time += dt;
    s->step++;

    /* skin criterion for the next step */
    {
        double e2 = 0.0;
        for (int i = 0; i < 3; ++i)
            for (int j = 0; j < 3; ++j) {
                double d = A[i][j] - (i == j ? 1.0 : 0.0);
                e2 += d * d;
            }
        if (bad_position) {
            snprintf(s->fail_msg, sizeof s->fail_msg,
                     "non-finite particle position at step %ld, t=%.6g", s->step, s->time);
            return LUB_SHEAR_NONFINITE;
        }
        if (umax2 > s->nl.skin * s->nl.skin && runaway(s, A, umax2))
            return LUB_SHEAR_RUNAWAY;
        s->skin_used = 2.0 * sqrt(umax2) + sqrt(e2) * s->nl.max_dist;
        if (s->skin_used > s->nl.skin)
            s->need_rebuild = 1;
        double tilt = fabs(s->cell.h[0][1] / s->cell.h[0][0]);
        if (tilt > 0.5)
            s->need_rebuild = 1;
    }

    if (out) {
        memset(out, 0, sizeof *out);
        double iv = 1.0 / volume;
        double syy = 0.0;
        for (int k = 0; k < nt; ++k) {
            syy += s->tsyy[k];
            if (want_stress) {
                lub_stress_accumulate(&out->stress, &s->tstress[k]);
                const size_t *count = &s->tcount[LUB_COUNT_N * k];
                out->n_active += count[LUB_COUNT_ACTIVE];
                out->n_contacts += count[LUB_COUNT_CONTACT];
                out->n_crushed += count[LUB_COUNT_CRUSHED];
                out->n_sliding += count[LUB_COUNT_SLIDING];
            }
        }
        out->syy = syy * iv;
        if (want_stress)
            lub_stress_scale(&out->stress, iv);
    }
    if (want_pdf) {
        for (int k = 0; k < nt; ++k)
            lub_pdf_accumulate(&s->pdf, &s->tpdf[k]);
        s->pdf.snapshots++;
    }
    return LUB_SHEAR_OK;
}
