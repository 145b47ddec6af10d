/* simple_shear_spec.c — reading and checking a `simple_shear` spec (simple_shear_spec.h). */
#include "simple_shear_spec.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

#include "network_output.h"
#include "packing.h"
#include "shear_system.h"
#include "step_count.h"
#include "step_stiffness.h"

#define SS_PI 3.14159265358979323846

static const lub_law_spec_opts ss_law_opts = {
    .allowed_terms = LUB_TERM_ALL,
    .default_terms = LUB_TERM_ALL,
    .tangential = 1,
    .default_eps = 0.02,
    .default_alpha = 1.0,
    .default_kt_ratio = 0.5,
    .default_mu = 0.5,
};

/* Smallest admissible cube side for the neighbour search (with margin for tilt/servo). */
static double ss_min_side(double radius_std, double cutoff, double skin, int delaunay)
{
    return 2.0 * lub_shear_listing_distance(cutoff, radius_std, skin, delaunay) / 0.8;
}

/* Defaults of the members the step count depends on (lub_ss_read, ss_check_steps). */
#define SS_DEFAULT_IV 0.01
#define SS_DEFAULT_ST 1e-2
#define SS_DEFAULT_DT_SAFETY 0.3
#define SS_DEFAULT_STRAIN 20.0
static double ss_default_stiffness(const lub_ss_params *p) { return p->pressure ? 1e4 : 1e6; }

/* The elastic bound of a particle of radius r (lub_shear_elastic_dt, which takes the lightest
 * particle's), from the spec: m = (4/3) pi r^3 rho, rho = St/gd, g = stiffness, k_t = kt_ratio
 * g, I = 0.4 m r^2. */
double lub_ss_elastic_dt(const lub_ss_params *p, double r)
{
    const double gd = p->pressure ? p->Iv : 1.0;
    const double m = 4.0 / 3.0 * SS_PI * r * r * r * p->St / gd;
    const double k_bulk = p->stiffness, k_t = p->law.kt_ratio * p->stiffness;
    double t2 = m / k_bulk;
    if (k_t > 0.0)
        t2 = fmin(t2, 0.4 * m / k_t);
    return sqrt(t2);
}

/* The run's step when its lightest particle has radius r. */
static double ss_step_at(const lub_ss_params *p, double r)
{
    return p->dt > 0.0 ? p->dt : p->dt_safety * lub_ss_elastic_dt(p, r);
}

/* The run's steps (step_count.h) when its lightest particle has radius r. */
static double ss_steps_at(const lub_ss_params *p, double r)
{
    const double gd = p->pressure ? p->Iv : 1.0;
    return lub_step_count(p->strain / gd, ss_step_at(p, r));
}

/* The refusal of `count` steps of length dt (qualifier: "" for the run's own, "at least " or
 * "at most " for a bound), the run's lightest particle (or the one of the bound) having radius
 * r: names the member whose default brings the count nearest the allowed range. -1. */
int lub_ss_step_refusal(const lub_ss_params *p, double r, double count, double dt,
                        const char *qualifier, lub_error *err)
{
    lub_step_alt alt[7];
    int n = 0;
    lub_ss_params q;
/* alt[n++]: the count with member `field` of the spec at `value`, the rest as it is */
#define SS_ALT(name, field, value)                                                                 \
    (q = *p, q.field = (value), alt[n++] = (lub_step_alt){(name), ss_steps_at(&q, r)})
    if (p->pressure) {
        SS_ALT("/Iv", Iv, SS_DEFAULT_IV);
    }
    if (p->dt > 0.0) {
        SS_ALT("/dt", dt, 0.0);
    } else {
        SS_ALT("/stiffness", stiffness, ss_default_stiffness(p));
        SS_ALT("/St", St, SS_DEFAULT_ST);
        SS_ALT("/law/kt_ratio", law.kt_ratio, ss_law_opts.default_kt_ratio);
        SS_ALT("/dt_safety", dt_safety, SS_DEFAULT_DT_SAFETY);
    }
    SS_ALT("/strain", strain, SS_DEFAULT_STRAIN);
    char duration[96], origin[240];
    if (p->pressure)
        snprintf(duration, sizeof duration, "/strain %.6g over /Iv %g (a time of %.6g eta/P)",
                 p->strain, p->Iv, p->strain / p->Iv);
    else
        snprintf(duration, sizeof duration, "/strain %.6g", p->strain);
    if (p->dt > 0.0)
        snprintf(origin, sizeof origin, "fixed by /dt");
    else
        snprintf(origin, sizeof origin,
                 "/dt_safety %g times dt_elastic, the elastic bound of the lightest particle, "
                 "which /stiffness, /St, /law/kt_ratio%s and /radius_std set",
                 p->dt_safety, p->pressure ? ", /Iv" : "");
#undef SS_ALT
    return lub_step_count_fail(err, lub_step_count_culprit(count, alt, n), count, qualifier,
                               "/strain", duration, dt, origin);
}

/* The step-count rule at validation: with /dt fixed the count is known; otherwise it lies
 * between the counts of the lightest particle's largest and smallest possible radii
 * (lub_packing_radius_bounds), and a spec is refused here when the whole range is outside
 * (the run checks its own count once the packing has given its radii). */
static int ss_check_steps(const lub_ss_params *p, lub_error *err)
{
    double r_lo = 1.0, r_hi = 1.0;
    if (p->dt <= 0.0)
        lub_packing_radius_bounds(p->radius_std, &r_lo, &r_hi);
    const double fewest = ss_steps_at(p, r_hi), most = ss_steps_at(p, r_lo);
    const char *qualifier;
    const int out = lub_step_count_range_outside(fewest, most, p->dt > 0.0, &qualifier);
    if (!out)
        return 0;
    const double count = out > 0 ? fewest : most;
    /* the step itself, not the duration over the count (0 for a count of inf at 5e-324) */
    const double r = out > 0 ? r_hi : r_lo;
    return lub_ss_step_refusal(p, r, count, ss_step_at(p, r), qualifier, err);
}

/* Imposed pressure: the servo sets the strain rate of L_y to /servo/gain gd times the pressure
 * error, which it clips to [-1, 1], and the cell is advanced by one explicit step, L_y (1 +
 * L_yy dt): at a full error (a cell below the pressure, as every run starts) L_y changes by
 * gain gd dt of itself in one step, and the cell closes at 1. A servo is meant to follow the
 * pressure over many steps; refused when that change reaches LUB_SS_SERVO_STEP_MAX at the shortest
 * step the spec allows (the lightest particle's, radius r_lo of lub_packing_radius_bounds, or
 * /dt). Runs with changes of 0.17 to 0.87 per step (Iv 10, St 10, gains 4-20) failed within 14
 * steps, the cell squeezed below the listing distance or particles thrown across it. */
static int ss_check_servo(const lub_ss_params *p, lub_error *err)
{
    if (!p->pressure)
        return 0;
    double r_lo = 1.0, r_hi = 1.0;
    if (p->dt <= 0.0)
        lub_packing_radius_bounds(p->radius_std, &r_lo, &r_hi);
    const double dt = p->dt > 0.0 ? p->dt : p->dt_safety * lub_ss_elastic_dt(p, r_lo);
    const double closing = p->servo_gain * p->Iv * dt; /* gd = Iv in units of eta/P */
    if (closing < LUB_SS_SERVO_STEP_MAX)
        return 0;
    return lub_fail(err, "/servo/gain",
                    "the pressure servo would change L_y by %.3g of itself in one step "
                    "(/servo/gain times the shear rate times the step %.3g eta/P, which is %s), "
                    "where it must stay below %g (studied: 0.25-4 at steps far below that); lower "
                    "/servo/gain below %.3g, or shorten the step (got %g)",
                    closing, dt,
                    p->dt > 0.0 ? "fixed by /dt"
                                : "/dt_safety times the elastic bound, which /St, /stiffness, "
                                  "/law/kt_ratio and /Iv set",
                    LUB_SS_SERVO_STEP_MAX, p->servo_gain * LUB_SS_SERVO_STEP_MAX / closing,
                    p->servo_gain);
}

int lub_ss_read(json_t *spec, lub_ss_params *p, lub_error *err)
{
    static const char *keys[] = {"scene",
                                 "n_particles",
                                 "seed",
                                 "radius_std",
                                 "control",
                                 "phi",
                                 "Iv",
                                 "St",
                                 "stiffness",
                                 "cutoff",
                                 "skin",
                                 "dt",
                                 "dt_safety",
                                 "dt_stiffness_safety",
                                 "strain",
                                 "target_rel_error",
                                 "target_min_strain",
                                 "transient_strain",
                                 "sample_strain",
                                 "snapshots",
                                 "pair_network",
                                 "servo",
                                 "microstructure",
                                 "law",
                                 "drag_viscosity",
                                 "lubrication_pairs",
                                 "delaunay_update_strain",
                                 "initial_gap",
                                 NULL};
    static const char *controls[] = {"volume", "pressure", NULL};
    static const char *pair_sets[] = {"cutoff", "delaunay", NULL};
    if (lub_spec_only_keys(spec, "", keys, err))
        return -1;
    const char *control = NULL;
    if (lub_spec_enum(spec, "", "control", controls, "volume", &control, err))
        return -1;
    p->pressure = strcmp(control, "pressure") == 0;
    const lub_range phi_r = {0.05, 0.6, 0, 0};
    const lub_range std_r = {0.0, 0.2, 0, 0};
    const lub_range iv_r = {1e-6, 10.0, 0, 0};
    const lub_range st_r = {1e-8, 10.0, 0, 0};
    const lub_range k_r = {10.0, 1e9, 0, 0};
    const lub_range cut_r = {0.1, 10.0, 0, 0};
    const lub_range skin_r = {0.05, 2.0, 0, 0};
    const lub_range saf_r = {0.0, 1.0, 1, 0};
    const lub_range rel_r = {0.0, 1.0, 0, 1};
    const lub_range samp_r = {1e-4, 10.0, 0, 0};
    if (lub_spec_integer(spec, "", "n_particles", 2, 10000000, 1, 1000, &p->n, err) ||
        lub_spec_integer(spec, "", "seed", 0, 4294967295LL, 1, 1, &p->seed, err) ||
        lub_spec_number(spec, "", "radius_std", std_r, 1, 0.05, &p->radius_std, err) ||
        lub_spec_number(spec, "", "phi", phi_r, 1, 0.5, &p->phi, err) ||
        lub_spec_number(spec, "", "initial_gap", (lub_range){0.001, 0.2, 0, 0}, 1, 0.01,
                        &p->initial_gap, err))
        return -1;
    /* the packing must reach /phi with every gap >= /initial_gap a_ij (packing.h) */
    const double grown = p->phi * pow(1.0 + 0.5 * p->initial_gap, 3);
    if (grown > LUB_SS_GROWN_PHI_MAX)
        return lub_fail(err, "/initial_gap",
                        "the packing cannot promise gaps of %g a_ij at /phi %g: the spheres grown "
                        "by half that gap would fill phi (1 + initial_gap/2)^3 = %.4g, above the "
                        "%g the packing reaches reliably; lower /initial_gap to at most %g or "
                        "/phi to at most %g",
                        p->initial_gap, p->phi, grown, LUB_SS_GROWN_PHI_MAX,
                        floor(2e5 * (cbrt(LUB_SS_GROWN_PHI_MAX / p->phi) - 1.0)) / 1e5,
                        floor(1e4 * LUB_SS_GROWN_PHI_MAX / pow(1.0 + 0.5 * p->initial_gap, 3)) /
                            1e4);
    if (p->pressure) {
        if (lub_spec_number(spec, "", "Iv", iv_r, 1, SS_DEFAULT_IV, &p->Iv, err))
            return -1;
    } else if (json_object_get(spec, "Iv")) {
        return lub_fail(err, "/Iv", "only used with \"control\": \"pressure\"");
    }
    if (lub_spec_number(spec, "", "St", st_r, 1, SS_DEFAULT_ST, &p->St, err) ||
        lub_spec_number(spec, "", "stiffness", k_r, 1, ss_default_stiffness(p), &p->stiffness,
                        err) ||
        lub_spec_number(spec, "", "cutoff", cut_r, 1, 2.0, &p->cutoff, err) ||
        lub_spec_number(spec, "", "skin", skin_r, 1, 0.5, &p->skin, err) ||
        lub_spec_number(spec, "", "dt", LUB_NONNEGATIVE, 1, 0.0, &p->dt, err) ||
        lub_spec_number(spec, "", "dt_safety", saf_r, 1, SS_DEFAULT_DT_SAFETY, &p->dt_safety,
                        err) ||
        lub_spec_number(spec, "", "dt_stiffness_safety", (lub_range){0.0, 2.0, 0, 0}, 1,
                        LUB_DT_STIFFNESS_SAFETY, &p->dt_stiffness_safety, err) ||
        lub_spec_number(spec, "", "strain", (lub_range){0.0, 1e6, 1, 0}, 1, SS_DEFAULT_STRAIN,
                        &p->strain, err) ||
        lub_spec_number(spec, "", "target_rel_error", rel_r, 1, 0.0, &p->target_rel_error, err) ||
        lub_spec_number(spec, "", "target_min_strain", LUB_NONNEGATIVE, 1, 5.0,
                        &p->target_min_strain, err) ||
        lub_spec_number(spec, "", "transient_strain", LUB_NONNEGATIVE, 1, 2.0, &p->transient_strain,
                        err) ||
        lub_spec_number(spec, "", "sample_strain", samp_r, 1, 0.02, &p->sample_strain, err) ||
        lub_spec_integer(spec, "", "snapshots", 0, 1000, 1, 1, &p->snapshots, err) ||
        lub_spec_pair_network(spec, &p->pair_network, err) ||
        lub_spec_number(spec, "", "drag_viscosity", (lub_range){0.0, 1e3, 0, 0}, 1, 0.0,
                        &p->drag_viscosity, err))
        return -1;
    char cost[120];
    snprintf(cost, sizeof cost,
             "%d bytes of memory each, reserved for the whole /strain, and %d bytes of result.h5",
             LUB_SS_SAMPLE_BYTES, LUB_SS_ROW_BYTES);
    if (lub_spec_sample_count(p->strain, p->sample_strain, LUB_SS_MAX_SAMPLES, cost, err))
        return -1;
    const char *pair_set = NULL;
    if (lub_spec_enum(spec, "", "lubrication_pairs", pair_sets, "cutoff", &pair_set, err))
        return -1;
    p->delaunay = strcmp(pair_set, "delaunay") == 0;
    if (p->delaunay) {
        if (lub_spec_number(spec, "", "delaunay_update_strain", (lub_range){0.0, 1.0, 1, 0}, 1,
                            0.005, &p->delaunay_strain, err))
            return -1;
    } else if (json_object_get(spec, "delaunay_update_strain")) {
        return lub_fail(err, "/delaunay_update_strain",
                        "only used with \"lubrication_pairs\": \"delaunay\"");
    }
    if (p->pressure) {
        json_t *servo = lub_spec_object(spec, "", "servo", err);
        static const char *skeys[] = {"gain", "filter_strain", NULL};
        if (!servo || lub_spec_only_keys(servo, "/servo", skeys, err) ||
            lub_spec_number(servo, "/servo", "gain", (lub_range){0.0, 100.0, 1, 0}, 1, 1.0,
                            &p->servo_gain, err) ||
            lub_spec_number(servo, "/servo", "filter_strain", (lub_range){1e-4, 10.0, 0, 0}, 1,
                            0.05, &p->servo_filter_strain, err))
            return -1;
    } else if (json_object_get(spec, "servo")) {
        return lub_fail(err, "/servo", "only used with \"control\": \"pressure\"");
    }
    json_t *ms = lub_spec_object(spec, "", "microstructure", err);
    static const char *mkeys[] = {"enabled",      "n_theta",         "n_phi",
                                  "start_strain", "interval_strain", NULL};
    if (!ms || lub_spec_only_keys(ms, "/microstructure", mkeys, err) ||
        lub_spec_bool(ms, "/microstructure", "enabled", 1, 0, &p->pdf_on, err) ||
        lub_spec_integer(ms, "/microstructure", "n_theta", 1, 360, 1, 13, &p->pdf_nt, err) ||
        lub_spec_integer(ms, "/microstructure", "n_phi", 1, 360, 1, 9, &p->pdf_np, err) ||
        lub_spec_number(ms, "/microstructure", "start_strain", LUB_NONNEGATIVE, 1, 5.0,
                        &p->pdf_start, err) ||
        lub_spec_number(ms, "/microstructure", "interval_strain", samp_r, 1, 0.1, &p->pdf_interval,
                        err))
        return -1;
    json_t *law = lub_spec_object(spec, "", "law", err);
    if (!law || lub_law_spec_resolve(law, "/law", &ss_law_opts, &p->law, err) ||
        lub_law_spec_check_cutoff(&p->law, "/law", p->cutoff, err))
        return -1;

    /* the cell must hold twice the neighbour listing distance (see neighbor_list.h) */
    double mean_r3 = 1.0 + 3.0 * p->radius_std * p->radius_std;
    double side = cbrt((double)p->n * 4.0 / 3.0 * SS_PI * mean_r3 / p->phi);
    double need = ss_min_side(p->radius_std, p->cutoff, p->skin, p->delaunay);
    if (side < need) {
        long long nmin =
            (long long)ceil(need * need * need * p->phi / (4.0 / 3.0 * SS_PI * mean_r3));
        return lub_fail(err, "/n_particles",
                        "too few particles for the cut-off and skin: the cubic cell side %.3g a "
                        "must be >= %.3g a, i.e. n_particles >= %lld at phi = %g (got %lld)",
                        side, need, nmin, p->phi, p->n);
    }
    if (ss_check_servo(p, err))
        return -1;
    return ss_check_steps(p, err);
}

/* lub_ss_read fills the defaults in place: a copy of the resolved spec is read */
int lub_ss_read_resolved(const json_t *resolved, lub_ss_params *p, lub_error *err)
{
    json_t *copy = json_deep_copy(resolved);
    const int rc = copy ? lub_ss_read(copy, p, err) : -1;
    json_decref(copy);
    return rc;
}
