/* shear_checkpoint.c — a sheared system into a checkpoint and back (see shear_checkpoint.h). */
#include "shear_checkpoint.h"

#include "state_checkpoint.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* the microstructure sums: name, pointer and element count of each array */
static int pdf_arrays(const lub_pdf *p, const char **names, double **arrays, size_t *counts)
{
    const size_t nb = (size_t)p->nt * (size_t)p->np;
    const char *nm[6] = {"pdf/density", "pdf/contact_density", "pdf/gap_sum",
                         "pdf/count",   "pdf/vel_sum",         "pdf/stress"};
    double *ar[6] = {p->density, p->contact_density, p->gap_sum, p->count, p->vel_sum, p->stress};
    const size_t ct[6] = {nb, nb, nb, nb, 3 * nb, 4 * 9 * nb};
    for (int k = 0; k < 6; ++k) {
        names[k] = nm[k];
        arrays[k] = ar[k];
        counts[k] = ct[k];
    }
    return 6;
}

int lub_shear_save(lub_ckpt *c, const lub_shear_system *s)
{
    const size_t n = (size_t)s->n;
    const int64_t topo[4] = {(int64_t)s->topo.inside, (int64_t)s->topo.allowed,
                             (int64_t)s->topo.open, (int64_t)s->topo.updates};
    int rc = lub_ckpt_put_i64(c, "system/n", s->n) ||
             lub_ckpt_put(c, "system/radius", LUB_CKPT_F64, n, s->r) ||
             lub_ckpt_put(c, "system/x", LUB_CKPT_F64, 3 * n, s->x) ||
             lub_ckpt_put(c, "system/v", LUB_CKPT_F64, 3 * n, s->v) ||
             lub_ckpt_put(c, "system/w", LUB_CKPT_F64, 3 * n, s->w) ||
             lub_ckpt_put(c, "system/x_ref", LUB_CKPT_F64, 3 * n, s->x_ref) ||
             lub_ckpt_put(c, "system/inv_i_share", LUB_CKPT_F64, n, s->inv_i_share) ||
             lub_ckpt_put(c, "system/images", LUB_CKPT_I32, 3 * n, s->img) ||
             lub_cell_save(c, "system/cell", &s->cell) ||
             lub_ckpt_put(c, "system/h_ref", LUB_CKPT_F64, 9, s->h_ref) ||
             lub_ckpt_put_f64(c, "system/dt", s->dt) ||
             lub_ckpt_put_f64(c, "system/time", s->time) ||
             lub_ckpt_put_f64(c, "system/skin_used", s->skin_used) ||
             lub_ckpt_put_f64(c, "system/list_distance", s->nl.max_dist) ||
             lub_ckpt_put_i64(c, "system/step", s->step) ||
             lub_ckpt_put_i64(c, "system/rebuilds", s->rebuilds) ||
             lub_ckpt_put_i64(c, "system/flips", s->flips) ||
             lub_ckpt_put_i64(c, "system/lost_pairs", s->lost_pairs) ||
             lub_ckpt_put_i64(c, "system/need_rebuild", s->need_rebuild) ||
             lub_ckpt_put_i64(c, "system/topology_interval", s->topology_interval) ||
             lub_ckpt_put_i64(c, "system/topology_step", s->topology_step) ||
             lub_ckpt_put(c, "system/topology_statistics", LUB_CKPT_I64, 4, topo) ||
             lub_pairs_save(c, "pairs", &s->pairs);
    if (!rc && s->tpdf) {
        const char *names[6];
        double *arrays[6];
        size_t counts[6];
        const int k_n = pdf_arrays(&s->pdf, names, arrays, counts);
        const double range[2] = {s->pdf.strain_first, s->pdf.strain_last};
        rc = lub_ckpt_put_i64(c, "pdf/snapshots", s->pdf.snapshots) ||
             lub_ckpt_put(c, "pdf/vel_com_sum", LUB_CKPT_F64, 3 * (size_t)s->pdf.nt * s->pdf.np,
                          s->pdf.vel_com_sum) ||
             lub_ckpt_put(c, "pdf/strain_range", LUB_CKPT_F64, 2, range);
        for (int k = 0; k < k_n && !rc; ++k)
            rc = lub_ckpt_put(c, names[k], LUB_CKPT_F64, counts[k], arrays[k]);
    }
    return rc ? -1 : 0;
}

int lub_shear_saved_particles(lub_ckpt *c, int *n, double **radius)
{
    int64_t count = 0;
    *radius = NULL;
    if (lub_ckpt_get_i64(c, "system/n", &count) || count < 2 || count > 2147483647)
        return -1;
    double *r = malloc((size_t)count * sizeof *r);
    if (!r || lub_ckpt_get(c, "system/radius", LUB_CKPT_F64, (size_t)count, r)) {
        free(r);
        return -1;
    }
    *n = (int)count;
    *radius = r;
    return 0;
}

/* The particles' images (system/images, since 2026-12-06): a checkpoint written before holds
 * none, and its run goes on with images counted from 0 at the resumed step (the snapshots'
 * unwrapped positions jump there by whole cell vectors). 0, or -1 with the error set. */
static int restore_images(lub_ckpt *c, lub_shear_system *s)
{
    if (!lub_ckpt_has(c, "system/images")) {
        memset(s->img, 0, 3 * (size_t)s->n * sizeof *s->img);
        return 0;
    }
    return lub_ckpt_get(c, "system/images", LUB_CKPT_I32, 3 * (size_t)s->n, s->img);
}

int lub_shear_restore(lub_ckpt *c, lub_shear_system *s)
{
    const size_t n = (size_t)s->n;
    int64_t step, rebuilds, flips, lost, need, interval, topo_step, topo[4];
    if (lub_ckpt_get(c, "system/x", LUB_CKPT_F64, 3 * n, s->x) ||
        lub_ckpt_get(c, "system/v", LUB_CKPT_F64, 3 * n, s->v) ||
        lub_ckpt_get(c, "system/w", LUB_CKPT_F64, 3 * n, s->w) ||
        lub_ckpt_get(c, "system/x_ref", LUB_CKPT_F64, 3 * n, s->x_ref) ||
        lub_ckpt_get(c, "system/inv_i_share", LUB_CKPT_F64, n, s->inv_i_share) ||
        restore_images(c, s) || lub_cell_load(c, "system/cell", &s->cell) ||
        lub_ckpt_get(c, "system/h_ref", LUB_CKPT_F64, 9, s->h_ref) ||
        lub_ckpt_get_f64(c, "system/dt", &s->dt) || lub_ckpt_get_f64(c, "system/time", &s->time) ||
        lub_ckpt_get_f64(c, "system/skin_used", &s->skin_used) ||
        lub_ckpt_get_f64(c, "system/list_distance", &s->nl.max_dist) ||
        lub_ckpt_get_i64(c, "system/step", &step) ||
        lub_ckpt_get_i64(c, "system/rebuilds", &rebuilds) ||
        lub_ckpt_get_i64(c, "system/flips", &flips) ||
        lub_ckpt_get_i64(c, "system/lost_pairs", &lost) ||
        lub_ckpt_get_i64(c, "system/need_rebuild", &need) ||
        lub_ckpt_get_i64(c, "system/topology_interval", &interval) ||
        lub_ckpt_get_i64_or(c, "system/topology_step", -1, &topo_step) ||
        lub_ckpt_get(c, "system/topology_statistics", LUB_CKPT_I64, 4, topo) ||
        lub_pairs_load(c, "pairs", &s->pairs, s->n, s->threads))
        return -1;
    s->step = (long)step;
    s->rebuilds = (long)rebuilds;
    s->flips = (long)flips;
    s->lost_pairs = (long)lost;
    s->need_rebuild = (int)need;
    s->topology_interval = (int)interval;
    s->topology_step = (long)topo_step;
    s->topo.inside = (size_t)topo[0];
    s->topo.allowed = (size_t)topo[1];
    s->topo.open = (size_t)topo[2];
    s->topo.updates = (long)topo[3];
    if (s->tpdf) {
        const char *names[6];
        double *arrays[6];
        size_t counts[6];
        const int k_n = pdf_arrays(&s->pdf, names, arrays, counts);
        int64_t snapshots = 0;
        if (lub_ckpt_get_i64(c, "pdf/snapshots", &snapshots))
            return -1;
        s->pdf.snapshots = (long)snapshots;
        for (int k = 0; k < k_n; ++k)
            if (lub_ckpt_get(c, names[k], LUB_CKPT_F64, counts[k], arrays[k]))
                return -1;
        /* since 2026-12-07; a checkpoint written before has neither: the centre-of-mass
         * velocity map of its continuation is NaN where the stopped run had taken a pair, and
         * the averaging window's strains are not known (NaN) */
        const size_t nb = (size_t)s->pdf.nt * (size_t)s->pdf.np;
        double range[2] = {NAN, NAN};
        if (lub_ckpt_has(c, "pdf/vel_com_sum")) {
            if (lub_ckpt_get(c, "pdf/vel_com_sum", LUB_CKPT_F64, 3 * nb, s->pdf.vel_com_sum))
                return -1;
        } else {
            for (size_t k = 0; k < nb; ++k)
                for (int d = 0; d < 3; ++d)
                    s->pdf.vel_com_sum[3 * k + d] = s->pdf.count[k] > 0 ? NAN : 0.0;
        }
        if (lub_ckpt_has(c, "pdf/strain_range") &&
            lub_ckpt_get(c, "pdf/strain_range", LUB_CKPT_F64, 2, range))
            return -1;
        s->pdf.strain_first = range[0];
        s->pdf.strain_last = range[1];
    }
    return 0;
}
