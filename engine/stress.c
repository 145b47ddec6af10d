/* stress.c — virial stress sums (see stress.h). */
#include "stress.h"

#include <string.h>

void lub_stress_zero(lub_stress *s) { memset(s, 0, sizeof *s); }

static void add_outer(double *t, vec3 f, vec3 l)
{
    t[0] += f.x * l.x;
    t[1] += f.x * l.y;
    t[2] += f.x * l.z;
    t[3] += f.y * l.x;
    t[4] += f.y * l.y;
    t[5] += f.y * l.z;
    t[6] += f.z * l.x;
    t[7] += f.z * l.y;
    t[8] += f.z * l.z;
}

void lub_stress_add_pair(lub_stress *s, const lub_pair_output *o, vec3 branch)
{
    add_outer(s->part[LUB_SP_NC], v3_scale(o->n, o->fn_contact), branch);
    add_outer(s->part[LUB_SP_SC], o->fs_contact, branch);
    add_outer(s->part[LUB_SP_NL], v3_scale(o->n, o->fn_lub), branch);
    add_outer(s->part[LUB_SP_SL], o->fs_lub, branch);
}

void lub_stress_add_kinetic(lub_stress *s, double mass, vec3 vp)
{
    add_outer(s->part[LUB_SP_KIN], v3_scale(vp, -mass), vp);
}

void lub_stress_accumulate(lub_stress *a, const lub_stress *b)
{
    for (int p = 0; p < LUB_SP_N; ++p)
        for (int k = 0; k < 9; ++k)
            a->part[p][k] += b->part[p][k];
}

void lub_stress_scale(lub_stress *s, double factor)
{
    for (int p = 0; p < LUB_SP_N; ++p)
        for (int k = 0; k < 9; ++k)
            s->part[p][k] *= factor;
}

void lub_stress_total(const lub_stress *s, double total[9])
{
    for (int k = 0; k < 9; ++k) {
        double t = 0.0;
        for (int p = 0; p < LUB_SP_N; ++p)
            t += s->part[p][k];
        total[k] = t;
    }
}
