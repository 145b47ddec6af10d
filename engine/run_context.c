/* run_context.c — summary helpers for scenes (see run_context.h). */
#include "run_context.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "memory_budget.h"
#include "scene.h"

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

void lub_summary_warn(lub_run_ctx *ctx, const char *text)
{
    json_t *list = json_object_get(ctx->summary_extra, "warnings");
    if (!json_is_array(list)) {
        list = json_array();
        json_object_set_new(ctx->summary_extra, "warnings", list);
    }
    json_array_append_new(list, json_string(text));
}

void lub_fixed_dt_warning(char *out, size_t len, double ratio, const char *bound_name)
{
    snprintf(out, len,
             "the spec fixes /dt at %.3g times %s, beyond the largest step /dt_safety allows "
             "(1): the contacts are not resolved and the results are not the law's; lower /dt, "
             "or set it to 0 so that /dt_safety sets the step",
             ratio, bound_name);
}

void lub_fixed_dt_stiffness_warning(char *out, size_t len, double ratio, double limit)
{
    snprintf(out, len,
             "the spec fixes /dt at %.3g times the step the pairs' summed stiffness allows (many "
             "stiffly coupled partners: a large /cutoff, light or soft particles), above %.3g: "
             "the motion may be unstable; lower /dt, or set it to 0 so that the step follows "
             "the pairs (/dt_stiffness_safety)",
             ratio, limit);
}

void lub_warn_fixed_dt(json_t *warnings, double dt_spec, double dt_bound, const char *bound_name)
{
    if (!(dt_spec > dt_bound))
        return;
    char text[320];
    lub_fixed_dt_warning(text, sizeof text, dt_spec / dt_bound, bound_name);
    json_array_append_new(warnings, json_string(text));
}

void lub_warn_fixed_dt_stiffness(json_t *warnings, double dt_spec, double dt_bound, double ratio,
                                 double limit)
{
    if (!(dt_spec > 0.0 && dt_spec <= dt_bound && ratio > limit))
        return;
    char text[320];
    lub_fixed_dt_stiffness_warning(text, sizeof text, ratio, limit);
    json_array_append_new(warnings, json_string(text));
}

void lub_diagnostic_dt_hint(lub_run_ctx *ctx, double dt_spec, double dt_safety, double dt_bound,
                            const char *bound_name)
{
    const size_t used = strlen(ctx->diagnostic);
    char *out = ctx->diagnostic + used;
    const size_t room = sizeof ctx->diagnostic - used;
    if (dt_spec > 0.0 && dt_spec > dt_bound)
        snprintf(out, room,
                 "; the spec fixes /dt = %.3g, %.3g times the stability bound %s = %.3g: leave "
                 "/dt at 0 so that /dt_safety sets the step",
                 dt_spec, dt_spec / dt_bound, bound_name, dt_bound);
    else if (dt_spec > 0.0)
        snprintf(out, room,
                 "; the spec fixes /dt = %.3g, %.3g times the single-pair stability bound %s = "
                 "%.3g, which many stiffly coupled neighbours lower: lower /dt",
                 dt_spec, dt_spec / dt_bound, bound_name, dt_bound);
    else
        snprintf(out, room,
                 "; the step was /dt_safety = %.3g times the single-pair stability bound %s = "
                 "%.3g, which many stiffly coupled neighbours lower (a large /cutoff, light or "
                 "soft particles): lower /dt_safety",
                 dt_safety, bound_name, dt_bound);
}

void lub_diagnostic_adapted_dt_hint(lub_run_ctx *ctx, double dt, double dt_safety, double dt_bound,
                                    const char *bound_name, long changes, double stiffness_safety,
                                    double ratio_max)
{
    const size_t used = strlen(ctx->diagnostic);
    snprintf(ctx->diagnostic + used, sizeof ctx->diagnostic - used,
             "; the step was %.3g: /dt_safety = %.3g times %s = %.3g, lowered %ld times to keep "
             "it within /dt_stiffness_safety = %.3g times the step the pairs' summed stiffness "
             "allows (checked at each neighbour-list rebuild, where it was at most %.3g times "
             "that step): lower /dt_stiffness_safety",
             dt, dt_safety, bound_name, dt_bound, changes, stiffness_safety, ratio_max);
}

void lub_report_time_step(lub_run_ctx *ctx, int exit_code, double dt_spec, double dt_safety,
                          double dt_bound, const char *bound_name, json_t *warnings)
{
    if (exit_code == LUB_EXIT_NUMERICAL)
        lub_diagnostic_dt_hint(ctx, dt_spec, dt_safety, dt_bound, bound_name);
    if (exit_code == LUB_EXIT_OK)
        lub_warn_fixed_dt(warnings, dt_spec, dt_bound, bound_name);
}

void lub_diagnostic_out_of_memory(lub_run_ctx *ctx, const char *what, long long n_particles,
                                  double bytes_in_use, const char *member)
{
    char *d = ctx->diagnostic;
    const size_t cap = sizeof ctx->diagnostic;
    const double mb = 1.0 / (1024.0 * 1024.0);
    int len = snprintf(d, cap, "out of memory (%s)", what);
    if (n_particles > 0 && len >= 0 && (size_t)len < cap)
        len += snprintf(d + len, cap - (size_t)len, ": %lld particles", n_particles);
    if (bytes_in_use > 0.0 && len >= 0 && (size_t)len < cap)
        len += snprintf(d + len, cap - (size_t)len, ", %.4g MiB (%.3g kB per particle) held",
                        bytes_in_use * mb,
                        n_particles > 0 ? bytes_in_use / (double)n_particles / 1e3 : 0.0);
    const double address_space = lub_address_space_limit();
    if (isfinite(address_space) && len >= 0 && (size_t)len < cap)
        len += snprintf(d + len, cap - (size_t)len,
                        "; this process may use at most %.4g MiB of " LUB_ADDRESS_SPACE_NAME,
                        address_space * mb);
    if (member && len >= 0 && (size_t)len < cap)
        snprintf(d + len, cap - (size_t)len, "; lower %s", member);
}

int lub_memory_need_fits(lub_run_ctx *ctx, const lub_memory_need *need)
{
    lub_memory_room room;
    lub_memory_room_now(&room);
    char msg[sizeof ctx->diagnostic - 32];
    if (!lub_memory_need_check(need, &room, "this process", msg, sizeof msg))
        return 1;
    snprintf(ctx->diagnostic, sizeof ctx->diagnostic, "%s (nothing was run)", msg);
    return 0;
}

int lub_memory_fits(lub_run_ctx *ctx, double bytes, const char *what, const char *member)
{
    lub_memory_need need;
    memset(&need, 0, sizeof need);
    need.bytes = bytes;
    need.member = member;
    snprintf(need.what, sizeof need.what, "%s", what);
    return lub_memory_need_fits(ctx, &need);
}

int lub_run_resumable(const lub_run_ctx *ctx)
{
    return ctx->checkpoint_written || ctx->resume_path ||
           (ctx->periodic && ctx->periodic->written > 0);
}

int lub_run_withdraw_resume_advice(json_t *summary_extra)
{
    json_t *list = json_object_get(summary_extra, "warnings");
    size_t k;
    json_t *w;
    int replaced = 0;
    const size_t from = strlen(LUB_RESUME_ADVICE), to = strlen(LUB_RERUN_ADVICE);
    json_array_foreach (list, k, w) {
        const char *text = json_string_value(w);
        const char *at = text ? strstr(text, LUB_RESUME_ADVICE) : NULL;
        if (!at)
            continue;
        const size_t head = (size_t)(at - text), len = strlen(text);
        char *out = malloc(len - from + to + 1);
        if (!out)
            continue; /* out of memory: the advice stays, beside the driver's own warning */
        memcpy(out, text, head);
        memcpy(out + head, LUB_RERUN_ADVICE, to);
        memcpy(out + head + to, at + from, len - head - from + 1);
        json_array_set_new(list, k, json_string(out));
        free(out);
        ++replaced;
    }
    return replaced;
}
