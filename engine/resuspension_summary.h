/* resuspension_summary.h — the results of a resuspension run (scene_resuspension.c) into its
 * outputs: the steady-state profiles (resuspension_statistics.h) into result.h5 /profiles and
 * /eta_vs_phi, and the summary (summary.json through the run context): the headline numbers with
 * units and error bars, the dimensionless groups (Shields, Acrivos, inertial and Stokes numbers),
 * what the run did (steps, time step and its changes, bed and cell geometry, the loop's extremes),
 * the active force terms, and the warnings that say which member to change when a result cannot
 * be read as the steady viscous resuspension (inertia, no steady state, an inhomogeneous shear,
 * the lid reached, a fixed /dt above its bounds, crushed asperities, network frames skipped).
 *
 * Units: those of the scene (a = eta = gd = 1: length a, time 1/gd, energy eta gd a^3); each
 * summary entry states its own. Ownership: nothing is kept; the pointers in lub_rs_outcome are
 * borrowed for the call. Errors: lub_rs_write_profiles returns 0, or -1 with the reason in
 * lub_h5_last_error(out); the summary cannot fail (jansson's allocation failures are not
 * checked, as elsewhere in the scenes).
 */
#ifndef LUBDEM_RESUSPENSION_SUMMARY_H
#define LUBDEM_RESUSPENSION_SUMMARY_H

#include <stdint.h>

#include "h5md_writer.h"
#include "resuspension_spec.h"
#include "resuspension_statistics.h"
#include "resuspension_system.h"
#include "run_context.h"
#include "step_stiffness.h"

/* What the run did besides its statistics. */
typedef struct {
    const lub_rs_system *system;          /* at the end: step, time, counters, law terms */
    const lub_step_control *step_control; /* the step's history: smallest, changes, ratio */
    const lub_h5_frames *network;         /* /pair_network frames (NULL: none written) */
    double dt;                            /* the step at the end (1/gd) */
    double dt_critical;                   /* the single-pair elastic bound (1/gd) */
    double cell_width, floor_radius;      /* a */
    double y_floor, y_lid;                /* floor centre plane and lid (a) */
    double initial_height;                /* of the bed above the floor centre plane (a) */
    double solid_volume;                  /* of the free spheres (a^3) */
    double initial_phi;                   /* the packed layer's solid fraction */
    int64_t averaged_samples;             /* profiles averaged */
    double transient_end_strain;      /* strain of the height sample where MSER-5 ends the height's
                                         transient (lub_rs_stats.transient_end; NaN without samples) */
    double min_clearance;             /* smallest gap of a free sphere above the floor plane (a) */
    int64_t below_floor_max;          /* most free sphere centres below the floor plane at once */
    double max_kinetic_energy;        /* largest fluctuating kinetic energy sampled (eta gd a^3) */
    double contacts_sum, crushed_sum; /* contacts and crushed ones summed over the averaged
                                         samples */
    double drag_share_sum;            /* gradient: the shear drag's vertical force over the
                                         buoyant weight, summed over the averaged samples */
    int stopped;                      /* 1: a stop request ended the time loop */
} lub_rs_outcome;

/* The profiles of st (nb bins; eta_vs_phi with `rows` rows, none when 0) into out. */
int lub_rs_write_profiles(lub_h5 *out, int nb, const lub_rs_stats_profiles *pr, int rows);

/* The summary's results and extras (ctx->summary_results, ctx->summary_extra). */
void lub_rs_write_summary(lub_run_ctx *ctx, const lub_rs_spec *p, const lub_rs_scales *sc,
                          const lub_rs_stats *st, const lub_rs_outcome *o);

#endif
