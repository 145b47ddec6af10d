/* contact_torque.c — rolling / twisting lubrication torques, exponentially integrated.
 *
 * Why (notes §11 P12): the roll coefficient grows like ln(a/u) without bound, and the
 * explicit leap-frog update of the relative spin dOmega/dt = -c (1/I1 + 1/I2) Omega is only
 * stable for dt < 2 I_eff / c, a limit the elastic time step (built on g) does not see.
 * Integrating the pair-local damping exactly over dt gives the torque
 *     T = I_eff Omega (1 - e^{-k}) / dt,  k = c dt / I_eff,
 * which equals c Omega to O(k) and removes at most the whole relative spin in one step.
 *
 * Several neighbours: each pair assumes it acts alone. If the caller passes the true 1/I,
 * N stiff pairs around one body can together remove up to N times its spin (overshoot,
 * growth for N >= 3). Passing inv_i = N_i / I_i (N_i = number of pairs of body i) gives each
 * pair the share I_i / N_i of the body's inertia; then the summed update of the spins is a
 * non-expansive map (see README.md "Roll/twist torques and stability with many neighbours" and
 * tests/law/test_law_matrix.c). */
#include "contact_torque.h"

#include "contact_law.h"

#include <math.h>

double lub_stable_damping(double c, double dt, double inv_sum)
{
    const double k = c * dt * inv_sum;
    if (!(k > 1e-3)) /* also k == 0 (fixed bodies): explicit c. Series truncation k^4/120 */
        return c * (1.0 - k * (0.5 - k * (1.0 / 6.0 - k / 24.0)));
    return -expm1(-k) / (dt * inv_sum); /* = c (1 - e^-k)/k, no inf * 0 for huge c */
}

void lub_spin_torques(double eta, double a, double delta, double x, vec3 n, vec3 omega_rel,
                      double inv_i1, double inv_i2, double dt, int with_roll, int with_twist,
                      vec3 *t_roll, vec3 *t_twist)
{
    const vec3 zero = v3(0.0, 0.0, 0.0);
    *t_roll = zero;
    *t_twist = zero;
    if (!(delta < 0.0) || !(eta > 0.0))
        return;
    const double base = LUB_PI * eta * a * a * a * (-delta); /* pi eta a^3 ln(a/u) */
    const double inv_sum = inv_i1 + inv_i2;
    const double wn = v3_dot(omega_rel, n);
    if (with_roll) {
        const vec3 om_r = v3_axpy(omega_rel, -wn, n);
        const double c = base * (1.5 + 0.126 * x); /* 63/500 = 0.126 */
        *t_roll = v3_scale(om_r, lub_stable_damping(c, dt, inv_sum));
    }
    if (with_twist) {
        const double c = base * x;
        *t_twist = v3_scale(n, wn * lub_stable_damping(c, dt, inv_sum));
    }
}
