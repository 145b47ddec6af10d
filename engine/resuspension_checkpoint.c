/* resuspension_checkpoint.c — a resuspension system into a checkpoint and back
 * (resuspension_checkpoint.h). */
#include "resuspension_checkpoint.h"

#include "state_checkpoint.h"

_Static_assert(sizeof(int) == sizeof(int32_t), "int arrays are stored as int32");

int lub_rs_save(lub_ckpt *c, const lub_rs_system *s)
{
    const size_t n = (size_t)s->n;
    const int64_t counts[8] = {s->step,         s->rebuilds,   s->flips,     s->lid_hits,
                               s->need_rebuild, s->n_contacts, s->n_crushed, s->n};
    const double reals[5] = {s->time, s->t_ref, s->p.dt, s->nl.max_dist, s->max_speed};
    return lub_ckpt_put(c, "system/x", LUB_CKPT_F64, 3 * n, s->x) ||
                   lub_ckpt_put(c, "system/v", LUB_CKPT_F64, 3 * n, s->v) ||
                   lub_ckpt_put(c, "system/w", LUB_CKPT_F64, 3 * n, s->w) ||
                   lub_ckpt_put(c, "system/x_ref", LUB_CKPT_F64, 3 * n, s->x_ref) ||
                   lub_ckpt_put(c, "system/images", LUB_CKPT_I32, 3 * n, s->img) ||
                   lub_ckpt_put(c, "system/interactions", LUB_CKPT_I32, n, s->nint) ||
                   lub_ckpt_put(c, "system/inv_i_share", LUB_CKPT_F64, n, s->inv_i_share) ||
                   lub_cell_save(c, "system/cell", &s->cell) ||
                   lub_ckpt_put(c, "system/counts", LUB_CKPT_I64, 8, counts) ||
                   lub_ckpt_put(c, "system/reals", LUB_CKPT_F64, 5, reals) ||
                   lub_pairs_save(c, "pairs", &s->pairs)
               ? -1
               : 0;
}

int lub_rs_restore(lub_ckpt *c, lub_rs_system *s)
{
    const size_t n = (size_t)s->n;
    int64_t counts[8];
    double reals[5];
    if (lub_ckpt_get(c, "system/counts", LUB_CKPT_I64, 8, counts) || counts[7] != s->n ||
        lub_ckpt_get(c, "system/x", LUB_CKPT_F64, 3 * n, s->x) ||
        lub_ckpt_get(c, "system/v", LUB_CKPT_F64, 3 * n, s->v) ||
        lub_ckpt_get(c, "system/w", LUB_CKPT_F64, 3 * n, s->w) ||
        lub_ckpt_get(c, "system/x_ref", LUB_CKPT_F64, 3 * n, s->x_ref) ||
        lub_ckpt_get(c, "system/images", LUB_CKPT_I32, 3 * n, s->img) ||
        lub_ckpt_get(c, "system/interactions", LUB_CKPT_I32, n, s->nint) ||
        lub_ckpt_get(c, "system/inv_i_share", LUB_CKPT_F64, n, s->inv_i_share) ||
        lub_cell_load(c, "system/cell", &s->cell) ||
        lub_ckpt_get(c, "system/reals", LUB_CKPT_F64, 5, reals) ||
        lub_pairs_load(c, "pairs", &s->pairs, s->n, s->p.threads > 0 ? s->p.threads : 1))
        return -1;
    s->step = (long)counts[0];
    s->rebuilds = (long)counts[1];
    s->flips = (long)counts[2];
    s->lid_hits = (long)counts[3];
    s->need_rebuild = (int)counts[4];
    s->n_contacts = (long)counts[5];
    s->n_crushed = (long)counts[6];
    s->time = reals[0];
    s->t_ref = reals[1];
    s->p.dt = reals[2];
    s->nl.max_dist = reals[3];
    s->max_speed = reals[4];
    return 0;
}
