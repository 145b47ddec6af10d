/* scene_summary.c — summary entries with references, sampling schedule (scene_summary.h). */
#include "scene_summary.h"

#include <math.h>

void lub_summary_put_ref(lub_run_ctx *ctx, const char *name, double value, const char *unit,
                         double ref)
{
    lub_summary_put(ctx, name, value, NAN, unit);
    json_t *e = json_object_get(ctx->summary_results, name);
    if (e)
        json_object_set_new(e, "ref", isfinite(ref) ? json_real(ref) : json_null());
}

static double target_time(const lub_sampler *s, int64_t k)
{
    if (k <= 0)
        return 0.0;
    if (k >= s->count - 1)
        return s->t_end;
    double f = (double)(k - 1) / (double)(s->count - 2);
    if (s->log_spacing)
        return s->t_first * pow(s->t_end / s->t_first, f);
    return s->t_end * (double)k / (double)(s->count - 1);
}

void lub_sampler_init(lub_sampler *s, double t_end, int64_t count, int log_spacing, double t_first)
{
    s->t_end = t_end;
    s->count = count < 2 ? 2 : count;
    s->log_spacing = log_spacing && t_first > 0.0 && t_first < t_end;
    s->t_first = t_first;
    s->next = 0;
}

int lub_sampler_due(lub_sampler *s, double t)
{
    if (s->next >= s->count || t < target_time(s, s->next))
        return 0;
    while (s->next < s->count && target_time(s, s->next) <= t)
        s->next++;
    return 1;
}
