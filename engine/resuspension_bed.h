/* resuspension_bed.h — initial bed of the resuspension scene: k stacked copies of one periodic
 * packing of a cube (packing.h), the N lowest spheres kept.
 *
 * The cube side L is the packing's own (close to the requested width); the number of layers k
 * is the smallest with a per-layer solid fraction n_layer <V>/width^3 <= min(phi_target, 0.55)
 * rounded to whole layers, so the achieved fraction may be below phi_target. Copies stacked
 * along y touch without overlap because the packing is periodic in y. Output positions have
 * x, z in [0, L) and y >= 0 (bottom layer starts at the packing's own y range).
 *
 * Units: lengths in the mean radius (radii have mean 1, see packing.h). Memory: allocates work
 * arrays on entry, frees them on exit; radius[n] and pos[n] are caller-owned.
 * Returns 0, -1 (out of memory) or -2 (packing failed; *info_code holds packing's code).
 */
#ifndef LUBDEM_RESUSPENSION_BED_H
#define LUBDEM_RESUSPENSION_BED_H

#include <stdint.h>

#include "vec3.h"

typedef struct {
    int n;             /* spheres wanted (>= 2) */
    double width;      /* requested cube side (> 0) */
    double phi_target; /* wanted solid fraction of the stacked bed, (0, 0.55] */
    double radius_std; /* relative std of the Gaussian radii (packing.h) */
    uint64_t seed;
} lub_bed_params;

typedef struct {
    double side;      /* actual cube side L (cell width) */
    int layers;       /* k */
    int per_layer;    /* spheres per packed cube */
    double layer_phi; /* solid fraction of one cube */
    int info_code;    /* lub_packing_generate's return code on failure */
} lub_bed_info;

int lub_bed_build(const lub_bed_params *p, double *radius, vec3 *pos, lub_bed_info *info);

/* What lub_bed_build will give for *p without packing: info's side (the cell width L), layers,
 * per_layer and layer_phi, and in *r_max the largest radius of the packed layer (the bed's
 * spheres are among its copies). Equal to the build's to the last bit when the packing
 * succeeds. Allocates per_layer doubles for the draw; returns 0, or -1 when out of memory. */
int lub_bed_geometry(const lub_bed_params *p, lub_bed_info *info, double *r_max);

#endif
