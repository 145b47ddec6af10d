/* floor_wall.c — rough floor lattice and lid (floor_wall.h). */
#include "floor_wall.h"

#include <math.h>
#include <stddef.h>

#include "rng.h"

int lub_floor_side_count(double width_target, double rf, int min_side)
{
    double n = floor(width_target / (2.0 * rf) + 0.5);
    if (!(n >= (double)min_side))
        n = (double)min_side;
    if (n > 100000.0)
        n = 100000.0;
    return (int)n;
}

void lub_floor_build(int n_side, double rf, double y_base, double jitter, uint64_t seed, vec3 *pos)
{
    lub_rng rng;
    lub_rng_seed(&rng, seed);
    for (int k = 0; k < n_side; ++k)
        for (int i = 0; i < n_side; ++i) {
            double dy = jitter * rf * (2.0 * lub_rng_uniform(&rng) - 1.0);
            pos[(size_t)k * (size_t)n_side + (size_t)i] =
                v3((i + 0.5) * 2.0 * rf, y_base + dy, (k + 0.5) * 2.0 * rf);
        }
}

double lub_floor_max_passing_radius(double rf, double jitter)
{
    /* Hole of four touching spheres at the corners of a square of side 2 rf: the centre is at
     * distance sqrt(2) rf from each, so a sphere of radius (sqrt(2) - 1) rf fits. Height
     * differences dy <= 2 jitter rf between neighbours move centres apart in 3D but not in the
     * plane; the in-plane distance stays 2 rf while the 3D passage widens at most by the
     * height spread, bounded by adding jitter rf to the in-plane hole radius. */
    return (sqrt(2.0) - 1.0) * rf + jitter * rf;
}
