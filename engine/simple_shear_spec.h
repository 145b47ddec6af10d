/* simple_shear_spec.h — the spec of the `simple_shear` scene: its members, their ranges and
 * defaults, and the checks a spec must pass before anything runs (the cell must hold the
 * neighbour search, the step count must be in range, the pressure servo must not close the cell
 * in one step). schema/simple_shear.schema.json describes the same members for users.
 *
 * Units (dimensionless, scene_simple_shear.c): lengths in the mean radius a, viscosities in the
 * fluid's eta; stress unit eta gd (control "volume", gd = 1) or P (control "pressure", gd =
 * Iv); times in 1/gd or eta/P.
 *
 * Ownership: a lub_ss_params holds no pointer into the spec; nothing is allocated. Error
 * behaviour: the readers return 0, or -1 with *err naming the member (JSON pointer) and the
 * constraint it breaks.
 */
#ifndef LUBDEM_SIMPLE_SHEAR_SPEC_H
#define LUBDEM_SIMPLE_SHEAR_SPEC_H

#include <jansson.h>

#include "law_spec.h"
#include "spec_reader.h"

typedef struct {
    long long n, seed, snapshots;
    double initial_gap; /* the packing's smallest gap, units of a_ij (its margin, packing.h) */
    double radius_std, phi, Iv, St, stiffness, cutoff, skin, dt, dt_safety, strain;
    double dt_stiffness_safety; /* largest dt / lub_pairs_stiffness_dt of the automatic step */
    double target_rel_error, target_min_strain, transient_strain, sample_strain;
    double drag_viscosity;  /* drag towards the affine flow, units of eta (0: none) */
    int delaunay;           /* lubrication_pairs "delaunay" (1) or "cutoff" (0) */
    double delaunay_strain; /* strain between triangulation updates */
    int pressure;           /* control */
    double servo_gain, servo_filter_strain;
    int pdf_on;
    int pair_network; /* LUB_NETWORK_*: when to write the interaction network (pair_network.h) */
    long long pdf_nt, pdf_np;
    double pdf_start, pdf_interval;
    lub_law_spec law;
} lub_ss_params;

/* Most samples of the time series a run may keep (strain / sample_strain): each costs
 * LUB_SS_SAMPLE_BYTES of memory, reserved before the time loop for the whole /strain (also when
 * /target_rel_error stops the run earlier), and a row of LUB_SS_ROW_BYTES in result.h5. */
#define LUB_SS_MAX_SAMPLES 1e6
/* (SS_OBS_COUNT + 3) doubles: the series, their strain and two scratch arrays */
#define LUB_SS_SAMPLE_BYTES 232
#define LUB_SS_ROW_BYTES 520 /* the 65 doubles of one time-series row */

/* Largest change of L_y, as a fraction of itself, the pressure servo may make in one step (its
 * gain times the shear rate times the step); see lub_ss_read. */
#define LUB_SS_SERVO_STEP_MAX 0.5

/* Largest phi (1 + initial_gap/2)^3 a spec may ask for: the fraction of the spheres grown by
 * half the gap, which the packing reaches for every seed tried up to here (packing.h); the
 * defaults at /phi 0.6 give 0.609. */
#define LUB_SS_GROWN_PHI_MAX 0.62

/* Reads and checks spec (a JSON object, the "scene" member included), inserting every default
 * into it, so that it becomes the resolved spec; fills *p. */
int lub_ss_read(json_t *spec, lub_ss_params *p, lub_error *err);

/* lub_ss_read of a resolved spec, which it leaves untouched. */
int lub_ss_read_resolved(const json_t *resolved, lub_ss_params *p, lub_error *err);

/* The elastic bound of the step for a particle of radius r (in a), in the run's time unit:
 * sqrt(min(m/g, 0.4 m/k_t)) with m = (4/3) pi r^3 St/gd, g = /stiffness, k_t = /law/kt_ratio g
 * (lub_shear_elastic_dt computes the same for the packing's lightest particle). */
double lub_ss_elastic_dt(const lub_ss_params *p, double r);

/* The refusal of `count` steps of length dt (step_count.h; qualifier "" for the run's own
 * count, "at least " or "at most " for a bound), the run's lightest particle having radius r:
 * names the member whose default brings the count nearest the allowed range. Returns -1. */
int lub_ss_step_refusal(const lub_ss_params *p, double r, double count, double dt,
                        const char *qualifier, lub_error *err);

#endif
