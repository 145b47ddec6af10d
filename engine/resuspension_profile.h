/* resuspension_profile.h — volume-fraction profile phi(y) of spheres in a horizontally periodic
 * cell, binned in slabs along y with the EXACT sphere–slab volume intersection.
 *
 * Bin i covers [y0 + i dy, y0 + (i + 1) dy]; phi_i = sum_p V(p ∩ slab_i) / (area dy), where
 * area is the horizontal cross-section of the cell (x-z plane) and V(p ∩ slab) is computed
 * from spherical caps: the volume of a sphere of radius r below a plane at height h above its
 * lowest point is pi h^2 (3 r - h)/3 (h clamped to [0, 2r]). Parts of spheres outside
 * [y0, y0 + n dy] are not counted.
 *
 * Units: any length unit (the scene uses a). Pure functions, no allocation, no global state.
 */
#ifndef LUBDEM_RESUSPENSION_PROFILE_H
#define LUBDEM_RESUSPENSION_PROFILE_H

/* Volume of a sphere (centre height yc, radius r > 0) inside the slab y1 <= y <= y2
 * (y1 <= y2). Exact; 0 if they do not intersect. */
double lub_sphere_slab_volume(double yc, double r, double y1, double y2);

/* Adds the slab volumes of one sphere into vol[0..n) (bins as above). */
void lub_profile_add_sphere(double *vol, int n, double y0, double dy, double yc, double r);

/* Same, and also adds value * (slab volume) into wsum[0..n) (for volume-weighted averages of
 * a particle property, e.g. the velocity profile wsum/vol). wsum may be NULL. */
void lub_profile_add_sphere_weighted(double *vol, double *wsum, int n, double y0, double dy,
                                     double yc, double r, double value);

/* phi[i] = vol[i] / (area dy) for i < n. */
void lub_profile_normalise(const double *vol, int n, double dy, double area, double *phi);

#endif
