/* test_two_spheres_shear.c — two_spheres_shear (physics-reference §1b): reversibility of
 * smooth rigid spheres, roughness-induced streamline change, and negative tests (shear
 * lubrication off, rotation off, cut-off) that must change the trajectory clearly. */
#include <math.h>
#include <stdio.h>

#include "scene_harness.h"

static int fails = 0;

static void run(const char *label, const char *spec, scene_outcome *o)
{
    scene_run_text(spec, NULL, o);
    printf("-- %s: rc=%d wall=%.3fs steps=%lld %s\n", label, o->rc, o->wall_s,
           o->extra ? (long long)json_integer_value(json_object_get(o->extra, "steps")) : -1LL,
           o->message);
    printf("   final_offset_y=%.8g min_gap=%.6g max_offset_y=%.6g contact=%g separated=%g\n",
           scene_value(o, "final_offset_y"), scene_value(o, "min_gap"),
           scene_value(o, "max_offset_y"), scene_value(o, "contact"), scene_value(o, "separated"));
    if (o->rc != 0 || scene_value(o, "separated") != 1.0)
        fails++;
}

int main(void)
{
    scene_outcome o, ref;
    char spec[512];
    /* 1. smooth rigid spheres: final offset = initial offset within 1% (d0 >= 0.1a) */
    const double d0s[] = {0.1, 0.5, 1.0};
    for (int i = 0; i < 3; ++i) {
        snprintf(spec, sizeof spec,
                 "{\"scene\":\"two_spheres_shear\",\"St\":1e-4,\"Ca\":1e-6,\"d0\":%g}", d0s[i]);
        run("smooth rigid", spec, &o);
        double rel = fabs(scene_value(&o, "offset_rel_change"));
        fails += scene_check(rel < 0.01, "reversible: |y_end/d0 - 1|", rel, 0.01);
        fails += scene_check(scene_value(&o, "contact") == 0, "no contact",
                             scene_value(&o, "contact"), 0);
        scene_outcome_free(&o);
    }

    /* reference for the comparisons below: defaults (St 1e-3), d0 = 0.1 */
    run("reference d0=0.1", "{\"scene\":\"two_spheres_shear\",\"d0\":0.1}", &ref);
    const double g_ref = scene_value(&ref, "min_gap");
    const double y_ref = scene_value(&ref, "final_offset_y");

    /* 2. rough spheres (eps = 0.1 > smooth min gap): contact, min gap ~ eps, new streamline */
    run("rough eps=0.1", "{\"scene\":\"two_spheres_shear\",\"d0\":0.1,\"law\":{\"eps\":0.1}}", &o);
    fails += scene_check(scene_value(&o, "contact") == 1, "contact", scene_value(&o, "contact"), 1);
    fails += scene_check(fabs(scene_value(&o, "min_gap") / 0.1 - 1) < 0.05, "min gap ~ eps a",
                         scene_value(&o, "min_gap"), 0.1);
    fails +=
        scene_check(scene_value(&o, "offset_rel_change") > 0.5, "irreversible: y_end/d0 - 1 > 0.5",
                    scene_value(&o, "offset_rel_change"), 0.5);
    scene_outcome_free(&o);
    /* eps below the smooth minimum gap: nothing changes (seed: eps < min gap is harmless) */
    run("rough eps=0.02 (< smooth min gap)",
        "{\"scene\":\"two_spheres_shear\",\"d0\":0.1,\"law\":{\"eps\":0.02}}", &o);
    fails += scene_check(fabs(scene_value(&o, "final_offset_y") - y_ref) < 1e-9,
                         "same final offset as smooth", scene_value(&o, "final_offset_y"), y_ref);
    scene_outcome_free(&o);

    /* 3. negative tests: dropping shear lubrication or rotation changes the trajectory */
    run("no shear lubrication",
        "{\"scene\":\"two_spheres_shear\",\"d0\":0.1,\"law\":{\"terms\":{\"shear_lubrication\":"
        "false}}}",
        &o);
    double r = scene_value(&o, "min_gap") / g_ref;
    fails += scene_check(r < 0.1, "min gap / reference < 0.1", r, 0.1);
    scene_outcome_free(&o);
    run("no rotation", "{\"scene\":\"two_spheres_shear\",\"d0\":0.1,\"rotation\":false}", &o);
    r = scene_value(&o, "min_gap") / g_ref;
    fails += scene_check(fabs(r - 1) > 0.1, "|min gap / reference - 1| > 0.1", fabs(r - 1), 0.1);
    scene_outcome_free(&o);
    run("cut-off 2a", "{\"scene\":\"two_spheres_shear\",\"d0\":0.1,\"cutoff\":2}", &o);
    r = scene_value(&o, "min_gap") / g_ref;
    fails += scene_check(r < 0.9, "smaller cut-off, smaller min gap (ratio)", r, 0.9);
    scene_outcome_free(&o);
    scene_outcome_free(&ref);
    printf("%d failure(s)\n", fails);
    return fails != 0;
}
