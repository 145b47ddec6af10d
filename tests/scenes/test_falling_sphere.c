/* test_falling_sphere.c — falling_sphere against the seed's analytic results
 * (physics-reference §1a): viscous rigid exponential, rough equilibrium gap, smooth spheres
 * down to gaps < 1e-12 a, regime spot checks, and a negative test (no lubrication). */
#include <math.h>
#include <stdio.h>

#include "scene_harness.h"

static int fails = 0;

static int run(const char *label, const char *spec, scene_outcome *o)
{
    scene_run_text(spec, NULL, o);
    printf("-- %s: rc=%d wall=%.3fs %s\n", label, o->rc, o->wall_s, o->message);
    if (o->rc != 0)
        fails++;
    return o->rc;
}

static void regime_is(const char *spec, int want, const char *label)
{
    scene_outcome o;
    run(label, spec, &o);
    double code = scene_value(&o, "regime_code");
    printf("   bounces=%g oscillations=%g late_swing=%g\n", scene_value(&o, "bounces"),
           scene_value(&o, "oscillations"), scene_value(&o, "late_swing"));
    fails += scene_check(code == want, label, code, want);
    scene_outcome_free(&o);
}

int main(void)
{
    scene_outcome o;
    /* 1. viscous rigid limit, smooth: u = u0 exp(-(8/9) t/tau_c) within 1e-3 over >= 5 tau_c */
    run("viscous rigid, eps=0, 6 tau_c",
        "{\"scene\":\"falling_sphere\",\"St\":0.01,\"stiffness\":1e4,\"duration\":6}", &o);
    fails += scene_check(scene_value(&o, "exp_max_rel_dev") < 1e-3, "max |u/u_exp - 1|",
                         scene_value(&o, "exp_max_rel_dev"), 1e-3);
    fails += scene_check(scene_value(&o, "exp_window_end") >= 5.0, "window end [tau_c]",
                         scene_value(&o, "exp_window_end"), 5.0);
    fails += scene_check(scene_value(&o, "exp_rate_rel_error") < 1e-3, "fitted rate vs 8/9",
                         scene_value(&o, "exp_rate_rel_error"), 1e-3);
    scene_outcome_free(&o);

    /* 2. rough spheres settle at u_eq = eps a - m g/k_n (K = 100) within 1e-6 */
    run("rough eps=0.01 K=100",
        "{\"scene\":\"falling_sphere\",\"St\":0.01,\"K\":100,\"duration\":8,\"law\":{\"eps\":0.01}"
        "}",
        &o);
    fails += scene_check(scene_value(&o, "equilibrium_gap_rel_error") < 1e-6,
                         "|u_end/u_eq - 1| (u_eq = 0.0099)",
                         scene_value(&o, "equilibrium_gap_rel_error"), 1e-6);
    fails += scene_check(scene_value(&o, "exp_max_rel_dev") < 1e-3, "exponential before contact",
                         scene_value(&o, "exp_max_rel_dev"), 1e-3);
    fails +=
        scene_check(fabs(scene_value(&o, "equilibrium_gap") / 0.0099 - 1) < 1e-6,
                    "equilibrium_gap reported (K > 1)", scene_value(&o, "equilibrium_gap"), 0.0099);
    scene_outcome_free(&o);
    /* alpha != 1: u_eq = eps - 1/(alpha G) = 0.01 - 1/(2 * 2500) = 0.0098 */
    run("rough eps=0.01 alpha=2 stiffness=2500",
        "{\"scene\":\"falling_sphere\",\"St\":0.01,\"stiffness\":2500,\"duration\":8,"
        "\"law\":{\"eps\":0.01,\"alpha\":2}}",
        &o);
    fails +=
        scene_check(fabs(scene_value(&o, "final_gap") / 0.0098 - 1) < 1e-6, "|u_end/0.0098 - 1|",
                    fabs(scene_value(&o, "final_gap") / 0.0098 - 1), 1e-6);
    scene_outcome_free(&o);

    /* K < 1: no static equilibrium; in contact the gap decays with the apparent weight
     * m g - k_n eps a, i.e. at the rate (8/9)(1 - K) */
    run("rough eps=0.01 K=0.5 (no equilibrium)",
        "{\"scene\":\"falling_sphere\",\"St\":0.01,\"K\":0.5,\"duration\":30,"
        "\"law\":{\"eps\":0.01}}",
        &o);
    {
        double r = scene_value(&o, "contact_rate"), want = 8.0 / 9.0 * 0.5;
        fails +=
            scene_check(fabs(r / want - 1) < 1e-3, "contact rate vs (8/9)(1-K) = 0.4444", r, want);
    }
    /* no equilibrium, so no equilibrium gap: null (until 2026-12-07 the final gap) */
    fails += scene_check(isnan(scene_value(&o, "equilibrium_gap")), "equilibrium_gap null (K < 1)",
                         scene_value(&o, "equilibrium_gap"), NAN);
    scene_outcome_free(&o);

    /* 3. smooth spheres to gaps < 1e-12 a: no NaN (rc 0), gap > 0, rate kept */
    run("smooth, 33 tau_c", "{\"scene\":\"falling_sphere\",\"St\":0.01,\"duration\":33}", &o);
    fails += scene_check(scene_value(&o, "min_gap") < 1e-12 && scene_value(&o, "min_gap") > 0,
                         "min gap in (0, 1e-12)", scene_value(&o, "min_gap"), 1e-12);
    fails += scene_check(scene_value(&o, "exp_window_end") > 32.9, "exponential until the end",
                         scene_value(&o, "exp_window_end"), 32.9);
    fails += scene_check(scene_value(&o, "exp_rate_rel_error") < 1e-3, "fitted rate vs 8/9",
                         scene_value(&o, "exp_rate_rel_error"), 1e-3);
    fails += scene_check(scene_value(&o, "exp_max_rel_dev") < 2e-3, "max |u/u_exp - 1|",
                         scene_value(&o, "exp_max_rel_dev"), 2e-3);
    fails += scene_check(isnan(scene_value(&o, "equilibrium_gap")),
                         "equilibrium_gap null (smooth: eps 0)", scene_value(&o, "equilibrium_gap"),
                         NAN);
    scene_outcome_free(&o);

    /* 4. negative test: without normal lubrication the sphere falls freely, no exponential */
    run("no lubrication (negative)",
        "{\"scene\":\"falling_sphere\",\"St\":0.01,\"duration\":2,"
        "\"law\":{\"terms\":{\"normal_lubrication\":false}}}",
        &o);
    fails += scene_check(!(scene_value(&o, "exp_window_end") >= 1.0),
                         "leaves the exponential before 1 tau_c", scene_value(&o, "exp_window_end"),
                         1.0);
    scene_outcome_free(&o);

    /* 5. regimes (seed fig. 4-5): low St damped; stiff + high St bouncing; soft oscillating */
    regime_is("{\"scene\":\"falling_sphere\",\"St\":0.01,\"K\":100,\"duration\":10,"
              "\"law\":{\"eps\":0.01}}",
              0, "St=0.01 K=100: damped (0)");
    regime_is("{\"scene\":\"falling_sphere\",\"St\":0.01,\"K\":10,\"duration\":10,"
              "\"law\":{\"eps\":0.01}}",
              0, "St=0.01 K=10: damped (0)");
    regime_is("{\"scene\":\"falling_sphere\",\"St\":1,\"K\":0.1,\"duration\":20,"
              "\"law\":{\"eps\":0.01}}",
              1, "St=1 K=0.1: oscillating (1)");
    regime_is("{\"scene\":\"falling_sphere\",\"St\":10,\"K\":10,\"duration\":200,"
              "\"law\":{\"eps\":0.01}}",
              2, "St=10 K=10: bouncing (2)");
    regime_is("{\"scene\":\"falling_sphere\",\"St\":1000,\"K\":100,\"duration\":20000,"
              "\"law\":{\"eps\":0.01}}",
              2, "St=1000 K=100: bouncing (2)");
    printf("%d failure(s)\n", fails);
    return fails != 0;
}
