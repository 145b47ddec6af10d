/* resuspension_analysis.h — from a steady concentration profile phi(y) to normal viscosities
 * (seed 000, resuspension article eq. 3–6; ../shared/spec/physics-reference.md §4).
 *
 * Dimensionless units: lengths in units of the mean radius a, viscosities in units of the
 * fluid viscosity eta. The profile is binned along the gravity direction: bin i covers
 * [y0 + i*dy, y0 + (i+1)*dy] and holds the cell-averaged volume fraction phi[i] with its
 * standard error phi_err[i] (NULL if unknown). The errors these functions propagate from
 * phi_err hold only for statistically independent bins. The bins of a sampled suspension are
 * not: a sphere spans several bins and the inventory is fixed, so the propagated error can be
 * too large (next to the floor, where eta_ii is the fixed inventory, it is the largest while the
 * true error is ~0) or too small (in the bulk, where neighbouring bins fluctuate together); it
 * is neither a lower nor an upper bound. The scene does not use it: resuspension_statistics.c
 * takes the standard error of each bin's series of per-sample eta_ii and coarse phi.
 *
 * All functions are pure: no allocation, no global state. Errors: a function that cannot
 * produce a value returns NAN (documented per function).
 */
#ifndef LUBDEM_RESUSPENSION_ANALYSIS_H
#define LUBDEM_RESUSPENSION_ANALYSIS_H

/* Shields number Sh = eta gd / (drho g a) (eq. 4) and Acrivos number
 * A = (9/2) eta gd / (drho g h0) = (9/2) Sh a / h0. */
double lub_shields_number(double eta, double shear_rate, double drho, double g, double a);
double lub_acrivos_number(double eta, double shear_rate, double drho, double g, double h0);

/* Normal viscosity profile from eq. 6: eta_ii(y) = (1/Sh) * integral_y^inf phi(y') dy',
 * evaluated at the bin centres (the bin's own half-width included). eta_err may be NULL;
 * otherwise it receives the propagated standard errors (needs phi_err). */
void lub_profile_normal_viscosity(const double *phi, const double *phi_err, int n, double dy,
                                  double shields, double *eta, double *eta_err);

/* Particle inventory: integral of phi dy over the profile (a length: the height of the bed
 * if it were packed at phi = 1). */
double lub_profile_inventory(const double *phi, int n, double dy);

/* Height of the suspension: the highest y at which phi crosses `phi_level` going down
 * (linear interpolation between bin centres). NAN if phi never reaches phi_level. */
double lub_profile_height(const double *phi, int n, double y0, double dy, double phi_level);

/* Base of the bed: the lowest y at which phi crosses `phi_level` going up (linear interpolation
 * between the centres of the bins below and at the first bin with phi >= phi_level; the centre
 * of bin 0 if that bin is already at the level). NAN if phi never reaches phi_level. With
 * phi_level = max(phi)/2 it is the y_b of tests/resuspension/resuspension_consistency.py
 * (half_max_crossings), the same arithmetic: the spheres rest on the floor's, whose centres are
 * at y0, so the bed starts ~1.1 a above y0. */
double lub_profile_base(const double *phi, int n, double y0, double dy, double phi_level);

/* The interface-discarding rule (documented in README, Scene `resuspension`, *Observables*,
 * `bulk_mask`; the scene's defaults: spec /analysis): the
 * interface is at y_int = lub_profile_height(phi, ..., phi_level = phi_half) with
 * phi_half = 0.5 * max(phi); bins whose centre is above y_int - interface_width (default 5a,
 * the width over which the seed's profiles fall from ~0.5 to 0) are flagged as interface
 * bins, as are bins whose centre is closer than floor_skip to y0 (layering at the floor) and
 * bins with phi below phi_min. keep[i] = 1 for bins kept for eta_ii(phi). Returns the number
 * of kept bins. */
int lub_profile_select_bulk(const double *phi, int n, double y0, double dy, double interface_width,
                            double floor_skip, double phi_min, int *keep);

/* Coarse-grained profile: phi_cg[i] is the mean of phi over the window of total width `width`
 * centred on bin i (bin j enters with the length of its overlap with the window; the window
 * is cut at the ends of the profile and the weights renormalised), and phi_cg_err[i] the
 * error of that mean for independent bins, sqrt(sum (w_j phi_err[j])^2) (NAN if an error that
 * enters is not finite; phi_err and phi_cg_err may be NULL). width <= dy copies phi.
 * Why: next to the floor the suspension is layered, and 0.5 a bins see phi oscillate by
 * +-0.05 with a period of one diameter while eta_ii(y), an integral, does not; pairing the
 * raw bin phi with eta_ii biases eta_ii(phi) low at the dense end (the densest bins are layer
 * peaks). The continuum quantity is phi averaged over at least one diameter (width 2 a). */
void lub_profile_coarse_grain(const double *phi, const double *phi_err, int n, double dy,
                              double width, double *phi_cg, double *phi_cg_err);

/* phi_cg[i] of lub_profile_coarse_grain alone (the same arithmetic). */
double lub_profile_coarse_bin(const double *phi, int n, double dy, double width, int i);

#endif
