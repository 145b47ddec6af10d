/* step_stiffness.h — how stiff the pairs of a many-particle system are for the explicit motion
 * update, and the time step that stiffness allows.
 *
 * The law integrates each pair's normal and tangential elements implicitly, so one pair alone
 * is stable with the elastic step built on g and k_t (notes §7). The motion of the bodies is
 * still explicit (leap-frog): over one step dt a pair answers a change of its gap or of its
 * tangential displacement with an incremental stiffness, and the stiffnesses of all the pairs
 * of a body add up. Per pair (backward Euler, x = u/a = e^delta, h = dt g a / nu_n,
 * nu_n = 3/2 pi eta a^2, alpha_c = alpha in contact (x < eps), 0 outside):
 *   normal      k_n = g (1 + alpha_c h x) / (1 + (1 + alpha_c) h x)
 *               (g in series with the film dashpot nu_n/u and, in contact, the asperity
 *               spring alpha g; without normal lubrication (h = inf) g alpha_c/(1 + alpha_c),
 *               and g in the hard core, where the law holds the gap at LUB_DELTA_STATIC_FLOOR
 *               and the pair is a contact even for eps = 0);
 *   tangential  k_s = k_t                              in a frictional contact (stick bound),
 *               k_s = k_t nu_t / (nu_t + k_t dt)       otherwise (Maxwell element; 0 without
 *                                                      shear lubrication).
 * A film is thus as stiff as g where nu_n/u >> g dt: for light or soft spheres that covers
 * most of a large cut-off, and a body with many such partners needs a smaller step than one
 * pair does. The roll/twist torques are not counted: they are integrated with the inertia
 * shared among a body's close pairs (contact_torque.h) and cannot destabilise the step.
 *
 * Bound: with the pair stiffnesses assembled over translations and rotations (lever arms r_i,
 * r_j as in contact_shear.h) and scaled by the masses and inertias, the largest eigenvalue
 * omega_max^2 of M^-1/2 K M^-1/2 is at most the largest block row sum (Gershgorin with 3 x 3
 * blocks, each of spectral norm <= its pair stiffness times its lever arms):
 *   translation row of i: sum_j (k_n + k_s)(1/m_i + 1/sqrt(m_i m_j))
 *                                + k_s (r_i/sqrt(m_i I_i) + r_j/sqrt(m_i I_j))
 *   rotation row of i:    sum_j k_s (r_i^2/I_i + r_i r_j/sqrt(I_i I_j)
 *                                + r_i/sqrt(I_i m_i) + r_i/sqrt(I_i m_j))
 * and the leap-frog is stable for dt < 2/omega_max. For one pair of equal spheres and normal
 * stiffness g alone this is sqrt(2 m/g), the single-pair bound. The bound is conservative
 * (an isotropic network's true omega_max^2 is below the row sum), which is why callers scale
 * it by a calibrated factor (README, simple_shear, Method).
 *
 * Units: any consistent set. Pure functions; no allocation, no global state.
 */
#ifndef LUBDEM_STEP_STIFFNESS_H
#define LUBDEM_STEP_STIFFNESS_H

#include "contact_law.h"
#include "pair_store.h"

/* Default largest ratio of an automatic step to lub_pairs_stiffness_dt (the scenes'
 * /dt_stiffness_safety). Runs at the single-pair step blew up from a ratio of 1.22 on (light,
 * soft spheres; tests/shear/step_stability_study.py, README simple_shear, Method), and no run
 * of the committed simple_shear table goes above 0.91: at 1 the table keeps its step. */
#define LUB_DT_STIFFNESS_SAFETY 1.0

/* Incremental normal and tangential stiffness (force per length) of a pair of mean radius a
 * whose film gap is u = a e^delta, for a step dt > 0 (formulas above; honours p->terms:
 * without normal lubrication the film is absent, without friction a contact is a Maxwell
 * element too). Both are >= 0 and finite for finite inputs. */
void lub_pair_step_stiffness(const lub_law_params *p, double a, double delta, double dt,
                             double *k_normal, double *k_tangential);

/* Adds pair (i, j)'s normal stiffness kn and tangential stiffness ks to the Gershgorin row
 * sums trans[] and rot[] (per body; units 1/time^2) of bodies i and j. r, inv_m, inv_i: radii,
 * inverse masses, inverse moments of inertia per body. */
void lub_step_rows_add(double *trans, double *rot, int i, int j, const double *r,
                       const double *inv_m, const double *inv_i, double kn, double ks);

/* Largest row sum over n bodies: an upper bound on omega_max^2; 0 without pairs. Also
 * returns the body holding it in *body (may be NULL; -1 without pairs). */
double lub_step_rows_max(const double *trans, const double *rot, int n, int *body);

/* The step the active, allowed, evaluated pairs of `ps` allow: 2/sqrt(omega_max^2) from
 * their stored gaps (state delta) for a step dt, over n bodies with radii r, inverse masses
 * inv_m and inverse inertias inv_i (0 for a body whose motion is prescribed). INFINITY without
 * such a pair; *body (may be NULL) gets the body with the largest row sum. rows: caller's
 * scratch of 2n doubles. Serial, O(pairs). */
double lub_pairs_stiffness_dt(const lub_pairs *ps, const lub_law_params *law, const double *r,
                              const double *inv_m, const double *inv_i, int n, double dt,
                              double *rows, int *body);

/* The largest step dt <= dt_max with dt <= safety * lub_pairs_stiffness_dt(..., dt, ...) (to
 * 1 %: the films stiffen as dt falls, so the bound is iterated to its fixed point); dt_max when
 * the pairs allow it. safety > 0. Same arguments as lub_pairs_stiffness_dt. */
double lub_pairs_stable_dt(const lub_pairs *ps, const lub_law_params *law, const double *r,
                           const double *inv_m, const double *inv_i, int n, double dt_max,
                           double safety, double *rows);

/* The automatic step after a neighbour-list rebuild, from the step dt in use and the step
 * dt_base the spec's single-pair rule gives: lowered to 0.9 of lub_pairs_stable_dt(..., dt,
 * safety) when dt exceeds safety times the pairs' bound; raised back to
 * min(dt_base, 0.9 lub_pairs_stable_dt(..., dt_base, safety)) once the pairs allow 1.25 times
 * dt; otherwise dt unchanged (the margins keep changes rare). safety <= 0: dt is kept (a fixed
 * step, or the single-pair step throughout). *ratio (may be NULL) gets the returned step over
 * the bound at that step (one pass over the pairs when the step stays). Same arguments as
 * above. */
double lub_pairs_adapted_dt(const lub_pairs *ps, const lub_law_params *law, const double *r,
                            const double *inv_m, const double *inv_i, int n, double dt,
                            double dt_base, double safety, double *rows, double *ratio);

/* The step of a run that follows its pairs (the scenes' /dt_stiffness_safety): the step in
 * use and what the summary reports of it. */
typedef struct {
    double dt;        /* step in use */
    double dt_base;   /* the spec's step: /dt, or /dt_safety times the single-pair bound */
    double safety;    /* /dt_stiffness_safety; 0: dt stays dt_base (fixed /dt, or off) */
    double dt_min;    /* smallest step used */
    double ratio_max; /* largest dt / lub_pairs_stiffness_dt met at a rebuild */
    long changes;     /* times the step changed */
    long rebuilds;    /* neighbour-list rebuilds seen */
} lub_step_control;

void lub_step_control_init(lub_step_control *c, double dt_base, double safety);

/* After a step: when the system has rebuilt its neighbour list since the last call
 * (`rebuilds` is its rebuild count), applies lub_pairs_adapted_dt and records the ratio.
 * Returns 1 when c->dt changed (the caller reschedules), else 0. Same pair and body arguments
 * as lub_pairs_adapted_dt. */
int lub_step_control_at_rebuild(lub_step_control *c, long rebuilds, const lub_pairs *ps,
                                const lub_law_params *law, const double *r, const double *inv_m,
                                const double *inv_i, int n, double *rows);

#endif
