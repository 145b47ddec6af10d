/* scene_summary.h — small helpers shared by scenes to fill the summary and the time-series
 * sampler used by the verification scenes.
 *
 * Ownership: the helpers write into ctx->summary_results / ctx->summary_extra (owned by the
 * run driver). No allocation except the jansson values they add. No global state.
 */
#ifndef LUBDEM_SCENE_SUMMARY_H
#define LUBDEM_SCENE_SUMMARY_H

#include <stdint.h>

#include "run_context.h"

/* lub_summary_put() plus a reference value ("ref", null if NaN) for the entry. */
void lub_summary_put_ref(lub_run_ctx *ctx, const char *name, double value, const char *unit,
                         double ref);

/* Sampling schedule: sample times 0 = t_0 < t_1 < ... <= t_end, either evenly spaced or
 * geometric from t_first (first positive sample) to t_end. A sample is taken at the first
 * step whose time reaches the next target. Pure arithmetic, no allocation. */
typedef struct {
    double t_end, t_first;
    int64_t count, next; /* number of targets, index of the next one */
    int log_spacing;
} lub_sampler;

void lub_sampler_init(lub_sampler *s, double t_end, int64_t count, int log_spacing, double t_first);
/* 1 if time t reaches the next target (and advances past every target <= t). */
int lub_sampler_due(lub_sampler *s, double t);

#endif
