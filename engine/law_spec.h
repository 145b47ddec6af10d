/* law_spec.h — reading the contact-law part of a job spec into lub_law_params (shared by every
 * scene that uses the lubricated contact law).
 *
 * The law object of a spec (usually the member "law") holds only DIMENSIONLESS parameters:
 *
 *   "eps"      roughness, PHYSICAL convention: contact when the gap u < eps*a (>= 0).
 *              A seed/Yade value eps_Y corresponds to eps = 2*eps_Y (physics-reference §6).
 *   "alpha"    k_n/g, asperity-to-bulk stiffness ratio (> 0; the paper and Yade use 1)
 *   "kt_ratio" k_t/g, tangential-to-bulk stiffness ratio (>= 0)
 *   "mu"       Coulomb friction coefficient of rough contacts (>= 0)
 *   "terms"    {"normal_lubrication","shear_lubrication","roll","twist","friction"}: booleans
 *
 * The scales (viscosity eta and bulk stiffness g) are set by the scene from its own
 * dimensionless groups with lub_law_spec_scale(). Which members exist is chosen by the scene
 * (lub_law_spec_opts): members the scene does not use are rejected as unknown, so a resolved
 * spec never shows a parameter that has no effect.
 *
 * Errors: JSON pointer + constraint in *err (spec_reader.h); functions return 0 or -1.
 * Ownership: nothing keeps a reference to the json objects. No global state.
 */
#ifndef LUBDEM_LAW_SPEC_H
#define LUBDEM_LAW_SPEC_H

#include <jansson.h>

#include "contact_law.h"
#include "spec_reader.h"

typedef struct {
    unsigned allowed_terms; /* LUB_TERM_* the scene can use; only these appear in "terms" */
    unsigned default_terms; /* default value of each allowed term (bit set = on) */
    int tangential;         /* 1: the members "kt_ratio" and "mu" exist */
    double default_eps, default_alpha, default_kt_ratio, default_mu;
} lub_law_spec_opts;

typedef struct {
    lub_law_params params; /* eps, alpha, mu, terms set; eta, k_bulk, k_t set by _scale() */
    double kt_ratio;       /* k_t/g (0 when the scene has no tangential motion) */
} lub_law_spec;

/* Validates the law object `law` (JSON pointer `ptr`) in place, inserts defaults, rejects
 * unknown members (also inside "terms") and fills *out. Returns 0 or -1 with *err set. */
int lub_law_spec_resolve(json_t *law, const char *ptr, const lub_law_spec_opts *opts,
                         lub_law_spec *out, lub_error *err);

/* Sets the dimensional scales: params.eta = eta, params.k_bulk = k_bulk,
 * params.k_t = kt_ratio * k_bulk. */
void lub_law_spec_scale(lub_law_spec *s, double eta, double k_bulk);

/* JSON spec key of one LUB_TERM_* bit ("normal_lubrication", ...), NULL if not a single term. */
const char *lub_law_term_key(unsigned term);

/* Many-particle scenes: pairs are listed within u_n <= cutoff a_ij, so a roughness at or
 * beyond the cut-off would put pairs in contact that are never listed (and every listed pair
 * in contact from its first step, with the asperity force of the whole overlap). Returns 0
 * when eps < cutoff, or -1 with *err naming `ptr`/eps. */
int lub_law_spec_check_cutoff(const lub_law_spec *l, const char *ptr, double cutoff,
                              lub_error *err);

/* Appends the spec keys of the terms set in `terms` to the JSON array `arr` (summary
 * "active_terms"). Returns 0, or -1 if arr is not an array. */
int lub_law_terms_append(json_t *arr, unsigned terms);

#endif
