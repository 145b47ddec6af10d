/* shear_run_checks.h — advisory checks of a finished simple_shear run.
 *
 * The summary of a run says whether its numbers can be read as the suspension's steady,
 * rigid-particle, viscous-limit rheology. Each check compares one steady-state mean with the
 * threshold that the measurements behind the README's simple_shear section (record:
 * tests/shear/README.md) found necessary, and explains how to fix the spec. The checks are
 * advisory: they never change a result or the exit code.
 *
 * Pure functions; no I/O, no allocation. */
#ifndef LUBDEM_SHEAR_RUN_CHECKS_H
#define LUBDEM_SHEAR_RUN_CHECKS_H

#include <stddef.h>

/* Steady-state means of one run (NaN where the run has no value; a NaN or infinite value skips
 * its check). */
typedef struct {
    double elastic_number; /* El = g/(<P> a): bulk stiffness over the mean particle pressure,
                              i.e. `stiffness` * s0 / <P> (s0 = eta gd or the imposed P) */
    double kinetic_share;  /* |<sigma_xy kinetic>| / |<sigma_xy>| */
    double kinetic_share_pressure; /* |<sigma_yy kinetic>| / |<sigma_yy>| */
    double crushed_fraction;       /* <crushed_contact_fraction> */
    double bond_order_q6;          /* <bond_order_q6> */
    double bond_order_random;      /* Q6 of random bond directions, 1/sqrt(mean bonds per sample)
                                      (NaN: not known) */
    double lost_pairs;             /* active pair states lost at neighbour-list rebuilds (count) */
    int steady;                    /* 1 if the steady state was detected */
    double steady_samples;         /* samples in the steady window (0: the run ended inside the
                                      transient) */
    double strain_reached;         /* strain at the end of the run */
    int stopped;                   /* 1: a signal stopped the run before /strain (its steady-state
                                      advice is then --resume, not a longer /strain) */
    int failed;                    /* 1: the run failed (a numerical or internal error) before
                                      /strain: raising /strain is not the advice */
    double strain_target;          /* the spec's /strain (for the stopped run's message) */
    int checkpoint_kept;           /* a stopped run has a checkpoint to go on from (its own, the
                                      one it continued from, or a periodic one) */
    double transient_strain;       /* the spec's /transient_strain */
    double sample_strain;          /* the spec's /sample_strain (0: not known) */
    double dt_over_elastic;        /* a time step fixed by the spec's /dt, over dt_elastic
                                      (sqrt(min(m/g, I/(k_t r^2)))); 0 when /dt_safety set it */
    double dt_over_stiffness;      /* a time step fixed by the spec's /dt, over the smallest
                                      many-partner bound lub_pairs_stiffness_dt met at a neighbour-list
                                      rebuild (step_stiffness.h); 0 when the step was automatic */
    double phi_imposed;            /* the imposed solid fraction (control volume; NaN or 0 under
                                      pressure control, where phi is free and cannot jam) */
    double phi_jamming;        /* the seed's jamming fraction phi_m(mu_m) of physics-reference §2
                                  for the spec's friction (0 or NaN: not checked) */
    double mu_m;               /* the spec's friction coefficient (for the message) */
    double pressure_ratio;     /* imposed pressure: steady mean of -sigma_yy over the imposed P
                                  (NaN at imposed volume) */
    double pressure_ratio_sem; /* its standard error (NaN: unknown) */
    double pressure_rms_ratio; /* imposed pressure: rms of -sigma_yy about its steady mean, over
                                  that mean (NaN at imposed volume or without samples) */
    double headline;           /* steady mean of the headline: mu (imposed pressure) or eta_r */
    double headline_law;       /* the §2 law's value at the run's Iv or phi (0 or NaN: none) */
    int headline_is_mu;        /* 1: headline is mu (imposed pressure), 0: eta_r */
    double phi_mean;           /* imposed pressure: steady mean of phi (NaN at imposed volume) */
    double phi_law;            /* imposed pressure: the §2 law's phi_m/(1 + Iv^1/2) (0 or
                                  NaN: none) */
    int article_set;           /* 1 when the run uses the interaction set the §2 law was fitted
                                  with (lubrication_pairs "delaunay", no roll/twist torque) */
    double headline_sem;       /* the headline's standard error (NaN: unknown) */
    double target_rel_error;   /* the spec's /target_rel_error (0: none) */
    double headline_rel_bound; /* the 90 % upper bound of headline_sem / |headline| that the
                                  stop tests (NaN: unknown) */
    int stopped_on_target;     /* 1: the run stopped on it */
    int target_zero_mean;      /* 1: the headline averaged 0 (the scene says so itself) */
    double pdf_first_strain;   /* strain of the first microstructure snapshot averaged into
                                  /profiles (NaN: none) */
    double steady_from_strain; /* strain where the detected steady window starts (NaN: none) */
} lub_shear_run_state;

/* Thresholds and why (tests/shear/README.md, sections named):
 * - El below 5e3: not the rigid limit. At imposed phi = 0.55, El = 1.6e3 gave eta_r 16 % low,
 *   and the frictionless phi at Iv = 1e-4 was 0.007 high at El = 1e3; eta_r and phi are flat
 *   from El ~ 5e3 on ("Asymptotic regime").
 * - Kinetic stress above 1 % of sigma_xy or of -sigma_yy: the seed's own bound on inertia
 *   (physics-reference §2). Below it the contacts can still ring ("Contact-scale inertia"), so
 *   passing this check does not prove the viscous limit; a rerun at St/10 does. The pressure
 *   share is checked too because the pressure and the normal-stress ratios are headline
 *   observables and the kinetic stress loads them more: elastic contacts without lubrication
 *   or friction (every law term off, N = 300, phi 0.5) carried 0.84 % of sigma_xy but 7.2 % of
 *   the pressure, while the runs of the committed table's kind keep both below 0.11 %
 *   (N = 300: Iv 1, 1e-4 and phi 0.35).
 * - Crushed contacts above 1 % (u_n < -alpha eps a): the asperity model no longer holds and the
 *   results depend on the stiffness (README "Stiffness"). The resuspension scene's warning
 *   uses the same constant.
 * - Bond order Q6 above 0.1: the cell orders. Disordered runs give 0.04-0.09, the small
 *   frictionless cells that partly order 0.10-0.17 ("Frictionless dilatancy is too weak").
 *   With few bonds Q6 is noise: random directions give 1/sqrt(bonds) (bond_order.h), so the
 *   threshold is at least LUB_SHEAR_Q6_NOISE times that (phi = 0.05, N = 300: Q6 0.168 from
 *   a few tens of bonds per sample, which warned that a gas was ordering).
 * - Any lost pair state: a contact restarted without its history ("Robustness").
 * - A fixed /dt above dt_elastic: beyond what /dt_safety (at most 1) allows; the contacts are
 *   not resolved. dt = 0.01 (70 dt_elastic, N = 300, phi 0.5) completed without a NaN but
 *   lost 17 793 pair states in 2 strain.
 * - A fixed /dt within dt_elastic but above LUB_SHEAR_DT_STIFFNESS_MAX times the
 *   many-partner bound of step_stiffness.h: the automatic step never goes there
 *   (/dt_stiffness_safety, default LUB_DT_STIFFNESS_SAFETY), and runs blew up from 1.22
 *   (light, soft spheres; README simple_shear, Method).
 * - No steady state detected: the means include the transient or a drift; or the run ended
 *   before /transient_strain and has no steady-state means at all (null in the summary);
 *   when the run went on after the transient for less than one /sample_strain, that is
 *   the member named (raising /strain is no cure when /sample_strain is 10 and /strain 0.01).
 * - An imposed phi at or above the seed's phi_m(mu_m) (uncertain by ~0.01; this engine's phi
 *   at Iv = 1e-3 is 0.003-0.005 below the law at mu_m = 0.5, README simple_shear, so it jams
 *   below phi_m too): rigid spheres cannot flow, the stress follows the stiffness, and the El
 *   and crushed-contact warnings would advise a stiffer run, which only raises the stress
 *   (phi = 0.6, mu_m = 0.5, N = 300: El 80, 64 % crushed). This warning replaces those two and
 *   quotes their values.
 * - Imposed pressure not held: the steady mean of -sigma_yy more than 10 % (and 3 standard
 *   errors) from the imposed P. The default servo holds it within 2.1 % in every
 *   imposed-pressure run of the committed table (Iv / Iv_meas - 1), and the servo study's gains
 *   0.25-4 and filters 0.01-0.25 strain kept phi and mu within 1.2 combined standard errors of
 *   the default's; gain 100 with a 1e-4 filter switches between its clamps, and its
 *   samples, all taken in the dilating phase, read -19 P (N = 300, Iv = 0.01):
 *   results at no defined Iv. An El from a mean pressure <= 0 means nothing and is not
 *   checked. Without a detected steady state the pressure may simply not have been reached
 *   yet (Iv = 10, St = 10, strain 2: 58.8 P from 26 samples without an error bar); the
 *   message then advises a longer run first. A mean known only to more than 10 % (its standard
 *   error) is not held either, whatever its distance from P: a servo switching between its
 *   clamps (Iv 10, St 0.1, N = 300, default servo and step) read 1.31 +- 0.56 P and passed the
 *   3-standard-error gate (until 2026-12-07).
 * - The servo oscillating: -sigma_yy fluctuating by more than LUB_SHEAR_SERVO_PRESSURE_RMS_MAX
 *   (50 %) rms about its steady mean. The default servo gives 2.6-6.8 % at N = 300, Iv 1-0.01
 *   (servo study; 3.2-12 % in single runs at Iv 1-1e-3, 26 % at Iv 1e-4), imposed volume
 *   23-33 %. The servo's
 *   own dilation raises a viscous pressure that grows with gain Iv; with the step too long to
 *   resolve that loop it switches between its clamps (Iv 10, St 0.1, default servo and step:
 *   +-70 P every 8 steps, 2740 % rms, mu 24.3 where 17-19 is right; dt_safety 0.03 cures it),
 *   and Iv 1, St 10 gives 390 %: the oscillation, not the suspension, sets the stress. Until
 *   2026-12-07 no warning said so.
 * - Headline off the §2 law with another interaction set than the law's: the summary quotes
 *   the law as `ref`, but the law was fitted with the seed article's set (Delaunay
 *   lubrication, no roll/twist torque; README "Where we disagree" 7). With the defaults
 *   (cut-off 2 a, roll/twist) eta_r(0.45) is 28.0 +- 0.9 against the law's 13.1 (N = 300,
 *   10 strain; 22.2 without roll/twist; the article's set: 14.0 in the committed table, 14.6
 *   with its set before 2026-12-07) and mu is 17-31 % high: a user comparing `value` with
 *   `ref` should know which set the law speaks for. Fires when the
 *   steady headline (mu, or eta_r) is off by more than the tolerance (10 %, 15 %) or
 *   phi by more than 0.015; the article's set's own misses (eta_r at 0.55, mu at Iv = 1) are
 *   listed in the README and not warned (there is no member to change).
 * - The microstructure averaged from before the detected steady state: /profiles mixes the
 *   transient into its maps (they average every snapshot from /microstructure/start_strain,
 *   which the scene cannot know to be steady before the run ends); until 2026-12-07 nothing
 *   said so. */
#define LUB_SHEAR_EL_MIN 5e3
#define LUB_SHEAR_KINETIC_SHARE_MAX 1e-2
#define LUB_CRUSHED_CONTACT_FRACTION_MAX 1e-2
#define LUB_SHEAR_Q6_MAX 0.1
#define LUB_SHEAR_Q6_NOISE 3.0
#define LUB_SHEAR_DT_OVER_ELASTIC_MAX 1.0
#define LUB_SHEAR_DT_STIFFNESS_MAX 1.0

#define LUB_SHEAR_PRESSURE_DEVIATION_MAX 0.1
#define LUB_SHEAR_SERVO_PRESSURE_RMS_MAX 0.5
/* The tolerances against the §2 law (physics suite, tests/shear/run_physics.py). */
#define LUB_SHEAR_LAW_MU_TOL 0.10
#define LUB_SHEAR_LAW_ETA_TOL 0.15
#define LUB_SHEAR_LAW_PHI_TOL 0.015

/* at most 11 at once: the jamming warning replaces two, the law's and the microstructure
 * window's need a steady state and the steady state's a run without one (12 leaves one spare;
 * add_warning drops any beyond) */
enum { LUB_SHEAR_WARNINGS_MAX = 12, LUB_SHEAR_WARNING_LEN = 400 };
/* A run that ends less than this strain after /transient_strain is told to raise /strain,
 * not to lower /sample_strain: 10 samples at the smallest /sample_strain (1e-4) */
#define LUB_SHEAR_SAMPLE_SPAN_MIN 1e-3

/* Writes one message per failed check into out[0..], each naming what failed (with its value
 * and threshold, where the check has them) and the spec member to change (a JSON pointer).
 * Returns the number written (0..LUB_SHEAR_WARNINGS_MAX). */
int lub_shear_run_warnings(const lub_shear_run_state *st,
                           char out[LUB_SHEAR_WARNINGS_MAX][LUB_SHEAR_WARNING_LEN]);

#endif
