/* Fast runs of the `resuspension` scene through resolve + run (scene_harness):
 *  - gradient and vorticity orientations (N = 200, strain 1): finish without NaN, the
 *    time-averaged profile integrates exactly to the solid volume per area (mass
 *    conservation of the slab binning), its maximum is a dense-suspension value, nothing
 *    went through the floor, Sh / I / Acrivos are reported consistently;
 *  - a light run whose particles reach the lid (lid reflections, no NaN);
 *  - a heavy run where the dilute region empties (no NaN, the bed does not expand), and its
 *    crushed-contact diagnostic at stiffness 1e4 and at the default, 100x stiffer.
 * Short strains: these are smoke tests of the machinery, not of the physics (label physics). */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "../scenes/scene_harness.h"

static int failures = 0;

static int near(double a, double b, double rel) { return fabs(a - b) <= rel * fabs(b); }

static void check_common(const scene_outcome *o, const char *tag, double sh, double inert)
{
    char what[160];
    snprintf(what, sizeof what, "%s: finished (rc 0)", tag);
    failures += scene_check(o->rc == 0, what, o->rc, 0);
    if (o->rc != 0) {
        fprintf(stderr, "%s: %s\n", tag, o->message);
        return;
    }
    const double inv = scene_value(o, "inventory"), vol = scene_value(o, "solid_volume");
    const double w = scene_value(o, "cell_width");
    snprintf(what, sizeof what, "%s: inventory = solid volume / area", tag);
    failures += scene_check(near(inv, vol / (w * w), 1e-9), what, inv, vol / (w * w));
    const double pmax = scene_value(o, "max_phi");
    snprintf(what, sizeof what, "%s: 0.3 < max phi < 0.66", tag);
    failures += scene_check(pmax > 0.3 && pmax < 0.66, what, pmax, 0.5);
    snprintf(what, sizeof what, "%s: no particle below the floor", tag);
    failures += scene_check(scene_value(o, "particles_below_floor") == 0.0, what,
                            scene_value(o, "particles_below_floor"), 0);
    snprintf(what, sizeof what, "%s: Shields number", tag);
    failures += scene_check(near(scene_value(o, "shields"), sh, 1e-12), what,
                            scene_value(o, "shields"), sh);
    snprintf(what, sizeof what, "%s: inertial number", tag);
    failures += scene_check(near(scene_value(o, "inertial_number"), inert, 1e-12), what,
                            scene_value(o, "inertial_number"), inert);
    const double h0 = scene_value(o, "settled_height");
    snprintf(what, sizeof what, "%s: Acrivos = 9/2 Sh a/h0", tag);
    failures += scene_check(near(scene_value(o, "acrivos"), 4.5 * sh / h0, 1e-12), what,
                            scene_value(o, "acrivos"), 4.5 * sh / h0);
    const double hs = scene_value(o, "suspension_height");
    snprintf(what, sizeof what, "%s: suspension height finite, between 0.5 h0 and the lid", tag);
    failures += scene_check(isfinite(hs) && hs > 0.5 * h0 && hs < scene_value(o, "lid_height"),
                            what, hs, h0);
    snprintf(what, sizeof what, "%s: finite kinetic energy", tag);
    failures += scene_check(isfinite(scene_value(o, "max_kinetic_energy")), what,
                            scene_value(o, "max_kinetic_energy"), 0);
}

int main(void)
{
    scene_outcome o;
    /* 1. gradient orientation (strong shear drag so that the bed is actually sheared) */
    scene_run_text("{\"scene\":\"resuspension\",\"n\":200,\"width\":12,\"strain\":1.0,"
                   "\"average_from\":0.5,\"sample_strain\":0.05,\"shields\":0.5,"
                   "\"inertial_number\":0.05,\"density_ratio\":10,\"shear_drag_viscosity\":3}",
                   NULL, &o);
    check_common(&o, "gradient", 0.5, 0.05);
    printf("gradient: height=%.3f max_phi=%.3f bulk_bins=%g wall_s=%.2f\n",
           scene_value(&o, "suspension_height"), scene_value(&o, "max_phi"),
           scene_value(&o, "bulk_bins"), o.wall_s);
    scene_outcome_free(&o);

    /* 2. vorticity orientation (Lees–Edwards in x-z) */
    scene_run_text("{\"scene\":\"resuspension\",\"n\":200,\"width\":12,\"strain\":1.0,"
                   "\"average_from\":0.5,\"sample_strain\":0.05,\"shields\":0.5,"
                   "\"inertial_number\":0.05,\"density_ratio\":10,\"orientation\":\"vorticity\"}",
                   NULL, &o);
    check_common(&o, "vorticity", 0.5, 0.05);
    printf("vorticity: height=%.3f max_phi=%.3f wall_s=%.2f\n",
           scene_value(&o, "suspension_height"), scene_value(&o, "max_phi"), o.wall_s);
    scene_outcome_free(&o);

    /* 3. light particles, low lid: particles reach the top */
    scene_run_text("{\"scene\":\"resuspension\",\"n\":200,\"width\":12,\"strain\":1.0,"
                   "\"average_from\":0.5,\"shields\":50,\"inertial_number\":0.05,"
                   "\"density_ratio\":200,\"lid_height\":1.0,\"shear_drag_viscosity\":3,"
                   "\"dilute_drag\":{\"viscosity\":0.1}}",
                   NULL, &o);
    failures += scene_check(o.rc == 0, "lid run finished", o.rc, 0);
    if (o.rc)
        fprintf(stderr, "lid run: %s\n", o.message);
    failures += scene_check(scene_value(&o, "lid_reflections") > 0, "lid reached",
                            scene_value(&o, "lid_reflections"), 1);
    failures += scene_check(isfinite(scene_value(&o, "suspension_height")),
                            "lid run: finite height", scene_value(&o, "suspension_height"), 0);
    printf("lid: reflections=%g height=%.3f wall_s=%.2f\n", scene_value(&o, "lid_reflections"),
           scene_value(&o, "suspension_height"), o.wall_s);
    scene_outcome_free(&o);

    /* 4. heavy particles: the dilute region empties completely */
    scene_run_text("{\"scene\":\"resuspension\",\"n\":200,\"width\":12,\"strain\":1.0,"
                   "\"average_from\":0.5,\"shields\":0.02,\"inertial_number\":0.05,"
                   "\"density_ratio\":1,\"stiffness\":1e4}",
                   NULL, &o);
    failures += scene_check(o.rc == 0, "heavy run finished", o.rc, 0);
    if (o.rc)
        fprintf(stderr, "heavy run: %s\n", o.message);
    const double hs = scene_value(&o, "suspension_height");
    const double hi = scene_value(&o, "initial_height");
    failures += scene_check(isfinite(hs) && hs < hi, "heavy run: bed compacts", hs, hi);
    failures += scene_check(scene_value(&o, "particles_below_floor") == 0.0,
                            "heavy run: floor holds", scene_value(&o, "particles_below_floor"), 0);
    /* crushed asperities: at Sh = 0.02 the bed weight far exceeds alpha g eps a at
     * stiffness 1e4 (measured 0.95 of the contacts crushed); the default stiffness 1e6 must crush
     * far fewer (measured 0.08): the diagnostic follows the physics, not only its range */
    const double crushed_soft = scene_value(&o, "crushed_contact_fraction");
    failures +=
        scene_check(crushed_soft > 0.5 && crushed_soft <= 1.0,
                    "heavy run: most contacts crushed at stiffness 1e4", crushed_soft, 0.95);
    printf("heavy: height=%.3f initial=%.3f crushed=%.3f wall_s=%.2f\n", hs, hi, crushed_soft,
           o.wall_s);
    scene_outcome_free(&o);
    scene_run_text("{\"scene\":\"resuspension\",\"n\":200,\"width\":12,\"strain\":1.0,"
                   "\"average_from\":0.5,\"shields\":0.02,\"inertial_number\":0.05,"
                   "\"density_ratio\":1}",
                   NULL, &o);
    failures += scene_check(o.rc == 0, "default-stiffness heavy run finished", o.rc, 0);
    const double crushed_stiff = scene_value(&o, "crushed_contact_fraction");
    failures +=
        scene_check(crushed_stiff < 0.2 && crushed_stiff < crushed_soft,
                    "default-stiffness heavy run: few contacts crushed", crushed_stiff, 0.08);
    printf("heavy stiff: crushed=%.3f wall_s=%.2f\n", crushed_stiff, o.wall_s);
    scene_outcome_free(&o);

    /* 5. spec validation: the floor must not let the smallest particle through */
    scene_run_text("{\"scene\":\"resuspension\",\"radius_std\":0.1,\"floor\":{\"radius\":2,"
                   "\"jitter\":0.3}}",
                   NULL, &o);
    failures += scene_check(o.rc == 2 && strstr(o.message, "/floor/radius") != NULL,
                            "permeable floor rejected", o.rc, 2);
    scene_outcome_free(&o);
    scene_run_text("{\"scene\":\"resuspension\",\"strain\":5,\"average_from\":5}", NULL, &o);
    failures += scene_check(o.rc == 2, "average_from >= strain rejected", o.rc, 2);
    scene_outcome_free(&o);

    if (failures) {
        fprintf(stderr, "%d failure(s)\n", failures);
        return 1;
    }
    printf("resuspension_scene=ok\n");
    return 0;
}
