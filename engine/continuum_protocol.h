/* continuum_protocol.h — piecewise shear protocols for the texture model (the 0-D
 * "rheometer"): startup, reversal, pause, steps, at imposed shear rate or shear stress.
 *
 * Method (note §2.1-2.2, §5 N3): within a segment the sign of gd is constant, so the state is
 * the exact strain-space solution lub_texture_advance(); segments split the protocol at every
 * sign change (event location is exact). Imposed rate: t = gamma/|gd|. Imposed stress sigma:
 * sgn(gd) = sgn(sigma) and gd = sigma/eta_app (generalised (3.20)); the curve eta_app(gamma) is
 * the imposed-rate one and only the time map changes, t(gamma) = int eta_app(gamma')/|sigma|
 * dgamma', evaluated with composite 5-point Gauss–Legendre quadrature on panels of strain
 * 0.1/max(delta1, sqrt(1 - a^2)) (the solution's own decay and oscillation scales; relative error
 * < 1e-12), switching to the exact linear map once the transient has decayed (delta1 * gamma >
 * 40). Where the transient outlives 4096 panels (sqrt(1 - a^2) > 10 delta1) the panels are summed
 * by doubling (the deviation from the steady state is a free linear evolution and eta_app is
 * quadratic in it), so that the work per call is bounded: at most ~4400 panels and O(log^2) 3 x 3
 * products, whatever the strain or delta1. A segment that ends after a duration under imposed
 * stress finds its strain by binary lifting on the doubled panels, then Newton in one panel. sigma
 * = 0 freezes the state (like a pause). OSCILLATION (LAOS at imposed rate): the sign changes at
 * every half period t = k/(2f) are located exactly; within half period k the strain is (A/omega)(1
 * - cos omega tau) and the state is again the exact strain solution. If eta_app <= 0 is met under
 * imposed stress (possible for strongly non-steady gamma_e with negative beta3, delta2; note §5 N2)
 * the run stops with an error.
 *
 * Pure: no allocation; samples go to a caller-supplied sink.
 */
#ifndef LUBDEM_CONTINUUM_PROTOCOL_H
#define LUBDEM_CONTINUUM_PROTOCOL_H

#include "continuum_texture.h"

typedef enum {
    LUB_SEG_RATE = 0,
    LUB_SEG_STRESS = 1,
    LUB_SEG_PAUSE = 2,
    LUB_SEG_OSCILLATION = 3 /* gd = value sin(2 pi frequency t), t from the segment start */
} lub_seg_mode;

typedef struct {
    lub_seg_mode mode;
    double value;     /* RATE: gd in 1/s (nonzero); STRESS: sigma_xy in Pa; PAUSE: unused;
                         OSCILLATION: rate amplitude in 1/s (> 0) */
    double strain;    /* > 0: the segment ends after this strain int|gd|dt; 0: use duration
                         (PAUSE and OSCILLATION always use duration) */
    double duration;  /* s, > 0 when strain == 0 */
    double frequency; /* OSCILLATION: Hz (> 0); unused otherwise */
} lub_segment;

typedef struct {
    int segment;       /* index of the segment that produced the sample */
    double time;       /* s since the start of the protocol */
    double strain;     /* accumulated int |gd| dt */
    double gd;         /* 1/s (0 in a pause) */
    double sigma_xy;   /* Pa */
    double n1, n2, pp; /* Pa */
    double eta_app;    /* Pa.s; in a pause: the value for the last direction of motion */
    lub_texture_state g;
    lub_texture_micro micro;
} lub_rheo_sample;

/* Return 0 to continue, nonzero to stop the run (e.g. on a stop request). */
typedef int (*lub_rheo_sink)(void *user, const lub_rheo_sample *s);

typedef struct {
    int segment;   /* where it failed */
    double strain; /* total strain at failure */
    char message[256];
} lub_rheo_error;

/* Runs the protocol from state g0; s0 = +1/-1 is the direction used to report eta_app before
 * any motion. samples >= 2 per segment (uniform in strain, or in time for a pause; the first
 * sample of a segment repeats the instant of the previous segment's last sample so that jumps
 * of the stress show). Returns 0 when done, 1 if the sink stopped it, -1 on a numerical failure
 * (err filled). Segments must be valid (checked by the caller's spec validation). */
int lub_rheo_run(const lub_texture_params *p, lub_texture_state g0, int s0, const lub_segment *segs,
                 int nseg, int samples, lub_rheo_sink sink, void *user, lub_rheo_error *err);

/* Imposed stress |sigma| > 0 at sign s from state g0: time needed to accumulate strain dgamma
 * (returns -1 with *gamma_bad = the strain where eta_app <= 0 was met). */
int lub_rheo_time_for_strain(const lub_texture_params *p, int s, lub_texture_state g0,
                             double sigma_abs, double dgamma, double *t, double *gamma_bad);
/* Inverse: strain accumulated in time t (same failure convention). */
int lub_rheo_strain_for_time(const lub_texture_params *p, int s, lub_texture_state g0,
                             double sigma_abs, double t, double *dgamma, double *gamma_bad);

#endif
