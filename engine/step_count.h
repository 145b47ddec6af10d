/* step_count.h — the one rule on how many steps a time-stepping scene may take
 * (falling_sphere, two_spheres_shear, simple_shear, resuspension; README, CLI contract, "Step
 * count").
 *
 * A run of duration T at step dt takes T/dt steps, counted in double before anything becomes an
 * integer. A run may take from 1 to LUB_MAX_STEPS of them:
 *   - at least one whole step (T >= dt to 1e-9): a longer step ends the run past its duration,
 *     and a step so long that T/dt rounds to no step at all leaves the initial state as the
 *     "result";
 *   - at most 1e12: far beyond any run that can finish (two spheres, the cheapest scene, take
 *     about 50 ns a step: 1e12 steps are 14 hours; a many-particle step takes microseconds to
 *     seconds), and well inside the int64 step counters (2^63 = 9.2e18) whatever the rounding.
 * A spec outside is refused with exit 2: at validation where the step follows from the spec,
 * otherwise as soon as the run knows its step (simple_shear: after the packing), before any step.
 *
 * Units: any consistent time unit. Pure functions; no allocation, no global state.
 */
#ifndef LUBDEM_STEP_COUNT_H
#define LUBDEM_STEP_COUNT_H

#include "spec_reader.h"

#define LUB_MAX_STEPS 1e12

/* T/dt, the steps of a run of duration T at step dt (NaN, 0 or inf when either is not a
 * positive finite number: lub_step_count_ok says no to all three). */
double lub_step_count(double duration, double dt);

/* 1 when 1 - 1e-9 <= count <= LUB_MAX_STEPS, else 0 (also for NaN). */
int lub_step_count_ok(double count);

/* For a run that knows its count only as a range [fewest, most] before it starts (the step set
 * by its lightest particle, whose radius lies between two bounds): +1 when even the fewest is
 * too many (or NaN), -1 when even the most is too few, 0 when some count in the range is
 * allowed (the run then checks its own count once it knows it). *qualifier: the words before
 * the refused count (lub_step_count_fail): "" when `exact` (the range is one count), else
 * "at least " or "at most ". */
int lub_step_count_range_outside(double fewest, double most, int exact, const char **qualifier);

/* How far count lies outside the allowed range, in decades: 0 inside, +inf for 0, inf or NaN. */
double lub_step_count_excess(double count);

/* A member a step count depends on, and the count the run would have with that member at its
 * default value (the other members as given). */
typedef struct {
    const char *pointer;
    double count;
} lub_step_alt;

/* The member a refusal names: of alts[0..n-1], the one whose default brings the count nearest
 * the allowed range (lub_step_count_excess; the first on a tie: the scenes list the members of
 * the step before the duration), or alts[0] when none brings it nearer than `count`, the run's
 * own. */
const char *lub_step_count_culprit(double count, const lub_step_alt *alts, int n);

/* The refusal of a count that is not lub_step_count_ok: fills *err at `pointer` with what the
 * count would be (`qualifier` before it: "" for the run's own count, "at least " or "at most "
 * for a bound), the duration (`duration_text`, e.g. "/duration 10"), the step dt and where it
 * comes from (`step_origin`, e.g. "fixed by /dt", or "/dt_safety 0.5 times dt_critical, which
 * /stiffness, /St and /u0 set"), and what to change (`duration_member`, e.g. "/duration", or
 * the step). Returns -1 (for "return lub_step_count_fail(...)"). */
int lub_step_count_fail(lub_error *err, const char *pointer, double count, const char *qualifier,
                        const char *duration_member, const char *duration_text, double dt,
                        const char *step_origin);

/* The diagnostic of a run whose automatic step (step_stiffness.h) fell, at `strain`, to dt, so
 * far that the run would take `count` steps, beyond LUB_MAX_STEPS: into out[len]. safety: the
 * spec's /dt_stiffness_safety; changes: the step's changes so far. */
void lub_step_count_fell(char *out, size_t len, double dt, double strain, double safety,
                         long changes, double count);

#endif
