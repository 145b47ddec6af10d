/* stress.h — virial stress of a particle system and its decomposition (notes §6).
 *
 *   sigma = (1/V) sum_pairs F1 (x) l  -  (1/V) sum_i m_i v'_i (x) v'_i
 *
 * F1 = force on body 1, l = x2 + H c - x1 the branch vector, layout sigma_ij = value[3i + j]
 * (force index first), V = cell volume, v' = v - L x the velocity fluctuation. Compression is
 * negative. The pair part is split with the law's outputs:
 *   NC normal contact   fn_contact n      SC tangential contact   fs_contact
 *   NL normal lubric.   fn_lub n          SL tangential lubric.   fs_lub
 * and the kinetic part KIN carries the minus sign above (Yade's getTotalDynamicStress returns
 * +sum m v'v', notes §6.5: not followed). Units: force/length^2 of the caller.
 * Accumulators are plain arrays (unnormalised sums); pure functions, no allocation.
 */
#ifndef LUBDEM_STRESS_H
#define LUBDEM_STRESS_H

#include "contact_law.h"
#include "vec3.h"

enum { LUB_SP_NC = 0, LUB_SP_SC, LUB_SP_NL, LUB_SP_SL, LUB_SP_KIN, LUB_SP_N };

typedef struct {
    double part[LUB_SP_N][9]; /* each part, row-major */
} lub_stress;

void lub_stress_zero(lub_stress *s);
/* Adds the four pair parts of one evaluation (unnormalised: F (x) l). */
void lub_stress_add_pair(lub_stress *s, const lub_pair_output *o, vec3 branch);
/* Adds -m v' (x) v' to the kinetic part. */
void lub_stress_add_kinetic(lub_stress *s, double mass, vec3 vprime);
/* a += b */
void lub_stress_accumulate(lub_stress *a, const lub_stress *b);
/* Divides every part by the volume. */
void lub_stress_scale(lub_stress *s, double factor);
/* total[9] = sum of the parts */
void lub_stress_total(const lub_stress *s, double total[9]);

#endif
