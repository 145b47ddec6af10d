/* state_checkpoint.c — cell and pair store into a checkpoint and back (state_checkpoint.h). */
#include "state_checkpoint.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "json_text.h"

_Static_assert(sizeof(lub_pair_state) == 8 * sizeof(double), "a pair state is 8 doubles");

enum { CELL_DOUBLES = 28 }; /* h, hinv, L, volume */

int lub_cell_save(lub_ckpt *c, const char *name, const lub_cell *cell)
{
    double v[CELL_DOUBLES];
    memcpy(v, cell->h, sizeof cell->h);
    memcpy(v + 9, cell->hinv, sizeof cell->hinv);
    memcpy(v + 18, cell->L, sizeof cell->L);
    v[27] = cell->volume;
    return lub_ckpt_put(c, name, LUB_CKPT_F64, CELL_DOUBLES, v);
}

int lub_cell_load(lub_ckpt *c, const char *name, lub_cell *cell)
{
    double v[CELL_DOUBLES];
    if (lub_ckpt_get(c, name, LUB_CKPT_F64, CELL_DOUBLES, v))
        return -1;
    memcpy(cell->h, v, sizeof cell->h);
    memcpy(cell->hinv, v + 9, sizeof cell->hinv);
    memcpy(cell->L, v + 18, sizeof cell->L);
    cell->volume = v[27];
    return 0;
}

static const char *at(char *buf, size_t len, const char *prefix, const char *name)
{
    snprintf(buf, len, "%s/%s", prefix, name);
    return buf;
}

int lub_pairs_save(lub_ckpt *c, const char *prefix, const lub_pairs *ps)
{
    char b[160];
    int64_t bounds[LUB_PAIRS_MAX_PARTS + 1];
    for (int k = 0; k <= ps->nbounds; ++k)
        bounds[k] = (int64_t)ps->bounds[k];
    const size_t n = ps->n;
    return lub_ckpt_put(c, at(b, sizeof b, prefix, "i"), LUB_CKPT_I32, n, ps->i) ||
                   lub_ckpt_put(c, at(b, sizeof b, prefix, "j"), LUB_CKPT_I32, n, ps->j) ||
                   lub_ckpt_put(c, at(b, sizeof b, prefix, "c"), LUB_CKPT_I32, 3 * n, ps->c) ||
                   lub_ckpt_put(c, at(b, sizeof b, prefix, "state"), LUB_CKPT_F64, 8 * n,
                                ps->state) ||
                   lub_ckpt_put(c, at(b, sizeof b, prefix, "active"), LUB_CKPT_U8, n, ps->active) ||
                   lub_ckpt_put(c, at(b, sizeof b, prefix, "near"), LUB_CKPT_U8, n, ps->near) ||
                   lub_ckpt_put(c, at(b, sizeof b, prefix, "allow"), LUB_CKPT_U8, n, ps->allow) ||
                   lub_ckpt_put(c, at(b, sizeof b, prefix, "bounds"), LUB_CKPT_I64,
                                ps->nbounds > 0 ? (size_t)ps->nbounds + 1 : 0, bounds)
               ? -1
               : 0;
}

int lub_pairs_load(lub_ckpt *c, const char *prefix, lub_pairs *ps, int n_particles, int threads)
{
    char b[160];
    size_t n = 0, nbounds = 0;
    if (lub_ckpt_count(c, at(b, sizeof b, prefix, "i"), &n) ||
        lub_ckpt_count(c, at(b, sizeof b, prefix, "bounds"), &nbounds) ||
        nbounds > LUB_PAIRS_MAX_PARTS + 1 || lub_pairs_reserve(ps, n, n_particles))
        return -1;
    int64_t bounds[LUB_PAIRS_MAX_PARTS + 1];
    if (lub_ckpt_get(c, at(b, sizeof b, prefix, "i"), LUB_CKPT_I32, n, ps->i) ||
        lub_ckpt_get(c, at(b, sizeof b, prefix, "j"), LUB_CKPT_I32, n, ps->j) ||
        lub_ckpt_get(c, at(b, sizeof b, prefix, "c"), LUB_CKPT_I32, 3 * n, ps->c) ||
        lub_ckpt_get(c, at(b, sizeof b, prefix, "state"), LUB_CKPT_F64, 8 * n, ps->state) ||
        lub_ckpt_get(c, at(b, sizeof b, prefix, "active"), LUB_CKPT_U8, n, ps->active) ||
        lub_ckpt_get(c, at(b, sizeof b, prefix, "near"), LUB_CKPT_U8, n, ps->near) ||
        lub_ckpt_get(c, at(b, sizeof b, prefix, "allow"), LUB_CKPT_U8, n, ps->allow) ||
        lub_ckpt_get(c, at(b, sizeof b, prefix, "bounds"), LUB_CKPT_I64, nbounds, bounds)) {
        ps->n = 0;
        return -1;
    }
    for (size_t k = 0; k < n; ++k) {
        if (ps->i[k] < 0 || ps->j[k] < 0 || ps->i[k] >= n_particles || ps->j[k] >= n_particles) {
            ps->n = 0;
            return -1;
        }
        ps->img[k] = lub_pairs_image_code(&ps->c[3 * k]);
    }
    if (nbounds > 1 && (int)nbounds - 1 == threads) {
        for (size_t k = 0; k < nbounds; ++k)
            ps->bounds[k] = (size_t)bounds[k];
        ps->nbounds = (int)nbounds - 1;
    }
    return 0;
}

enum {
    CTL_F64 = 5,
    SCHED_F64 = 3 + LUB_SCHEDULE_MAX_EVENTS,
    SCHED_I64 = 3 + 2 * LUB_SCHEDULE_MAX_EVENTS
};

int lub_step_control_save(lub_ckpt *c, const char *name, const lub_step_control *ctl)
{
    char b[160];
    const double f[CTL_F64] = {ctl->dt, ctl->dt_base, ctl->safety, ctl->dt_min, ctl->ratio_max};
    const int64_t i[2] = {ctl->changes, ctl->rebuilds};
    return lub_ckpt_put(c, at(b, sizeof b, name, "f64"), LUB_CKPT_F64, CTL_F64, f) ||
                   lub_ckpt_put(c, at(b, sizeof b, name, "i64"), LUB_CKPT_I64, 2, i)
               ? -1
               : 0;
}

int lub_step_control_load(lub_ckpt *c, const char *name, lub_step_control *ctl)
{
    char b[160];
    double f[CTL_F64];
    int64_t i[2];
    if (lub_ckpt_get(c, at(b, sizeof b, name, "f64"), LUB_CKPT_F64, CTL_F64, f) ||
        lub_ckpt_get(c, at(b, sizeof b, name, "i64"), LUB_CKPT_I64, 2, i) || !(f[0] > 0.0))
        return -1;
    *ctl = (lub_step_control){.dt = f[0],
                              .dt_base = f[1],
                              .safety = f[2],
                              .dt_min = f[3],
                              .ratio_max = f[4],
                              .changes = (long)i[0],
                              .rebuilds = (long)i[1]};
    return 0;
}

int lub_schedule_save(lub_ckpt *c, const char *name, const lub_schedule *sc)
{
    char b[160];
    double f[SCHED_F64] = {sc->dt, sc->t_end, sc->anchor_time};
    int64_t i[SCHED_I64] = {sc->nsteps, sc->n_events, sc->anchor_step};
    for (int e = 0; e < LUB_SCHEDULE_MAX_EVENTS; ++e) {
        f[3 + e] = e < sc->n_events ? sc->ev[e].spacing : 0.0;
        i[3 + 2 * e] = e < sc->n_events ? sc->ev[e].every : 0;
        i[4 + 2 * e] = e < sc->n_events ? sc->ev[e].next : 0;
    }
    return lub_ckpt_put(c, at(b, sizeof b, name, "f64"), LUB_CKPT_F64, SCHED_F64, f) ||
                   lub_ckpt_put(c, at(b, sizeof b, name, "i64"), LUB_CKPT_I64, SCHED_I64, i)
               ? -1
               : 0;
}

int lub_schedule_load(lub_ckpt *c, const char *name, lub_schedule *sc)
{
    char b[160];
    double f[SCHED_F64];
    int64_t i[SCHED_I64];
    if (lub_ckpt_get(c, at(b, sizeof b, name, "f64"), LUB_CKPT_F64, SCHED_F64, f) ||
        lub_ckpt_get(c, at(b, sizeof b, name, "i64"), LUB_CKPT_I64, SCHED_I64, i) ||
        !(f[0] > 0.0) || i[0] < 0 || i[1] < 0 || i[1] > LUB_SCHEDULE_MAX_EVENTS || i[2] < 0)
        return -1;
    sc->dt = f[0];
    sc->t_end = f[1];
    sc->anchor_time = f[2];
    sc->nsteps = i[0];
    sc->n_events = (int)i[1];
    sc->anchor_step = i[2];
    for (int e = 0; e < sc->n_events; ++e) {
        sc->ev[e].spacing = f[3 + e];
        sc->ev[e].every = i[3 + 2 * e];
        sc->ev[e].next = i[4 + 2 * e];
        if (sc->ev[e].every < 1)
            return -1;
    }
    return 0;
}

lub_ckpt *lub_run_checkpoint_create(const char *path, const char *scene, int64_t step,
                                    const json_t *resolved, const char *output_file, char *why,
                                    size_t len)
{
    lub_ckpt *c = lub_ckpt_create(path, why, len);
    if (!c)
        return NULL;
    char *spec = lub_json_dumps(resolved, JSON_COMPACT | JSON_SORT_KEYS);
    const int no_spec = !spec;
    const int rc = no_spec || lub_ckpt_put_text(c, "scene", scene) ||
                   lub_ckpt_put_i64(c, "step", step) ||
                   lub_ckpt_put_text(c, "spec_resolved", spec) ||
                   lub_ckpt_put_text(c, "output_file", output_file);
    free(spec);
    if (rc) {
        lub_ckpt_close(c, why, len);
        if (no_spec)
            snprintf(why, len, "out of memory (spec text)");
        return NULL;
    }
    return c;
}

int64_t lub_run_checkpoint_step(const char *path)
{
    char err[300];
    lub_ckpt *c = lub_ckpt_open(path, err, sizeof err);
    int64_t step = -1;
    if (c && lub_ckpt_get_i64_or(c, "step", -1, &step) != 0)
        step = -1;
    if (c)
        lub_ckpt_close(c, NULL, 0);
    return step;
}

int lub_run_checkpoint_close(lub_ckpt *c, int failed, char *why, size_t len)
{
    const int closed = lub_ckpt_close(c, why, len); /* why: the first failed write */
    return failed || closed ? -1 : 0;
}
