/* resuspension_bed.c — stacked periodic packings for the initial bed (resuspension_bed.h). */
#include "resuspension_bed.h"

#include <math.h>
#include <stdlib.h>

#include "packing.h"

static const double BED_PI = 3.14159265358979323846;

/* entries (y, index in layer, layer), sorted by decreasing y */
static int cmp_desc_y(const void *a, const void *b)
{
    const double ya = ((const double *)a)[0], yb = ((const double *)b)[0];
    return (ya < yb) - (ya > yb);
}

/* The layers of the bed (info's layers, per_layer, layer_phi; info_code 0) and the packing of one
 * layer. */
static lub_packing_params bed_layers(const lub_bed_params *p, lub_bed_info *info)
{
    const double N = (double)p->n;
    const double vbar = 4.0 / 3.0 * BED_PI * (1.0 + 3.0 * p->radius_std * p->radius_std);
    const double cube = p->width * p->width * p->width;
    const double phi_cap = fmin(p->phi_target, 0.55);
    long k = (long)ceil(N * vbar / (phi_cap * cube) - 1e-9);
    if (k < 1)
        k = 1;
    long nl = (long)ceil(N / (double)k);
    if (nl < 2)
        nl = 2;
    info->layers = (int)k;
    info->per_layer = (int)nl;
    info->layer_phi = (double)nl * vbar / cube;
    info->info_code = 0;
    return (lub_packing_params){.n = (int)nl,
                                .phi = info->layer_phi,
                                .radius_std = p->radius_std,
                                .seed = p->seed,
                                .margin = 0.01,
                                .max_sweeps = 200000};
}

int lub_bed_geometry(const lub_bed_params *p, lub_bed_info *info, double *r_max)
{
    const lub_packing_params pp = bed_layers(p, info);
    double *lr = malloc((size_t)pp.n * sizeof *lr);
    if (!lr)
        return -1;
    info->side = lub_packing_radii(&pp, lr);
    *r_max = 0.0;
    for (int i = 0; i < pp.n; ++i)
        *r_max = fmax(*r_max, lr[i]);
    free(lr);
    return 0;
}

int lub_bed_build(const lub_bed_params *p, double *radius, vec3 *pos, lub_bed_info *info)
{
    const lub_packing_params pp = bed_layers(p, info);
    const long k = info->layers, nl = info->per_layer;
    double *lr = malloc((size_t)nl * sizeof *lr);
    vec3 *lp = malloc((size_t)nl * sizeof *lp);
    double *sb = malloc((size_t)(nl * k) * 3 * sizeof *sb);
    if (!lr || !lp || !sb) {
        free(lr);
        free(lp);
        free(sb);
        return -1;
    }
    lub_cell cell;
    lub_packing_info pinfo;
    int rc = lub_packing_generate(&pp, lr, lp, &cell, &pinfo);
    if (rc) {
        info->info_code = rc;
        free(lr);
        free(lp);
        free(sb);
        return rc == -1 ? -1 : -2;
    }
    const double L = cell.h[0][0];
    info->side = L;
    const long tot = nl * k;
    for (long l = 0; l < k; ++l)
        for (long i = 0; i < nl; ++i) {
            double *e = &sb[3 * (l * nl + i)];
            e[0] = lp[i].y + (double)l * L;
            e[1] = (double)i;
            e[2] = (double)l;
        }
    qsort(sb, (size_t)tot, 3 * sizeof(double), cmp_desc_y);
    const long drop = tot - p->n;
    for (long q = 0; q < p->n; ++q) {
        const double *e = &sb[3 * (q + drop)];
        const long i = (long)e[1], l = (long)e[2];
        radius[q] = lr[i];
        pos[q] = v3(lp[i].x, lp[i].y + (double)l * L, lp[i].z);
    }
    free(lr);
    free(lp);
    free(sb);
    return 0;
}
