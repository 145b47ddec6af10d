/* microstructure.c — binned pair statistics on the unit sphere (see microstructure.h). */
#include "microstructure.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static const double PI = 3.14159265358979323846;

int lub_pdf_init(lub_pdf *p, int n_theta, int n_phi)
{
    memset(p, 0, sizeof *p);
    p->nt = n_theta;
    p->np = n_phi;
    size_t nb = (size_t)n_theta * (size_t)n_phi;
    p->density = calloc(nb, sizeof(double));
    p->contact_density = calloc(nb, sizeof(double));
    p->gap_sum = calloc(nb, sizeof(double));
    p->count = calloc(nb, sizeof(double));
    p->vel_sum = calloc(3 * nb, sizeof(double));
    p->vel_com_sum = calloc(3 * nb, sizeof(double));
    p->stress = calloc(4 * 9 * nb, sizeof(double));
    if (!p->density || !p->contact_density || !p->gap_sum || !p->count || !p->vel_sum ||
        !p->vel_com_sum || !p->stress) {
        lub_pdf_free(p);
        return -1;
    }
    p->strain_first = p->strain_last = NAN;
    return 0;
}

double lub_pdf_bytes(int n_theta, int n_phi)
{
    /* density, contact density, gap, count (1 each), two velocities (3 each), stress (36) */
    return (4.0 + 6.0 + 36.0) * (double)n_theta * (double)n_phi * sizeof(double);
}

void lub_pdf_free(lub_pdf *p)
{
    free(p->density);
    free(p->contact_density);
    free(p->gap_sum);
    free(p->count);
    free(p->vel_sum);
    free(p->vel_com_sum);
    free(p->stress);
    memset(p, 0, sizeof *p);
}

void lub_pdf_clear(lub_pdf *p)
{
    size_t nb = (size_t)p->nt * (size_t)p->np;
    memset(p->density, 0, nb * sizeof(double));
    memset(p->contact_density, 0, nb * sizeof(double));
    memset(p->gap_sum, 0, nb * sizeof(double));
    memset(p->count, 0, nb * sizeof(double));
    memset(p->vel_sum, 0, 3 * nb * sizeof(double));
    memset(p->vel_com_sum, 0, 3 * nb * sizeof(double));
    memset(p->stress, 0, 36 * nb * sizeof(double));
    p->snapshots = 0;
    p->strain_first = p->strain_last = NAN;
}

int lub_pdf_bin(const lub_pdf *p, vec3 n, int *inversed)
{
    double c = n.y > 1.0 ? 1.0 : (n.y < -1.0 ? -1.0 : n.y);
    double th = acos(c);
    double ph = atan2(n.x, n.z);
    int inv = 0;
    if (ph < 0) {
        th = PI - th;
        ph += PI;
        inv = 1;
    }
    int it = (int)(th / (PI / p->nt));
    int ip = (int)(ph / (PI / p->np));
    if (it >= p->nt)
        it = p->nt - 1;
    if (it < 0)
        it = 0;
    if (ip >= p->np)
        ip = p->np - 1;
    if (ip < 0)
        ip = 0;
    if (inversed)
        *inversed = inv;
    return it * p->np + ip;
}

double lub_pdf_solid_angle(const lub_pdf *p, int bin)
{
    /* the bin's exact area, (cos theta_i - cos theta_i+1) dphi: the midpoint rule
     * sin((i + 1/2) dtheta) dtheta dphi used until 2026-12-06 made every density low by
     * sin(dtheta/2)/(dtheta/2) (0.9976 at 13 bins in theta, 0.64 at 1) */
    const int it = bin / p->np;
    const double dt = PI / p->nt, dp = PI / p->np;
    return (cos(it * dt) - cos((it + 1) * dt)) * dp;
}

void lub_pdf_add_pair(lub_pdf *p, const lub_pair_output *o, vec3 branch, vec3 w, vec3 wc, double a,
                      int n_particles, double volume)
{
    int inv;
    int b = lub_pdf_bin(p, o->n, &inv);
    double ds = lub_pdf_solid_angle(p, b);
    double add = 1.0 / (n_particles * ds);
    p->density[b] += add;
    if (o->contact)
        p->contact_density[b] += add;
    p->gap_sum[b] += o->un / a;
    p->count[b] += 1.0;
    double sg = inv ? -1.0 : 1.0;
    p->vel_sum[3 * b] += sg * w.x;
    p->vel_sum[3 * b + 1] += sg * w.y;
    p->vel_sum[3 * b + 2] += sg * w.z;
    p->vel_com_sum[3 * b] += sg * wc.x;
    p->vel_com_sum[3 * b + 1] += sg * wc.y;
    p->vel_com_sum[3 * b + 2] += sg * wc.z;
    size_t nb = (size_t)p->nt * (size_t)p->np;
    vec3 f[4] = {v3_scale(o->n, o->fn_contact), o->fs_contact, v3_scale(o->n, o->fn_lub),
                 o->fs_lub};
    double sc = 1.0 / (volume * ds);
    for (int part = 0; part < 4; ++part) {
        double *t = p->stress + ((size_t)part * nb + (size_t)b) * 9;
        double fv[3] = {f[part].x, f[part].y, f[part].z};
        double lv[3] = {branch.x, branch.y, branch.z};
        for (int i = 0; i < 3; ++i)
            for (int j = 0; j < 3; ++j)
                t[3 * i + j] += sc * fv[i] * lv[j];
    }
}

void lub_pdf_accumulate(lub_pdf *a, const lub_pdf *b)
{
    size_t nb = (size_t)a->nt * (size_t)a->np;
    for (size_t k = 0; k < nb; ++k) {
        a->density[k] += b->density[k];
        a->contact_density[k] += b->contact_density[k];
        a->gap_sum[k] += b->gap_sum[k];
        a->count[k] += b->count[k];
    }
    for (size_t k = 0; k < 3 * nb; ++k) {
        a->vel_sum[k] += b->vel_sum[k];
        a->vel_com_sum[k] += b->vel_com_sum[k];
    }
    for (size_t k = 0; k < 36 * nb; ++k)
        a->stress[k] += b->stress[k];
}

void lub_pdf_finish(lub_pdf *p)
{
    size_t nb = (size_t)p->nt * (size_t)p->np;
    double s = p->snapshots > 0 ? 1.0 / (double)p->snapshots : 0.0;
    for (size_t k = 0; k < nb; ++k) {
        p->density[k] *= s;
        p->contact_density[k] *= s;
        /* an empty bin has no mean: NaN (until 2026-12-07 0, a touching pair at rest) */
        const double c = p->count[k] > 0 ? 1.0 / p->count[k] : NAN;
        p->gap_sum[k] *= c;
        for (int d = 0; d < 3; ++d) {
            p->vel_sum[3 * k + d] *= c;
            p->vel_com_sum[3 * k + d] *= c;
        }
    }
    for (size_t k = 0; k < 36 * nb; ++k)
        p->stress[k] *= s;
}
