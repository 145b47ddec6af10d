/* pair_network.c — the interaction network of a sheared system (see pair_network.h). */
#include "pair_network.h"

#include <stdio.h>
#include <stdlib.h>

#include "pair_eval.h"

void lub_pair_network_free(lub_pair_network *net)
{
    free(net->i);
    free(net->j);
    free(net->image);
    free(net->branch);
    free(net->centre_gap);
    free(net->gap);
    free(net->contact);
    free(net->sliding);
    free(net->fn_contact);
    free(net->fn_lub);
    free(net->fs_contact);
    free(net->fs_lub);
    free(net->torque_roll);
    free(net->torque_twist);
    *net = (lub_pair_network){0};
}

/* Room for `need` pairs: the arrays kept when they have it, otherwise replaced by arrays for
 * need + need / 4 (a later network of a few more pairs allocates nothing). 0, or -1 with the
 * network emptied. */
static int network_reserve(lub_pair_network *net, size_t need)
{
    if (net->i && need <= net->cap)
        return 0;
    lub_pair_network_free(net);
    const size_t c = need + need / 4 > 0 ? need + need / 4 : 1;
    net->cap = c;
    net->i = malloc(c * sizeof *net->i);
    net->j = malloc(c * sizeof *net->j);
    net->image = malloc(3 * c * sizeof *net->image);
    net->branch = malloc(3 * c * sizeof *net->branch);
    net->centre_gap = malloc(c * sizeof *net->centre_gap);
    net->gap = malloc(c * sizeof *net->gap);
    net->contact = malloc(c * sizeof *net->contact);
    net->sliding = malloc(c * sizeof *net->sliding);
    net->fn_contact = malloc(c * sizeof *net->fn_contact);
    net->fn_lub = malloc(c * sizeof *net->fn_lub);
    net->fs_contact = malloc(3 * c * sizeof *net->fs_contact);
    net->fs_lub = malloc(3 * c * sizeof *net->fs_lub);
    net->torque_roll = malloc(3 * c * sizeof *net->torque_roll);
    net->torque_twist = malloc(3 * c * sizeof *net->torque_twist);
    if (net->i && net->j && net->image && net->branch && net->centre_gap && net->gap &&
        net->contact && net->sliding && net->fn_contact && net->fn_lub && net->fs_contact &&
        net->fs_lub && net->torque_roll && net->torque_twist)
        return 0;
    lub_pair_network_free(net);
    return -1;
}

static void put3(double *dst, size_t k, vec3 v)
{
    dst[3 * k] = v.x;
    dst[3 * k + 1] = v.y;
    dst[3 * k + 2] = v.z;
}

int lub_pair_network_build(const lub_pair_network_source *src, lub_pair_network *net,
                           char *fail_msg, size_t len)
{
    net->n = 0;
    const lub_pairs *ps = src->pairs;
    size_t inside = 0; /* the arrays hold the interacting pairs, not every listed one */
    for (size_t k = 0; k < ps->n; ++k) {
        lub_pair_input in;
        double un;
        inside +=
            ps->i[k] < src->n_free && lub_pair_input_of(ps, k, src->cell, &src->bodies, src->cutoff,
                                                        src->dt, &in, &un) == LUB_PAIR_OK;
    }
    if (network_reserve(net, inside) != 0)
        return LUB_PAIR_NETWORK_NOMEM;
    size_t m = 0;
    for (size_t k = 0; k < ps->n; ++k) {
        lub_pair_input in;
        double un;
        if (ps->i[k] >= src->n_free || /* i < j: two fixed bodies never interact */
            lub_pair_input_of(ps, k, src->cell, &src->bodies, src->cutoff, src->dt, &in, &un) !=
                LUB_PAIR_OK) /* as counted above: the arrays have room for exactly these */
            continue;
        lub_pair_state st = ps->state[k];
        if (!ps->active[k])
            lub_pair_state_reset(&st); /* as lub_pairs_enter: a pair entering the cut-off */
        lub_pair_output o;
        if (lub_pair_step(src->law, &in, &st, &o) != 0 || !v3_isfinite(o.force1) ||
            !v3_isfinite(o.torque1) || !v3_isfinite(o.torque2)) {
            snprintf(fail_msg, len,
                     "pair law non-finite for pair %zu (particles %d, %d; u_n=%.6g) in the "
                     "interaction network at step %ld",
                     k, ps->i[k], ps->j[k], un, src->step);
            net->n = 0;
            return LUB_PAIR_NETWORK_NONFINITE;
        }
        net->i[m] = ps->i[k];
        net->j[m] = ps->j[k];
        for (int c = 0; c < 3; ++c)
            net->image[3 * m + c] = ps->c[3 * k + c];
        put3(net->branch, m, in.branch);
        net->centre_gap[m] = un;
        net->gap[m] = o.gap;
        net->contact[m] = (int8_t)(o.contact != 0);
        net->sliding[m] = (int8_t)(o.slip != 0);
        net->fn_contact[m] = o.fn_contact;
        net->fn_lub[m] = o.fn_lub;
        put3(net->fs_contact, m, o.fs_contact);
        put3(net->fs_lub, m, o.fs_lub);
        put3(net->torque_roll, m, o.torque_roll1);
        put3(net->torque_twist, m, o.torque_twist1);
        ++m;
    }
    net->n = m;
    return LUB_PAIR_NETWORK_OK;
}

int lub_shear_pair_network(lub_shear_system *s, lub_pair_network *net)
{
    net->n = 0;
    const int rc = lub_shear_complete_list(s);
    if (rc != LUB_SHEAR_OK)
        return rc;
    const lub_pair_network_source src = {
        .pairs = &s->pairs,
        .cell = &s->cell,
        .bodies = {.x = s->x, .v = s->v, .w = s->w, .r = s->r, .inv_i_share = s->inv_i_share},
        .law = &s->law,
        .cutoff = s->cutoff,
        .dt = s->dt,
        .n_free = s->n,
        .step = s->step};
    switch (lub_pair_network_build(&src, net, s->fail_msg, sizeof s->fail_msg)) {
    case LUB_PAIR_NETWORK_OK: return LUB_SHEAR_OK;
    case LUB_PAIR_NETWORK_NOMEM: return LUB_SHEAR_NOMEM;
    default: return LUB_SHEAR_NONFINITE;
    }
}
