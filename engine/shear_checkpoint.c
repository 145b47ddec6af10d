/* shear_checkpoint.c — a sheared system into a checkpoint and back (see shear_checkpoint.h). */
#include "shear_checkpoint.h"

#include <stdlib.h>
#include <string.h>

_Static_assert(sizeof(vec3) == 3 * sizeof(double), "vec3 arrays are stored as doubles");
_Static_assert(sizeof(lub_pair_state) == 8 * sizeof(double), "a pair state is 8 doubles");

enum { CELL_DOUBLES = 28 }; /* h, hinv, L, volume */

static void cell_pack(const lub_cell *cell, double out[CELL_DOUBLES])
{
    memcpy(out, cell->h, sizeof cell->h);
    memcpy(out + 9, cell->hinv, sizeof cell->hinv);
    memcpy(out + 18, cell->L, sizeof cell->L);
    out[27] = cell->volume;
}

static void cell_unpack(const double in[CELL_DOUBLES], lub_cell *cell)
{
    memcpy(cell->h, in, sizeof cell->h);
    memcpy(cell->hinv, in + 9, sizeof cell->hinv);
    memcpy(cell->L, in + 18, sizeof cell->L);
    cell->volume = in[27];
}

/* the microstructure sums: name, pointer and element count of each array */
static int pdf_arrays(const lub_pdf *p, const char **names, double **arrays, size_t *counts)
{
    const size_t nb = (size_t)p->nt * (size_t)p->np;
    const char *nm[6] = {"pdf/density", "pdf/contact_density", "pdf/gap_sum",
                         "pdf/count",   "pdf/vel_sum",         "pdf/stress"};
    double *ar[6] = {p->density, p->contact_density, p->gap_sum, p->count, p->vel_sum, p->stress};
    const size_t ct[6] = {nb, nb, nb, nb, 3 * nb, 4 * 9 * nb};
    for (int k = 0; k < 6; ++k) {
        names[k] = nm[k];
        arrays[k] = ar[k];
        counts[k] = ct[k];
    }
    return 6;
}

int lub_shear_save(lub_ckpt *c, const lub_shear_system *s)
{
    const size_t n = (size_t)s->n;
    const lub_pairs *ps = &s->pairs;
    double cell[CELL_DOUBLES];
    cell_pack(&s->cell, cell);
    const int64_t topo[4] = {(int64_t)s->topo.inside, (int64_t)s->topo.allowed,
                             (int64_t)s->topo.open, (int64_t)s->topo.updates};
    int64_t bounds[LUB_PAIRS_MAX_PARTS + 1];
    for (int k = 0; k <= ps->nbounds; ++k)
        bounds[k] = (int64_t)ps->bounds[k];
    int rc = lub_ckpt_put_i64(c, "system/n", s->n) ||
             lub_ckpt_put(c, "system/radius", LUB_CKPT_F64, n, s->r) ||
             lub_ckpt_put(c, "system/x", LUB_CKPT_F64, 3 * n, s->x) ||
             lub_ckpt_put(c, "system/v", LUB_CKPT_F64, 3 * n, s->v) ||
             lub_ckpt_put(c, "system/w", LUB_CKPT_F64, 3 * n, s->w) ||
             lub_ckpt_put(c, "system/x_ref", LUB_CKPT_F64, 3 * n, s->x_ref) ||
             lub_ckpt_put(c, "system/inv_i_share", LUB_CKPT_F64, n, s->inv_i_share) ||
             lub_ckpt_put(c, "system/cell", LUB_CKPT_F64, CELL_DOUBLES, cell) ||
             lub_ckpt_put(c, "system/h_ref", LUB_CKPT_F64, 9, s->h_ref) ||
             lub_ckpt_put_f64(c, "system/dt", s->dt) ||
             lub_ckpt_put_f64(c, "system/time", s->time) ||
             lub_ckpt_put_f64(c, "system/skin_used", s->skin_used) ||
             lub_ckpt_put_f64(c, "system/list_distance", s->nl.max_dist) ||
             lub_ckpt_put_i64(c, "system/step", s->step) ||
             lub_ckpt_put_i64(c, "system/rebuilds", s->rebuilds) ||
             lub_ckpt_put_i64(c, "system/flips", s->flips) ||
             lub_ckpt_put_i64(c, "system/lost_pairs", s->lost_pairs) ||
             lub_ckpt_put_i64(c, "system/need_rebuild", s->need_rebuild) ||
             lub_ckpt_put_i64(c, "system/topology_interval", s->topology_interval) ||
             lub_ckpt_put(c, "system/topology_statistics", LUB_CKPT_I64, 4, topo) ||
             lub_ckpt_put(c, "pairs/i", LUB_CKPT_I32, ps->n, ps->i) ||
             lub_ckpt_put(c, "pairs/j", LUB_CKPT_I32, ps->n, ps->j) ||
             lub_ckpt_put(c, "pairs/c", LUB_CKPT_I32, 3 * ps->n, ps->c) ||
             lub_ckpt_put(c, "pairs/state", LUB_CKPT_F64, 8 * ps->n, ps->state) ||
             lub_ckpt_put(c, "pairs/active", LUB_CKPT_U8, ps->n, ps->active) ||
             lub_ckpt_put(c, "pairs/near", LUB_CKPT_U8, ps->n, ps->near) ||
             lub_ckpt_put(c, "pairs/allow", LUB_CKPT_U8, ps->n, ps->allow) ||
             lub_ckpt_put(c, "pairs/bounds", LUB_CKPT_I64,
                          ps->nbounds > 0 ? (size_t)ps->nbounds + 1 : 0, bounds);
    if (!rc && s->tpdf) {
        const char *names[6];
        double *arrays[6];
        size_t counts[6];
        const int k_n = pdf_arrays(&s->pdf, names, arrays, counts);
        rc = lub_ckpt_put_i64(c, "pdf/snapshots", s->pdf.snapshots);
        for (int k = 0; k < k_n && !rc; ++k)
            rc = lub_ckpt_put(c, names[k], LUB_CKPT_F64, counts[k], arrays[k]);
    }
    return rc ? -1 : 0;
}

int lub_shear_saved_particles(lub_ckpt *c, int *n, double **radius)
{
    int64_t count = 0;
    *radius = NULL;
    if (lub_ckpt_get_i64(c, "system/n", &count) || count < 2 || count > 2147483647)
        return -1;
    double *r = malloc((size_t)count * sizeof *r);
    if (!r || lub_ckpt_get(c, "system/radius", LUB_CKPT_F64, (size_t)count, r)) {
        free(r);
        return -1;
    }
    *n = (int)count;
    *radius = r;
    return 0;
}

int lub_shear_restore(lub_ckpt *c, lub_shear_system *s)
{
    const size_t n = (size_t)s->n;
    double cell[CELL_DOUBLES];
    int64_t step, rebuilds, flips, lost, need, interval, topo[4];
    size_t npairs = 0, nbounds = 0;
    if (lub_ckpt_get(c, "system/x", LUB_CKPT_F64, 3 * n, s->x) ||
        lub_ckpt_get(c, "system/v", LUB_CKPT_F64, 3 * n, s->v) ||
        lub_ckpt_get(c, "system/w", LUB_CKPT_F64, 3 * n, s->w) ||
        lub_ckpt_get(c, "system/x_ref", LUB_CKPT_F64, 3 * n, s->x_ref) ||
        lub_ckpt_get(c, "system/inv_i_share", LUB_CKPT_F64, n, s->inv_i_share) ||
        lub_ckpt_get(c, "system/cell", LUB_CKPT_F64, CELL_DOUBLES, cell) ||
        lub_ckpt_get(c, "system/h_ref", LUB_CKPT_F64, 9, s->h_ref) ||
        lub_ckpt_get_f64(c, "system/dt", &s->dt) || lub_ckpt_get_f64(c, "system/time", &s->time) ||
        lub_ckpt_get_f64(c, "system/skin_used", &s->skin_used) ||
        lub_ckpt_get_f64(c, "system/list_distance", &s->nl.max_dist) ||
        lub_ckpt_get_i64(c, "system/step", &step) ||
        lub_ckpt_get_i64(c, "system/rebuilds", &rebuilds) ||
        lub_ckpt_get_i64(c, "system/flips", &flips) ||
        lub_ckpt_get_i64(c, "system/lost_pairs", &lost) ||
        lub_ckpt_get_i64(c, "system/need_rebuild", &need) ||
        lub_ckpt_get_i64(c, "system/topology_interval", &interval) ||
        lub_ckpt_get(c, "system/topology_statistics", LUB_CKPT_I64, 4, topo) ||
        lub_ckpt_count(c, "pairs/i", &npairs) || lub_ckpt_count(c, "pairs/bounds", &nbounds) ||
        nbounds > LUB_PAIRS_MAX_PARTS + 1)
        return -1;
    cell_unpack(cell, &s->cell);
    s->step = (long)step;
    s->rebuilds = (long)rebuilds;
    s->flips = (long)flips;
    s->lost_pairs = (long)lost;
    s->need_rebuild = (int)need;
    s->topology_interval = (int)interval;
    s->topo.inside = (size_t)topo[0];
    s->topo.allowed = (size_t)topo[1];
    s->topo.open = (size_t)topo[2];
    s->topo.updates = (long)topo[3];
    lub_pairs *ps = &s->pairs;
    if (lub_pairs_reserve(ps, npairs, s->n))
        return -1;
    int64_t bounds[LUB_PAIRS_MAX_PARTS + 1];
    if (lub_ckpt_get(c, "pairs/i", LUB_CKPT_I32, npairs, ps->i) ||
        lub_ckpt_get(c, "pairs/j", LUB_CKPT_I32, npairs, ps->j) ||
        lub_ckpt_get(c, "pairs/c", LUB_CKPT_I32, 3 * npairs, ps->c) ||
        lub_ckpt_get(c, "pairs/state", LUB_CKPT_F64, 8 * npairs, ps->state) ||
        lub_ckpt_get(c, "pairs/active", LUB_CKPT_U8, npairs, ps->active) ||
        lub_ckpt_get(c, "pairs/near", LUB_CKPT_U8, npairs, ps->near) ||
        lub_ckpt_get(c, "pairs/allow", LUB_CKPT_U8, npairs, ps->allow) ||
        lub_ckpt_get(c, "pairs/bounds", LUB_CKPT_I64, nbounds, bounds))
        return -1;
    for (size_t k = 0; k < npairs; ++k) {
        if (ps->i[k] < 0 || ps->j[k] < 0 || ps->i[k] >= s->n || ps->j[k] >= s->n) {
            ps->n = 0;
            return -1;
        }
        ps->img[k] = lub_pairs_image_code(&ps->c[3 * k]);
    }
    /* the split of the thread count that saved it (another count balances at its first step) */
    if (nbounds > 1 && (int)nbounds - 1 == s->threads) {
        for (size_t k = 0; k < nbounds; ++k)
            ps->bounds[k] = (size_t)bounds[k];
        ps->nbounds = (int)nbounds - 1;
    }
    if (s->tpdf) {
        const char *names[6];
        double *arrays[6];
        size_t counts[6];
        const int k_n = pdf_arrays(&s->pdf, names, arrays, counts);
        int64_t snapshots = 0;
        if (lub_ckpt_get_i64(c, "pdf/snapshots", &snapshots))
            return -1;
        s->pdf.snapshots = (long)snapshots;
        for (int k = 0; k < k_n; ++k)
            if (lub_ckpt_get(c, names[k], LUB_CKPT_F64, counts[k], arrays[k]))
                return -1;
    }
    return 0;
}
