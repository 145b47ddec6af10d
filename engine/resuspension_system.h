/* resuspension_system.h — many lubricated spheres under gravity above a rough floor in a cell
 * periodic in x and z (viscous resuspension, seed 000 resuspension article §II.C).
 *
 * Bodies: indices [0, n_mobile) are free particles, [n_mobile, n) are floor spheres
 * (floor_wall.h) whose velocity is prescribed (the mean flow at their centre) and which feel
 * no force. Gravity g acts along -y on the buoyant mass drho V; the inertia uses rho V.
 * The y extent of the periodic cell is only a bookkeeping period: the floor and a reflecting
 * lid at y_lid confine the particles, and Ly exceeds y_lid by more than the listing distance,
 * so no pair ever crosses the y boundary.
 *
 * Orientation (the mean flow u(x), gd = shear_rate):
 *  - LUB_RS_GRADIENT: gravity along the gradient direction. The cell does not deform; the
 *    shear is imposed by a linear drag F = -6 pi eta_shear r (v - u) on every free particle
 *    towards u = gd (y - y_floor) e_x (floor spheres are at rest).
 *  - LUB_RS_VORTICITY: gravity along the vorticity direction. The cell is sheared in the x-z
 *    plane: L = gd e_x (x) e_z, H <- (I + dt L) H (Lees–Edwards across z), velocities are
 *    absolute and the leap-frog uses dv = dt (F/m + L v) as in periodic_cell.h / Yade;
 *    u = L x; floor spheres move with u (so the floor imposes no extra shear); no shear drag.
 * In both, free particles with at most `dilute_max_interactions` active pairs get an extra
 * Stokes drag F = -6 pi eta_dilute r (v - u) (seed: "fewer than three interactions").
 * Drags are integrated implicitly (v^{n+1/2} = (v* + dt c u/m)/(1 + dt c/m)), so they never
 * limit the time step. No drag torque is applied.
 *
 * Time stepping: leap-frog as shear_system.h (forces from x^n and v^{n-1/2}); the pair life
 * cycle and neighbour list follow pair_store.h / neighbor_list.h (reused, not modified).
 * Skin rule: with A = I + tau L_flow (tau = time since the last rebuild, L_flow = grad u) and
 * u_max the largest displacement of a free particle relative to A applied to its position at
 * the rebuild, the list stays valid while 2 u_max + ||A - I||_F d_list <= skin.
 *
 * Units: those of the caller (the scene: a = 1, eta = 1, gd = 1).
 * Memory: lub_rs_init allocates every particle array; pair arrays grow only at neighbour-list
 * rebuilds; lub_rs_step allocates nothing otherwise. Free with lub_rs_free.
 * Errors: LUB_RS_* codes; fail_msg holds a sentence on failure. Threads: OpenMP over pairs and
 * particles (`threads`), one pair accumulator per thread (pair_accum.h): a run is reproducible
 * for a given thread count, and different thread counts agree to round-off.
 */
#ifndef LUBDEM_RESUSPENSION_SYSTEM_H
#define LUBDEM_RESUSPENSION_SYSTEM_H

#include <stddef.h>

#include "contact_law.h"
#include "neighbor_list.h"
#include "pair_accum.h"
#include "pair_store.h"
#include "periodic_cell.h"
#include "step_stiffness.h"

enum { LUB_RS_GRADIENT = 0, LUB_RS_VORTICITY = 1 };

enum {
    LUB_RS_OK = 0,
    LUB_RS_NOMEM = -1,
    LUB_RS_CELL_TOO_SMALL = -2,
    LUB_RS_NONFINITE = -3,
    LUB_RS_ESCAPED = -4, /* a free particle left [floor, top of the cell] (floor breached) */
    LUB_RS_RUNAWAY = -5  /* a particle moved more than half the cell's width in one step */
};

typedef struct {
    int orientation;             /* LUB_RS_GRADIENT or LUB_RS_VORTICITY */
    double shear_rate;           /* gd (1/time) */
    double gravity;              /* g (>= 0), along -y */
    double drho;                 /* buoyant density difference (weight = drho V g) */
    double rho;                  /* particle density (mass = rho V) */
    double eta_shear;            /* viscosity of the shear drag (gradient orientation; >= 0) */
    double eta_dilute;           /* viscosity of the dilute-particle drag (>= 0) */
    int dilute_max_interactions; /* drag when active pairs <= this (2: "fewer than three") */
    double y_floor;              /* height where the mean flow vanishes (floor centre plane) */
    double y_lid;                /* reflecting lid */
    double cutoff;               /* lubrication cut-off in units of the pair mean radius */
    double skin;                 /* Verlet skin (length) */
    double dt;                   /* time step */
    int threads;                 /* >= 1 */
} lub_rs_params;

typedef struct {
    int n, n_mobile;
    vec3 *x, *v, *w, *f, *t, *x_ref;
    double *r, *m, *inv_m, *inv_i, *weight;
    int *nint;           /* active pairs of each body at the last step */
    double *inv_i_share; /* lub_inertia_share(inv_i, nint): what the pair law is given */
    double *row_scratch; /* [2n] Gershgorin row sums of lub_rs_step_control */
    int *img;            /* [3n] cell images removed by wrapping so far (x_unwrapped = x + H img) */
    lub_cell cell;       /* cell (deforms only in the vorticity orientation) */
    double L_flow[3][3]; /* gradient of the mean flow u */
    lub_nlist nl;
    lub_pairs pairs;
    lub_pair_accum *acc; /* [p.threads] per-particle pair sums of each thread */
    int team;            /* threads of the last pair pass (accumulators in use) */
    int team_min;        /* smallest team of the pair passes since init (0: none yet): below
                            p.threads when OpenMP gave fewer (OMP_THREAD_LIMIT, OMP_DYNAMIC) */
    lub_law_params law;
    lub_rs_params p;
    double time, t_ref;
    long step, rebuilds, flips, lid_hits;
    int need_rebuild;
    double max_speed; /* largest |v - u| of a free particle at the last step */
    long n_contacts;  /* pairs in contact (u < eps a) at the last step */
    long n_crushed;   /* of which asperities crushed, u_n < -alpha eps a (notes §11 P5): the bulk
                         spring and a persistent lubrication force carry the load; keep ~0 by
                         raising the stiffness */
    long fail_pair;
    char fail_msg[256];
    int escaped_below; /* after LUB_RS_ESCAPED: 1 when the particle went through the floor */
} lub_rs_system;

/* n_mobile free particles (radius, pos) followed by n_floor floor spheres (floor_r,
 * floor_pos); cell: orthorhombic Lx, Ly, Lz. Velocities start at u(x), spins at the mean
 * vorticity. Returns LUB_RS_*. */
int lub_rs_init(lub_rs_system *s, const lub_rs_params *p, const lub_law_params *law, int n_mobile,
                const double *radius, const vec3 *pos, int n_floor, const double *floor_r,
                const vec3 *floor_pos, double lx, double ly, double lz);
void lub_rs_free(lub_rs_system *s);

/* Mean flow u at x. */
vec3 lub_rs_mean_velocity(const lub_rs_system *s, vec3 x);

/* One time step. Returns LUB_RS_*; on failure s->fail_msg explains. */
int lub_rs_step(lub_rs_system *s);

/* The neighbour-list rebuild the next step would do first, done now (when due): every pair
 * inside the cut-off is then listed (an interaction network, pair_network.h). It wraps
 * positions (the unwrapped ones, lub_rs_unwrapped, do not change) and counts in s->rebuilds,
 * like the step's own, which then does none. Returns LUB_RS_* (fail_msg set on failure). */
int lub_rs_complete_list(lub_rs_system *s);

/* Unwrapped position x + H img and matching absolute velocity v + L H img of body i. */
void lub_rs_unwrapped(const lub_rs_system *s, int i, vec3 *x, vec3 *v);

/* Fluctuating kinetic energy sum 1/2 m |v - u|^2 over free particles. */
double lub_rs_kinetic_energy(const lub_rs_system *s);

/* lub_step_control_at_rebuild (step_stiffness.h) for this system's pairs (floor spheres, whose
 * motion is prescribed, have no row of the bound): after a step, 1 when a rebuild since the
 * last call changed c->dt (set s->p.dt to it and reschedule). Serial, a few passes over the
 * pairs at a rebuild, no allocation. */
int lub_rs_step_control(lub_rs_system *s, lub_step_control *c);

/* Horizontal cross-section of the cell (x-z area = volume / Ly). */
double lub_rs_area(const lub_rs_system *s);

/* Smallest y - r over free particles and the count of free particles whose centre is below
 * the floor centre plane y_floor (0 for an impermeable floor). */
double lub_rs_lowest(const lub_rs_system *s, int *below_floor);

#endif
