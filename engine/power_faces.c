/* power_faces.c — faces of the power diagram of spheres (see power_faces.h). */
#include "power_faces.h"

#include <math.h>

enum { MAX_VERTS = 136 }; /* octagon + one vertex per clip, clips capped below */
enum { OCTAGON_LABEL = -1 };

void lub_power_sort(lub_power_site *s, int n)
{
    for (int a = 1; a < n; ++a) {
        const lub_power_site key = s[a];
        const double k2 = v3_norm2(key.d);
        int b = a - 1;
        while (b >= 0 && v3_norm2(s[b].d) > k2) {
            s[b + 1] = s[b];
            --b;
        }
        s[b + 1] = key;
    }
}

double lub_power_certified_radius(double known, double r0, double r_max)
{
    /* largest R with R + sqrt(R^2 + q) <= known, q = r_max^2 - r0^2:
     * sqrt(R^2 + q) <= known - R  <=>  R <= (known^2 - q) / (2 known) */
    const double q = r_max * r_max - r0 * r0;
    if (known <= 0.0)
        return 0.0;
    const double R = (known * known - (q > 0.0 ? q : 0.0)) / (2.0 * known);
    return R > 0.0 ? R : 0.0;
}

typedef struct {
    double s, t;
    int label; /* origin of the edge from this vertex to the next */
} vertex;

/* Clips the convex polygon p[0 .. *m) by A s + B t <= C (edge label `label`) into q. */
static int clip(const vertex *p, int m, double A, double B, double C, int label, vertex *q)
{
    int out = 0;
    for (int i = 0; i < m; ++i) {
        const vertex P = p[i], Q = p[i + 1 < m ? i + 1 : 0];
        const double fp = A * P.s + B * P.t - C, fq = A * Q.s + B * Q.t - C;
        const int in_p = fp <= 0.0, in_q = fq <= 0.0;
        if (in_p)
            q[out++] = P;
        if (in_p != in_q && out < MAX_VERTS) {
            const double u = fp / (fp - fq);
            const vertex I = {P.s + u * (Q.s - P.s), P.t + u * (Q.t - P.t), in_p ? label : P.label};
            q[out++] = I;
        }
        if (out >= MAX_VERTS)
            break;
    }
    return out;
}

double lub_power_face_area(double r0, const lub_power_site *sites, int n, int j, double R,
                           double r_max, int *open)
{
    if (open)
        *open = 1;
    const vec3 dj = sites[j].d;
    const double lj = v3_norm(dj);
    if (!(lj > 0.0))
        return 0.0;
    const vec3 nrm = v3_scale(dj, 1.0 / lj);
    const double h = (lj * lj + r0 * r0 - sites[j].r * sites[j].r) / (2.0 * lj);
    const double rho2 = R * R - h * h;
    if (!(rho2 > 0.0))
        return 0.0;
    /* orthonormal basis of the plane */
    const double ax = fabs(nrm.x), ay = fabs(nrm.y), az = fabs(nrm.z);
    const vec3 axis = ax <= ay && ax <= az ? v3(1, 0, 0) : (ay <= az ? v3(0, 1, 0) : v3(0, 0, 1));
    vec3 e1 = v3_cross(nrm, axis);
    e1 = v3_scale(e1, 1.0 / v3_norm(e1));
    const vec3 e2 = v3_cross(nrm, e1);

    vertex buf[2][MAX_VERTS];
    int m = 8, cur = 0;
    const double rho = sqrt(rho2);
    static const double h2 = 0.70710678118654752440; /* cos 45 deg */
    static const double oc[8] = {1.0, h2, 0.0, -h2, -1.0, -h2, 0.0, h2};
    static const double os[8] = {0.0, h2, 1.0, h2, 0.0, -h2, -1.0, -h2};
    for (int k = 0; k < 8; ++k)
        buf[0][k] = (vertex){rho * oc[k], rho * os[k], OCTAGON_LABEL};
    double ext2 = rho2; /* largest s^2 + t^2 of the polygon */
    int clips = 0;
    for (int k = 0; k < n && m > 0; ++k) {
        if (k == j)
            continue;
        const vec3 dk = sites[k].d;
        const double lk2 = v3_norm2(dk), lk = sqrt(lk2);
        /* no vertex x (|x| <= xmax) can have 2 x.dk > |dk|^2 + r0^2 - rk^2 once
         * |dk|^2 - 2 xmax |dk| + r0^2 - r_max^2 >= 0 with |dk| >= xmax; later sites are farther */
        const double xmax = sqrt(h * h + ext2);
        if (lk >= xmax && lk2 - 2.0 * xmax * lk + r0 * r0 - r_max * r_max >= 0.0)
            break;
        const double A = 2.0 * v3_dot(e1, dk), B = 2.0 * v3_dot(e2, dk);
        const double C = lk2 + r0 * r0 - sites[k].r * sites[k].r - 2.0 * h * v3_dot(nrm, dk);
        if (++clips > MAX_VERTS - 9)
            break; /* cannot happen for a physical packing; keeps the buffers in bounds */
        m = clip(buf[cur], m, A, B, C, k, buf[1 - cur]);
        cur = 1 - cur;
        ext2 = 0.0;
        for (int v = 0; v < m; ++v) {
            const double e = buf[cur][v].s * buf[cur][v].s + buf[cur][v].t * buf[cur][v].t;
            ext2 = e > ext2 ? e : ext2;
        }
    }
    if (m < 3) {
        if (open)
            *open = 0;
        return 0.0;
    }
    double area2 = 0.0;
    int touches = 0;
    for (int v = 0; v < m; ++v) {
        const vertex P = buf[cur][v], Q = buf[cur][v + 1 < m ? v + 1 : 0];
        area2 += P.s * Q.t - Q.s * P.t;
        touches |= P.label == OCTAGON_LABEL;
    }
    if (open)
        *open = touches;
    return 0.5 * fabs(area2);
}
