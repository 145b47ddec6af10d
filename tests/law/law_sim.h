/* law_sim.h — a tiny few-body leap-frog integrator around lub_pair_step, used by the law
 * tests to check finiteness and energy boundedness (no periodic cell, all pairs i < j,
 * pair created when u_n < create*a, erased when u_n > cutoff*a). Test-only code.
 * The caller owns the struct; no allocation. */
#ifndef LUBDEM_LAW_SIM_H
#define LUBDEM_LAW_SIM_H

#include "contact_law.h"

#define LAW_SIM_MAX 16

typedef struct {
    int n;
    vec3 x[LAW_SIM_MAX], v[LAW_SIM_MAX], w[LAW_SIM_MAX]; /* v, w: half-step values */
    double r[LAW_SIM_MAX], m[LAW_SIM_MAX], I[LAW_SIM_MAX];
    int fixed[LAW_SIM_MAX];
    vec3 fext[LAW_SIM_MAX]; /* constant external forces */
    lub_law_params p;
    double dt;
    double create, cutoff;                       /* in units of a */
    int share_torque_budget;                     /* pass N_i/I_i (1) or 1/I_i (0) as inv_inertia */
    vec3 v_old[LAW_SIM_MAX], w_old[LAW_SIM_MAX]; /* half-step values before the last kick */
    int exists[LAW_SIM_MAX][LAW_SIM_MAX];
    lub_pair_state st[LAW_SIM_MAX][LAW_SIM_MAX];
    lub_pair_output out[LAW_SIM_MAX][LAW_SIM_MAX];
    /* diagnostics, accumulated by law_sim_step */
    long steps;
    double work_ext; /* work of the external forces so far */
    double work_abs; /* sum of |work| increments (energy throughput of the forcing) */
    int bad;         /* non-zero return of lub_pair_step seen */
    double min_delta, max_delta;
    long contact_steps, slip_steps, enter_events, leave_events, create_events, erase_events;
    long skip_band_events; /* pair went from x >= e to x < e/2 (or back) in one step */
} law_sim;

/* Set defaults (after the caller filled n, x, v, w, r, m, I, p, dt). */
void law_sim_prepare(law_sim *s);
/* One leap-frog step. Returns 0, or non-zero if the law reported a non-finite result. */
int law_sim_step(law_sim *s);
double law_sim_kinetic(const law_sim *s);
/* Kinetic energy at the integer time of the last force evaluation, from the mean of the
 * half-step velocities before and after the kick (second-order accurate; pairs with
 * law_sim_elastic, which is evaluated at the same positions). */
double law_sim_kinetic_mid(const law_sim *s);
/* Stored elastic energy of the springs of all pairs (bulk g, asperity alpha g, tangential k_t). */
double law_sim_elastic(const law_sim *s);

#endif
