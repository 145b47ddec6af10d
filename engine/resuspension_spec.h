/* resuspension_spec.h — the spec of the resuspension scene (scene_resuspension.c): its members
 * and defaults read from a job spec, the rules checked before a run (cross-member ranges, the
 * floor's impermeability, the cell width against the neighbour listing distance, the bed's weight
 * against its contacts, the step count), and the time-step bounds the run uses again once its bed
 * is built.
 *
 * Units (dimensionless): length a (mean radius), viscosity eta, time 1/gd; the members are the
 * scene's dimensionless groups (Shields number Sh, inertial number I, density ratio, contact
 * stiffness g_bulk/(eta gd a); README, Scene `resuspension`). lub_rs_spec_scales gives what
 * they make of gravity, densities and the Stokes number with a = eta = gd = 1.
 * Ownership: lub_rs_spec_read fills a caller-owned struct and keeps no reference to the JSON;
 * it writes defaults and the normalised /pair_network into the spec it is given (as every
 * scene's reader does: the resolved spec states every member). No global state.
 * Errors: the readers and checks return 0, or -1 with the JSON pointer of the member to change
 * and the constraint in *err (spec_reader.h); the time-step functions cannot fail.
 */
#ifndef LUBDEM_RESUSPENSION_SPEC_H
#define LUBDEM_RESUSPENSION_SPEC_H

#include <jansson.h>

#include "law_spec.h"
#include "spec_reader.h"

typedef struct {
    long long n, seed, snapshots, dilute_max;
    double width, radius_std, Sh, I, density_ratio, stiffness, eta_shear, eta_dilute;
    double floor_radius, floor_jitter, lid_height, strain, average_from, sample_strain, bin_width,
        interface_width, floor_skip, phi_min, phi_m, phi_window, dt, dt_safety, dt_stiffness_safety,
        cutoff, skin, initial_phi;
    int orientation;  /* LUB_RS_GRADIENT or LUB_RS_VORTICITY (resuspension_system.h) */
    int pair_network; /* LUB_NETWORK_*: when to write the interaction network */
    lub_law_spec law;
} lub_rs_spec;

/* The run's scales: units a = eta = gd = 1 and what the spec's groups make of the gravity g =
 * 1/I^2, the buoyant density difference drho = I^2/Sh, the particle density rho = density_ratio
 * drho and the particle Stokes number St = rho gd a^2/eta = density_ratio I^2/Sh. */
typedef struct {
    double a, eta, gd;
    double gravity, drho, rho, stokes;
} lub_rs_scales;

/* Reads every member of spec (the scene's resolve and run), defaults written in, and checks the
 * rules above: 0 or -1 with err. */
int lub_rs_spec_read(json_t *spec, lub_rs_spec *p, lub_error *err);

/* The scene's resolve (scene.h): lub_rs_spec_read into a struct that is thrown away. */
int lub_rs_spec_resolve(json_t *spec, lub_error *err);

lub_rs_scales lub_rs_spec_scales(const lub_rs_spec *p);

/* The elastic bound of a particle of radius r (the run takes the lightest particle's), from
 * the spec: m = (4/3) pi r^3 rho, rho = density_ratio drho, drho = I^2/Sh, g = stiffness,
 * k_t = kt_ratio g. Units a = eta = gd = 1. */
double lub_rs_elastic_dt(const lub_rs_spec *p, double r);

/* The refusal of `count` steps of length dt (qualifier: "" for the run's own, "at least " or
 * "at most " for a bound), the lightest particle having radius r: names the member whose
 * default brings the count nearest the allowed range. -1. */
int lub_rs_step_refusal(const lub_rs_spec *p, double r, double count, double dt,
                        const char *qualifier, lub_error *err);

/* How far a sphere of radius a compresses a contact under its own weight, (4/3) pi a^3 drho g
 * over the contact stiffness g_bulk a, in a: (4/3) pi / (/shields /stiffness). The bed's lowest
 * contacts carry more (the spheres above them). */
double lub_rs_weight_overlap(const lub_rs_spec *p);

/* Refused at this weight overlap: the floor cannot hold such a bed (runs with 20 spheres at
 * 0.07 a and above, 400 at 0.042 a, let spheres through the floor within 150 steps). The
 * overlap is an estimate (the asperities in series with the bulk, 1/alpha, are left out): the
 * threshold rests on those runs. */
#define LUB_RS_WEIGHT_OVERLAP_MAX 0.05
/* At a tenth of it an escape through the floor is blamed on the weight, not the time step. */
#define LUB_RS_WEIGHT_OVERLAP_BLAMED (0.1 * LUB_RS_WEIGHT_OVERLAP_MAX)

#endif
