/* law_spec.c — the "law" object of a spec -> lub_law_params (see law_spec.h). */
#include "law_spec.h"

#include <stddef.h>
#include <stdio.h>

static const struct {
    unsigned bit;
    const char *key;
} term_keys[] = {
    {LUB_TERM_NORMAL_LUB, "normal_lubrication"},
    {LUB_TERM_SHEAR_LUB, "shear_lubrication"},
    {LUB_TERM_ROLL, "roll"},
    {LUB_TERM_TWIST, "twist"},
    {LUB_TERM_FRICTION, "friction"},
};
enum { N_TERMS = (int)(sizeof term_keys / sizeof term_keys[0]) };

const char *lub_law_term_key(unsigned term)
{
    for (int i = 0; i < N_TERMS; ++i)
        if (term_keys[i].bit == term)
            return term_keys[i].key;
    return NULL;
}

int lub_law_terms_append(json_t *arr, unsigned terms)
{
    if (!json_is_array(arr))
        return -1;
    for (int i = 0; i < N_TERMS; ++i)
        if (terms & term_keys[i].bit)
            json_array_append_new(arr, json_string(term_keys[i].key));
    return 0;
}

int lub_law_spec_resolve(json_t *law, const char *ptr, const lub_law_spec_opts *o,
                         lub_law_spec *out, lub_error *err)
{
    const char *keys_t[] = {"eps", "alpha", "kt_ratio", "mu", "terms", NULL};
    const char *keys_n[] = {"eps", "alpha", "terms", NULL};
    if (lub_spec_only_keys(law, ptr, o->tangential ? keys_t : keys_n, err))
        return -1;
    lub_law_params *p = &out->params;
    p->eta = 0.0;
    p->k_bulk = 0.0;
    p->k_t = 0.0;
    p->mu = 0.0;
    out->kt_ratio = 0.0;
    if (lub_spec_number(law, ptr, "eps", LUB_NONNEGATIVE, 1, o->default_eps, &p->eps, err) ||
        lub_spec_number(law, ptr, "alpha", LUB_POSITIVE, 1, o->default_alpha, &p->alpha, err))
        return -1;
    if (o->tangential &&
        (lub_spec_number(law, ptr, "kt_ratio", LUB_NONNEGATIVE, 1, o->default_kt_ratio,
                         &out->kt_ratio, err) ||
         lub_spec_number(law, ptr, "mu", LUB_NONNEGATIVE, 1, o->default_mu, &p->mu, err)))
        return -1;

    char tp[256];
    lub_pointer_join(tp, sizeof tp, ptr, "terms");
    json_t *terms = lub_spec_object(law, ptr, "terms", err);
    if (!terms)
        return -1;
    const char *allowed[N_TERMS + 1];
    int na = 0;
    for (int i = 0; i < N_TERMS; ++i)
        if (o->allowed_terms & term_keys[i].bit)
            allowed[na++] = term_keys[i].key;
    allowed[na] = NULL;
    if (lub_spec_only_keys(terms, tp, allowed, err))
        return -1;
    p->terms = 0u;
    for (int i = 0; i < N_TERMS; ++i) {
        if (!(o->allowed_terms & term_keys[i].bit))
            continue;
        int on = 0;
        if (lub_spec_bool(terms, tp, term_keys[i].key, 1,
                          (o->default_terms & term_keys[i].bit) != 0, &on, err))
            return -1;
        if (on)
            p->terms |= term_keys[i].bit;
    }
    return 0;
}

void lub_law_spec_scale(lub_law_spec *s, double eta, double k_bulk)
{
    s->params.eta = eta;
    s->params.k_bulk = k_bulk;
    s->params.k_t = s->kt_ratio * k_bulk;
}

int lub_law_spec_check_cutoff(const lub_law_spec *l, const char *ptr, double cutoff, lub_error *err)
{
    if (l->params.eps < cutoff)
        return 0;
    char where[200];
    snprintf(where, sizeof where, "%s/eps", ptr);
    return lub_fail(err, where,
                    "must be below /cutoff (%g): contacts start at u < eps a, and pairs are "
                    "only listed within the cut-off (got %g)",
                    cutoff, l->params.eps);
}
