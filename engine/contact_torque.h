/* contact_torque.h — internal interface of the rolling and twisting lubrication torques
 * (notes §4, paper eq. 5-6 with the corrections of notes §4.3-4.4) with a pair-local
 * unconditionally stable time integration (notes §11 P12). Pure, no allocation. */
#ifndef LUBDEM_CONTACT_TORQUE_H
#define LUBDEM_CONTACT_TORQUE_H

#include "vec3.h"

/* Torques ON BODY 1 (body 2 receives the opposite) from the relative spin
 * Omega = w2 - w1, split into twist Omega_t = (Omega.n) n and roll Omega_r = Omega - Omega_t.
 * Applied only for u < a, i.e. delta < 0 (the correct cut-off; Yade's log branch has it
 * inverted, notes §4.3 / §11 P8). With c_r = pi eta a^3 (3/2 + 63/500 x) ln(1/x) and
 * c_t = pi eta a^3 x ln(1/x) (x = u/a = e^delta), the explicit torque c Omega is replaced by
 * its exponential (exact for the isolated pair) integral over dt:
 *     T = c Omega (1 - exp(-k))/k,   k = c dt (inv_i1 + inv_i2),
 * i.e. T dt = I_eff Omega (1 - e^-k) with 1/I_eff = inv_i1 + inv_i2. T -> c Omega when
 * k -> 0, and one step never removes more than the relative spin. inv_i1 + inv_i2 = 0 (two
 * fixed bodies) gives T = c Omega. with_roll / with_twist select the terms.
 * delta may be any finite value (no floor, notes §11 P5) and x = e^delta subnormal or 0:
 * c grows like -delta (finite) and the exponential integration bounds the torque by
 * I_eff |Omega| / dt whatever c is. */
void lub_spin_torques(double eta, double a, double delta, double x, vec3 n, vec3 omega_rel,
                      double inv_i1, double inv_i2, double dt, int with_roll, int with_twist,
                      vec3 *t_roll, vec3 *t_twist);

/* (1 - exp(-k))/k * c with k = c*dt*inv_sum, computed without overflow or 0/0 for any
 * c >= 0, dt > 0, inv_sum >= 0: the effective damping coefficient of the exponential
 * integration above. */
double lub_stable_damping(double c, double dt, double inv_sum);

#endif
