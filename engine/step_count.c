/* step_count.c — the allowed number of steps of a run (step_count.h). */
#include "step_count.h"

#include <math.h>
#include <stdio.h>

double lub_step_count(double duration, double dt) { return duration / dt; }

int lub_step_count_ok(double count) { return count >= 1.0 - 1e-9 && count <= LUB_MAX_STEPS; }

int lub_step_count_range_outside(double fewest, double most, int exact, const char **qualifier)
{
    int out = 0;
    if (fewest > LUB_MAX_STEPS || !(fewest == fewest))
        out = 1;
    else if (!lub_step_count_ok(most) && !(most > LUB_MAX_STEPS))
        out = -1;
    *qualifier = exact ? "" : out > 0 ? "at least " : "at most ";
    return out;
}

double lub_step_count_excess(double count)
{
    if (lub_step_count_ok(count))
        return 0.0;
    if (!(count > 0.0) || !isfinite(count))
        return INFINITY;
    return count < 1.0 ? -log10(count) : log10(count / LUB_MAX_STEPS);
}

const char *lub_step_count_culprit(double count, const lub_step_alt *alts, int n)
{
    int best = 0;
    double best_excess = lub_step_count_excess(count);
    for (int k = 0; k < n; ++k) {
        const double e = lub_step_count_excess(alts[k].count);
        if (e < best_excess) {
            best_excess = e;
            best = k;
        }
    }
    return alts[best].pointer;
}

int lub_step_count_fail(lub_error *err, const char *pointer, double count, const char *qualifier,
                        const char *duration_member, const char *duration_text, double dt,
                        const char *step_origin)
{
    if (count > LUB_MAX_STEPS)
        return lub_fail(err, pointer,
                        "the run would take %s%.3g steps, more than the %.0e a run may take "
                        "(README, CLI contract, \"Step count\"): %s at a step of %.3g (%s); "
                        "lengthen the step or shorten %s",
                        qualifier, count, LUB_MAX_STEPS, duration_text, dt, step_origin,
                        duration_member);
    return lub_fail(err, pointer,
                    "the run would take %s%.3g steps: its step, %.3g (%s), is longer than %s, "
                    "and a run takes at least one whole step (README, CLI contract, \"Step "
                    "count\"); shorten the step or lengthen %s",
                    qualifier, count, dt, step_origin, duration_text, duration_member);
}

void lub_step_count_fell(char *out, size_t len, double dt, double strain, double safety,
                         long changes, double count)
{
    snprintf(out, len,
             "the automatic step fell to %.3g at strain %.4f (the pairs' summed stiffness, "
             "/dt_stiffness_safety %g; %ld changes), which would take the run to %.3g steps, "
             "more than the %.0e a run may take (README, CLI contract, \"Step count\"); lower "
             "/strain or /stiffness",
             dt, strain, safety, changes, count, LUB_MAX_STEPS);
}
