/* contact_normal.h — internal interface of the normal part of the lubricated contact law
 * (backward-Euler visco-elastic coupling, notes §2). Public entry points are declared in
 * contact_law.h; this header adds the variant used by lub_pair_step that also returns
 * x+ = u+/a without an extra exp().
 *
 * All quantities are dimensionless (see contact_law.h: x = u/a, s = u_n/a, h = dt/tau).
 * Pure functions, no allocation, no global state. */
#ifndef LUBDEM_CONTACT_NORMAL_H
#define LUBDEM_CONTACT_NORMAL_H

/* As lub_normal_solve(), and additionally *x_out = exp(returned delta), finite and >= 0: it
 * is subnormal or exactly 0 when the returned delta is below about -708 / -745 (a compressed
 * pair decaying without floor, notes §11 P5). Callers must use x only where x -> 0 is
 * harmless (forces, R+) and the returned delta wherever ln x is needed (nu_t, torques, the
 * contact test delta < ln e). contact and x_out must be non-NULL. */
double lub_normal_solve_ex(double delta_prev, double s, double h, double e, double alpha,
                           int *contact, double *x_out);

#endif
