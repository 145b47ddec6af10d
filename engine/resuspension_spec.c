/* resuspension_spec.c — the resuspension scene's spec: members, defaults and the rules checked
 * before a run (resuspension_spec.h).
 */
#include "resuspension_spec.h"

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include "floor_wall.h"
#include "json_text.h"
#include "network_output.h"
#include "packing.h"
#include "resuspension_bed.h"
#include "resuspension_system.h"
#include "step_count.h"
#include "step_stiffness.h"

#define RS_PI 3.14159265358979323846
/* Most samples a run may take (strain / sample_strain): each one from /average_from on keeps
 * a profile of every bin in memory until the end of the run. */
#define RS_MAX_SAMPLES 1e6

static const lub_law_spec_opts rs_law_opts = {
    .allowed_terms = LUB_TERM_ALL,
    .default_terms = LUB_TERM_ALL,
    .tangential = 1,
    .default_eps = 2e-3, /* physical convention: the seed's eps = 1e-3 (Yade's eps_Y) */
    .default_alpha = 1.0,
    .default_kt_ratio = 0.5,
    .default_mu = 0.5,
};

/* Defaults of the members the step count depends on (lub_rs_spec_read, rs_check_steps). */
#define RS_DEFAULT_SHIELDS 0.5
#define RS_DEFAULT_INERTIAL_NUMBER 0.03
#define RS_DEFAULT_DENSITY_RATIO 1.0
#define RS_DEFAULT_STIFFNESS 1e6
#define RS_DEFAULT_STRAIN 40.0
#define RS_DEFAULT_DT_SAFETY 0.3

double lub_rs_elastic_dt(const lub_rs_spec *p, double r)
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
static double rs_step_at(const lub_rs_spec *p, double r)
{
    return p->dt > 0.0 ? p->dt : p->dt_safety * lub_rs_elastic_dt(p, r);
}

/* The run's steps (step_count.h) when its lightest particle has radius r. */
static double rs_steps_at(const lub_rs_spec *p, double r)
{
    return lub_step_count(p->strain, rs_step_at(p, r));
}

int lub_rs_step_refusal(const lub_rs_spec *p, double r, double count, double dt,
                        const char *qualifier, lub_error *err)
{
    lub_step_alt alt[8];
    int n = 0;
    lub_rs_spec q;
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
static int rs_check_steps(const lub_rs_spec *p, lub_error *err)
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
    return lub_rs_step_refusal(p, r, count, rs_step_at(p, r), qualifier, err);
}

double lub_rs_weight_overlap(const lub_rs_spec *p)
{
    return 4.0 / 3.0 * RS_PI / (p->Sh * p->stiffness);
}

static int rs_check_weight(const lub_rs_spec *p, lub_error *err)
{
    const double overlap = lub_rs_weight_overlap(p);
    if (overlap < LUB_RS_WEIGHT_OVERLAP_MAX)
        return 0;
    return lub_fail(err, "/stiffness",
                    "a sphere's own weight would compress its contact by %.3g a ((4/3) pi / "
                    "(/shields /stiffness)), at least %g a: the floor cannot hold the bed, whose "
                    "lowest contacts carry more; raise /stiffness above %.3g or /shields (got "
                    "/stiffness %g, /shields %g)",
                    overlap, LUB_RS_WEIGHT_OVERLAP_MAX,
                    p->stiffness * overlap / LUB_RS_WEIGHT_OVERLAP_MAX, p->stiffness, p->Sh);
}

/* The cell must be at least twice the neighbour listing distance wide (neighbor_list.h): the
 * bed's width L and its largest sphere (floor spheres included) are known from the radii alone
 * (lub_bed_geometry), so a spec the run would stop on is refused here, before the packing. In the
 * vorticity orientation the x-z plane is sheared (Lees-Edwards) and flipped at rebuilds once its
 * tilt passes one half, so its narrowest width falls to L/sqrt(1 + 1/4) (n = 20, width 9.8, the
 * default cut-off: validated, then stopped at strain 0.24 with the cell too narrow). */
static int rs_check_width(const lub_rs_spec *p, lub_error *err)
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

/* The top-level members (objects aside), the orientation, the sample count and the averaging
 * window. */
static int rs_read_members(json_t *spec, lub_rs_spec *p, lub_error *err)
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
    return 0;
}

/* /dilute_drag: the Stokes drag on particles with few interactions. */
static int rs_read_dilute_drag(json_t *spec, lub_rs_spec *p, lub_error *err)
{
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
    return 0;
}

/* /floor: its spheres' radius and jitter, which must not let the smallest particle through. */
static int rs_read_floor(json_t *spec, lub_rs_spec *p, lub_error *err)
{
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
    return 0;
}

/* /analysis: the bulk selection and the law comparison of the statistics. */
static int rs_read_analysis(json_t *spec, lub_rs_spec *p, lub_error *err)
{
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
    return 0;
}

int lub_rs_spec_read(json_t *spec, lub_rs_spec *p, lub_error *err)
{
    if (rs_read_members(spec, p, err) || rs_read_dilute_drag(spec, p, err) ||
        rs_read_floor(spec, p, err) || rs_read_analysis(spec, p, err))
        return -1;
    json_t *law = lub_spec_object(spec, "", "law", err);
    if (!law || lub_law_spec_resolve(law, "/law", &rs_law_opts, &p->law, err) ||
        lub_law_spec_check_cutoff(&p->law, "/law", p->cutoff, err))
        return -1;
    if (rs_check_width(p, err) || rs_check_steps(p, err))
        return -1;
    return rs_check_weight(p, err);
}

int lub_rs_spec_resolve(json_t *spec, lub_error *err)
{
    lub_rs_spec p;
    return lub_rs_spec_read(spec, &p, err);
}

lub_rs_scales lub_rs_spec_scales(const lub_rs_spec *p)
{
    lub_rs_scales s;
    /* units: a = eta = gd = 1 */
    s.a = 1.0;
    s.eta = 1.0;
    s.gd = 1.0;
    s.gravity = s.a * s.gd * s.gd / (p->I * p->I);
    s.drho = s.eta * s.gd / (p->Sh * s.gravity * s.a);
    s.rho = p->density_ratio * s.drho;
    s.stokes = s.rho * s.gd * s.a * s.a / s.eta;
    return s;
}
