/* shear_run_checks.c — advisory checks of a finished simple_shear run (see the header). */
#include "shear_run_checks.h"

#include <math.h>
#include <stdio.h>

int lub_shear_run_warnings(const lub_shear_run_state *st,
                           char out[LUB_SHEAR_WARNINGS_MAX][LUB_SHEAR_WARNING_LEN])
{
    int n = 0;
    if (isfinite(st->elastic_number) && st->elastic_number < LUB_SHEAR_EL_MIN)
        snprintf(out[n++], LUB_SHEAR_WARNING_LEN,
                 "elastic number k/(P a) = %.3g is below %.0e: the contacts are not rigid "
                 "enough for rigid-sphere rheology (eta_r and phi still move with the "
                 "stiffness there); raise /stiffness by %.2g or more",
                 st->elastic_number, LUB_SHEAR_EL_MIN, LUB_SHEAR_EL_MIN / st->elastic_number);
    if (isfinite(st->kinetic_share) && st->kinetic_share > LUB_SHEAR_KINETIC_SHARE_MAX)
        snprintf(out[n++], LUB_SHEAR_WARNING_LEN,
                 "the kinetic stress is %.2g %% of sigma_xy, above %.0f %%: particle inertia "
                 "enters the rheology; lower /St",
                 100.0 * st->kinetic_share, 100.0 * LUB_SHEAR_KINETIC_SHARE_MAX);
    if (isfinite(st->crushed_fraction) && st->crushed_fraction > LUB_SHEAR_CRUSHED_MAX)
        snprintf(out[n++], LUB_SHEAR_WARNING_LEN,
                 "asperities crushed in %.2g %% of the contacts (crushed_contact_fraction, "
                 "u_n < -alpha eps a), above %.0f %%: the results depend on the stiffness; "
                 "raise /stiffness",
                 100.0 * st->crushed_fraction, 100.0 * LUB_SHEAR_CRUSHED_MAX);
    if (isfinite(st->bond_order_q6) && st->bond_order_q6 > LUB_SHEAR_Q6_MAX)
        snprintf(out[n++], LUB_SHEAR_WARNING_LEN,
                 "bond order Q6 = %.3f is above %.2g: the cell is ordering (disordered "
                 "sheared packings give 0.04-0.09), a finite-size effect; raise /n_particles "
                 "or /radius_std",
                 st->bond_order_q6, LUB_SHEAR_Q6_MAX);
    if (isfinite(st->lost_pairs) && st->lost_pairs > 0.0)
        snprintf(out[n++], LUB_SHEAR_WARNING_LEN,
                 "%.0f active pair states were lost at neighbour-list rebuilds (contacts "
                 "restarted without their history); raise /skin or lower /dt_safety",
                 st->lost_pairs);
    if (!st->steady)
        snprintf(out[n++], LUB_SHEAR_WARNING_LEN,
                 "no steady state detected (the transient lasts into the second half of the "
                 "run, or the watched series drift after it): the means are not steady-state "
                 "values; raise /strain");
    return n;
}
