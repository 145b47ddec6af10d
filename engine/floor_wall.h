/* floor_wall.h — the rough floor and the reflecting lid of the resuspension cell.
 *
 * Geometry (units of the mean particle radius a): the cell is periodic in x and z; gravity
 * points along -y. The floor is a square lattice of n_side x n_side spheres of radius rf,
 * spacing 2 rf (neighbours touch), centres at height y_base + jitter_i with jitter_i uniform in
 * [-jitter rf, +jitter rf] (roughness). The cell widths are then Lx = Lz = n_side * 2 rf.
 * Impermeability: the largest hole of a square lattice of touching spheres admits a sphere of
 * radius (sqrt(2) - 1) rf ~ 0.41 rf; vertical jitter of at most jitter*rf is accounted for by
 * the conservative bound lub_floor_max_passing_radius() = (sqrt(2) - 1 + jitter) rf, which
 * the scene's validation requires to be below the smallest particle radius.
 *
 * The lid is a flat reflecting plane at y_lid: a particle whose top (y + r) is above the lid
 * while moving upwards gets its vertical velocity reversed (specular, no energy loss; the
 * lid exerts no viscous force). It only bounds the cell for the neighbour list; in a run it
 * is placed far above the suspension and the summary reports how many reflections happened.
 *
 * All functions are pure (no allocation, no global state) and write only their outputs.
 */
#ifndef LUBDEM_FLOOR_WALL_H
#define LUBDEM_FLOOR_WALL_H

#include <stdint.h>

#include "vec3.h"

/* Number of floor spheres per side so that the width is the closest to `width_target` with at
 * least `min_side` spheres per side: n = max(min_side, round(width_target / (2 rf))). */
int lub_floor_side_count(double width_target, double rf, int min_side);

/* Fills pos[n_side * n_side] (row-major in x then z) with the floor sphere centres:
 * x = (i + 1/2) 2 rf, z = (k + 1/2) 2 rf, y = y_base + jitter rf (2 U - 1), U from a
 * xoshiro stream seeded with `seed`. jitter in [0, 0.3]. */
void lub_floor_build(int n_side, double rf, double y_base, double jitter, uint64_t seed, vec3 *pos);

/* Radius of the largest sphere that can pass through a square floor of touching spheres of
 * radius rf whose centres differ in height by at most 2 jitter rf (conservative bound). */
double lub_floor_max_passing_radius(double rf, double jitter);

/* Lid reflection: if y + r > y_lid and *vy > 0, *vy = -*vy. Returns 1 if it reflected. */
static inline int lub_lid_reflect(double y, double r, double y_lid, double *vy)
{
    if (y + r > y_lid && *vy > 0.0) {
        *vy = -*vy;
        return 1;
    }
    return 0;
}

#endif
