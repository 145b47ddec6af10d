/* run_context.c — summary helpers for scenes (see run_context.h). */
#include "run_context.h"

#include <math.h>

void lub_summary_put(lub_run_ctx *ctx, const char *name, double value, double stderr_value,
                     const char *unit)
{
    json_t *e = json_object();
    /* JSON has no NaN/Inf: a non-finite headline number is reported as null */
    json_object_set_new(e, "value", isfinite(value) ? json_real(value) : json_null());
    json_object_set_new(e, "stderr",
                        (isfinite(stderr_value) && stderr_value >= 0) ? json_real(stderr_value)
                                                                      : json_null());
    json_object_set_new(e, "unit", json_string(unit ? unit : "1"));
    json_object_set_new(ctx->summary_results, name, e);
}
