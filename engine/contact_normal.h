/* contact_normal.h — internal interface of the normal part of the lubricated contact law
 * (backward-Euler visco-elastic coupling, notes §2). Public entry points are declared in
 * contact_law.h; this header adds the variant used by lub_pair_step that also returns
 * x+ = u+/a without an extra exp().
 *
 * All quantities are dimensionless (see contact_law.h: x = u/a, s = u_n/a, h = dt/tau).
 * Pure functions, no allocation, no global state. */
#ifndef LUBDEM_CONTACT_NORMAL_H
#define LUBDEM_CONTACT_NORMAL_H

/* As lub_normal_solve(), and additionally *x_out = exp(returned delta) (always a normal,
 * positive double because the returned delta is clamped to [LUB_DELTA_MIN, LUB_DELTA_MAX]).
 * contact and x_out must be non-NULL. */
double lub_normal_solve_ex(double delta_prev, double s, double h, double e, double alpha,
                           int *contact, double *x_out);

#endif
