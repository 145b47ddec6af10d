/* power_faces.h — nearest neighbours of a sphere packing in the sense of the regular (weighted
 * Delaunay) triangulation, the interaction set of the seed's rheology article (seed 000
 * l.908: lubrication only between the neighbours of the triangulation; Yade uses CGAL's
 * regular triangulation, i.e. weights r^2).
 *
 * Two spheres are neighbours when their cells of the power diagram share a face of positive
 * area. The power of a point x with respect to sphere (c, r) is |x - c|^2 - r^2; the cell of
 * sphere 0 is the set of points whose power to it is the smallest. The face between sphere 0
 * and sphere j lies in their radical plane 2 x.d_j = |d_j|^2 + r_0^2 - r_j^2 (x relative to the
 * centre of sphere 0); every other sphere k cuts it by the half-plane 2 x.d_k <= |d_k|^2 +
 * r_0^2 - r_k^2. lub_power_face_area clips a polygon in the radical plane by those half-planes.
 *
 * Bounding ball: the polygon starts as the regular octagon inscribed in the disc where the
 * plane meets the ball |x| <= R, so the result is exact when the face lies within that octagon
 * (a face beyond it is clipped to it; one that meets the disc only outside the octagon, within
 * 1 - cos(22.5 deg) = 7.6 % of the disc's radius from its rim, has area 0 like a face beyond R). A
 * caller that only knows the spheres within a distance D of sphere 0 gets exact answers for R <=
 * R_cert with R_cert + sqrt(R_cert^2 + r_max^2 - r_0^2) <= D: any sphere that cuts a point of the
 * ball is then among the known ones (lub_power_certified_radius).
 *
 * Units: any length unit; all positions are relative to the centre of sphere 0. Pure
 * functions, no allocation, no error paths (degenerate input gives area 0).
 */
#ifndef LUBDEM_POWER_FACES_H
#define LUBDEM_POWER_FACES_H

#include "vec3.h"

typedef struct {
    vec3 d;   /* centre relative to the centre of sphere 0 */
    double r; /* radius */
    long tag; /* the caller's (moves with the site when sorted) */
} lub_power_site;

/* Sorts sites by increasing |d| (insertion sort: the lists are short, ~20-60 sites). */
void lub_power_sort(lub_power_site *sites, int n);

/* Largest R for which faces within the ball |x| <= R are exact when every sphere whose centre
 * is closer than `known` to sphere 0 is given (see above); 0 if none. r_max: the largest
 * radius of the packing. */
double lub_power_certified_radius(double known, double r0, double r_max);

/* Area of the face between sphere 0 (radius r0) and sites[j], clipped by every other site of
 * sites[0 .. n) and by the ball of radius R. The sites must be sorted by lub_power_sort: the
 * clipping stops at the first site that cannot reach the polygon (r_max bounds the radii of
 * the sites). *open (may be NULL) is set to 1 when the result still touches the bounding
 * octagon (the face may extend beyond R), else 0. */
double lub_power_face_area(double r0, const lub_power_site *sites, int n, int j, double R,
                           double r_max, int *open);

#endif
