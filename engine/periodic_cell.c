/* periodic_cell.c — deforming tri-periodic cell (see periodic_cell.h). */
#include "periodic_cell.h"

#include <math.h>

int lub_cell_refresh(lub_cell *c)
{
    const double(*h)[3] = c->h;
    double det = h[0][0] * (h[1][1] * h[2][2] - h[1][2] * h[2][1]) -
                 h[0][1] * (h[1][0] * h[2][2] - h[1][2] * h[2][0]) +
                 h[0][2] * (h[1][0] * h[2][1] - h[1][1] * h[2][0]);
    c->volume = det;
    if (!(det > 0.0))
        return -1;
    double id = 1.0 / det;
    c->hinv[0][0] = (h[1][1] * h[2][2] - h[1][2] * h[2][1]) * id;
    c->hinv[0][1] = (h[0][2] * h[2][1] - h[0][1] * h[2][2]) * id;
    c->hinv[0][2] = (h[0][1] * h[1][2] - h[0][2] * h[1][1]) * id;
    c->hinv[1][0] = (h[1][2] * h[2][0] - h[1][0] * h[2][2]) * id;
    c->hinv[1][1] = (h[0][0] * h[2][2] - h[0][2] * h[2][0]) * id;
    c->hinv[1][2] = (h[0][2] * h[1][0] - h[0][0] * h[1][2]) * id;
    c->hinv[2][0] = (h[1][0] * h[2][1] - h[1][1] * h[2][0]) * id;
    c->hinv[2][1] = (h[0][1] * h[2][0] - h[0][0] * h[2][1]) * id;
    c->hinv[2][2] = (h[0][0] * h[1][1] - h[0][1] * h[1][0]) * id;
    return 0;
}

void lub_cell_init_box(lub_cell *c, double lx, double ly, double lz)
{
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) {
            c->h[i][j] = 0.0;
            c->L[i][j] = 0.0;
        }
    c->h[0][0] = lx;
    c->h[1][1] = ly;
    c->h[2][2] = lz;
    lub_cell_refresh(c);
}

int lub_cell_update(lub_cell *c, double dt)
{
    double n[3][3];
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) {
            double s = c->h[i][j];
            for (int k = 0; k < 3; ++k)
                s += dt * c->L[i][k] * c->h[k][j];
            n[i][j] = s;
        }
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j)
            c->h[i][j] = n[i][j];
    return lub_cell_refresh(c);
}

static vec3 mat_vec(const double m[3][3], vec3 x)
{
    return v3(m[0][0] * x.x + m[0][1] * x.y + m[0][2] * x.z,
              m[1][0] * x.x + m[1][1] * x.y + m[1][2] * x.z,
              m[2][0] * x.x + m[2][1] * x.y + m[2][2] * x.z);
}

vec3 lub_cell_to_frac(const lub_cell *c, vec3 x) { return mat_vec(c->hinv, x); }
vec3 lub_cell_to_cart(const lub_cell *c, vec3 s) { return mat_vec(c->h, s); }

void lub_cell_wrap(const lub_cell *c, vec3 *x, vec3 *v, int k_out[3])
{
    vec3 s = lub_cell_to_frac(c, *x);
    int k[3] = {(int)floor(s.x), (int)floor(s.y), (int)floor(s.z)};
    if (k[0] | k[1] | k[2]) {
        vec3 d = lub_cell_shift(c, k);
        *x = v3_sub(*x, d);
        if (v)
            *v = v3_sub(*v, mat_vec(c->L, d));
        /* guard against round-off putting the point exactly at 1.0 */
        vec3 s2 = lub_cell_to_frac(c, *x);
        double sv[3] = {s2.x, s2.y, s2.z};
        for (int a = 0; a < 3; ++a)
            if (sv[a] < 0.0 || sv[a] >= 1.0) {
                int e[3] = {0, 0, 0};
                e[a] = (int)floor(sv[a]);
                vec3 dd = lub_cell_shift(c, e);
                *x = v3_sub(*x, dd);
                if (v)
                    *v = v3_sub(*v, mat_vec(c->L, dd));
                k[a] += e[a];
            }
    }
    if (k_out) {
        k_out[0] = k[0];
        k_out[1] = k[1];
        k_out[2] = k[2];
    }
}

void lub_cell_widths(const lub_cell *c, double w[3])
{
    /* width along cell vector a = 1 / |row a of H^-1| */
    for (int a = 0; a < 3; ++a) {
        double n2 = c->hinv[a][0] * c->hinv[a][0] + c->hinv[a][1] * c->hinv[a][1] +
                    c->hinv[a][2] * c->hinv[a][2];
        w[a] = 1.0 / sqrt(n2);
    }
}

int lub_cell_flip(lub_cell *c, int m[3])
{
    int changed = 0;
    m[0] = 0;
    for (int j = 1; j < 3; ++j) {
        /* fractional component of h_j along h_0 (h_0 is along x for our cells) */
        double t = c->h[0][j] / c->h[0][0];
        int mj = (fabs(t) > 0.5) ? (int)lround(t) : 0;
        m[j] = mj;
        if (mj) {
            for (int r = 0; r < 3; ++r)
                c->h[r][j] -= mj * c->h[r][0];
            changed = 1;
        }
    }
    if (changed)
        lub_cell_refresh(c);
    return changed;
}

void lub_cell_flip_shift(const int m[3], int shift[3])
{
    shift[0] += m[1] * shift[1] + m[2] * shift[2];
}

void lub_cell_wrap_counted(const lub_cell *c, const int m[3], int flipped, vec3 *x, vec3 *v,
                           int img[3])
{
    if (flipped)
        lub_cell_flip_shift(m, img);
    int k[3];
    lub_cell_wrap(c, x, v, k);
    img[0] += k[0];
    img[1] += k[1];
    img[2] += k[2];
}
