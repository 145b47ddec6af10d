/* scene_resuspension.c — viscous resuspension of buoyant lubricated spheres sheared above a
 * rough floor (physics-reference §4; seed 000, resuspension article §II.C–E, §III.B).
 *
 * Units (dimensionless): length a (mean radius), viscosity eta (fluid), time 1/gd (gd = 1).
 * Hence stresses are in eta gd, forces in eta gd a^2, energies in eta gd a^3.
 * Inputs are dimensionless groups:
 *   Sh = eta gd/(drho g a)          Shields number: drho g = 1/Sh (buoyant weight of a sphere
 *                                    = (4/3) pi r^3 / Sh)
 *   I  = gd sqrt(a/g)               inertial number: g = 1/I^2, hence drho = I^2/Sh
 *   density_ratio = rho_p/drho      particle mass density rho_p = density_ratio * drho
 *                                    (1: gravity acts on the whole particle mass, as in Yade)
 *   stiffness = g_bulk/(eta gd a)   contact-law bulk stiffness
 * The particle Stokes number St = rho_p gd a^2/eta = density_ratio I^2/Sh is reported.
 *
 * Cell: periodic in x (flow) and z; gravity along -y; rough floor of fixed spheres
 * (floor_wall.h), reflecting lid far above (lid_height x initial bed height). Orientation
 * "gradient": gravity along the gradient direction, shear imposed by a drag of viscosity
 * shear_drag_viscosity*eta towards u = gd (y - y_floor) e_x. "vorticity": gravity along the
 * vorticity direction, Lees–Edwards shear of the x-z plane (u = gd z e_x), no shear drag.
 * Dilute-region damping: Stokes drag with viscosity dilute_drag.viscosity*eta on particles
 * with at most dilute_drag.max_interactions active pairs (default 2: "fewer than three").
 *
 * Observables: phi(y) time- and plane-averaged over strain >= average_from with the stats.h
 * error bars (exact sphere–slab volumes, resuspension_profile.h), suspension height (phi
 * crosses half its maximum), eta_ii(y) = (1/Sh) int_y^inf phi (resuspension_analysis.h), the
 * bulk points eta_ii(phi) after lub_profile_select_bulk, phi averaged over analysis.phi_window
 * (default 2 a, one diameter: lub_profile_coarse_grain) so that the layering next to the floor
 * does not bias them, and the seed's laws (eq. 9; for the vorticity orientation eta_33 =
 * lambda_33 eta_22 with eq. 8) at that averaged phi for comparison.
 * y in all outputs is measured from the floor centre plane.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "floor_wall.h"
#include "h5md_continue.h"
#include "json_text.h"
#include "law_spec.h"
#include "network_output.h"
#include "packing.h"
#include "resuspension_analysis.h"
#include "resuspension_bed.h"
#include "resuspension_checkpoint.h"
#include "resuspension_profile.h"
#include "resuspension_system.h"
#include "run_context.h"
#include "scene.h"
#include "scene_summary.h"
#include "shear_run_checks.h"
#include "state_checkpoint.h"
#include "stats.h"
#include "step_count.h"
#include "step_schedule.h"
#include "step_stiffness.h"

#define RS_PI 3.14159265358979323846
/* Most samples a run may take (strain / sample_strain): each one from /average_from on keeps
 * a profile of every bin in memory until the end of the run. */
#define RS_MAX_SAMPLES 1e6

typedef struct {
    long long n, seed, snapshots, dilute_max;
    double width, radius_std, Sh, I, density_ratio, stiffness, eta_shear, eta_dilute;
    double floor_radius, floor_jitter, lid_height, strain, average_from, sample_strain, bin_width,
        interface_width, floor_skip, phi_min, phi_m, phi_window, dt, dt_safety, dt_stiffness_safety,
        cutoff, skin, initial_phi;
    int orientation;
    int pair_network; /* LUB_NETWORK_*: when to write the interaction network */
    lub_law_spec law;
} rs_params;

static const lub_law_spec_opts rs_law_opts = {
    .allowed_terms = LUB_TERM_ALL,
    .default_terms = LUB_TERM_ALL,
    .tangential = 1,
    .default_eps = 2e-3, /* physical convention: the seed's eps = 1e-3 (Yade's eps_Y) */
    .default_alpha = 1.0,
    .default_kt_ratio = 0.5,
    .default_mu = 0.5,
};

/* Defaults of the members the step count depends on (rs_read, rs_check_steps). */
#define RS_DEFAULT_SHIELDS 0.5
#define RS_DEFAULT_INERTIAL_NUMBER 0.03
#define RS_DEFAULT_DENSITY_RATIO 1.0
#define RS_DEFAULT_STIFFNESS 1e6
#define RS_DEFAULT_STRAIN 40.0
#define RS_DEFAULT_DT_SAFETY 0.3

/* The elastic bound of a particle of radius r (rs_run takes the lightest particle's), from
 * the spec: m = (4/3) pi r^3 rho, rho = density_ratio drho, drho = I^2/Sh, g = stiffness,
 * k_t = kt_ratio g. Units a = eta = gd = 1. */
static double rs_elastic_dt(const rs_params *p, double r)
{
    const double rho = p->density_ratio * p->I * p->I / p->Sh;
    const double m = rho * 4.0 / 3.0 * RS_PI * r * r * r;
    const double k_bulk = p->stiffness, k_t = p->law.kt_ratio * p->stiffness;
    double dt = sqrt(m / k_bulk);
    if (k_t > 0.0)
        dt = fmin(dt, sqrt(0.4 * m / k_t));
    return dt;
}

/* The run's step when its lightest particle has radius r. */
static double rs_step_at(const rs_params *p, double r)
{
    return p->dt > 0.0 ? p->dt : p->dt_safety * rs_elastic_dt(p, r);
}

/* The run's steps (step_count.h) when its lightest particle has radius r. */
static double rs_steps_at(const rs_params *p, double r)
{
    return lub_step_count(p->strain, rs_step_at(p, r));
}

/* The refusal of `count` steps of length dt (qualifier: "" for the run's own, "at least " or
 * "at most " for a bound), the lightest particle having radius r: names the member whose
 * default brings the count nearest the allowed range. -1. */
static int rs_step_refusal(const rs_params *p, double r, double count, double dt,
                           const char *qualifier, lub_error *err)
{
    lub_step_alt alt[8];
    int n = 0;
    rs_params q;
/* alt[n++]: the count with member `field` of the spec at `value`, the rest as it is */
#define RS_ALT(name, field, value)                                                                 \
    (q = *p, q.field = (value), alt[n++] = (lub_step_alt){(name), rs_steps_at(&q, r)})
    if (p->dt > 0.0) {
        RS_ALT("/dt", dt, 0.0);
    } else {
        RS_ALT("/stiffness", stiffness, RS_DEFAULT_STIFFNESS);
        RS_ALT("/shields", Sh, RS_DEFAULT_SHIELDS);
        RS_ALT("/inertial_number", I, RS_DEFAULT_INERTIAL_NUMBER);
        RS_ALT("/density_ratio", density_ratio, RS_DEFAULT_DENSITY_RATIO);
        RS_ALT("/law/kt_ratio", law.kt_ratio, rs_law_opts.default_kt_ratio);
        RS_ALT("/dt_safety", dt_safety, RS_DEFAULT_DT_SAFETY);
    }
    RS_ALT("/strain", strain, RS_DEFAULT_STRAIN);
    char duration[48], origin[240];
    snprintf(duration, sizeof duration, "/strain %.6g", p->strain);
    if (p->dt > 0.0)
        snprintf(origin, sizeof origin, "fixed by /dt");
    else
        snprintf(origin, sizeof origin,
                 "/dt_safety %g times dt_critical, the elastic bound of the lightest particle, "
                 "which /stiffness, /shields, /inertial_number, /density_ratio, /law/kt_ratio "
                 "and /radius_std set",
                 p->dt_safety);
#undef RS_ALT
    return lub_step_count_fail(err, lub_step_count_culprit(count, alt, n), count, qualifier,
                               "/strain", duration, dt, origin);
}

/* The step-count rule at validation: with /dt fixed the count is known; otherwise it lies
 * between the counts of the lightest particle's largest and smallest possible radii
 * (lub_packing_radius_bounds: the bed is cut from a packing), and a spec is refused here when
 * the whole range is outside (the run checks its own count once the bed is built). */
static int rs_check_steps(const rs_params *p, lub_error *err)
{
    double r_lo = 1.0, r_hi = 1.0;
    if (p->dt <= 0.0)
        lub_packing_radius_bounds(p->radius_std, &r_lo, &r_hi);
    const double fewest = rs_steps_at(p, r_hi), most = rs_steps_at(p, r_lo);
    const char *qualifier;
    const int out = lub_step_count_range_outside(fewest, most, p->dt > 0.0, &qualifier);
    if (!out)
        return 0;
    const double count = out > 0 ? fewest : most;
    /* the step itself, not the duration over the count (0 for a count of inf at 5e-324) */
    const double r = out > 0 ? r_hi : r_lo;
    return rs_step_refusal(p, r, count, rs_step_at(p, r), qualifier, err);
}

/* How far a sphere of radius a compresses a contact under its own weight, (4/3) pi a^3 drho g
 * over the contact stiffness g_bulk a, in a: (4/3) pi / (/shields /stiffness). The bed's lowest
 * contacts carry more (the spheres above them). */
static double rs_weight_overlap(const rs_params *p)
{
    return 4.0 / 3.0 * RS_PI / (p->Sh * p->stiffness);
}

/* Refused at this weight overlap: the floor cannot hold such a bed (runs with 20 spheres at
 * 0.07 a and above, 400 at 0.042 a, let spheres through the floor within 150 steps). The
 * overlap is an estimate (the asperities in series with the bulk, 1/alpha, are left out): the
 * threshold rests on those runs. */
#define RS_WEIGHT_OVERLAP_MAX 0.05
/* At a tenth of it an escape through the floor is blamed on the weight, not the time step. */
#define RS_WEIGHT_OVERLAP_BLAMED (0.1 * RS_WEIGHT_OVERLAP_MAX)

static int rs_check_weight(const rs_params *p, lub_error *err)
{
    const double overlap = rs_weight_overlap(p);
    if (overlap < RS_WEIGHT_OVERLAP_MAX)
        return 0;
    return lub_fail(err, "/stiffness",
                    "a sphere's own weight would compress its contact by %.3g a ((4/3) pi / "
                    "(/shields /stiffness)), at least %g a: the floor cannot hold the bed, whose "
                    "lowest contacts carry more; raise /stiffness above %.3g or /shields (got "
                    "/stiffness %g, /shields %g)",
                    overlap, RS_WEIGHT_OVERLAP_MAX, p->stiffness * overlap / RS_WEIGHT_OVERLAP_MAX,
                    p->stiffness, p->Sh);
}

/* The cell must be at least twice the neighbour listing distance wide (neighbor_list.h): the
 * bed's width L and its largest sphere (floor spheres included) are known from the radii alone
 * (lub_bed_geometry), so a spec the run would stop on is refused here, before the packing. In the
 * vorticity orientation the x-z plane is sheared (Lees-Edwards) and flipped at rebuilds once its
 * tilt passes one half, so its narrowest width falls to L/sqrt(1 + 1/4) (n = 20, width 9.8, the
 * default cut-off: validated, then stopped at strain 0.24 with the cell too narrow). */
static int rs_check_width(const rs_params *p, lub_error *err)
{
    const lub_bed_params bp = {.n = (int)p->n,
                               .width = p->width,
                               .phi_target = p->initial_phi,
                               .radius_std = p->radius_std,
                               .seed = (uint64_t)p->seed};
    lub_bed_info info;
    double r_max;
    if (lub_bed_geometry(&bp, &info, &r_max) != 0)
        return lub_fail(err, "/n", "out of memory for the radii of %lld spheres", p->n);
    const double L = info.side;
    const double r_floor = L / (2.0 * lub_floor_side_count(L, p->floor_radius, 4));
    const double r_big = fmax(r_max, r_floor);
    const double d_list = 2.0 * r_big * (1.0 + 0.5 * p->cutoff) + p->skin;
    const int tilts = p->orientation == LUB_RS_VORTICITY;
    const double need = 2.0 * d_list * (tilts ? sqrt(1.25) : 1.0);
    if (L >= need * (1.0 + 1e-12))
        return 0;
    return lub_fail(err, "/width",
                    "the cell must be at least %s the neighbour listing distance wide: it is "
                    "%.4g a (the packed layer's side for this /width, /n, /initial_phi, "
                    "/radius_std and /seed), the listing distance 2 r_max (1 + /cutoff/2) + /skin "
                    "is %.4g a with r_max = %.4g a (the largest %s); raise /width to about %.3g "
                    "or lower /cutoff or /skin%s (got %g)",
                    tilts ? "2 sqrt(1.25) times (twice, and the vorticity orientation's cell "
                            "tilts by up to one half)"
                          : "twice",
                    L, d_list, r_big, r_floor > r_max ? "sphere, a floor sphere" : "sphere",
                    ceil(p->width * need / L * 1.01 * 10.0) / 10.0,
                    r_floor > r_max ? " or /floor/radius" : "", p->width);
}

static int rs_read(json_t *spec, rs_params *p, lub_error *err)
{
    static const char *keys[] = {"scene",
                                 "n",
                                 "width",
                                 "radius_std",
                                 "orientation",
                                 "shields",
                                 "inertial_number",
                                 "density_ratio",
                                 "stiffness",
                                 "shear_drag_viscosity",
                                 "dilute_drag",
                                 "floor",
                                 "lid_height",
                                 "strain",
                                 "average_from",
                                 "sample_strain",
                                 "bin_width",
                                 "analysis",
                                 "dt",
                                 "dt_safety",
                                 "dt_stiffness_safety",
                                 "cutoff",
                                 "skin",
                                 "initial_phi",
                                 "seed",
                                 "snapshots",
                                 "pair_network",
                                 "law",
                                 NULL};
    static const char *orient[] = {"gradient", "vorticity", NULL};
    if (lub_spec_only_keys(spec, "", keys, err))
        return -1;
    const char *o = NULL;
    const lub_range unit_half = {0.0, 1.0, 1, 0};
    if (lub_spec_integer(spec, "", "n", 20, 100000, 1, 400, &p->n, err) ||
        lub_spec_number(spec, "", "width", (lub_range){8.0, 1000.0, 0, 0}, 1, 14.0, &p->width,
                        err) ||
        lub_spec_number(spec, "", "radius_std", (lub_range){0.0, 0.1, 0, 0}, 1, 0.05,
                        &p->radius_std, err) ||
        lub_spec_enum(spec, "", "orientation", orient, "gradient", &o, err) ||
        lub_spec_number(spec, "", "shields", LUB_POSITIVE, 1, RS_DEFAULT_SHIELDS, &p->Sh, err) ||
        lub_spec_number(spec, "", "inertial_number", (lub_range){0.0, 10.0, 1, 0}, 1,
                        RS_DEFAULT_INERTIAL_NUMBER, &p->I, err) ||
        lub_spec_number(spec, "", "density_ratio", (lub_range){1.0, INFINITY, 0, 0}, 1,
                        RS_DEFAULT_DENSITY_RATIO, &p->density_ratio, err) ||
        lub_spec_number(spec, "", "stiffness", LUB_POSITIVE, 1, RS_DEFAULT_STIFFNESS, &p->stiffness,
                        err) ||
        lub_spec_number(spec, "", "shear_drag_viscosity", LUB_NONNEGATIVE, 1, 1.0 / 30.0,
                        &p->eta_shear, err) ||
        lub_spec_number(spec, "", "lid_height", (lub_range){1.0, 100.0, 0, 0}, 1, 3.0,
                        &p->lid_height, err) ||
        lub_spec_number(spec, "", "strain", (lub_range){0.0, 1e6, 1, 0}, 1, RS_DEFAULT_STRAIN,
                        &p->strain, err) ||
        lub_spec_number(spec, "", "average_from", LUB_NONNEGATIVE, 1, 20.0, &p->average_from,
                        err) ||
        lub_spec_number(spec, "", "sample_strain", LUB_POSITIVE, 1, 0.1, &p->sample_strain, err) ||
        lub_spec_number(spec, "", "bin_width", (lub_range){0.01, 10.0, 0, 0}, 1, 0.5, &p->bin_width,
                        err) ||
        lub_spec_number(spec, "", "dt", LUB_NONNEGATIVE, 1, 0.0, &p->dt, err) ||
        lub_spec_number(spec, "", "dt_safety", unit_half, 1, RS_DEFAULT_DT_SAFETY, &p->dt_safety,
                        err) ||
        lub_spec_number(spec, "", "dt_stiffness_safety", (lub_range){0.0, 2.0, 0, 0}, 1,
                        LUB_DT_STIFFNESS_SAFETY, &p->dt_stiffness_safety, err) ||
        lub_spec_number(spec, "", "cutoff", (lub_range){0.0, 4.0, 1, 0}, 1, 2.0, &p->cutoff, err) ||
        lub_spec_number(spec, "", "skin", (lub_range){0.0, 2.0, 1, 0}, 1, 0.3, &p->skin, err) ||
        lub_spec_number(spec, "", "initial_phi", (lub_range){0.05, 0.55, 0, 0}, 1, 0.5,
                        &p->initial_phi, err) ||
        lub_spec_integer(spec, "", "seed", 0, 4294967295LL, 1, 1, &p->seed, err) ||
        lub_spec_integer(spec, "", "snapshots", 0, 1000, 1, 2, &p->snapshots, err) ||
        lub_spec_pair_network(spec, &p->pair_network, err))
        return -1;
    p->orientation = strcmp(o, "vorticity") == 0 ? LUB_RS_VORTICITY : LUB_RS_GRADIENT;
    char strain[40], from[40];
    if (lub_spec_sample_count(p->strain, p->sample_strain, RS_MAX_SAMPLES,
                              "each keeps a profile of every bin in memory from /average_from on",
                              err))
        return -1;
    if (p->average_from >= p->strain)
        return lub_fail(err, "/average_from",
                        "must be below /strain (%s) so that something is averaged (got %s)",
                        lub_real_text(p->strain, strain), lub_real_text(p->average_from, from));

    json_t *dd = lub_spec_object(spec, "", "dilute_drag", err);
    if (!dd)
        return -1;
    static const char *dd_keys[] = {"viscosity", "max_interactions", NULL};
    if (lub_spec_only_keys(dd, "/dilute_drag", dd_keys, err) ||
        lub_spec_number(dd, "/dilute_drag", "viscosity", LUB_NONNEGATIVE, 1, 1.0, &p->eta_dilute,
                        err) ||
        lub_spec_integer(dd, "/dilute_drag", "max_interactions", -1, 1000, 1, 2, &p->dilute_max,
                         err))
        return -1;

    json_t *fl = lub_spec_object(spec, "", "floor", err);
    if (!fl)
        return -1;
    static const char *fl_keys[] = {"radius", "jitter", NULL};
    if (lub_spec_only_keys(fl, "/floor", fl_keys, err) ||
        lub_spec_number(fl, "/floor", "radius", (lub_range){0.5, 2.0, 0, 0}, 1, 1.0,
                        &p->floor_radius, err) ||
        lub_spec_number(fl, "/floor", "jitter", (lub_range){0.0, 0.3, 0, 0}, 1, 0.15,
                        &p->floor_jitter, err))
        return -1;
    /* impermeability: the smallest particle must not fit through the floor (floor_wall.h);
     * the actual floor radius may be up to 12.5 % larger (>= 4 spheres per side) than requested
     * (fitted to the cell) */
    const double rmin = 1.0 - 3.0 * p->radius_std;
    const double pass = lub_floor_max_passing_radius(1.13 * p->floor_radius, p->floor_jitter);
    if (!(pass < rmin))
        return lub_fail(err, "/floor/radius",
                        "the floor would let particles through: a sphere of radius %.4g a "
                        "passes a floor of radius %.4g with jitter %.4g, smallest particle "
                        "radius is %.4g a",
                        pass, p->floor_radius, p->floor_jitter, rmin);

    json_t *an = lub_spec_object(spec, "", "analysis", err);
    if (!an)
        return -1;
    static const char *an_keys[] = {"interface_width", "floor_skip", "phi_min",
                                    "phi_m",           "phi_window", NULL};
    if (lub_spec_only_keys(an, "/analysis", an_keys, err) ||
        lub_spec_number(an, "/analysis", "interface_width", LUB_NONNEGATIVE, 1, 5.0,
                        &p->interface_width, err) ||
        lub_spec_number(an, "/analysis", "floor_skip", LUB_NONNEGATIVE, 1, 3.0, &p->floor_skip,
                        err) ||
        lub_spec_number(an, "/analysis", "phi_min", (lub_range){0.0, 1.0, 0, 1}, 1, 0.05,
                        &p->phi_min, err) ||
        /* a jamming fraction of spheres: at most the densest packing pi/sqrt(18); below 0.2 the
         * settled height inventory/phi_m and the eta_22 law's phi/phi_m are meaningless (at 1e-300
         * they overflowed to null results, exit 0) */
        lub_spec_number(an, "/analysis", "phi_m", (lub_range){0.2, 0.7405, 0, 0}, 1, 0.58,
                        &p->phi_m, err) ||
        lub_spec_number(an, "/analysis", "phi_window", (lub_range){0.0, 100.0, 0, 0}, 1, 2.0,
                        &p->phi_window, err))
        return -1;

    json_t *law = lub_spec_object(spec, "", "law", err);
    if (!law || lub_law_spec_resolve(law, "/law", &rs_law_opts, &p->law, err) ||
        lub_law_spec_check_cutoff(&p->law, "/law", p->cutoff, err))
        return -1;
    if (rs_check_width(p, err) || rs_check_steps(p, err))
        return -1;
    return rs_check_weight(p, err);
}

static int rs_resolve(json_t *spec, lub_error *err)
{
    rs_params p;
    return rs_read(spec, &p, err);
}

/* Seed's laws (resuspension article eq. 8–9). */
static double eta22_law(double phi, double phi_m)
{
    const double x = phi / phi_m;
    if (!(x < 1.0))
        return INFINITY;
    return pow(x, 9.0) / ((1.0 - x) * (1.0 - x)) + 150.0 * pow(x, 10.0);
}
static double lambda33_law(double phi)
{
    const double x = phi / 0.64;
    return pow(x, 7.5) / (1e-3 + pow(x, 6.0));
}

/* Everything allocated for a run (freed in one place). */
typedef struct {
    double *radius, *floor_r, *samples, *scratch, *series_h, *phi_inst, *vol;
    double *phi, *phi_err, *eta, *eta_err, *ybin, *keepd, *law, *pairs_out, *scratch2, *vx_vol,
        *vx_sum, *vx_inst, *phi_cg, *phi_cg_err;
    vec3 *pos, *floor_pos;
    int *keep;
    double *snap_x, *snap_v, *snap_w;
} rs_buffers;

static void rs_buffers_free(rs_buffers *b)
{
    double *d[] = {b->radius,  b->floor_r, b->samples,   b->scratch,  b->series_h, b->phi_inst,
                   b->vol,     b->phi,     b->phi_err,   b->eta,      b->eta_err,  b->ybin,
                   b->keepd,   b->law,     b->pairs_out, b->scratch2, b->vx_vol,   b->vx_sum,
                   b->vx_inst, b->snap_x,  b->snap_v,    b->snap_w,   b->phi_cg,   b->phi_cg_err};
    for (size_t i = 0; i < sizeof d / sizeof d[0]; ++i)
        free(d[i]);
    free(b->pos);
    free(b->floor_pos);
    free(b->keep);
    memset(b, 0, sizeof *b);
}

/* Grows the sample buffers so that the series holds `total` height samples and the average
 * `avg` profiles (the statistics' scratch max(total, avg) + 1); 0 or -1 (no memory: the buffers
 * keep their contents). Called when the step changes. */
static int rs_samples_reserve(rs_buffers *b, int nb, int64_t total, int64_t avg,
                              int64_t *nsamp_total, int64_t *nsamp_avg)
{
    if (total > *nsamp_total) {
        double *h = realloc(b->series_h, (size_t)total * sizeof *h);
        if (!h)
            return -1;
        b->series_h = h;
        *nsamp_total = total;
    }
    if (avg > *nsamp_avg) {
        double *sm = realloc(b->samples, (size_t)(avg * nb) * sizeof *sm);
        if (!sm)
            return -1;
        b->samples = sm;
        *nsamp_avg = avg;
    }
    const size_t scratch = (size_t)(*nsamp_avg > *nsamp_total ? *nsamp_avg : *nsamp_total) + 1;
    double *s1 = realloc(b->scratch, scratch * sizeof *s1);
    if (!s1)
        return -1;
    b->scratch = s1;
    double *s2 = realloc(b->scratch2, scratch * sizeof *s2);
    if (!s2)
        return -1;
    b->scratch2 = s2;
    return 0;
}

static int write_profiles(lub_h5 *h5, const char *name, int n, const double *data, const char *unit)
{
    int64_t dims[1] = {n};
    return lub_h5_write_array(h5, name, 1, dims, data, unit);
}

/* The time loop's state besides the system and the sample buffers: what a checkpoint holds
 * with them, so that a stopped run continues as if it had not stopped. */
typedef struct {
    int64_t step;           /* loop index to continue at (its sample is taken) */
    int64_t avg_start_step; /* first step averaged into the profiles */
    int64_t nh, navg;       /* height samples (= time-series rows) and averaged profiles */
    int64_t below_floor_max, frames_in_file;
    int64_t network_frames_in_file; /* /pair_network frames in the output file */
    double max_ke, min_lowest, contacts_sum, crushed_sum;
    double y_floor, y_lid; /* the geometry the bed gave (checked on resuming) */
    lub_step_control ctl;
    lub_schedule sched;
} rs_loop;

/* The loop state, the samples and the system into path (a new file). 0, or -1 with why[len]. */
static int rs_checkpoint_write(const char *path, const json_t *resolved, const rs_loop *lp,
                               const rs_buffers *b, int nb, const lub_rs_system *S,
                               const char *output_file, char *why, size_t len)
{
    lub_ckpt *c =
        lub_run_checkpoint_create(path, "resuspension", lp->step, resolved, output_file, why, len);
    if (!c)
        return -1;
    const int64_t ints[6] = {lp->step, lp->avg_start_step,  lp->nh,
                             lp->navg, lp->below_floor_max, lp->frames_in_file};
    const double reals[6] = {lp->max_ke,      lp->min_lowest, lp->contacts_sum,
                             lp->crushed_sum, lp->y_floor,    lp->y_lid};
    int rc =
        lub_ckpt_put(c, "run/ints", LUB_CKPT_I64, 6, ints) ||
        lub_ckpt_put(c, "run/reals", LUB_CKPT_F64, 6, reals) ||
        lub_ckpt_put_i64(c, "run/network_frames_in_file", lp->network_frames_in_file) ||
        lub_step_control_save(c, "run/step_control", &lp->ctl) ||
        lub_schedule_save(c, "run/schedule", &lp->sched) ||
        lub_ckpt_put(c, "series/height", LUB_CKPT_F64, (size_t)lp->nh, b->series_h) ||
        lub_ckpt_put(c, "profiles/samples", LUB_CKPT_F64, (size_t)(lp->navg * nb), b->samples) ||
        lub_ckpt_put(c, "profiles/vx_volume", LUB_CKPT_F64, (size_t)nb, b->vx_vol) ||
        lub_ckpt_put(c, "profiles/vx_sum", LUB_CKPT_F64, (size_t)nb, b->vx_sum) ||
        lub_rs_save(c, S);
    return lub_run_checkpoint_close(c, rc, why, len);
}

/* The loop state of checkpoint c. 0, or -1 with why[len]. */
static int rs_checkpoint_read_loop(lub_ckpt *c, rs_loop *lp, char *why, size_t len)
{
    int64_t ints[6];
    double reals[6];
    if (lub_ckpt_get(c, "run/ints", LUB_CKPT_I64, 6, ints) ||
        lub_ckpt_get(c, "run/reals", LUB_CKPT_F64, 6, reals) ||
        lub_step_control_load(c, "run/step_control", &lp->ctl) ||
        lub_schedule_load(c, "run/schedule", &lp->sched) || ints[0] < 0 ||
        ints[0] > lp->sched.nsteps || ints[2] < 0 || ints[3] < 0 || ints[3] > ints[2]) {
        snprintf(why, len, "%s",
                 lub_ckpt_error(c)[0] ? lub_ckpt_error(c) : "inconsistent loop state");
        return -1;
    }
    lp->step = ints[0];
    lp->avg_start_step = ints[1];
    lp->nh = ints[2];
    lp->navg = ints[3];
    lp->below_floor_max = ints[4];
    lp->frames_in_file = ints[5];
    lp->max_ke = reals[0];
    lp->min_lowest = reals[1];
    lp->contacts_sum = reals[2];
    lp->crushed_sum = reals[3];
    lp->y_floor = reals[4];
    lp->y_lid = reals[5];
    /* none in a checkpoint older than the frames */
    if (lub_ckpt_get_i64_or(c, "run/network_frames_in_file", 0, &lp->network_frames_in_file)) {
        snprintf(why, len, "%s", lub_ckpt_error(c));
        return -1;
    }
    return 0;
}

/* The samples of checkpoint c into b (room reserved). 0 or -1. */
static int rs_checkpoint_read_samples(lub_ckpt *c, const rs_loop *lp, rs_buffers *b, int nb)
{
    return lub_ckpt_get(c, "series/height", LUB_CKPT_F64, (size_t)lp->nh, b->series_h) ||
                   lub_ckpt_get(c, "profiles/samples", LUB_CKPT_F64, (size_t)(lp->navg * nb),
                                b->samples) ||
                   lub_ckpt_get(c, "profiles/vx_volume", LUB_CKPT_F64, (size_t)nb, b->vx_vol) ||
                   lub_ckpt_get(c, "profiles/vx_sum", LUB_CKPT_F64, (size_t)nb, b->vx_sum)
               ? -1
               : 0;
}

/* The interaction network of the system's current state (pair_network.h: the floor spheres'
 * pairs with free particles included, theirs with one another left out) into net (arrays
 * kept for the next frame), appended to /pair_network. final: no step of this run follows
 * (the rebuild the network may do is then not counted). 0, or the exit code with
 * ctx->diagnostic set. */
static int rs_network_frame(lub_run_ctx *ctx, lub_rs_system *S, lub_h5_frames *frames,
                            lub_pair_network *net, double gd, int final)
{
    const long rebuilds = S->rebuilds, flips = S->flips;
    int rc = lub_rs_complete_list(S);
    if (rc == LUB_RS_OK) {
        const lub_pair_network_source src = {
            .pairs = &S->pairs,
            .cell = &S->cell,
            .bodies = {.x = S->x, .v = S->v, .w = S->w, .r = S->r, .inv_i_share = S->inv_i_share},
            .law = &S->law,
            .cutoff = S->p.cutoff,
            .dt = S->p.dt,
            .n_free = S->n_mobile,
            .step = S->step};
        const int b = lub_pair_network_build(&src, net, S->fail_msg, sizeof S->fail_msg);
        rc = b == LUB_PAIR_NETWORK_OK      ? LUB_RS_OK
             : b == LUB_PAIR_NETWORK_NOMEM ? LUB_RS_NOMEM
                                           : LUB_RS_NONFINITE;
    }
    if (final) {
        S->rebuilds = rebuilds;
        S->flips = flips;
    }
    if (rc != LUB_RS_OK) {
        snprintf(
            ctx->diagnostic, sizeof ctx->diagnostic, "interaction network at step %ld: %s", S->step,
            rc == LUB_RS_NOMEM ? "out of memory (/pair_network: \"none\" avoids it)" : S->fail_msg);
        return rc == LUB_RS_NOMEM ? LUB_EXIT_INTERNAL : LUB_EXIT_NUMERICAL;
    }
    if (lub_network_append(frames, net, S->step, S->time * gd)) {
        snprintf(ctx->diagnostic, sizeof ctx->diagnostic, "%s", lub_h5_last_error(ctx->out));
        return LUB_EXIT_IO;
    }
    return LUB_EXIT_OK;
}

static int rs_run(const json_t *resolved, lub_run_ctx *ctx)
{
    rs_params p;
    lub_error err;
    json_t *spec = json_deep_copy(resolved);
    int rr = rs_read(spec, &p, &err);
    json_decref(spec);
    if (rr) {
        snprintf(ctx->diagnostic, sizeof ctx->diagnostic, "%s: %s", err.pointer, err.message);
        return LUB_EXIT_INTERNAL;
    }
    /* units: a = eta = gd = 1 */
    const double a = 1.0, eta = 1.0, gd = 1.0;
    const double grav = a * gd * gd / (p.I * p.I);
    const double drho = eta * gd / (p.Sh * grav * a);
    const double rho = p.density_ratio * drho;
    const double St = rho * gd * a * a / eta;
    const int N = (int)p.n;

    rs_buffers B;
    memset(&B, 0, sizeof B);
    lub_rs_system S;
    memset(&S, 0, sizeof S);
    int rc = LUB_EXIT_OK;
    /* the failure is one the time step causes (non-finite, escape, runaway) */
    int step_unstable = 0;
    B.radius = malloc((size_t)N * sizeof *B.radius);
    B.pos = malloc((size_t)N * sizeof *B.pos);
    if (!B.radius || !B.pos) {
        snprintf(ctx->diagnostic, sizeof ctx->diagnostic, "out of memory");
        rs_buffers_free(&B);
        return LUB_EXIT_INTERNAL;
    }
    lub_bed_params bp = {.n = N,
                         .width = p.width,
                         .phi_target = p.initial_phi,
                         .radius_std = p.radius_std,
                         .seed = (uint64_t)p.seed};
    lub_bed_info binfo;
    int brc = lub_bed_build(&bp, B.radius, B.pos, &binfo);
    if (brc) {
        snprintf(ctx->diagnostic, sizeof ctx->diagnostic,
                 "initial bed failed (%s; packing code %d, %d per layer, phi %.4g)",
                 brc == -1 ? "out of memory" : "packing", binfo.info_code, binfo.per_layer,
                 binfo.layer_phi);
        rs_buffers_free(&B);
        return LUB_EXIT_INTERNAL;
    }
    const double L = binfo.side;
    /* floor: square lattice fitted to the cell width */
    const int nside = lub_floor_side_count(L, p.floor_radius, 4);
    const double rf = L / (2.0 * nside);
    const int nfloor = nside * nside;
    double rmax = 0.0, rmin = INFINITY, vsum = 0.0, ylow = INFINITY;
    for (int i = 0; i < N; ++i) {
        rmax = fmax(rmax, B.radius[i]);
        rmin = fmin(rmin, B.radius[i]);
        vsum += 4.0 / 3.0 * RS_PI * pow(B.radius[i], 3.0);
        ylow = fmin(ylow, B.pos[i].y - B.radius[i]);
    }
    if (!(lub_floor_max_passing_radius(rf, p.floor_jitter) < rmin)) {
        snprintf(ctx->diagnostic, sizeof ctx->diagnostic,
                 "fitted floor radius %.4g lets particles of radius %.4g through", rf, rmin);
        rs_buffers_free(&B);
        return LUB_EXIT_INTERNAL;
    }
    const double y_floor = rf * (1.0 + p.floor_jitter) + 1.0;
    const double y_start = y_floor + rf * (1.0 + p.floor_jitter) + 0.05;
    double ytop = 0.0;
    for (int i = 0; i < N; ++i) {
        B.pos[i].y += y_start - ylow;
        ytop = fmax(ytop, B.pos[i].y + B.radius[i]);
    }
    const double h_init = ytop - y_floor;
    const double y_lid = y_floor + p.lid_height * h_init;
    const double d_list = 2.0 * rmax * (1.0 + 0.5 * p.cutoff) + p.skin;
    const double Ly = y_lid + d_list + 2.0 * rmax + 1.0;

    B.floor_r = malloc((size_t)nfloor * sizeof *B.floor_r);
    B.floor_pos = malloc((size_t)nfloor * sizeof *B.floor_pos);
    if (!B.floor_r || !B.floor_pos) {
        snprintf(ctx->diagnostic, sizeof ctx->diagnostic, "out of memory");
        rs_buffers_free(&B);
        return LUB_EXIT_INTERNAL;
    }
    for (int i = 0; i < nfloor; ++i)
        B.floor_r[i] = rf;
    lub_floor_build(nside, rf, y_floor, p.floor_jitter, (uint64_t)p.seed + 7919u, B.floor_pos);

    lub_law_spec_scale(&p.law, eta, p.stiffness * eta * gd * a);
    lub_rs_params sp = {.orientation = p.orientation,
                        .shear_rate = gd,
                        .gravity = grav,
                        .drho = drho,
                        .rho = rho,
                        .eta_shear = p.eta_shear * eta,
                        .eta_dilute = p.eta_dilute * eta,
                        .dilute_max_interactions = (int)p.dilute_max,
                        .y_floor = y_floor,
                        .y_lid = y_lid,
                        .cutoff = p.cutoff,
                        .skin = p.skin,
                        .dt = 1.0,
                        .threads = ctx->threads};
    /* time step: elastic bound on the lightest particle (normal and tangential), notes §7 */
    const double mmin = rho * 4.0 / 3.0 * RS_PI * rmin * rmin * rmin;
    double dt_crit = sqrt(mmin / p.law.params.k_bulk);
    if (p.law.params.k_t > 0.0)
        dt_crit = fmin(dt_crit, sqrt(0.4 * mmin / p.law.params.k_t));
    sp.dt = p.dt > 0.0 ? p.dt : p.dt_safety * dt_crit;
    int src = lub_rs_init(&S, &sp, &p.law.params, N, B.radius, B.pos, nfloor, B.floor_r,
                          B.floor_pos, L, Ly, L);
    if (src == LUB_RS_NOMEM) {
        lub_diagnostic_out_of_memory(ctx, "system", N, 0.0, "/n");
        rs_buffers_free(&B);
        return LUB_EXIT_INTERNAL;
    }
    if (src) {
        snprintf(ctx->diagnostic, sizeof ctx->diagnostic, "system init failed (%d)", src);
        rs_buffers_free(&B);
        return LUB_EXIT_INTERNAL;
    }
    /* the step: fixed (/dt), or /dt_safety of the single-pair bound, lowered while the pairs'
     * summed stiffness needs it (/dt_stiffness_safety; step_stiffness.h, checked at every
     * neighbour-list rebuild) */
    const int dt_adapts = p.dt <= 0.0 && p.dt_stiffness_safety > 0.0;
    rs_loop lp; /* the loop's state: a fresh start, or the checkpoint's (resumed) */
    memset(&lp, 0, sizeof lp);
    lub_step_control_init(&lp.ctl, sp.dt, dt_adapts ? p.dt_stiffness_safety : 0.0);
    double dt = lp.ctl.dt;
    if (!ctx->resume_path && !lub_step_count_ok(lub_step_count(p.strain / gd, dt))) {
        /* the step-count rule (step_count.h) with this bed's lightest particle, which
         * validation could only bound: refused before the first step, exit 2 */
        const double r_eff = p.dt > 0.0 ? 1.0 : pow(dt_crit / rs_elastic_dt(&p, 1.0), 2.0 / 3.0);
        rs_step_refusal(&p, r_eff, lub_step_count(p.strain / gd, dt), dt, "", &err);
        snprintf(ctx->diagnostic, sizeof ctx->diagnostic, "%s: %s", err.pointer, err.message);
        lub_rs_free(&S);
        rs_buffers_free(&B);
        return LUB_EXIT_BAD_SPEC;
    }
    const double area = lub_rs_area(&S);

    /* profile bins from the floor centre plane to the lid */
    const double dy = p.bin_width;
    const int nb = (int)ceil((y_lid - y_floor) / dy);
    lub_schedule_init(&lp.sched, dt, p.strain / gd);
    const int64_t sample_every = lub_schedule_period(p.sample_strain / gd, dt);
    const int ev_sample = lub_schedule_add(&lp.sched, sample_every, 0, p.sample_strain / gd);
    int64_t nsamp_total = lp.sched.nsteps / sample_every + 2;
    lp.avg_start_step = (int64_t)ceil(p.average_from / (gd * dt) - 1e-9);
    int64_t nsamp_avg = (lp.sched.nsteps - lp.avg_start_step) / sample_every + 2;
    char profiles_what[128];
    snprintf(profiles_what, sizeof profiles_what,
             "the profiles of %d bins over %lld samples from /average_from on", nb,
             (long long)nsamp_avg);
    if (!lub_memory_fits(ctx, (double)nsamp_avg * nb * sizeof *B.samples, profiles_what,
                         "/strain - /average_from (or raise /bin_width or /sample_strain)")) {
        lub_rs_free(&S);
        rs_buffers_free(&B);
        return LUB_EXIT_INTERNAL;
    }
    B.samples = calloc((size_t)(nsamp_avg * nb), sizeof *B.samples);
    B.scratch =
        calloc((size_t)(nsamp_avg > nsamp_total ? nsamp_avg : nsamp_total) + 1, sizeof *B.scratch);
    B.scratch2 =
        calloc((size_t)(nsamp_avg > nsamp_total ? nsamp_avg : nsamp_total) + 1, sizeof *B.scratch2);
    B.series_h = calloc((size_t)nsamp_total, sizeof *B.series_h);
    B.phi_inst = calloc((size_t)nb, sizeof *B.phi_inst);
    B.vx_vol = calloc((size_t)nb, sizeof *B.vx_vol);
    B.vx_sum = calloc((size_t)nb, sizeof *B.vx_sum);
    B.vx_inst = calloc((size_t)nb, sizeof *B.vx_inst);
    B.vol = calloc((size_t)nb, sizeof *B.vol);
    B.phi = calloc((size_t)nb, sizeof *B.phi);
    B.phi_err = calloc((size_t)nb, sizeof *B.phi_err);
    B.eta = calloc((size_t)nb, sizeof *B.eta);
    B.eta_err = calloc((size_t)nb, sizeof *B.eta_err);
    B.ybin = calloc((size_t)nb, sizeof *B.ybin);
    B.keepd = calloc((size_t)nb, sizeof *B.keepd);
    B.law = calloc((size_t)nb, sizeof *B.law);
    B.pairs_out = calloc((size_t)nb * 4, sizeof *B.pairs_out);
    B.phi_cg = calloc((size_t)nb, sizeof *B.phi_cg);
    B.phi_cg_err = calloc((size_t)nb, sizeof *B.phi_cg_err);
    B.keep = calloc((size_t)nb, sizeof *B.keep);
    B.snap_x = calloc((size_t)N * 3, sizeof *B.snap_x);
    B.snap_v = calloc((size_t)N * 3, sizeof *B.snap_v);
    B.snap_w = calloc((size_t)N * 3, sizeof *B.snap_w);
    if (!B.samples || !B.scratch || !B.scratch2 || !B.vx_vol || !B.vx_sum || !B.vx_inst ||
        !B.series_h || !B.phi_inst || !B.vol || !B.phi || !B.phi_err || !B.eta || !B.eta_err ||
        !B.ybin || !B.keepd || !B.law || !B.pairs_out || !B.keep || !B.snap_x || !B.snap_v ||
        !B.snap_w || !B.phi_cg || !B.phi_cg_err) {
        snprintf(ctx->diagnostic, sizeof ctx->diagnostic,
                 "out of memory for the profiles (%d bins x %lld samples): raise /bin_width or "
                 "/sample_strain, or lower /strain - /average_from",
                 nb, (long long)nsamp_avg);
        lub_rs_free(&S);
        rs_buffers_free(&B);
        return LUB_EXIT_INTERNAL;
    }

    const char *names[] = {"suspension_height", "center_of_mass_height", "mean_phi",
                           "kinetic_energy",    "max_fluctuation_speed", "dilute_particles"};
    const int ncomp[] = {1, 1, 1, 1, 1, 1};
    const char *units[] = {"a", "a", "1", "eta gd a^3", "a gd", "1"};
    lub_h5_table *tab = lub_h5_set_units(ctx->out, "1/gd", "a", "a gd", "gd") == 0
                            ? lub_h5_table_create(ctx->out, 6, names, ncomp, units)
                            : NULL;
    const char *bnd[3] = {"periodic", "none", "periodic"};
    int snap_ok = p.snapshots == 0 || lub_h5_particles_define(ctx->out, N, B.radius, bnd) == 0;
    /* /pair_network: its arrays (about 3 kB a particle at phi 0.5) are kept from frame to frame */
    lub_h5_frames *network = p.pair_network != LUB_NETWORK_NONE && tab && snap_ok
                                 ? lub_network_define(ctx->out, "eta*gd*a^2", "eta*gd*a^3", "1/gd")
                                 : NULL;
    lub_pair_network net = {0};
    int64_t network_last_step = -1;
    if (!tab || !snap_ok || (p.pair_network != LUB_NETWORK_NONE && !network)) {
        snprintf(ctx->diagnostic, sizeof ctx->diagnostic, "%s", lub_h5_last_error(ctx->out));
        lub_rs_free(&S);
        rs_buffers_free(&B);
        return LUB_EXIT_IO;
    }
    if (network &&
        !lub_memory_fits(ctx, 1.25 * 20.0 * (double)S.n * (double)LUB_PAIR_NETWORK_PAIR_BYTES,
                         "the interaction network (/pair_network, 20 pairs a particle)",
                         "/pair_network")) {
        lub_rs_free(&S);
        rs_buffers_free(&B);
        return LUB_EXIT_INTERNAL;
    }
    const int64_t snap_every = p.snapshots > 1
                                   ? (lp.sched.nsteps + p.snapshots - 2) / (p.snapshots - 1)
                                   : lp.sched.nsteps + 1;
    const int ev_snap =
        p.snapshots > 0 ? lub_schedule_add(&lp.sched, snap_every, 0, (double)snap_every * dt) : -1;

    lp.min_lowest = INFINITY;
    lp.y_floor = y_floor;
    lp.y_lid = y_lid;
    int64_t first_step = 0, frames = 0; /* loop start; snapshots asked for */
    if (ctx->resume_path) {             /* the stopped run's state replaces the fresh one */
        char why[600] = "";
        rs_loop saved;
        memset(&saved, 0, sizeof saved);
        lub_ckpt *ck = lub_ckpt_open(ctx->resume_path, why, sizeof why);
        if (ck && rs_checkpoint_read_loop(ck, &saved, why, sizeof why) == 0) {
            if (saved.y_floor != y_floor || saved.y_lid != y_lid ||
                saved.sched.n_events != lp.sched.n_events) {
                snprintf(why, sizeof why,
                         "the bed or the events differ from the stopped run's (another build?)");
            } else if (lub_rs_restore(ck, &S)) {
                snprintf(why, sizeof why, "%s",
                         lub_ckpt_error(ck)[0] ? lub_ckpt_error(ck) : "inconsistent pairs");
            } else if (saved.sched.t_end != p.strain / gd &&
                       p.strain < S.time * gd * (1.0 - 1e-12)) {
                /* a continuation may ask for another /strain (resume_may_differ), not for less
                 * than the stopped run has done */
                snprintf(why, sizeof why,
                         "/strain: %g here, but the stopped run has already sheared to %.6g",
                         p.strain, S.time * gd);
            } else {
                /* ... and then takes the steps of a run asked for that strain from the start
                 * (lub_schedule_set_end; the checkpoint of a completed run is taken before its
                 * last sample, which only the run's end forces) */
                if (saved.sched.t_end != p.strain / gd)
                    lub_schedule_set_end(&saved.sched, p.strain / gd);
                const int64_t left =
                    (saved.sched.nsteps - saved.step) / saved.sched.ev[ev_sample].every + 2;
                if ((double)saved.sched.nsteps > LUB_MAX_STEPS) /* at the stopped run's step */
                    snprintf(why, sizeof why,
                             "/strain: %g would take the run to %.3g steps at its step of %.3g, "
                             "more than the %.0e a run may take (README, CLI contract, \"Step "
                             "count\")",
                             p.strain, (double)saved.sched.nsteps, saved.ctl.dt, LUB_MAX_STEPS);
                else if (rs_samples_reserve(&B, nb, saved.nh + left, saved.navg + left,
                                            &nsamp_total, &nsamp_avg) ||
                         rs_checkpoint_read_samples(ck, &saved, &B, nb)) {
                    snprintf(why, sizeof why, "%s",
                             lub_ckpt_error(ck)[0] ? lub_ckpt_error(ck)
                                                   : "out of memory (samples)");
                } else if (lub_h5_continue_output(
                               ctx->resume_result, tab, 6, names, ncomp, saved.nh, ctx->out, N,
                               p.snapshots > 0 ? saved.frames_in_file : 0, why, sizeof why) == 0 &&
                           (!network || lub_h5_continue_frames(ctx->resume_result, network,
                                                               saved.network_frames_in_file, why,
                                                               sizeof why) == 0)) {
                    why[0] = '\0';
                }
            }
        }
        if (ck)
            lub_ckpt_close(ck, NULL, 0);
        if (!ck || why[0]) {
            snprintf(ctx->diagnostic, sizeof ctx->diagnostic, "cannot continue from %s: %s",
                     ctx->resume_path, why[0] ? why : "unreadable");
            ctx->resume_rejected = 1;
            lub_rs_free(&S);
            rs_buffers_free(&B);
            return LUB_EXIT_BAD_SPEC;
        }
        lp = saved;
        dt = lp.ctl.dt;
        first_step = saved.step;
        frames = saved.frames_in_file;
        ctx->resumed_from_step = S.step;
        ctx->resume_begun = 1;
    }
    int64_t stopped_at = -1; /* the loop index a stop request ended the loop at */
    int end_checkpoint = 0;  /* --keep-checkpoint: written at the last step, before its sample */
    for (int64_t step = first_step; step <= lp.sched.nsteps; ++step) {
        const double t = S.time;
        if (step == lp.sched.nsteps && ctx->checkpoint_always && ctx->checkpoint_path) {
            /* A completed run keeps its state before the samples of its last step, which the
             * end forces (a sample, a snapshot) and a longer run would not take: its extension
             * (a larger /strain) then takes the steps and samples of the longer run. */
            lp.step = step;
            lp.frames_in_file = frames - lub_h5_snapshots_skipped(ctx->out, NULL, NULL, 0);
            lp.network_frames_in_file = lub_h5_frames_written(network, NULL);
            end_checkpoint =
                rs_checkpoint_write(ctx->checkpoint_path, resolved, &lp, &B, nb, &S, "result.h5",
                                    ctx->checkpoint_failure, sizeof ctx->checkpoint_failure) == 0;
        }
        const int sample = lub_schedule_due(&lp.sched, ev_sample, step) || step == lp.sched.nsteps;
        const int snap =
            ev_snap >= 0 && (lub_schedule_due(&lp.sched, ev_snap, step) || step == lp.sched.nsteps);
        if (sample || snap) {
            int below = 0;
            double low = lub_rs_lowest(&S, &below);
            lp.min_lowest = fmin(lp.min_lowest, low - y_floor);
            if (below > lp.below_floor_max)
                lp.below_floor_max = below;
        }
        if (sample) {
            memset(B.vol, 0, (size_t)nb * sizeof *B.vol);
            double ysum = 0.0, msum = 0.0;
            int dilute = 0;
            const int in_avg = step >= lp.avg_start_step;
            memset(B.vx_inst, 0, (size_t)nb * sizeof *B.vx_inst);
            for (int i = 0; i < N; ++i) {
                /* velocity along the flow relative to the floor-plane mean flow: v_x for the
                 * gradient orientation, v_x - gd z for the vorticity one (should be ~ 0) */
                const double vrel = p.orientation == LUB_RS_VORTICITY
                                        ? S.v[i].x - lub_rs_mean_velocity(&S, S.x[i]).x
                                        : S.v[i].x;
                lub_profile_add_sphere_weighted(B.vol, B.vx_inst, nb, y_floor, dy, S.x[i].y, S.r[i],
                                                vrel);
                ysum += S.m[i] * (S.x[i].y - y_floor);
                msum += S.m[i];
                dilute += step > 0 && S.nint[i] <= (int)p.dilute_max;
            }
            if (in_avg) {
                lp.contacts_sum += (double)S.n_contacts;
                lp.crushed_sum += (double)S.n_crushed;
                for (int i = 0; i < nb; ++i) {
                    B.vx_vol[i] += B.vol[i];
                    B.vx_sum[i] += B.vx_inst[i];
                }
            }
            lub_profile_normalise(B.vol, nb, dy, area, B.phi_inst);
            double pmax = 0.0;
            for (int i = 0; i < nb; ++i)
                pmax = fmax(pmax, B.phi_inst[i]);
            const double hs = lub_profile_height(B.phi_inst, nb, 0.0, dy, 0.5 * pmax);
            const double inv = lub_profile_inventory(B.phi_inst, nb, dy);
            const double ke = lub_rs_kinetic_energy(&S);
            lp.max_ke = fmax(lp.max_ke, ke);
            double row[6] = {hs, ysum / msum, inv / hs, ke, S.max_speed, (double)dilute};
            if (lub_h5_table_append(tab, S.step, t * gd, row)) {
                snprintf(ctx->diagnostic, sizeof ctx->diagnostic, "%s",
                         lub_h5_last_error(ctx->out));
                rc = LUB_EXIT_IO;
                break;
            }
            if (lp.nh < nsamp_total)
                B.series_h[lp.nh++] = hs;
            if (step >= lp.avg_start_step && lp.navg < nsamp_avg) {
                memcpy(&B.samples[lp.navg * nb], B.phi_inst, (size_t)nb * sizeof *B.phi_inst);
                lp.navg++;
            }
        }
        /* the network first: its list completion may wrap positions (the snapshot's are
         * unwrapped, lub_rs_unwrapped) */
        if (snap && p.pair_network == LUB_NETWORK_SNAPSHOTS &&
            (rc = rs_network_frame(ctx, &S, network, &net, gd, step == lp.sched.nsteps)) !=
                LUB_EXIT_OK)
            break;
        if (snap) {
            for (int i = 0; i < N; ++i) {
                vec3 xu, vu;
                lub_rs_unwrapped(&S, i, &xu, &vu);
                memcpy(&B.snap_x[3 * i], &xu, 3 * sizeof(double));
                memcpy(&B.snap_v[3 * i], &vu, 3 * sizeof(double));
                memcpy(&B.snap_w[3 * i], &S.w[i], 3 * sizeof(double));
            }
            double edges[9];
            for (int r = 0; r < 3; ++r) /* rows = edge vectors = columns of H */
                for (int c = 0; c < 3; ++c)
                    edges[3 * r + c] = S.cell.h[c][r];
            if (lub_h5_particles_snapshot(ctx->out, S.step, t, edges, B.snap_x, B.snap_v, B.snap_w,
                                          NULL)) {
                snprintf(ctx->diagnostic, sizeof ctx->diagnostic, "%s",
                         lub_h5_last_error(ctx->out));
                rc = LUB_EXIT_IO;
                break;
            }
            frames++;
        }
        if (step == lp.sched.nsteps)
            break;
        if (ctx->periodic && lub_periodic_due(ctx->periodic, step)) {
            /* the state after the sample of step `step`, as at a stop (the run then goes on) */
            lp.step = step;
            lp.frames_in_file = frames - lub_h5_snapshots_skipped(ctx->out, NULL, NULL, 0);
            lp.network_frames_in_file = lub_h5_frames_written(network, NULL);
            char why[400] = "";
            if (lub_periodic_copy_output(ctx->periodic, ctx->out) == 0) {
                if (rs_checkpoint_write(ctx->periodic->ckpt_tmp, resolved, &lp, &B, nb, &S,
                                        LUB_PERIODIC_OUTPUT, why, sizeof why) == 0)
                    lub_periodic_publish(ctx->periodic);
                else
                    lub_periodic_failed(ctx->periodic, why);
            }
        }
        if (ctx->stop_requested && *ctx->stop_requested) {
            rc = LUB_EXIT_INTERRUPTED;
            stopped_at = step;
            break;
        }
        int e = lub_rs_step(&S);
        if (e != LUB_RS_OK) {
            if (e == LUB_RS_NOMEM && !S.fail_msg[0]) { /* the pair lists could not grow */
                char what[96];
                snprintf(what, sizeof what, "pair lists, step %lld", (long long)S.step);
                lub_diagnostic_out_of_memory(ctx, what, N, 0.0, "/n");
            } else {
                snprintf(ctx->diagnostic, sizeof ctx->diagnostic, "%s (code %d)", S.fail_msg, e);
            }
            rc = e == LUB_RS_NOMEM ? LUB_EXIT_INTERNAL : LUB_EXIT_NUMERICAL;
            step_unstable = e == LUB_RS_NONFINITE || e == LUB_RS_ESCAPED || e == LUB_RS_RUNAWAY;
            if (e == LUB_RS_ESCAPED && S.escaped_below &&
                rs_weight_overlap(&p) >= RS_WEIGHT_OVERLAP_BLAMED) {
                /* heavy spheres on soft contacts sink through the floor: not the step's doing */
                const size_t len = strlen(ctx->diagnostic);
                snprintf(ctx->diagnostic + len, sizeof ctx->diagnostic - len,
                         ": the contacts give way under the bed's weight (a sphere's own weight "
                         "compresses a contact by %.3g a, (4/3) pi / (/shields /stiffness)); "
                         "raise /stiffness",
                         rs_weight_overlap(&p));
                step_unstable = 0;
            }
            break;
        }
        if (lub_rs_step_control(&S, &lp.ctl)) {
            dt = lp.ctl.dt;
            S.p.dt = dt;
            lub_schedule_set_dt(&lp.sched, step + 1, S.time, dt);
            if ((double)lp.sched.nsteps > LUB_MAX_STEPS) { /* step-count rule (step_count.h) */
                snprintf(ctx->diagnostic, sizeof ctx->diagnostic,
                         "the automatic step fell to %.3g at strain %.4f (the pairs' summed "
                         "stiffness, /dt_stiffness_safety %g; %ld changes), which would take the "
                         "run to %.3g steps, more than the %.0e a run may take (README, CLI "
                         "contract, \"Step count\"); lower /strain or /stiffness",
                         dt, S.time * gd, p.dt_stiffness_safety, lp.ctl.changes,
                         (double)lp.sched.nsteps, LUB_MAX_STEPS);
                rc = LUB_EXIT_NUMERICAL;
                break;
            }
            if (lp.avg_start_step > step + 1)
                lp.avg_start_step =
                    step + 1 + (int64_t)ceil((p.average_from / gd - S.time) / dt - 1e-9);
            const int64_t left = (lp.sched.nsteps - step) / lp.sched.ev[ev_sample].every + 2;
            if (rs_samples_reserve(&B, nb, lp.nh + left, lp.navg + left, &nsamp_total,
                                   &nsamp_avg)) {
                snprintf(ctx->diagnostic, sizeof ctx->diagnostic, "out of memory (samples)");
                rc = LUB_EXIT_INTERNAL;
                break;
            }
        }
        if ((step & 255) == 0)
            lub_progress_update(ctx->progress, (double)step / (double)lp.sched.nsteps, S.step);
    }
    lub_progress_last_step(ctx->progress, S.step);
    ctx->checkpoint_written = end_checkpoint && rc == LUB_EXIT_OK;
    /* a stop between the sample of a step and the step: that state into the checkpoint */
    if (stopped_at >= 0 && ctx->checkpoint_path) {
        lp.step = stopped_at;
        lp.frames_in_file = frames - lub_h5_snapshots_skipped(ctx->out, NULL, NULL, 0);
        lp.network_frames_in_file = lub_h5_frames_written(network, NULL);
        ctx->checkpoint_written =
            rs_checkpoint_write(ctx->checkpoint_path, resolved, &lp, &B, nb, &S, "result.h5",
                                ctx->checkpoint_failure, sizeof ctx->checkpoint_failure) == 0;
    }
    /* the network of the final state (after the checkpoint, which keeps the state before the
     * rebuild the network may do), unless a snapshot's frame already shows it */
    lub_h5_frames_written(network, &network_last_step);
    if (network && network_last_step != S.step &&
        (rc == LUB_EXIT_OK || rc == LUB_EXIT_INTERRUPTED)) {
        const int nrc = rs_network_frame(ctx, &S, network, &net, gd, 1);
        if (nrc != LUB_EXIT_OK)
            rc = nrc;
    }
    lub_pair_network_free(&net);
    if (rc == LUB_EXIT_NUMERICAL && dt_adapts && step_unstable)
        lub_diagnostic_adapted_dt_hint(ctx, dt, p.dt_safety, dt_crit, "dt_critical", lp.ctl.changes,
                                       p.dt_stiffness_safety, lp.ctl.ratio_max);
    else if (rc == LUB_EXIT_NUMERICAL && (step_unstable || p.dt > dt_crit))
        lub_diagnostic_dt_hint(ctx, p.dt, p.dt_safety, dt_crit, "dt_critical");

    /* ---- steady-state analysis (also for a partial run: whatever was averaged) ---- */
    int steady = 0;
    const size_t mser = lp.nh >= 10 ? lub_stats_mser(B.series_h, (size_t)lp.nh, 5, &steady) : 0;
    int sem_batch_means = 1;
    for (int i = 0; i < nb; ++i) {
        B.ybin[i] = (i + 0.5) * dy;
        for (int64_t j = 0; j < lp.navg; ++j)
            B.scratch[j] = B.samples[j * nb + i];
        B.phi[i] = lp.navg > 0 ? lub_stats_mean(B.scratch, (size_t)lp.navg) : NAN;
        /* NaN below LUB_STATS_MIN_BATCHES samples: then the naive SEM */
        double sem = lp.navg > 0 ? lub_stats_sem(B.scratch, (size_t)lp.navg, B.scratch2) : NAN;
        if (!(sem >= 0.0) && lp.navg >= 2) {
            sem = sqrt(lub_stats_var(B.scratch, (size_t)lp.navg) / (double)lp.navg);
            sem_batch_means = 0;
        }
        B.phi_err[i] = sem;
    }
    double hs_mean = NAN, hs_sem = NAN, inv = NAN, pmax = 0.0;
    int nkeep = 0;
    double law_rms = NAN, bulk_rate = NAN;
    if (lp.navg > 0) {
        for (int i = 0; i < nb; ++i)
            pmax = fmax(pmax, B.phi[i]);
        hs_mean = lub_profile_height(B.phi, nb, 0.0, dy, 0.5 * pmax);
        /* error of the height: stats.h standard error of the instantaneous heights */
        size_t h0i = (size_t)(lp.nh - lp.navg);
        lub_stats_result hr;
        lub_stats_analyse(B.series_h + h0i, (size_t)lp.navg, 0, B.scratch2, &hr);
        hs_sem = hr.sem;
        if (!(hs_sem >= 0.0) && lp.navg >= LUB_STATS_MIN_BATCHES) {
            /* too few samples after the MSER cut: batch means over the whole averaging
             * window, as phi_err */
            lub_stats_analyse_window(B.series_h + h0i, (size_t)lp.navg, 0, B.scratch2, &hr);
            hs_sem = hr.sem;
        } else if (!(hs_sem >= 0.0) && lp.navg >= 2) {
            /* fewer than 32 averaged samples: the naive SEM, as phi_err (phi_err_method) */
            hs_sem = sqrt(lub_stats_var(B.series_h + h0i, (size_t)lp.navg) / (double)lp.navg);
        }
        inv = lub_profile_inventory(B.phi, nb, dy);
        lub_profile_normal_viscosity(B.phi, B.phi_err, nb, dy, p.Sh, B.eta, B.eta_err);
        nkeep = lub_profile_select_bulk(B.phi, nb, 0.0, dy, p.interface_width, p.floor_skip,
                                        p.phi_min, B.keep);
        /* eta_ii(phi) pairs the exact eta_ii(y) with phi averaged over phi_window (layering) */
        lub_profile_coarse_grain(B.phi, B.phi_err, nb, dy, p.phi_window, B.phi_cg, B.phi_cg_err);
        double s2 = 0.0;
        int nl = 0, q = 0;
        for (int i = 0; i < nb; ++i) {
            double lw = eta22_law(B.phi_cg[i], p.phi_m);
            if (p.orientation == LUB_RS_VORTICITY)
                lw *= lambda33_law(B.phi_cg[i]);
            B.law[i] = isfinite(lw) ? lw : NAN;
            B.keepd[i] = B.keep[i];
            if (B.keep[i]) {
                B.pairs_out[4 * q + 0] = B.phi_cg[i];
                B.pairs_out[4 * q + 1] = B.phi_cg_err[i];
                B.pairs_out[4 * q + 2] = B.eta[i];
                B.pairs_out[4 * q + 3] = B.eta_err[i];
                ++q;
                if (isfinite(lw) && lw > 0.0 && B.eta[i] > 0.0) {
                    double d = log(B.eta[i] / lw);
                    s2 += d * d;
                    ++nl;
                }
            }
        }
        law_rms = nl > 0 ? sqrt(s2 / nl) : NAN;
        /* mean flow-direction velocity per bin and its least-squares slope over bulk bins */
        double sw = 0, sy = 0, sv = 0, syy = 0, syv = 0;
        for (int i = 0; i < nb; ++i) {
            B.vx_inst[i] = B.vx_vol[i] > 0.0 ? B.vx_sum[i] / B.vx_vol[i] : NAN;
            if (B.keep[i] && isfinite(B.vx_inst[i])) {
                sw += 1.0;
                sy += B.ybin[i];
                sv += B.vx_inst[i];
                syy += B.ybin[i] * B.ybin[i];
                syv += B.ybin[i] * B.vx_inst[i];
            }
        }
        if (sw >= 3.0)
            bulk_rate = (sw * syv - sy * sv) / (sw * syy - sy * sy);
        int wr = write_profiles(ctx->out, "y", nb, B.ybin, "a") ||
                 write_profiles(ctx->out, "phi", nb, B.phi, "1") ||
                 write_profiles(ctx->out, "phi_err", nb, B.phi_err, "1") ||
                 write_profiles(ctx->out, "phi_coarse", nb, B.phi_cg, "1") ||
                 write_profiles(ctx->out, "phi_coarse_err", nb, B.phi_cg_err, "1") ||
                 write_profiles(ctx->out, "eta_normal", nb, B.eta, "1") ||
                 write_profiles(ctx->out, "eta_normal_err", nb, B.eta_err, "1") ||
                 write_profiles(ctx->out, "bulk_mask", nb, B.keepd, "1") ||
                 write_profiles(ctx->out, "eta_normal_law", nb, B.law, "1") ||
                 write_profiles(ctx->out, "velocity_x", nb, B.vx_inst, "a gd");
        if (!wr && q > 0) {
            int64_t dims[2] = {q, 4};
            wr = lub_h5_write_array(ctx->out, "eta_vs_phi", 2, dims, B.pairs_out, "1");
        }
        if (wr && rc == LUB_EXIT_OK) {
            snprintf(ctx->diagnostic, sizeof ctx->diagnostic, "%s", lub_h5_last_error(ctx->out));
            rc = LUB_EXIT_IO;
        }
    }

    const double h0 = inv / p.phi_m;
    const double A = lub_acrivos_number(eta, gd, drho, grav, h0 * a);
    lub_summary_put(ctx, "shields", lub_shields_number(eta, gd, drho, grav, a), NAN, "1");
    lub_summary_put(ctx, "acrivos", A, NAN, "1");
    lub_summary_put(ctx, "inertial_number", gd * sqrt(a / grav), NAN, "1");
    lub_summary_put(ctx, "stokes_number", St, NAN, "1");
    lub_summary_put(ctx, "suspension_height", hs_mean, hs_sem, "a");
    lub_summary_put(ctx, "settled_height", h0, NAN, "a");
    lub_summary_put(ctx, "relative_height_increase", (hs_mean - h0) / h0, hs_sem / h0, "1");
    lub_summary_put(ctx, "inventory", inv, NAN, "a");
    lub_summary_put(ctx, "max_phi", pmax, NAN, "1");
    lub_summary_put(ctx, "bulk_bins", nkeep, NAN, "1");
    lub_summary_put(ctx, "bulk_velocity_slope", bulk_rate, NAN, "gd");
    lub_summary_put(ctx, "eta_vs_law_log_rms", law_rms, NAN, "1");
    lub_summary_put(ctx, "averaged_samples", (double)lp.navg, NAN, "1");
    lub_summary_put(ctx, "min_clearance_above_floor", lp.min_lowest, NAN, "a");
    lub_summary_put(ctx, "particles_below_floor", lp.below_floor_max, NAN, "1");
    lub_summary_put(ctx, "lid_reflections", (double)S.lid_hits, NAN, "1");
    const double crushed_fraction = lp.contacts_sum > 0 ? lp.crushed_sum / lp.contacts_sum : 0.0;
    lub_summary_put(ctx, "crushed_contact_fraction", crushed_fraction, NAN, "1");
    lub_summary_put(ctx, "max_kinetic_energy", lp.max_ke, NAN, "eta gd a^3");
    lub_summary_put(ctx, "cell_width", L, NAN, "a");
    lub_summary_put(ctx, "floor_radius", rf, NAN, "a");
    lub_summary_put(ctx, "lid_height", y_lid - y_floor, NAN, "a");
    lub_summary_put(ctx, "initial_height", h_init, NAN, "a");
    lub_summary_put(ctx, "dt", dt, NAN, "1/gd");
    lub_summary_put(ctx, "dt_min", lp.ctl.dt_min, NAN, "1/gd");
    lub_summary_put(ctx, "dt_changes", (double)lp.ctl.changes, NAN, "1");
    lub_summary_put(ctx, "dt_critical", dt_crit, NAN, "1/gd");
    lub_summary_put(ctx, "rebuilds", (double)S.rebuilds, NAN, "1");
    lub_summary_put(ctx, "dt_stiffness_ratio", lp.ctl.ratio_max, NAN, "1");
    lub_summary_put(ctx, "solid_volume", vsum, NAN, "a^3");
    lub_summary_put(ctx, "initial_phi", binfo.layer_phi, NAN, "1");

    json_t *terms = json_array();
    json_array_append_new(terms, json_string("gravity"));
    lub_law_terms_append(terms, S.law.terms);
    if (S.law.eps > 0.0)
        json_array_append_new(terms, json_string("normal_contact"));
    if (p.orientation == LUB_RS_GRADIENT && p.eta_shear > 0.0)
        json_array_append_new(terms, json_string("shear_drag"));
    if (p.eta_dilute > 0.0 && p.dilute_max >= 0)
        json_array_append_new(terms, json_string("dilute_drag"));
    json_array_append_new(terms, json_string("rough_floor"));
    json_array_append_new(terms, json_string("reflecting_lid"));
    json_object_set_new(ctx->summary_extra, "active_terms", terms);
    json_object_set_new(ctx->summary_extra, "steps", json_integer(S.step));
    json_object_set_new(ctx->summary_extra, "simulated_time", json_real(S.time));
    json_object_set_new(ctx->summary_extra, "orientation",
                        json_string(p.orientation == LUB_RS_VORTICITY ? "vorticity" : "gradient"));
    json_object_set_new(ctx->summary_extra, "height_steady", json_boolean(steady));
    json_object_set_new(ctx->summary_extra, "height_transient_end_strain",
                        json_real((double)mser * p.sample_strain));
    json_object_set_new(ctx->summary_extra, "phi_err_method",
                        json_string(lp.navg < 2            ? "none (fewer than 2 samples)"
                                    : sem_batch_means == 1 ? "batch_means_ar1"
                                                           : "naive (fewer than 32 samples)"));
    json_t *warn = json_array();
    if (gd * sqrt(a / grav) > 5e-2)
        json_array_append_new(warn, json_string("inertial number gd sqrt(a/g) above 5e-2: "
                                                "inertia enhances resuspension (seed 000 §IV.C)"));
    if (!steady) {
        const char *why = stopped_at < 0 ? "suspension height not steady (MSER-5): increase "
                                           "/strain"
                          : lub_run_resumable(ctx)
                              ? "suspension height not steady (MSER-5) when the run was "
                                "stopped by a signal: " LUB_RESUME_ADVICE
                              : "suspension height not steady (MSER-5) when the run was "
                                "stopped by a signal, whose checkpoint could not be written: "
                                "run it again";
        json_array_append_new(warn, json_string(why));
    }
    if (p.orientation == LUB_RS_GRADIENT && isfinite(bulk_rate) && fabs(bulk_rate - gd) > 0.2 * gd)
        json_array_append_new(warn, json_string("the bed is not sheared homogeneously (bulk "
                                                "dv_x/dy differs from gd by more than 20 %, see "
                                                "results/bulk_velocity_slope): raise "
                                                "/shear_drag_viscosity"));
    if (S.lid_hits > 0)
        json_array_append_new(warn, json_string("particles reached the lid: raise /lid_height"));
    lub_warn_fixed_dt(warn, p.dt, dt_crit, "dt_critical");
    lub_warn_fixed_dt_stiffness(warn, p.dt, dt_crit, lp.ctl.ratio_max, LUB_SHEAR_DT_STIFFNESS_MAX);
    if (crushed_fraction > LUB_CRUSHED_CONTACT_FRACTION_MAX) /* the message's "1 %" */
        json_array_append_new(warn,
                              json_string("asperities crushed in more than 1 % of the contacts "
                                          "(crushed_contact_fraction; u_n < -alpha eps a): "
                                          "contact forces exceed alpha stiffness eps, the "
                                          "results depend on /stiffness: raise it"));
    lub_network_warn_skipped(network, warn);
    json_object_set_new(ctx->summary_extra, "warnings", warn);
    json_object_set_new(
        ctx->summary_extra, "units",
        json_pack("{s:s, s:s, s:s, s:s, s:s, s:s}", "length", "a (mean particle radius)",
                  "viscosity", "eta (fluid viscosity)", "time", "1/gd (inverse shear rate)",
                  "stress", "eta gd", "energy", "eta gd a^3", "note",
                  "drho g = 1/Sh, g = 1/I^2, rho_p = density_ratio drho; y from the floor "
                  "centre plane"));
    lub_rs_free(&S);
    rs_buffers_free(&B);
    return rc;
}

/* what a continuation may change: a completed run is extended to a larger /strain, and may
 * write the interaction network otherwise */
static const char *const rs_resume_may_differ[] = {"strain", "pair_network", NULL};

const lub_scene lub_scene_resuspension = {
    .name = "resuspension",
    .title = "Viscous resuspension of buoyant spheres sheared above a rough floor",
    .description =
        "Viscous resuspension (Chevremont, Chareyre & Bodiguel, resuspension article): N "
        "lubricated spheres (Gaussian radii) in a cell periodic in x and z above a rough "
        "floor of fixed spheres, gravity along -y, a reflecting lid far above. orientation "
        "'gradient': gravity along the gradient, shear imposed by a drag (viscosity "
        "shear_drag_viscosity eta, default 1/30) towards u = gd y e_x; 'vorticity': gravity "
        "along the vorticity, Lees-Edwards shear of the x-z plane, no shear drag. Particles "
        "with at most dilute_drag.max_interactions pairs get a Stokes drag. Units: a, eta, "
        "1/gd; inputs Sh = eta gd/(drho g a), I = gd sqrt(a/g), density_ratio rho_p/drho. "
        "Reports the steady phi(y) with error bars, the suspension height, eta_ii(y) = "
        "(1/Sh) int_y phi, the bulk eta_ii(phi) (interface discarded), Sh, Acrivos A, I.",
    .resolve = rs_resolve,
    .run = rs_run,
    .resumable = 1,
    .resume_may_differ = rs_resume_may_differ,
};
