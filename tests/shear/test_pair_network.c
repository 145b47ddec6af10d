/* test_pair_network.c — the interaction network (engine/pair_network.h) of a dense sheared
 * system is what the next step computes, and computing it changes nothing:
 *  1. on a state whose pair list is complete, the network leaves every pair state, active and
 *     near flag as it was, and the next step's stress sample (each of the normal/tangential
 *     contact/lubrication parts) and its counts of active, contact and sliding pairs equal the
 *     sums over the network (branch ⊗ force / volume) to round-off;
 *  2. on a state whose last step found the Verlet skin possibly used up, the network first
 *     completes the list (the rebuild the step would do) and the same holds;
 *  3. with the Delaunay interaction set, only the allowed pairs are in the network, again
 *     equal to the next step's sample;
 *  4. each record is consistent in itself: i < j, the branch vector from the positions and the
 *     image shift, the centre gap from the branch and the radii, contact when u < eps a,
 *     sliding contacts at the Coulomb limit and sticking ones below it. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "pair_network.h"
#include "shear_checkpoint.h"
#include "shear_fixture.h"
#include "shear_system.h"
#include "shear_test.h"

/* sum over the network of F ⊗ branch / volume, per part, into part[4][9] (row-major F_a d_b,
 * as lub_stress_add_pair) */
static void network_stress(const lub_pair_network *net, double volume, double part[4][9])
{
    memset(part, 0, 4 * 9 * sizeof(double));
    for (size_t k = 0; k < net->n; ++k) {
        const double *d = &net->branch[3 * k];
        const double len = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
        double f[4][3];
        for (int a = 0; a < 3; ++a) {
            f[0][a] = net->fn_contact[k] * d[a] / len;
            f[1][a] = net->fs_contact[3 * k + a];
            f[2][a] = net->fn_lub[k] * d[a] / len;
            f[3][a] = net->fs_lub[3 * k + a];
        }
        for (int p = 0; p < 4; ++p)
            for (int a = 0; a < 3; ++a)
                for (int b = 0; b < 3; ++b)
                    part[p][3 * a + b] += f[p][a] * d[b] / volume;
    }
}

/* The network of s against its next step (cases 1-3), and the records (case 4). */
static void check_against_next_step(lub_shear_system *s, const char *what)
{
    lub_pair_network net = {0};
    const int rebuild_due = s->need_rebuild;
    const long rebuilds = s->rebuilds;
    int rc = lub_shear_pair_network(s, &net);
    ST_CHECK(rc == LUB_SHEAR_OK, "%s: network rc %d (%s)", what, rc, s->fail_msg);
    ST_CHECK(s->rebuilds == rebuilds + rebuild_due && !s->need_rebuild,
             "%s: the list is completed exactly when a rebuild is due (%d; %ld -> %ld)", what,
             rebuild_due, rebuilds, s->rebuilds);
    /* a second network from the completed list changes nothing either */
    const size_t n2 = s->pairs.n;
    lub_pair_state *st0 = malloc(n2 * sizeof *st0);
    unsigned char *act0 = malloc(n2), *near0 = malloc(n2);
    if (!st0 || !act0 || !near0)
        abort();
    memcpy(st0, s->pairs.state, n2 * sizeof *st0);
    memcpy(act0, s->pairs.active, n2);
    memcpy(near0, s->pairs.near, n2);
    lub_pair_network again = {0};
    rc = lub_shear_pair_network(s, &again);
    ST_CHECK(rc == LUB_SHEAR_OK && again.n == net.n &&
                 memcmp(again.fs_contact, net.fs_contact, 3 * net.n * sizeof(double)) == 0 &&
                 memcmp(again.fn_lub, net.fn_lub, net.n * sizeof(double)) == 0,
             "%s: a second network is the same (%zu, %zu pairs)", what, again.n, net.n);
    /* into the arrays of an earlier network with room: kept (nothing allocated), same records */
    const int64_t *kept = again.i;
    const size_t cap = again.cap;
    rc = lub_shear_pair_network(s, &again);
    ST_CHECK(rc == LUB_SHEAR_OK && again.i == kept && again.cap == cap && cap >= net.n &&
                 again.n == net.n && memcmp(again.j, net.j, net.n * sizeof *net.j) == 0 &&
                 memcmp(again.torque_roll, net.torque_roll, 3 * net.n * sizeof(double)) == 0,
             "%s: a network into kept arrays (room %zu) is the same", what, cap);
    lub_pair_network_free(&again);
    ST_CHECK(again.i == NULL && again.cap == 0 && again.n == 0, "%s: freed and emptied", what);
    ST_CHECK(memcmp(st0, s->pairs.state, n2 * sizeof *st0) == 0 &&
                 memcmp(act0, s->pairs.active, n2) == 0 && memcmp(near0, s->pairs.near, n2) == 0,
             "%s: the network leaves the pair states and flags as they were", what);
    free(st0);
    free(act0);
    free(near0);

    /* case 4: the records */
    const double eps = s->law.eps, mu = s->law.mu;
    int bad = 0;
    size_t contacts = 0, sliding = 0;
    for (size_t k = 0; k < net.n; ++k) {
        const int64_t i = net.i[k], j = net.j[k];
        const vec3 shift = lub_cell_shift(
            &s->cell, (const int32_t[3]){(int32_t)net.image[3 * k], (int32_t)net.image[3 * k + 1],
                                         (int32_t)net.image[3 * k + 2]});
        const vec3 d = v3_sub(v3_add(s->x[j], shift), s->x[i]);
        const double *b = &net.branch[3 * k];
        const double a = 0.5 * (s->r[i] + s->r[j]);
        const double fs = sqrt(net.fs_contact[3 * k] * net.fs_contact[3 * k] +
                               net.fs_contact[3 * k + 1] * net.fs_contact[3 * k + 1] +
                               net.fs_contact[3 * k + 2] * net.fs_contact[3 * k + 2]);
        const double limit = mu * fabs(net.fn_contact[k]);
        bad += !(i >= 0 && i < j && j < s->n);
        bad += d.x != b[0] || d.y != b[1] || d.z != b[2];
        bad += net.centre_gap[k] != v3_norm(d) - s->r[i] - s->r[j];
        bad += net.centre_gap[k] > s->cutoff * a;
        bad += (net.gap[k] < eps * a) != (net.contact[k] == 1);
        bad += net.sliding[k] && (!net.contact[k] || fabs(fs - limit) > 1e-12 * (1.0 + limit));
        bad += !net.sliding[k] && fs > limit * (1.0 + 1e-12);
        contacts += net.contact[k] == 1;
        sliding += net.sliding[k] == 1;
    }
    ST_CHECK(bad == 0, "%s: %d inconsistent record(s)", what, bad);

    /* cases 1-3: the next step's sample */
    double part[4][9];
    network_stress(&net, s->cell.volume, part);
    lub_shear_sample smp;
    rc = lub_shear_step(s, LUB_SAMPLE_STRESS, &smp);
    ST_CHECK(rc == LUB_SHEAR_OK, "%s: step rc %d", what, rc);
    double worst = 0.0, scale = 0.0;
    for (int p = 0; p < 4; ++p)
        for (int c = 0; c < 9; ++c) {
            worst = fmax(worst, fabs(part[p][c] - smp.stress.part[p][c]));
            scale = fmax(scale, fabs(smp.stress.part[p][c]));
        }
    ST_CHECK(scale > 0 && worst <= 1e-12 * scale,
             "%s: the network's stress parts are the next step's (largest difference %.3g of "
             "%.3g)",
             what, worst, scale);
    ST_CHECK(smp.n_active == net.n && smp.n_contacts == contacts && smp.n_sliding == sliding,
             "%s: pairs %zu/%zu, contacts %zu/%zu, sliding %zu/%zu (step/network)", what,
             smp.n_active, net.n, smp.n_contacts, contacts, smp.n_sliding, sliding);
    ST_CHECK(contacts > 0 && sliding > 0,
             "%s: a dense state has contacts (%zu) and sliding "
             "ones (%zu)",
             what, contacts, sliding);
    printf("%s: %zu pairs, %zu contacts, %zu sliding, stress difference %.3g of %.3g\n", what,
           net.n, contacts, sliding, worst, scale);
    lub_pair_network_free(&net);
}

/* Steps s until its last step left the list complete (want_rebuild 0) or found the skin used
 * up (1); at most 5000 steps. */
static int step_until(lub_shear_system *s, int want_rebuild)
{
    for (int k = 0; k < 5000; ++k) {
        if (lub_shear_step(s, 0, NULL) != LUB_SHEAR_OK)
            return -1;
        if (s->need_rebuild == want_rebuild && s->step > 200)
            return 0;
    }
    return -1;
}

int main(void)
{
    const lub_law_params law = shear_fixture_law(1e4);
    lub_shear_system s;
    ST_CHECK(shear_fixture_make(&s, 300, 0.52, &law, 2.0, 1, 7, 1e-2) == 0, "fixture");
    ST_CHECK(step_until(&s, 0) == 0, "a step with a complete list");
    check_against_next_step(&s, "complete list");
    ST_CHECK(step_until(&s, 1) == 0, "a step that used up the skin");
    check_against_next_step(&s, "rebuild due");
    lub_shear_free(&s);

    ST_CHECK(shear_fixture_make(&s, 300, 0.52, &law, 2.0, 1, 8, 1e-2) == 0, "fixture");
    lub_shear_use_delaunay(&s, 100000, 0.05);
    ST_CHECK(step_until(&s, 0) == 0, "Delaunay: a step with a complete list");
    size_t refused = 0;
    for (size_t k = 0; k < s.pairs.n; ++k)
        refused += s.pairs.allow[k] == 0;
    ST_CHECK(refused > 0, "Delaunay: some listed pairs are not allowed (%zu of %zu)", refused,
             s.pairs.n);
    check_against_next_step(&s, "Delaunay");
    lub_shear_free(&s);

    /* A network taken at a step whose Delaunay update is due holds the set that step uses
     * (the first version listed the previous update's: 1e-3 off in the lubrication parts). */
    ST_CHECK(shear_fixture_make(&s, 300, 0.52, &law, 2.0, 1, 9, 1e-2) == 0, "fixture");
    lub_shear_use_delaunay(&s, 40, 0.05);
    int due = 0;
    for (int k = 0; k < 5000 && !due; ++k) {
        ST_CHECK(lub_shear_step(&s, 0, NULL) == LUB_SHEAR_OK, "step");
        due = s.step > 200 && s.step % 40 == 0 && !s.need_rebuild;
    }
    ST_CHECK(due, "Delaunay: a step whose update is due, with a complete list");
    unsigned char *before = malloc(s.pairs.n);
    ST_CHECK(before != NULL, "memory");
    memcpy(before, s.pairs.allow, s.pairs.n);
    const size_t listed = s.pairs.n;
    const long updates = s.topo.updates;
    check_against_next_step(&s, "Delaunay update due");
    /* the networks (three) and the step share one triangulation: the summary's
     * delaunay_updates is that of a run without networks (until 2026-12-06: 4 here) */
    ST_CHECK(s.topo.updates == updates + 1,
             "Delaunay: one update for the networks and the step (%ld -> %ld)", updates,
             s.topo.updates);
    size_t changed = 0;
    for (size_t k = 0; k < listed && listed == s.pairs.n; ++k)
        changed += before[k] != s.pairs.allow[k];
    ST_CHECK(changed > 0, "Delaunay: the due update changed the set (%zu pairs)", changed);
    free(before);
    lub_shear_free(&s);

    /* A checkpoint written after such a network (a stop right after a frame) continues as the
     * run that did not stop: the same positions after the next update, and the update the
     * network did counted once (the step of the continued run does not compute it again) */
    ST_CHECK(shear_fixture_make(&s, 300, 0.52, &law, 2.0, 1, 9, 1e-2) == 0, "fixture");
    lub_shear_use_delaunay(&s, 40, 0.05);
    due = 0;
    for (int k = 0; k < 5000 && !due; ++k) {
        ST_CHECK(lub_shear_step(&s, 0, NULL) == LUB_SHEAR_OK, "step");
        due = s.step > 200 && s.step % 40 == 0 && !s.need_rebuild;
    }
    lub_pair_network frame = {0};
    ST_CHECK(lub_shear_pair_network(&s, &frame) == LUB_SHEAR_OK, "network at a due update");
    lub_pair_network_free(&frame);
    char err[400] = "";
    const char *ckpt_path = "pair_network_checkpoint.h5";
    lub_ckpt *ck = lub_ckpt_create(ckpt_path, err, sizeof err);
    ST_CHECK(ck && lub_shear_save(ck, &s) == 0 && lub_ckpt_close(ck, err, sizeof err) == 0,
             "checkpoint after the network: %s", err);
    lub_shear_system t;
    ST_CHECK(shear_fixture_make(&t, 300, 0.52, &law, 2.0, 1, 9, 1e-2) == 0, "fixture");
    lub_shear_use_delaunay(&t, 40, 0.05);
    ck = lub_ckpt_open(ckpt_path, err, sizeof err);
    ST_CHECK(ck && lub_shear_restore(ck, &t) == 0, "restore: %s", ck ? lub_ckpt_error(ck) : err);
    lub_ckpt_close(ck, NULL, 0);
    remove(ckpt_path);
    for (int k = 0; k < 50; ++k)
        ST_CHECK(lub_shear_step(&s, 0, NULL) == LUB_SHEAR_OK &&
                     lub_shear_step(&t, 0, NULL) == LUB_SHEAR_OK,
                 "steps after the checkpoint");
    ST_CHECK(t.topo.updates == s.topo.updates && memcmp(t.x, s.x, (size_t)s.n * sizeof *s.x) == 0,
             "continued from the checkpoint: %ld updates against %ld, positions %s", t.topo.updates,
             s.topo.updates, memcmp(t.x, s.x, (size_t)s.n * sizeof *s.x) ? "differ" : "equal");
    lub_shear_free(&t);
    lub_shear_free(&s);
    lub_pair_network empty = {0};
    lub_pair_network_free(&empty); /* safe on an empty network */
    ST_DONE();
}
