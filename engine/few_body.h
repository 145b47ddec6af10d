/* few_body.h — a tiny rigid-sphere system for verification scenes (2..LUB_FB_MAX_BODIES
 * spheres, at most LUB_FB_MAX_PAIRS lubricated pairs, no cell, no neighbour search).
 *
 * Integration: leap-frog (positions at t_n, velocities and spins at t_{n-1/2}) for
 * translation and, if enabled, rotation. Stokes drag F = -zeta_t (v - L x) and torque
 * T = -zeta_r (omega - Omega_f) (Omega_f = curl(L x)/2) are integrated EXACTLY over a step for
 * frozen position and non-drag force (exponential integrator):
 *     v+ = w + (v- - w) e^{-k} + (F dt/m) (1 - e^{-k})/k,   k = zeta_t dt / m, w = L x_n,
 * so the drag is unconditionally stable whatever m/zeta_t is (low Stokes numbers) and the
 * step is limited only by the elastic stiffnesses (lub_fb_critical_dt). Pair forces come from
 * lub_pair_step (contact_law.h); a pair exists while its centre gap u_n <= cutoff * a (it is
 * created with a fresh state when it enters, and loses its state when it leaves).
 *
 * Units: whatever the scene uses (consistent). No allocation, no global state; a system is a
 * plain value owned by the caller. Not thread-safe per system.
 */
#ifndef LUBDEM_FEW_BODY_H
#define LUBDEM_FEW_BODY_H

#include <stddef.h>
#include <stdint.h>

#include "contact_law.h"
#include "vec3.h"

enum { LUB_FB_MAX_BODIES = 4, LUB_FB_MAX_PAIRS = 6 };

typedef struct {
    double r;     /* radius (> 0) */
    double inv_m; /* 1/mass; 0 = fixed body (never moves, never rotates) */
    double inv_I; /* 1/moment of inertia; 0 = no rotation */
    vec3 x;       /* position at t_n */
    vec3 v;       /* velocity at t_{n-1/2} */
    vec3 w;       /* spin at t_{n-1/2} */
    vec3 f, t;    /* non-drag force and torque accumulated at t_n (workspace) */
} lub_fb_body;

typedef struct {
    int i, j;             /* bodies: i = body 1 of the law, j = body 2 (n points i -> j) */
    double cutoff;        /* pair lives while u_n <= cutoff * a (INFINITY: always) */
    int active;           /* 1 while inside the cut-off */
    lub_pair_state state; /* law history (valid while active) */
    lub_pair_output out;  /* last evaluation (valid while active) */
} lub_fb_pair;

typedef struct {
    vec3 gravity;   /* acceleration on every free body (0 = no gravity) */
    double zeta_t;  /* translational Stokes drag coefficient 6 pi eta a (0 = no drag) */
    double zeta_r;  /* rotational drag coefficient 8 pi eta a^3 (0 = no drag torque) */
    double L[3][3]; /* background velocity gradient: w(x) = L x (used only with drag) */
    int rotation;   /* 1: integrate spins; 0: spins stay at their initial value */
} lub_fb_env;

typedef struct {
    int nb, np;
    lub_fb_body b[LUB_FB_MAX_BODIES];
    lub_fb_pair p[LUB_FB_MAX_PAIRS];
    lub_law_params law;
    lub_fb_env env;
    double t;     /* time of the positions: t_seg + (step - step_seg) dt, counted from the
                     step, never accumulated (t += dt stops advancing when dt < ulp(t)/2) */
    int64_t step; /* steps done */
    /* the last change of the step length (lub_fb_step keeps them; zero to start at t = 0) */
    double t_seg, dt_seg;
    int64_t step_seg;
} lub_fb_system;

/* Background flow velocity L x and the fluid spin curl(L x)/2. */
vec3 lub_fb_flow_velocity(const lub_fb_env *e, vec3 x);
vec3 lub_fb_flow_spin(const lub_fb_env *e);

/* Largest stable leap-frog step from the stiffnesses only (never from viscosity):
 * 2/omega_max with omega_max^2 the largest of, over all pairs,
 *     g (1/m_i + 1/m_j)                                 (normal, bulk stiffness g)
 *     k_t (1/m_i + 1/m_j + r_i^2/I_i + r_j^2/I_j)        (tangential, if k_t > 0)
 * INFINITY if there is no stiffness between free bodies. */
double lub_fb_critical_dt(const lub_fb_system *s);

/* One step of length dt: pair forces at t_n (with v, w at t_{n-1/2}), then velocities to
 * t_{n+1/2} and positions to t_{n+1}; s->t becomes the time of the new positions, from the step
 * count (s->t above). Returns 0, or -1 with a diagnostic in diag if a force
 * or a position is not finite (the law failed). */
int lub_fb_step(lub_fb_system *s, double dt, char *diag, size_t diag_size);

#endif
