/* scene_simple_shear.c — tri-periodic simple-shear rheometer of a dense suspension of rough,
 * lubricated, frictional spheres (physics-reference §2–§3; seed 000 rheology article and
 * normal-stress chapter; seed 004).
 *
 * Units (dimensionless):
 *   length a = mean radius (radii Gaussian, relative std `radius_std`), fluid viscosity eta = 1;
 *   control "volume":   shear rate gd = 1  -> stress unit eta gd, time unit 1/gd;
 *   control "pressure": particle pressure P = 1 -> stress unit P, gd = Iv P/eta = Iv,
 *                       time unit eta/P.
 *   Density from the Stokes number St = rho gd a^2/eta; bulk stiffness g = stiffness * s0 * a
 *   with s0 = eta gd (volume) or P (pressure); k_n = alpha g; k_t = kt_ratio g.
 * Controls: imposed volume (cell fixed in y, pressure measured) or imposed particle pressure
 * (servo on the gradient-direction cell size, see servo_step()).
 * Observables: virial stress split NC/SC/NL/SL/kinetic (stress.h), phi, P = -sigma_yy,
 * mu = sigma_xy/P, eta_r = sigma_xy/(eta gd), Iv = eta gd/P, eta_ii = -sigma_ii/(eta gd),
 * sigma_11/sigma_22, sigma_33/sigma_22, coordination Z and contact number Z_c (2 x pairs / N),
 * the global bond order Q6 of the first neighbour shell (bond_order.h: 0.05-0.09 in sheared
 * disordered packings, 0.57 for fcc; a rise flags ordering of the cell), optional microstructure
 * (microstructure.h). Steady state and error bars: stats.h. Optional `drag_viscosity` eta_d: a
 * Stokes drag -6 pi eta_d eta r (v - L x) on every particle towards the affine flow (the shear drag
 * of the resuspension scene's gradient orientation), so that its effect on the stresses can be
 * measured in homogeneous shear; "affine_drag" is then listed in active_terms. The drag is a body
 * force: it is not part of the virial stress. The summary's elastic_number (stiffness s0/<P>)
 * and warnings come from the advisory checks of shear_run_checks.h.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "h5md_continue.h"
#include "law_spec.h"
#include "packing.h"
#include "network_output.h"
#include "pair_network.h"
#include "run_context.h"
#include "scene.h"
#include "scene_summary.h"
#include "shear_checkpoint.h"
#include "shear_run_checks.h"
#include "state_checkpoint.h"
#include "shear_system.h"
#include "stats.h"
#include "step_count.h"
#include "step_schedule.h"
#include "step_stiffness.h"

#define SS_PI 3.14159265358979323846
/* bond_order_q6: bonds are pairs with centre distance below this factor times r_i + r_j
 * (gaps below 0.4 a_ij: the first shell of neighbours) */
#define SS_BOND_FACTOR 1.2

typedef struct {
    long long n, seed, snapshots;
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
} ss_params;

static const lub_law_spec_opts ss_law_opts = {
    .allowed_terms = LUB_TERM_ALL,
    .default_terms = LUB_TERM_ALL,
    .tangential = 1,
    .default_eps = 0.02,
    .default_alpha = 1.0,
    .default_kt_ratio = 0.5,
    .default_mu = 0.5,
};

/* Most samples of the time series a run may keep (strain / sample_strain): each costs
 * SS_SAMPLE_BYTES of memory, reserved before the time loop for the whole /strain (also when
 * /target_rel_error stops the run earlier), and a row of SS_ROW_BYTES in result.h5. */
#define SS_MAX_SAMPLES 1e6
#define SS_SAMPLE_BYTES 232 /* (S_COUNT + 3) doubles: series, strain, two scratch arrays */
#define SS_ROW_BYTES 520    /* the 65 doubles of one time-series row */

/* Smallest admissible cube side for the neighbour search (with margin for tilt/servo). */
static double ss_min_side(double radius_std, double cutoff, double skin)
{
    double rmax = fmax(1.0 + 3.0 * radius_std, 1.0);
    double dmax = 2.0 * rmax * (1.0 + 0.5 * cutoff) + skin;
    return 2.0 * dmax / 0.8;
}

/* Defaults of the members the step count depends on (ss_read, ss_check_steps). */
#define SS_DEFAULT_IV 0.01
#define SS_DEFAULT_ST 1e-2
#define SS_DEFAULT_DT_SAFETY 0.3
#define SS_DEFAULT_STRAIN 20.0
static double ss_default_stiffness(const ss_params *p) { return p->pressure ? 1e4 : 1e6; }

/* The elastic bound of a particle of radius r (lub_shear_elastic_dt, which takes the lightest
 * particle's), from the spec: m = (4/3) pi r^3 rho, rho = St/gd, g = stiffness, k_t = kt_ratio
 * g, I = 0.4 m r^2. */
static double ss_elastic_dt(const ss_params *p, double r)
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
static double ss_step_at(const ss_params *p, double r)
{
    return p->dt > 0.0 ? p->dt : p->dt_safety * ss_elastic_dt(p, r);
}

/* The run's steps (step_count.h) when its lightest particle has radius r. */
static double ss_steps_at(const ss_params *p, double r)
{
    const double gd = p->pressure ? p->Iv : 1.0;
    return lub_step_count(p->strain / gd, ss_step_at(p, r));
}

/* The refusal of `count` steps of length dt (qualifier: "" for the run's own, "at least " or
 * "at most " for a bound), the run's lightest particle (or the one of the bound) having radius
 * r: names the member whose default brings the count nearest the allowed range. -1. */
static int ss_step_refusal(const ss_params *p, double r, double count, double dt,
                           const char *qualifier, lub_error *err)
{
    lub_step_alt alt[7];
    int n = 0;
    ss_params q;
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
static int ss_check_steps(const ss_params *p, lub_error *err)
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
    return ss_step_refusal(p, r, count, ss_step_at(p, r), qualifier, err);
}

/* Imposed pressure: the servo sets the strain rate of L_y to /servo/gain gd times the pressure
 * error, which it clips to [-1, 1], and the cell is advanced by one explicit step, L_y (1 +
 * L_yy dt): at a full error (a cell below the pressure, as every run starts) L_y changes by
 * gain gd dt of itself in one step, and the cell closes at 1. A servo is meant to follow the
 * pressure over many steps; refused when that change reaches SS_SERVO_STEP_MAX at the shortest
 * step the spec allows (the lightest particle's, radius r_lo of lub_packing_radius_bounds, or
 * /dt). Runs with changes of 0.17 to 0.87 per step (Iv 10, St 10, gains 4-20) failed within 14
 * steps, the cell squeezed below the listing distance or particles thrown across it. */
#define SS_SERVO_STEP_MAX 0.5
static int ss_check_servo(const ss_params *p, lub_error *err)
{
    if (!p->pressure)
        return 0;
    double r_lo = 1.0, r_hi = 1.0;
    if (p->dt <= 0.0)
        lub_packing_radius_bounds(p->radius_std, &r_lo, &r_hi);
    const double dt = p->dt > 0.0 ? p->dt : p->dt_safety * ss_elastic_dt(p, r_lo);
    const double closing = p->servo_gain * p->Iv * dt; /* gd = Iv in units of eta/P */
    if (closing < SS_SERVO_STEP_MAX)
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
                    SS_SERVO_STEP_MAX, p->servo_gain * SS_SERVO_STEP_MAX / closing, p->servo_gain);
}

static int ss_read(json_t *spec, ss_params *p, lub_error *err)
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
        lub_spec_number(spec, "", "phi", phi_r, 1, 0.5, &p->phi, err))
        return -1;
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
             SS_SAMPLE_BYTES, SS_ROW_BYTES);
    if (lub_spec_sample_count(p->strain, p->sample_strain, SS_MAX_SAMPLES, cost, err))
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
    double need = ss_min_side(p->radius_std, p->cutoff, p->skin);
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

static int ss_resolve(json_t *spec, lub_error *err)
{
    ss_params p;
    return ss_read(spec, &p, err);
}

/* ------------------------------------------------------------------------------------------ */

/* Scalar series kept in memory for the statistics (sampled every sample_strain). */
enum {
    S_PHI,
    S_P,
    S_MU,
    S_ETA,
    S_IV,
    S_SXY,
    S_ETA11,
    S_ETA22,
    S_ETA33,
    S_L1,
    S_L3,
    S_Z,
    S_ZC,
    S_XY_NC,
    S_XY_SC,
    S_XY_NL,
    S_XY_SL,
    S_XY_KIN,
    S_YY_NC,
    S_YY_SC,
    S_YY_NL,
    S_YY_SL,
    S_YY_KIN,
    S_CRUSHED,
    S_SLIDING,
    S_Q6,
    S_COUNT
};
_Static_assert((S_COUNT + 3) * sizeof(double) == SS_SAMPLE_BYTES,
               "SS_SAMPLE_BYTES: the series, their strain and the two scratch arrays");
static const char *s_names[S_COUNT] = {"phi",
                                       "pressure",
                                       "mu",
                                       "eta_r",
                                       "Iv",
                                       "sigma_xy",
                                       "eta_11",
                                       "eta_22",
                                       "eta_33",
                                       "sigma11_over_sigma22",
                                       "sigma33_over_sigma22",
                                       "Z",
                                       "Z_contact",
                                       "sigma_xy_normal_contact",
                                       "sigma_xy_tangential_contact",
                                       "sigma_xy_normal_lubrication",
                                       "sigma_xy_tangential_lubrication",
                                       "sigma_xy_kinetic",
                                       "sigma_yy_normal_contact",
                                       "sigma_yy_tangential_contact",
                                       "sigma_yy_normal_lubrication",
                                       "sigma_yy_tangential_lubrication",
                                       "sigma_yy_kinetic",
                                       "crushed_contact_fraction",
                                       "sliding_contact_fraction",
                                       "bond_order_q6"};

typedef struct {
    double *v[S_COUNT];
    double *strain;
    size_t n, cap;
} ss_series;

/* Grows the series (and the statistics' scratch arrays) to hold cap samples; 0 or -1 (no
 * memory: the arrays keep their contents). Called before the time loop and when the step
 * changes. */
static int ss_series_reserve(ss_series *ser, double **scratch, double **ratio_z, size_t cap)
{
    if (cap <= ser->cap)
        return 0;
    double **arrays[S_COUNT + 3];
    int n = 0;
    for (int k = 0; k < S_COUNT; ++k)
        arrays[n++] = &ser->v[k];
    arrays[n++] = &ser->strain;
    arrays[n++] = scratch;
    arrays[n++] = ratio_z;
    for (int k = 0; k < n; ++k) {
        double *grown = realloc(*arrays[k], cap * sizeof(double));
        if (!grown)
            return -1;
        *arrays[k] = grown;
    }
    ser->cap = cap;
    return 0;
}

/* Servo (imposed pressure). P_f is an exponential low-pass of the instantaneous pressure
 * -sigma_yy with time constant filter_strain/gd; the gradient-direction dilation rate is
 *   L_yy = gain * gd * clamp((P_f - P)/P, -1, 1):
 * the cell expands when the filtered pressure is too high and contracts when it is too low.
 * The change of L_yy is applied as a homogeneous velocity change (lub_shear_set_gradient),
 * so the particles follow the cell without a pressure wave. */
static void servo_step(lub_shear_system *s, double p_inst, double *p_f, double dt, double gd,
                       const ss_params *p)
{
    double tau = p->servo_filter_strain / gd;
    double w = dt / tau;
    if (w > 1.0)
        w = 1.0;
    *p_f += w * (p_inst - *p_f);
    double err = (*p_f - 1.0);
    if (err > 1.0)
        err = 1.0;
    if (err < -1.0)
        err = -1.0;
    double L[3][3];
    memcpy(L, s->cell.L, sizeof L);
    L[1][1] = p->servo_gain * gd * err;
    lub_shear_set_gradient(s, L);
}

/* End of the transient: the first sample at or after transient_strain, moved later to the
 * latest MSER-5 truncation of the control-relevant series (phi and mu at imposed pressure,
 * P and eta_r at imposed volume), which are written to watch[] (terminated by -1) unless
 * watch is NULL. The summary's steady window starts there; so does the target-error stop's. */
static size_t ss_steady_start(const ss_series *ser, int pressure, double transient_strain,
                              int watch[3])
{
    size_t start = 0;
    while (start < ser->n && ser->strain[start] < transient_strain)
        ++start;
    const int watched[3] = {pressure ? S_PHI : S_P, pressure ? S_MU : S_ETA, -1};
    if (watch)
        memcpy(watch, watched, sizeof watched);
    for (int w = 0; w < 2; ++w) {
        size_t d = lub_stats_mser(ser->v[watched[w]], ser->n, 5, NULL);
        if (d > start)
            start = d;
    }
    return start > ser->n ? ser->n : start;
}

/* A ratio observable as the ratio of the time averages of its numerator and denominator
 * series, over the later of their two steady windows (lub_stats_analyse with min_start), with
 * its delta-method standard error (lub_stats_ratio). The mean of the sampled ratios would be
 * biased where the denominator fluctuates: at imposed volume P varies by 20-45 % (rms),
 * mean(sigma_xy/P) exceeded <sigma_xy>/<P> by up to 4.4 % and mean(gd/P) exceeded gd/<P> by
 * up to 18 % (README "Steady state and error bars"), and where P nears zero the mean of the
 * ratios means nothing. z, scratch: ser->n doubles each. */
static void ss_ratio_stat(const ss_series *ser, int num, int den, size_t min_start, double *z,
                          double *scratch, lub_stats_result *r)
{
    lub_stats_result rx, ry;
    lub_stats_analyse(ser->v[num], ser->n, min_start, scratch, &rx);
    lub_stats_analyse(ser->v[den], ser->n, min_start, scratch, &ry);
    const size_t d = rx.start > ry.start ? rx.start : ry.start;
    lub_stats_ratio(ser->v[num] + d, ser->v[den] + d, ser->n - d, z, scratch, &r->mean, &r->sem);
}

/* The /target_rel_error check ("run until the headline is known to target_rel_error"): 1 when
 * the headline's standard error, as the summary written now would report it (same steady
 * window, same estimator), is at most target_rel_error of its mean over at least
 * target_min_strain of steady window; *zero_mean is set when that window is steady with a
 * mean of 0, which has no relative error (0 +- 0 is 0/0, not "known to x %"): no stop on it,
 * and a warning says why. scratch, ratio_z: ser->n doubles each. */
static int ss_target_reached(const ss_params *p, const ss_series *ser, int headline,
                             double *scratch, double *ratio_z, int *zero_mean)
{
    const size_t start = ss_steady_start(ser, p->pressure, p->transient_strain, NULL);
    lub_stats_result sr;
    lub_stats_analyse(ser->v[headline], ser->n, start, scratch, &sr);
    if (headline == S_MU)
        ss_ratio_stat(ser, S_SXY, S_P, start, ratio_z, scratch, &sr);
    /* shorter windows hold too few correlation times of phi, and a stop chosen by a low error
     * of mu then also picks a low error of phi (tests/shear/README.md, "Run until mu is
     * known") */
    const double averaged = start < ser->n ? ser->strain[ser->n - 1] - ser->strain[start] : 0.0;
    const int checked = sr.steady && averaged >= p->target_min_strain;
    *zero_mean = checked && sr.mean == 0.0;
    return checked && isfinite(sr.sem) && sr.mean != 0.0 &&
           sr.sem <= p->target_rel_error * fabs(sr.mean);
}

/* 1 when the stopped run's result file (path) has images with its snapshots, or none to copy;
 * 0 for a file written before images were: its continuation then has none either, so that no
 * frame carries images that are not its own. */
static int ss_stopped_has_image(const char *path, int64_t frames)
{
    if (frames <= 0)
        return 1;
    char err[8];
    lub_h5_reader *r = lub_h5r_open(path, err, sizeof err);
    const int has = r && lub_h5r_has_image(r) == 1;
    lub_h5r_close(r);
    return has;
}

static int ss_snapshot(lub_run_ctx *ctx, const lub_shear_system *s)
{
    _Static_assert(sizeof(int) == sizeof(int32_t), "the images are written as int32");
    double edges[9];
    for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c)
            edges[3 * r + c] = s->cell.h[c][r]; /* rows = edge vectors */
    return lub_h5_particles_snapshot(ctx->out, s->step, s->time, edges, (const double *)s->x,
                                     (const double *)s->v, (const double *)s->w,
                                     lub_h5_particles_has_image(ctx->out) ? s->img : NULL);
}

/* The interaction network of the system's current state (pair_network.h, computed into net,
 * whose arrays are kept for the next frame) appended to /pair_network. final: no step of this
 * run follows. 0, or the exit code with ctx->diagnostic set. */
static int ss_network_frame(lub_run_ctx *ctx, lub_shear_system *s, lub_h5_frames *frames,
                            lub_pair_network *net, int final)
{
    /* The rebuild the network may do first is the one the next step would do: before a step
     * it counts (the step control adapts the step after each rebuild it sees, and the step
     * then does none), at the end it is none of the run's, and the summary's
     * neighbor_rebuilds and cell_flips stay those of the steps; so do the Delaunay update
     * statistics (the update a final frame may do is none of the run's either). */
    const long rebuilds = s->rebuilds, flips = s->flips;
    const lub_topology topo = s->topo;
    const int rc = lub_shear_pair_network(s, net);
    if (final) {
        s->rebuilds = rebuilds;
        s->flips = flips;
        s->topo.updates = topo.updates;
        s->topo.inside = topo.inside;
        s->topo.allowed = topo.allowed;
        s->topo.open = topo.open;
    }
    if (rc != LUB_SHEAR_OK) {
        snprintf(ctx->diagnostic, sizeof ctx->diagnostic, "interaction network at step %ld: %s",
                 s->step,
                 rc == LUB_SHEAR_NOMEM ? "out of memory (/pair_network: \"none\" avoids it)"
                                       : s->fail_msg);
        return rc == LUB_SHEAR_NOMEM ? LUB_EXIT_INTERNAL : LUB_EXIT_NUMERICAL;
    }
    if (lub_network_append(frames, net, s->step, s->time)) {
        snprintf(ctx->diagnostic, sizeof ctx->diagnostic, "%s", lub_h5_last_error(ctx->out));
        return LUB_EXIT_IO;
    }
    return LUB_EXIT_OK;
}

static double ref_phi_m(double mu_m) { return 0.6301 - 0.0794 * (1.0 - exp(-mu_m / 0.4032)); }
static double ref_mu(double Iv, double phi_m)
{
    double mu1 = 0.36, mu2 = 0.7, I0 = 0.0133;
    double phi = phi_m / (1.0 + sqrt(Iv));
    return mu1 + (mu2 - mu1) / (1.0 + I0 / Iv) + Iv * pow(1.0 - phi, -2.5);
}
static double ref_eta_r(double phi, double phi_m)
{
    double mu1 = 0.36, mu2 = 0.7, I0 = 0.0133;
    if (phi >= phi_m)
        return INFINITY;
    double q = phi_m / phi - 1.0;
    return mu1 / (q * q) + (mu2 - mu1) / (q * q + I0) + pow(1.0 - phi, -2.5);
}

/* The time loop's state besides the system (shear_system.h): what a checkpoint holds with the
 * system and the series, so that a stopped run continues as if it had not stopped. */
typedef struct {
    int64_t step;          /* steps done */
    double strain;         /* shear strain done */
    double p_f;            /* the servo's filtered pressure (servo_step) */
    double next_check;     /* strain of the next /target_rel_error check */
    double bonds_sum;      /* Q6 bonds over all samples, for the noise floor of the Q6 check */
    int64_t bonds_samples; /* samples in bonds_sum */
    int64_t frames;        /* particle snapshots asked for so far */
    double packing_min_gap;
    lub_step_control ctl;
    lub_schedule sched;
} ss_loop;

/* The loop state, the series and the system into path (a new file), with the particle
 * snapshots and /pair_network frames its output file holds. 0, or -1 with why[len]. */
static int ss_checkpoint_write(const char *path, const json_t *resolved, const ss_loop *lp,
                               const ss_series *ser, int64_t frames_in_file,
                               int64_t network_frames_in_file, const lub_shear_system *sys,
                               const char *output_file, char *why, size_t len)
{
    lub_ckpt *c =
        lub_run_checkpoint_create(path, "simple_shear", lp->step, resolved, output_file, why, len);
    if (!c)
        return -1;
    int rc = lub_ckpt_put_i64(c, "run/step", lp->step) ||
             lub_ckpt_put_f64(c, "run/strain", lp->strain) ||
             lub_ckpt_put_f64(c, "run/servo_filtered_pressure", lp->p_f) ||
             lub_ckpt_put_f64(c, "run/next_check", lp->next_check) ||
             lub_ckpt_put_f64(c, "run/bonds_sum", lp->bonds_sum) ||
             lub_ckpt_put_i64(c, "run/bonds_samples", lp->bonds_samples) ||
             lub_ckpt_put_i64(c, "run/frames_in_file", frames_in_file) ||
             lub_ckpt_put_i64(c, "run/network_frames_in_file", network_frames_in_file) ||
             lub_ckpt_put_f64(c, "run/packing_min_gap", lp->packing_min_gap) ||
             lub_step_control_save(c, "run/step_control", &lp->ctl) ||
             lub_schedule_save(c, "run/schedule", &lp->sched) ||
             lub_ckpt_put(c, "series/strain", LUB_CKPT_F64, ser->n, ser->strain);
    for (int k = 0; k < S_COUNT && !rc; ++k) {
        char name[80];
        snprintf(name, sizeof name, "series/%s", s_names[k]);
        rc = lub_ckpt_put(c, name, LUB_CKPT_F64, ser->n, ser->v[k]);
    }
    rc = rc || lub_shear_save(c, sys);
    return lub_run_checkpoint_close(c, rc, why, len);
}

/* The loop state (lp: all but the series) of checkpoint c, with the rows, snapshots and
 * /pair_network frames its output file holds (a checkpoint older than the frames: none); the
 * series are read by ss_checkpoint_read_series once they have room. 0, or -1 with why[len]. */
static int ss_checkpoint_read_loop(lub_ckpt *c, ss_loop *lp, int64_t *rows, int64_t *frames_in_file,
                                   int64_t *network_frames_in_file, char *why, size_t len)
{
    size_t n_rows = 0;
    if (lub_ckpt_get_i64(c, "run/step", &lp->step) ||
        lub_ckpt_get_f64(c, "run/strain", &lp->strain) ||
        lub_ckpt_get_f64(c, "run/servo_filtered_pressure", &lp->p_f) ||
        lub_ckpt_get_f64(c, "run/next_check", &lp->next_check) ||
        lub_ckpt_get_f64(c, "run/bonds_sum", &lp->bonds_sum) ||
        lub_ckpt_get_i64(c, "run/bonds_samples", &lp->bonds_samples) ||
        lub_ckpt_get_i64(c, "run/frames_in_file", frames_in_file) ||
        lub_ckpt_get_f64(c, "run/packing_min_gap", &lp->packing_min_gap) ||
        lub_step_control_load(c, "run/step_control", &lp->ctl) ||
        lub_schedule_load(c, "run/schedule", &lp->sched) ||
        lub_ckpt_count(c, "series/strain", &n_rows)) {
        snprintf(why, len, "%s",
                 lub_ckpt_error(c)[0] ? lub_ckpt_error(c) : "inconsistent step control or events");
        return -1;
    }
    if (lp->step < 0 || lp->step > lp->sched.nsteps) {
        snprintf(why, len, "inconsistent loop state (step %lld of %lld)", (long long)lp->step,
                 (long long)lp->sched.nsteps);
        return -1;
    }
    if (lub_ckpt_get_i64_or(c, "run/network_frames_in_file", 0, network_frames_in_file)) {
        snprintf(why, len, "%s", lub_ckpt_error(c));
        return -1;
    }
    *rows = (int64_t)n_rows;
    return 0;
}

/* The series of checkpoint c into ser (room for its rows reserved). 0, or -1 with why[len]. */
static int ss_checkpoint_read_series(lub_ckpt *c, ss_series *ser, size_t rows, char *why,
                                     size_t len)
{
    int rc = lub_ckpt_get(c, "series/strain", LUB_CKPT_F64, rows, ser->strain);
    for (int k = 0; k < S_COUNT && !rc; ++k) {
        char name[80];
        snprintf(name, sizeof name, "series/%s", s_names[k]);
        rc = lub_ckpt_get(c, name, LUB_CKPT_F64, rows, ser->v[k]);
    }
    if (rc) {
        snprintf(why, len, "%s", lub_ckpt_error(c));
        return -1;
    }
    ser->n = rows;
    return 0;
}

/* ss_read of a resolved spec, which it leaves untouched (ss_read fills defaults in place) */
static int ss_read_resolved(const json_t *resolved, ss_params *p, lub_error *err)
{
    json_t *copy = json_deep_copy(resolved);
    const int rc = copy ? ss_read(copy, p, err) : -1;
    json_decref(copy);
    return rc;
}

/* The start of a continuation (ctx->resume_path): opens the checkpoint, reads the loop state
 * into *lp (rows, snapshots and network frames to copy into *rows, *frames, *network_frames),
 * the radii and positions into new arrays. 0, or -1 with ctx->resume_rejected and the
 * diagnostic set (the checkpoint closed). */
static int ss_resume_begin(lub_run_ctx *ctx, int n, lub_ckpt **ckpt, ss_loop *lp, int64_t *rows,
                           int64_t *frames, int64_t *network_frames, double **radius, vec3 **pos)
{
    char why[512] = "";
    int saved_n = 0;
    *ckpt = lub_ckpt_open(ctx->resume_path, why, sizeof why);
    if (*ckpt &&
        ss_checkpoint_read_loop(*ckpt, lp, rows, frames, network_frames, why, sizeof why) == 0) {
        if (lub_shear_saved_particles(*ckpt, &saved_n, radius) || saved_n != n) {
            snprintf(why, sizeof why, "%s",
                     lub_ckpt_error(*ckpt)[0] ? lub_ckpt_error(*ckpt) : "another particle count");
        } else if (!(*pos = malloc((size_t)n * sizeof **pos))) {
            snprintf(why, sizeof why, "out of memory (positions)");
        } else if (lub_ckpt_get(*ckpt, "system/x", LUB_CKPT_F64, 3 * (size_t)n, *pos)) {
            snprintf(why, sizeof why, "%s", lub_ckpt_error(*ckpt));
        } else {
            return 0;
        }
    }
    snprintf(ctx->diagnostic, sizeof ctx->diagnostic, "cannot continue from %s: %s",
             ctx->resume_path, why[0] ? why : "unreadable");
    ctx->resume_rejected = 1;
    if (*ckpt)
        lub_ckpt_close(*ckpt, NULL, 0);
    *ckpt = NULL;
    free(*radius);
    free(*pos);
    *radius = NULL;
    *pos = NULL;
    return -1;
}

static int ss_run(const json_t *resolved, lub_run_ctx *ctx)
{
    ss_params p;
    lub_error err;
    memset(&err, 0, sizeof err);
    if (ss_read_resolved(resolved, &p, &err)) {
        snprintf(ctx->diagnostic, sizeof ctx->diagnostic, "%s: %s", err.pointer, err.message);
        return LUB_EXIT_INTERNAL;
    }
    const int n = (int)p.n;
    const double gd = p.pressure ? p.Iv : 1.0; /* shear rate in the scene units */
    const double s0 = p.pressure ? 1.0 : gd;   /* stress unit: P or eta gd (eta = 1) */
    const double rho = p.St / gd;              /* St = rho gd a^2 / eta */
    lub_law_spec_scale(&p.law, 1.0, p.stiffness * s0);

    ss_series ser;
    memset(&ser, 0, sizeof ser);
    lub_shear_system sys;
    memset(&sys, 0, sizeof sys);
    double *scratch = NULL, *ratio_z = NULL;
    int exit_code = LUB_EXIT_OK;
    int step_unstable = 0;  /* the failure is one the time step causes (non-finite, runaway) */
    int servo_squeezed = 0; /* the failure is a cell the servo squeezed (its diagnostic says so) */
    ss_loop lp;             /* the loop's state: a fresh start, or the checkpoint's (resumed) */
    memset(&lp, 0, sizeof lp);
    ss_loop resumed;
    memset(&resumed, 0, sizeof resumed);
    lub_ckpt *resume = NULL; /* the checkpoint a continuation starts from */
    int64_t resume_rows = 0, resume_frames = 0, resume_network_frames = 0;
    lub_h5_frames *network = NULL; /* /pair_network, when asked for */
    lub_pair_network net = {0};    /* its arrays, kept from frame to frame */
    int64_t last_snapshot_step = -1;
    double *radius = NULL;
    vec3 *pos = NULL;
    lub_cell cell;
    lub_cell_init_box(&cell, 1.0, 1.0, 1.0); /* a continuation's cell comes from its checkpoint */
    if (ctx->resume_path) {
        if (ss_resume_begin(ctx, n, &resume, &resumed, &resume_rows, &resume_frames,
                            &resume_network_frames, &radius, &pos))
            return LUB_EXIT_BAD_SPEC;
        lp.packing_min_gap = resumed.packing_min_gap;
    } else {
        /* ---- packing ---- */
        radius = malloc((size_t)n * sizeof *radius);
        pos = malloc((size_t)n * sizeof *pos);
        if (!radius || !pos) {
            free(radius);
            free(pos);
            snprintf(ctx->diagnostic, sizeof ctx->diagnostic, "out of memory (packing)");
            return LUB_EXIT_INTERNAL;
        }
        lub_packing_params pp = {.n = n,
                                 .phi = p.phi,
                                 .radius_std = p.radius_std,
                                 .seed = (uint64_t)p.seed,
                                 .margin = 0.01,
                                 .max_sweeps = 2000000,
                                 .stop = ctx->stop_requested};
        lub_packing_info pinfo;
        int prc = lub_packing_generate(&pp, radius, pos, &cell, &pinfo);
        if (prc == -3) { /* SIGTERM/SIGINT while packing: a partial run without a step */
            snprintf(ctx->diagnostic, sizeof ctx->diagnostic,
                     "stopped while generating the packing, before the first step");
            free(radius);
            free(pos);
            return LUB_EXIT_INTERRUPTED;
        }
        if (prc) {
            if (prc == -1)
                lub_diagnostic_out_of_memory(ctx, "packing", n, 0.0, "/n_particles");
            else
                snprintf(ctx->diagnostic, sizeof ctx->diagnostic,
                         "packing generation failed (target fraction not reached without "
                         "overlaps) for n=%d phi=%g",
                         n, p.phi);
            free(radius);
            free(pos);
            return LUB_EXIT_INTERNAL;
        }
        lp.packing_min_gap = pinfo.min_gap;
    }
    cell.L[0][1] = gd;

    /* ---- system ---- */
    int pdf_nt = p.pdf_on ? (int)p.pdf_nt : 0, pdf_np = p.pdf_on ? (int)p.pdf_np : 0;
    int src = lub_shear_init(&sys, n, radius, pos, &cell, &p.law.params, rho, p.cutoff, p.skin, 1.0,
                             ctx->threads, pdf_nt, pdf_np);
    free(pos);
    pos = NULL;
    if (src) {
        lub_diagnostic_out_of_memory(ctx, "system", n, 0.0, "/n_particles");
        exit_code = LUB_EXIT_INTERNAL;
        goto cleanup;
    }
    sys.drag_viscosity = p.drag_viscosity; /* eta = 1 */
    const double dt_el = lub_shear_elastic_dt(&sys);
    /* the step: fixed (/dt), or /dt_safety of the single-pair bound, lowered while the pairs'
     * summed stiffness needs it (/dt_stiffness_safety; step_stiffness.h, checked at every
     * neighbour-list rebuild) */
    const int dt_adapts = p.dt <= 0.0 && p.dt_stiffness_safety > 0.0;
    lub_step_control_init(&lp.ctl, p.dt > 0 ? p.dt : p.dt_safety * dt_el,
                          dt_adapts ? p.dt_stiffness_safety : 0.0);
    double dt = lp.ctl.dt;
    sys.dt = dt;
    if (!resume && !lub_step_count_ok(lub_step_count(p.strain / gd, dt))) {
        /* the step-count rule (step_count.h) with this packing's lightest particle, which
         * validation could only bound: refused before the first step, exit 2 */
        const double r_eff = p.dt > 0.0 ? 1.0 : pow(dt_el / ss_elastic_dt(&p, 1.0), 2.0 / 3.0);
        ss_step_refusal(&p, r_eff, lub_step_count(p.strain / gd, dt), dt, "", &err);
        snprintf(ctx->diagnostic, sizeof ctx->diagnostic, "%s: %s", err.pointer, err.message);
        exit_code = LUB_EXIT_BAD_SPEC;
        goto cleanup;
    }
    if (p.delaunay) { /* contacts (u_n < eps a) are never cut off between updates */
        const double every = fmin(1e6, fmax(1.0, floor(p.delaunay_strain / (gd * dt) + 0.5)));
        lub_shear_use_delaunay(&sys, (int)every, fmax(0.05, 2.0 * p.law.params.eps));
    }
    const double t_end = p.strain / gd;
    lub_schedule_init(&lp.sched, dt, t_end);
    const int64_t sample_every = lub_schedule_period(p.sample_strain / gd, dt);
    const int64_t pdf_every = lub_schedule_period(p.pdf_interval / gd, dt);
    const int64_t snap_every =
        p.snapshots > 0 ? (lp.sched.nsteps + p.snapshots - 1) / p.snapshots : 0;
    const int ev_sample =
        lub_schedule_add(&lp.sched, sample_every, sample_every - 1, p.sample_strain / gd);
    const int ev_pdf = lub_schedule_add(&lp.sched, pdf_every, 0, p.pdf_interval / gd);
    const int ev_snap = snap_every > 0 ? lub_schedule_add(&lp.sched, snap_every, snap_every - 1,
                                                          (double)snap_every * dt)
                                       : -1;
    lp.next_check = fmax(p.transient_strain + 1.0, 1.0);
    if (resume) { /* the stopped run's state replaces the fresh one (same events, same ids) */
        if (lub_shear_restore(resume, &sys) || resumed.sched.n_events != lp.sched.n_events) {
            snprintf(ctx->diagnostic, sizeof ctx->diagnostic, "cannot continue from %s: %s",
                     ctx->resume_path,
                     lub_ckpt_error(resume)[0] ? lub_ckpt_error(resume)
                                               : "inconsistent pairs or events");
            ctx->resume_rejected = 1;
            exit_code = LUB_EXIT_BAD_SPEC;
            goto cleanup;
        }
        lp = resumed;
        dt = lp.ctl.dt;
        sys.dt = dt;
        ctx->resumed_from_step = lp.step;
        ctx->resume_begun = 1;
        /* a continuation may ask for another /strain (scene: resume_may_differ), not for less
         * than the stopped run has done: the run then takes the steps of one asked for that
         * strain from the start (lub_schedule_set_end) */
        if (t_end != lp.sched.t_end) {
            if (p.strain < lp.strain) {
                snprintf(ctx->diagnostic, sizeof ctx->diagnostic,
                         "cannot continue from %s: /strain: %g here, but the stopped run has "
                         "already sheared to %.6g",
                         ctx->resume_path, p.strain, lp.strain);
                ctx->resume_rejected = 1;
                exit_code = LUB_EXIT_BAD_SPEC;
                goto cleanup;
            }
            lub_schedule_set_end(&lp.sched, t_end);
            if ((double)lp.sched.nsteps > LUB_MAX_STEPS) { /* at the stopped run's step */
                snprintf(ctx->diagnostic, sizeof ctx->diagnostic,
                         "cannot continue from %s: /strain: %g would take the run to %.3g steps "
                         "at its step of %.3g, more than the %.0e a run may take (README, CLI "
                         "contract, \"Step count\")",
                         ctx->resume_path, p.strain, (double)lp.sched.nsteps, dt, LUB_MAX_STEPS);
                ctx->resume_rejected = 1;
                exit_code = LUB_EXIT_BAD_SPEC;
                goto cleanup;
            }
        }
    }

    /* the series from the first sample (a continuation: from the checkpoint's) to /strain */
    const size_t samples_cap =
        (size_t)resume_rows + (size_t)((lp.sched.nsteps - lp.step) / lp.sched.ev[ev_sample].every) +
        4;
    char series_what[96];
    snprintf(series_what, sizeof series_what, "the %zu samples of the time series", samples_cap);
    if (!lub_memory_fits(ctx, (double)samples_cap * SS_SAMPLE_BYTES, series_what,
                         "/strain (or raise /sample_strain)")) {
        exit_code = LUB_EXIT_INTERNAL;
        goto cleanup;
    }
    int mem_ok = ss_series_reserve(&ser, &scratch, &ratio_z, samples_cap) == 0;
    if (!mem_ok) {
        snprintf(ctx->diagnostic, sizeof ctx->diagnostic, "out of memory (series)");
        exit_code = LUB_EXIT_INTERNAL;
        goto cleanup;
    }
    if (resume) {
        char why[400];
        if (ss_checkpoint_read_series(resume, &ser, (size_t)resume_rows, why, sizeof why)) {
            snprintf(ctx->diagnostic, sizeof ctx->diagnostic, "cannot continue from %s: %s",
                     ctx->resume_path, why);
            ctx->resume_rejected = 1;
            exit_code = LUB_EXIT_BAD_SPEC;
            goto cleanup;
        }
        lub_ckpt_close(resume, NULL, 0);
        resume = NULL;
    }

    /* ---- output tables ---- */
    const char *su = p.pressure ? "P" : "eta*gd";
    const char *tnames[] = {"strain",
                            "phi",
                            "pressure",
                            "mu",
                            "eta_r",
                            "Iv",
                            "Z",
                            "Z_contact",
                            "cell_ly",
                            "servo_rate",
                            "stress/total",
                            "stress/normal_contact",
                            "stress/tangential_contact",
                            "stress/normal_lubrication",
                            "stress/tangential_lubrication",
                            "stress/kinetic",
                            "bond_order_q6"};
    const int tnc[] = {1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 9, 9, 9, 9, 9, 9, 1};
    const char *tunits[] = {"1",  "1", su, "1", "1", "1", "1", "1", "a",
                            "gd", su,  su, su,  su,  su,  su,  "1"};
    lub_h5_table *tab =
        lub_h5_set_units(ctx->out, p.pressure ? "eta/P" : "1/gd", "a",
                         p.pressure ? "a*P/eta" : "a*gd", p.pressure ? "P/eta" : "gd") == 0
            ? lub_h5_table_create(ctx->out, 17, tnames, tnc, tunits)
            : NULL;
    if (!tab) {
        snprintf(ctx->diagnostic, sizeof ctx->diagnostic, "%s", lub_h5_last_error(ctx->out));
        exit_code = LUB_EXIT_IO;
        goto cleanup;
    }
    const char *force_unit = p.pressure ? "P*a^2" : "eta*gd*a^2";
    const char *torque_unit = p.pressure ? "P*a^3" : "eta*gd*a^3";
    if (p.pair_network != LUB_NETWORK_NONE &&
        !(network = lub_network_define(ctx->out, force_unit, torque_unit,
                                       p.pressure ? "eta/P" : "1/gd"))) {
        snprintf(ctx->diagnostic, sizeof ctx->diagnostic, "%s", lub_h5_last_error(ctx->out));
        exit_code = LUB_EXIT_IO;
        goto cleanup;
    }
    if (ctx->resume_path) { /* the stopped run's rows, snapshots and network frames, unchanged */
        char why[600] = "";
        const char *bnd[3] = {"periodic", "periodic", "periodic"};
        if (p.snapshots > 0 && (lub_h5_particles_define(ctx->out, n, radius, bnd) ||
                                (ss_stopped_has_image(ctx->resume_result, resume_frames) &&
                                 lub_h5_particles_define_image(ctx->out))))
            snprintf(why, sizeof why, "%s", lub_h5_last_error(ctx->out));
        else if (lub_h5_continue_output(ctx->resume_result, tab, 17, tnames, tnc, resume_rows,
                                        ctx->out, n, p.snapshots > 0 ? resume_frames : 0, why,
                                        sizeof why) == 0 &&
                 network)
            lub_h5_continue_frames(ctx->resume_result, network, resume_network_frames, why,
                                   sizeof why);
        lp.frames = p.snapshots > 0 ? resume_frames : 0;
        if (why[0]) {
            snprintf(ctx->diagnostic, sizeof ctx->diagnostic, "cannot continue from %s: %s",
                     ctx->resume_result, why);
            ctx->resume_rejected = 1;
            exit_code = LUB_EXIT_BAD_SPEC;
            goto cleanup;
        }
    } else if (p.snapshots > 0) {
        const char *bnd[3] = {"periodic", "periodic", "periodic"};
        if (p.pair_network == LUB_NETWORK_SNAPSHOTS &&
            (exit_code = ss_network_frame(ctx, &sys, network, &net, 0)) != LUB_EXIT_OK)
            goto cleanup;
        if (lub_h5_particles_define(ctx->out, n, radius, bnd) ||
            lub_h5_particles_define_image(ctx->out) || ss_snapshot(ctx, &sys)) {
            snprintf(ctx->diagnostic, sizeof ctx->diagnostic, "%s", lub_h5_last_error(ctx->out));
            exit_code = LUB_EXIT_IO;
            goto cleanup;
        }
        lp.frames = 1;
        last_snapshot_step = sys.step;
    }

    /* ---- time loop ---- */
    int stopped_early = 0;
    int target_zero_mean = 0;   /* the last /target_rel_error check found the headline 0 +- 0 */
    int stopped_by_request = 0; /* a stop request ended the loop between two steps */
    const int headline = p.pressure ? S_MU : S_ETA;
    double row[10 + 6 * 9 + 1];
    _Static_assert(sizeof row == SS_ROW_BYTES, "SS_ROW_BYTES: one row of the time series");
    /* A continuation of a run whose last step was a /target_rel_error check (next_check is
     * set one strain past the strain of the check) repeats that check with its own
     * /target_rel_error and /target_min_strain, as a run asked for them from the start would
     * have made it at that step: a run stopped on its target and extended with the same target
     * and a longer /strain stops there, with no step more (until 2026-12-06 it went on to the
     * next check, one strain later). */
    if (ctx->resume_path && p.target_rel_error > 0 && lp.next_check == lp.strain + 1.0 &&
        ss_target_reached(&p, &ser, headline, scratch, ratio_z, &target_zero_mean))
        stopped_early = 1;
    int64_t step;
    for (step = lp.step; step < lp.sched.nsteps && !stopped_early; ++step) {

        if (ctx->periodic && lub_periodic_due(ctx->periodic, step)) {
            /* the state before step `step`, as at a stop (the run then goes on) */
            lp.step = step;
            const int64_t in_file = lp.frames - lub_h5_snapshots_skipped(ctx->out, NULL, NULL, 0);
            const int64_t network_in_file = lub_h5_frames_written(network, NULL);
            char why[400] = "";
            if (lub_periodic_copy_output(ctx->periodic, ctx->out) == 0) {
                if (ss_checkpoint_write(ctx->periodic->ckpt_tmp, resolved, &lp, &ser, in_file,
                                        network_in_file, &sys, LUB_PERIODIC_OUTPUT, why,
                                        sizeof why) == 0)
                    lub_periodic_publish(ctx->periodic);
                else
                    lub_periodic_failed(ctx->periodic, why);
            }
        }
        if (ctx->stop_requested && *ctx->stop_requested) {
            exit_code = LUB_EXIT_INTERRUPTED;
            stopped_by_request = 1;
            break;
        }
        const int sample = lub_schedule_due(&lp.sched, ev_sample, step);
        const double strain_here = lp.strain; /* strain of the evaluated configuration */
        const int pdf_due = lub_schedule_due(&lp.sched, ev_pdf, step);
        const int pdf = p.pdf_on && strain_here >= p.pdf_start && pdf_due;
        unsigned flags = (sample ? LUB_SAMPLE_STRESS : 0u) | (p.pressure ? LUB_SAMPLE_SYY : 0u) |
                         (pdf ? LUB_SAMPLE_PDF : 0u);
        lub_shear_sample smp;
        const double phi_here = lub_shear_phi(&sys);
        const double ly = sys.cell.h[1][1];
        const double rate = sys.cell.L[1][1];
        int r = lub_shear_step(&sys, flags, &smp);
        if (r) {
            if (r == LUB_SHEAR_NOMEM && !sys.fail_msg[0]) { /* the pair lists could not grow */
                char what[96];
                snprintf(what, sizeof what, "pair lists, step %lld, strain %.4f", (long long)step,
                         strain_here);
                lub_diagnostic_out_of_memory(ctx, what, n, (double)lub_shear_memory_bytes(&sys),
                                             "/n_particles");
            } else {
                snprintf(ctx->diagnostic, sizeof ctx->diagnostic, "%s (step %lld, strain %.4f)",
                         sys.fail_msg[0] ? sys.fail_msg : "simulation failure", (long long)step,
                         strain_here);
            }
            exit_code = (r == LUB_SHEAR_NOMEM) ? LUB_EXIT_INTERNAL : LUB_EXIT_NUMERICAL;
            step_unstable = r == LUB_SHEAR_NONFINITE || r == LUB_SHEAR_RUNAWAY;
            servo_squeezed = r == LUB_SHEAR_CELL_TOO_SMALL && p.pressure;
            if (servo_squeezed) { /* only the servo moves L_y */
                const size_t len = strlen(ctx->diagnostic);
                snprintf(ctx->diagnostic + len, sizeof ctx->diagnostic - len,
                         ": the pressure servo squeezed the cell (L_y %.3g a, phi %.3g); lower "
                         "/servo/gain (studied: 0.25-4; default 1), or raise /n_particles",
                         ly, phi_here);
            }
            break;
        }
        lp.strain += gd * dt;
        if (p.pressure) {
            if (step == 0)
                lp.p_f = -smp.syy;
            servo_step(&sys, -smp.syy, &lp.p_f, dt, gd, &p);
        }
        const double dt_of_step = dt; /* the step just taken (time of its sample row) */
        if (lub_shear_step_control(&sys, &lp.ctl)) {
            dt = lp.ctl.dt;
            sys.dt = dt;
            lub_schedule_set_dt(&lp.sched, step + 1, sys.time, dt);
            if ((double)lp.sched.nsteps > LUB_MAX_STEPS) { /* step-count rule (step_count.h) */
                snprintf(ctx->diagnostic, sizeof ctx->diagnostic,
                         "the automatic step fell to %.3g at strain %.4f (the pairs' summed "
                         "stiffness, /dt_stiffness_safety %g; %ld changes), which would take the "
                         "run to %.3g steps, more than the %.0e a run may take (README, CLI "
                         "contract, \"Step count\"); lower /strain or /stiffness",
                         dt, lp.strain, p.dt_stiffness_safety, lp.ctl.changes,
                         (double)lp.sched.nsteps, LUB_MAX_STEPS);
                exit_code = LUB_EXIT_NUMERICAL;
                break;
            }
            if (sys.topology_interval > 0)
                sys.topology_interval =
                    (int)fmin(1e6, (double)lub_schedule_period(p.delaunay_strain / gd, dt));
            const size_t more =
                (size_t)((lp.sched.nsteps - step) / lp.sched.ev[ev_sample].every) + 4;
            if (ss_series_reserve(&ser, &scratch, &ratio_z, ser.n + more)) {
                snprintf(ctx->diagnostic, sizeof ctx->diagnostic, "out of memory (series)");
                exit_code = LUB_EXIT_INTERNAL;
                break;
            }
        }
        if (sample) {
            /* bond order after the step (one pass over the pair list, which the first step
             * builds; image shifts stay consistent with the positions until the next rebuild) */
            long bonds_here = 0;
            const double q6_here = lub_shear_bond_order_q6(&sys, SS_BOND_FACTOR, &bonds_here);
            lp.bonds_sum += (double)bonds_here;
            ++lp.bonds_samples;
            double tot[9];
            lub_stress_total(&smp.stress, tot);
            const double P = -tot[4];
            const double sxy = tot[1];
            const double vals[S_COUNT] = {
                phi_here,
                P / s0,
                sxy / P,
                sxy / gd,
                gd / P,
                sxy / s0,
                -tot[0] / gd,
                -tot[4] / gd,
                -tot[8] / gd,
                tot[0] / tot[4],
                tot[8] / tot[4],
                2.0 * (double)smp.n_active / n,
                2.0 * (double)smp.n_contacts / n,
                smp.stress.part[LUB_SP_NC][1] / s0,
                smp.stress.part[LUB_SP_SC][1] / s0,
                smp.stress.part[LUB_SP_NL][1] / s0,
                smp.stress.part[LUB_SP_SL][1] / s0,
                smp.stress.part[LUB_SP_KIN][1] / s0,
                smp.stress.part[LUB_SP_NC][4] / s0,
                smp.stress.part[LUB_SP_SC][4] / s0,
                smp.stress.part[LUB_SP_NL][4] / s0,
                smp.stress.part[LUB_SP_SL][4] / s0,
                smp.stress.part[LUB_SP_KIN][4] / s0,
                smp.n_contacts ? (double)smp.n_crushed / (double)smp.n_contacts : 0.0,
                smp.n_contacts ? (double)smp.n_sliding / (double)smp.n_contacts : 0.0,
                q6_here};
            if (ser.n < ser.cap) {
                for (int k = 0; k < S_COUNT; ++k)
                    ser.v[k][ser.n] = vals[k];
                ser.strain[ser.n] = strain_here;
                ser.n++;
            }
            row[0] = strain_here;
            row[1] = phi_here;
            row[2] = P / s0;
            row[3] = sxy / P;
            row[4] = sxy / gd;
            row[5] = gd / P;
            row[6] = vals[S_Z];
            row[7] = vals[S_ZC];
            row[8] = ly;
            row[9] = rate / gd;
            for (int k = 0; k < 9; ++k)
                row[10 + k] = tot[k] / s0;
            for (int part = 0; part < LUB_SP_N; ++part)
                for (int k = 0; k < 9; ++k)
                    row[19 + 9 * part + k] = smp.stress.part[part][k] / s0;
            row[19 + 9 * LUB_SP_N] = q6_here;
            if (lub_h5_table_append(tab, step, sys.time - dt_of_step, row)) {
                snprintf(ctx->diagnostic, sizeof ctx->diagnostic, "%s",
                         lub_h5_last_error(ctx->out));
                exit_code = LUB_EXIT_IO;
                break;
            }
            if (!isfinite(P) || !isfinite(sxy)) {
                snprintf(ctx->diagnostic, sizeof ctx->diagnostic,
                         "non-finite stress at step %lld (strain %.4f)", (long long)step,
                         strain_here);
                exit_code = LUB_EXIT_NUMERICAL;
                step_unstable = 1;
                break;
            }
            /* "run until the headline is known to target_rel_error" */
            if (p.target_rel_error > 0 && lp.strain >= lp.next_check) {
                lp.next_check = lp.strain + 1.0;
                if (ss_target_reached(&p, &ser, headline, scratch, ratio_z, &target_zero_mean)) {
                    stopped_early = 1;
                    ++step;
                    break;
                }
            }
        }
        /* not within half a spacing of the end, whose snapshot follows the loop (an adapted
         * step moves the events: the last could fall a step before the end) */
        if (ev_snap >= 0 && lub_schedule_due(&lp.sched, ev_snap, step) &&
            step + 1 < lp.sched.nsteps &&
            lp.sched.t_end - sys.time > 0.5 * lp.sched.ev[ev_snap].spacing) {
            /* the network first: its list completion may move positions by cell vectors
             * (pair_network.h), which the snapshot then shows */
            if (p.pair_network == LUB_NETWORK_SNAPSHOTS &&
                (exit_code = ss_network_frame(ctx, &sys, network, &net, 0)) != LUB_EXIT_OK)
                break;
            if (ss_snapshot(ctx, &sys)) {
                exit_code = LUB_EXIT_IO;
                break;
            }
            lp.frames++;
            last_snapshot_step = sys.step;
        }
        lub_progress_update(ctx->progress, (double)(step + 1) / (double)lp.sched.nsteps, step + 1);
    }
    lub_progress_last_step(ctx->progress, step);
    /* a stop between two steps (or the end, with --keep-checkpoint): the state before step
     * `step` into the checkpoint, with the rows and snapshots written so far (before the
     * last snapshot written below) */
    if (ctx->checkpoint_path &&
        (stopped_by_request || (ctx->checkpoint_always && exit_code == LUB_EXIT_OK))) {
        lp.step = step;
        const int64_t frames_in_file =
            lp.frames - lub_h5_snapshots_skipped(ctx->out, NULL, NULL, 0);
        const int64_t network_in_file = lub_h5_frames_written(network, NULL);
        ctx->checkpoint_written =
            ss_checkpoint_write(ctx->checkpoint_path, resolved, &lp, &ser, frames_in_file,
                                network_in_file, &sys, "result.h5", ctx->checkpoint_failure,
                                sizeof ctx->checkpoint_failure) == 0;
    }
    /* the step's advice where the step is the likely cause (not for a cell squeezed below
     * the listing distance, unless /dt was fixed above the bound); the servo's instead where it
     * moves L_y by 0.1 SS_SERVO_STEP_MAX of itself or more in one step, unless the squeezed
     * cell's diagnostic already names the servo */
    const double servo_jump = p.pressure ? p.servo_gain * gd * dt : 0.0;
    if (exit_code == LUB_EXIT_NUMERICAL && servo_jump >= 0.1 * SS_SERVO_STEP_MAX &&
        !servo_squeezed) {
        const size_t len = strlen(ctx->diagnostic);
        snprintf(ctx->diagnostic + len, sizeof ctx->diagnostic - len,
                 ": the pressure servo changes L_y by up to %.3g of itself in one step "
                 "(/servo/gain times the shear rate times the step); lower /servo/gain (studied: "
                 "0.25-4; default 1)",
                 servo_jump);
    } else if (exit_code == LUB_EXIT_NUMERICAL && dt_adapts && step_unstable) {
        lub_diagnostic_adapted_dt_hint(ctx, dt, p.dt_safety, dt_el, "dt_elastic", lp.ctl.changes,
                                       p.dt_stiffness_safety, lp.ctl.ratio_max);
    } else if (exit_code == LUB_EXIT_NUMERICAL && (step_unstable || p.dt > dt_el)) {
        lub_diagnostic_dt_hint(ctx, p.dt, p.dt_safety, dt_el, "dt_elastic");
    }
    /* the interaction network of the final state (unless a snapshot's frame already shows
     * it), before the last snapshot, which then shows the positions and box its branch
     * vectors and images refer to */
    int64_t network_last_step = -1;
    lub_h5_frames_written(network, &network_last_step);
    if (network && network_last_step != sys.step &&
        (exit_code == LUB_EXIT_OK || exit_code == LUB_EXIT_INTERRUPTED)) {
        const int rc = ss_network_frame(ctx, &sys, network, &net, 1);
        if (rc != LUB_EXIT_OK)
            exit_code = rc;
    }
    /* the final state, unless the loop's last snapshot shows it (a stop just after it) */
    if (p.snapshots > 0 && exit_code != LUB_EXIT_IO && last_snapshot_step != sys.step)
        ss_snapshot(ctx, &sys);

    /* ---- statistics and summary (also for partial runs) ---- */
    {
        int watch[3];
        const size_t start = ss_steady_start(&ser, p.pressure, p.transient_strain, watch);
        /* verdict: no significant drift of the watched series after the common start */
        int steady = 1;
        double worst_z = 0.0;
        for (int w = 0; w < 3 && watch[w] >= 0; ++w) {
            double z = lub_stats_drift_z(ser.v[watch[w]] + start, ser.n - start, scratch);
            if (!isfinite(z) || fabs(z) > 3.0)
                steady = 0;
            if (isfinite(z) && fabs(z) > worst_z)
                worst_z = fabs(z);
        }
        lub_summary_put(ctx, "steady_drift_z", worst_z, NAN, "1");
        /* the contacts' friction coefficient as the seed's laws read it (law.terms.friction
         * off is mu_m = 0) */
        const double mu_m = (p.law.params.terms & LUB_TERM_FRICTION) ? p.law.params.mu : 0.0;
        const double phi_m = ref_phi_m(mu_m);
        double mean_of[S_COUNT], sem_of[S_COUNT]; /* steady-state means and their errors, for
                                                     the advisory checks */
        double ref_of[S_COUNT];                   /* the §2 law's values (NaN: none) */
        for (int k = 0; k < S_COUNT; ++k)
            ref_of[k] = NAN;
        for (int k = 0; k < S_COUNT; ++k) {
            /* only mean and sem are reported; ratio observables are ratios of time averages
             * (ss_ratio_stat), the others the mean of their series from the common start
             * (before 2026-12-06 each from the later of that and its own MSER truncation, so
             * that the parts of a stress, averaged over other windows, did not add up to it) */
            lub_stats_result sr;
            if (k == S_MU) {
                ss_ratio_stat(&ser, S_SXY, S_P, start, ratio_z, scratch, &sr);
            } else if (k == S_L1) {
                ss_ratio_stat(&ser, S_ETA11, S_ETA22, start, ratio_z, scratch, &sr);
            } else if (k == S_L3) {
                ss_ratio_stat(&ser, S_ETA33, S_ETA22, start, ratio_z, scratch, &sr);
            } else if (k == S_IV) { /* gd/<P>, P = s0 * S_P */
                lub_stats_analyse(ser.v[S_P], ser.n, start, scratch, &sr);
                sr.sem = gd * sr.sem / (s0 * sr.mean * sr.mean);
                sr.mean = gd / (s0 * sr.mean);
            } else { /* one window for all: the stress parts add up to their totals */
                lub_stats_analyse_window(ser.v[k], ser.n, start, scratch, &sr);
            }
            /* an imposed phi has no error: its series moves by round-off only (its error bar
             * was 1.7e-16 until 2026-12-06) */
            if (k == S_PHI && !p.pressure)
                sr.sem = 0.0;
            mean_of[k] = sr.mean;
            sem_of[k] = sr.sem;
            const char *unit = "1";
            if (k == S_P || k == S_SXY || (k >= S_XY_NC && k <= S_YY_KIN))
                unit = su;
            if (k == S_ETA || k == S_ETA11 || k == S_ETA22 || k == S_ETA33)
                unit = "1";
            double ref = NAN;
            if (mu_m >= 0.36) {
                if (k == S_MU && p.pressure)
                    ref = ref_mu(p.Iv, phi_m);
                if (k == S_PHI && p.pressure)
                    ref = phi_m / (1.0 + sqrt(p.Iv));
                if (k == S_ETA && !p.pressure)
                    ref = ref_eta_r(p.phi, phi_m);
            }
            if (isfinite(ref)) {
                ref_of[k] = ref;
                lub_summary_put_ref(ctx, s_names[k], sr.mean, unit, ref);
                json_t *e = json_object_get(ctx->summary_results, s_names[k]);
                if (e && isfinite(sr.sem))
                    json_object_set_new(e, "stderr", json_real(sr.sem));
            } else {
                lub_summary_put(ctx, s_names[k], sr.mean, sr.sem, unit);
            }
        }
        lub_summary_put(ctx, "steady_from_strain", start < ser.n ? ser.strain[start] : NAN, NAN,
                        "1");
        lub_summary_put(ctx, "steady_samples", (double)(ser.n - start), NAN, "1");
        lub_summary_put(ctx, "strain_reached", lp.strain, NAN, "1");
        lub_summary_put(ctx, "dt", dt, NAN, p.pressure ? "eta/P" : "1/gd");
        lub_summary_put(ctx, "dt_elastic", dt_el, NAN, p.pressure ? "eta/P" : "1/gd");
        lub_summary_put(ctx, "dt_min", lp.ctl.dt_min, NAN, p.pressure ? "eta/P" : "1/gd");
        lub_summary_put(ctx, "dt_changes", (double)lp.ctl.changes, NAN, "1");
        lub_summary_put(ctx, "dt_stiffness_ratio", lp.ctl.ratio_max, NAN, "1");
        lub_summary_put(ctx, "neighbor_rebuilds", (double)sys.rebuilds, NAN, "1");
        lub_summary_put(ctx, "cell_flips", (double)sys.flips, NAN, "1");
        lub_summary_put(ctx, "lost_pairs", (double)sys.lost_pairs, NAN, "1");
        lub_summary_put(ctx, "packing_min_gap", lp.packing_min_gap, NAN, "a");
        const int steady_detected = steady && start < ser.n;
        json_object_set_new(ctx->summary_extra, "steady_state_detected",
                            json_boolean(steady_detected));
        json_object_set_new(ctx->summary_extra, "stopped_on_target_error",
                            json_boolean(stopped_early));
        /* advisory checks: rigid limit, inertia, crushed asperities, ordering, lost pairs,
         * steady state (shear_run_checks.h); S_P is the pressure in units of s0 */
        const lub_shear_run_state checks = {
            .elastic_number = p.stiffness / mean_of[S_P],
            .kinetic_share = fabs(mean_of[S_XY_KIN]) / fabs(mean_of[S_SXY]),
            .kinetic_share_pressure = fabs(mean_of[S_YY_KIN]) / fabs(mean_of[S_P]),
            .crushed_fraction = mean_of[S_CRUSHED],
            .bond_order_q6 = mean_of[S_Q6],
            .bond_order_random =
                lp.bonds_sum > 0.0 ? sqrt((double)lp.bonds_samples / lp.bonds_sum) : NAN,
            .lost_pairs = (double)sys.lost_pairs,
            .steady = steady_detected,
            .steady_samples = (double)(ser.n - start),
            .strain_reached = lp.strain,
            .stopped = stopped_by_request,
            .strain_target = p.strain,
            .checkpoint_kept = lub_run_resumable(ctx),
            .transient_strain = p.transient_strain,
            .sample_strain = p.sample_strain,
            .dt_over_elastic = p.dt > 0.0 ? p.dt / dt_el : 0.0,
            .dt_over_stiffness = p.dt > 0.0 ? lp.ctl.ratio_max : 0.0,
            .phi_imposed = p.pressure ? NAN : p.phi,
            .phi_jamming = phi_m,
            .mu_m = mu_m,
            .pressure_ratio = p.pressure ? mean_of[S_P] : NAN, /* S_P is in units of s0 = P */
            .pressure_ratio_sem = p.pressure ? sem_of[S_P] : NAN,
            .headline = p.pressure ? mean_of[S_MU] : mean_of[S_ETA],
            .headline_law = p.pressure ? ref_of[S_MU] : ref_of[S_ETA],
            .headline_is_mu = p.pressure,
            .phi_mean = p.pressure ? mean_of[S_PHI] : NAN,
            .phi_law = p.pressure ? ref_of[S_PHI] : NAN,
            .article_set = p.delaunay && !(p.law.params.terms & (LUB_TERM_ROLL | LUB_TERM_TWIST)),
            .headline_sem = p.pressure ? sem_of[S_MU] : sem_of[S_ETA],
            .target_rel_error = p.target_rel_error,
            .stopped_on_target = stopped_early,
            .target_zero_mean = target_zero_mean,
        };
        char warning_text[LUB_SHEAR_WARNINGS_MAX][LUB_SHEAR_WARNING_LEN];
        const int n_warnings = lub_shear_run_warnings(&checks, warning_text);
        json_t *warnings = json_array();
        for (int w = 0; w < n_warnings; ++w)
            json_array_append_new(warnings, json_string(warning_text[w]));
        lub_network_warn_skipped(network, warnings);
        if (p.pdf_on && sys.pdf.snapshots == 0) { /* no /profiles would be written */
            char text[400];
            if (lp.strain < p.pdf_start)
                snprintf(text, sizeof text,
                         "no microstructure was sampled and result.h5 has no /profiles: the run "
                         "ended at strain %.3g, before /microstructure/start_strain %.3g; lower "
                         "/microstructure/start_strain (or raise /strain)",
                         lp.strain, p.pdf_start);
            else
                snprintf(text, sizeof text,
                         "no microstructure was sampled and result.h5 has no /profiles: no "
                         "sample fell between /microstructure/start_strain %.3g and the end at "
                         "strain %.3g; lower /microstructure/interval_strain %.3g",
                         p.pdf_start, lp.strain, p.pdf_interval);
            json_array_append_new(warnings, json_string(text));
        }
        if (target_zero_mean) {
            char text[400];
            snprintf(text, sizeof text,
                     "%s averaged exactly 0 over the steady window, whose relative error is "
                     "undefined: the run did not stop on /target_rel_error; unset "
                     "/target_rel_error (or make the particles interact: raise "
                     "/phi or /cutoff)",
                     p.pressure ? "mu" : "eta_r");
            json_array_append_new(warnings, json_string(text));
        }
        json_object_set_new(ctx->summary_extra, "warnings", warnings);
        lub_summary_put(ctx, "elastic_number", checks.elastic_number, NAN, "1");
        json_t *terms = json_array();
        lub_law_terms_append(terms, p.law.params.terms);
        if (p.drag_viscosity > 0.0)
            json_array_append_new(terms, json_string("affine_drag"));
        json_object_set_new(ctx->summary_extra, "active_terms", terms);
        json_object_set_new(ctx->summary_extra, "lubrication_pairs",
                            json_string(p.delaunay ? "delaunay" : "cutoff"));
        if (p.delaunay) {
            const lub_topology *tp = &sys.topo;
            lub_summary_put(ctx, "delaunay_updates", (double)tp->updates, NAN, "1");
            lub_summary_put(ctx, "delaunay_allowed_fraction",
                            tp->inside ? (double)tp->allowed / (double)tp->inside : NAN, NAN, "1");
            lub_summary_put(ctx, "delaunay_open_fraction",
                            tp->allowed ? (double)tp->open / (double)tp->allowed : NAN, NAN, "1");
        }
        json_object_set_new(ctx->summary_extra, "steps", json_integer(step));
        json_object_set_new(ctx->summary_extra, "simulated_time", json_real(sys.time));
        json_object_set_new(ctx->summary_extra, "units",
                            json_pack("{s:s, s:s, s:s, s:s, s:s}", "length",
                                      "a (mean particle radius)", "viscosity", "eta (fluid)",
                                      "stress",
                                      p.pressure ? "P (imposed particle pressure)" : "eta*gd",
                                      "time", p.pressure ? "eta/P (shear rate gd = Iv)" : "1/gd",
                                      "density", "rho = St*eta/(gd*a^2)"));
    }
    if (p.pdf_on && sys.pdf.snapshots > 0) {
        lub_pdf_finish(&sys.pdf);
        /* [n_theta][n_phi] maps; vectors and tensors as [n_theta * n_phi][3 or 9] rows
         * (bin index = i_theta * n_phi + i_phi) */
        size_t nb = (size_t)p.pdf_nt * (size_t)p.pdf_np;
        int64_t dims[2] = {p.pdf_nt, p.pdf_np};
        int64_t dims3[2] = {(int64_t)nb, 3};
        int64_t dims9[2] = {(int64_t)nb, 9};
        int io = lub_h5_write_array(ctx->out, "pdf_interaction_density", 2, dims, sys.pdf.density,
                                    "1/sr") ||
                 lub_h5_write_array(ctx->out, "pdf_contact_density", 2, dims,
                                    sys.pdf.contact_density, "1/sr") ||
                 lub_h5_write_array(ctx->out, "pdf_mean_gap", 2, dims, sys.pdf.gap_sum, "a") ||
                 lub_h5_write_array(ctx->out, "pdf_mean_relative_velocity", 2, dims3,
                                    sys.pdf.vel_sum, p.pressure ? "a*P/eta" : "a*gd");
        const char *pn[4] = {"pdf_stress_normal_contact", "pdf_stress_tangential_contact",
                             "pdf_stress_normal_lubrication", "pdf_stress_tangential_lubrication"};
        for (int k = 0; k < 4 && !io; ++k)
            io = lub_h5_write_array(ctx->out, pn[k], 2, dims9, sys.pdf.stress + k * nb * 9,
                                    p.pressure ? "P/sr" : "eta*gd/sr");
        if (io && exit_code == LUB_EXIT_OK) {
            snprintf(ctx->diagnostic, sizeof ctx->diagnostic, "%s", lub_h5_last_error(ctx->out));
            exit_code = LUB_EXIT_IO;
        }
        lub_summary_put(ctx, "pdf_snapshots", (double)sys.pdf.snapshots, NAN, "1");
    }

cleanup:
    if (resume)
        lub_ckpt_close(resume, NULL, 0);
    free(pos);
    for (int k = 0; k < S_COUNT; ++k)
        free(ser.v[k]);
    free(ser.strain);
    free(scratch);
    free(ratio_z);
    free(radius);
    lub_shear_free(&sys);
    lub_pair_network_free(&net);
    return exit_code;
}

/* The system after its first rebuild, or its second when the run certainly shears far enough
 * (lub_shear_min_bytes, lub_shear_rebuild_strain): /strain, or with /target_rel_error at
 * least /transient_strain + /target_min_strain, before which it cannot stop early. The time
 * series (SS_SAMPLE_BYTES per sample, up to 232 MB) is left out: its sample count depends on
 * the time step, which may exceed /sample_strain. */
static int ss_memory_need(const json_t *resolved, int threads, lub_memory_need *need)
{
    ss_params p;
    lub_error err;
    if (ss_read_resolved(resolved, &p, &err))
        return -1;
    const double n = (double)p.n;
    const double sheared = p.target_rel_error > 0.0
                               ? fmin(p.strain, p.transient_strain + p.target_min_strain)
                               : p.strain;
    const int rebuilt = sheared > 1.01 * lub_shear_rebuild_strain(p.cutoff, p.skin);
    need->bytes = lub_shear_min_bytes(n, p.phi, p.radius_std, p.cutoff, p.skin, threads, rebuilt);
    if (p.pair_network != LUB_NETWORK_NONE) /* the pairs inside the cut-off, and a quarter more */
        need->bytes += 1.25 * 0.9 * n *
                       lub_shear_listed_pairs_estimate(p.phi, p.radius_std, p.cutoff, 0.0) *
                       LUB_PAIR_NETWORK_PAIR_BYTES;
    need->per_item = need->bytes / n;
    need->member = "/n_particles";
    snprintf(need->what, sizeof need->what,
             "%lld particles at phi %.3g, cut-off %.3g a and skin %.3g a", (long long)p.n, p.phi,
             p.cutoff, p.skin);
    return 0;
}

/* the members that only decide when the run ends, or what it writes there: a continuation
 * may change them */
static const char *const ss_resume_may_differ[] = {"strain", "target_rel_error",
                                                   "target_min_strain", "pair_network", NULL};

const lub_scene lub_scene_simple_shear = {
    .name = "simple_shear",
    .title = "Periodic simple-shear rheometer (imposed volume or imposed particle pressure)",
    .description =
        "Tri-periodic simple shear (deforming cell with flips) of N polydisperse rough, "
        "frictional spheres with the lubricated contact law. Control 'volume' imposes phi and "
        "measures the pressure (units: a, eta, gd = 1); control 'pressure' imposes the particle "
        "pressure P = -sigma_yy through a servo on the gradient-direction cell size at the "
        "viscous number Iv = eta gd/P (units: a, eta, P = 1). Reports phi, P, mu = sigma_xy/P, "
        "eta_r, Iv, normal viscosities eta_ii, normal-stress ratios, coordination and contact "
        "numbers, the bond order Q6 (ordering indicator) and the stress split (normal/tangential "
        "contact/lubrication, kinetic) with "
        "steady-state detection (MSER) and AR(1)-corrected batch-means error bars.",
    .resolve = ss_resolve,
    .run = ss_run,
    .memory_need = ss_memory_need,
    .resumable = 1,
    .resume_may_differ = ss_resume_may_differ,
};
