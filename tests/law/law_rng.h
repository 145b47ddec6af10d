/* law_rng.h — tiny deterministic RNG for the law tests (splitmix64). Header-only, no state
 * outside the caller's struct. */
#ifndef LUBDEM_LAW_RNG_H
#define LUBDEM_LAW_RNG_H

#include <math.h>
#include <stdint.h>

typedef struct {
    uint64_t s;
} law_rng;

static inline uint64_t law_rng_u64(law_rng *r)
{
    uint64_t z = (r->s += 0x9e3779b97f4a7c15ull);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return z ^ (z >> 31);
}
/* uniform in [0, 1) */
static inline double law_rng_uniform(law_rng *r)
{
    return (double)(law_rng_u64(r) >> 11) * 0x1.0p-53;
}
static inline double law_rng_range(law_rng *r, double lo, double hi)
{
    return lo + (hi - lo) * law_rng_uniform(r);
}
/* log-uniform in [lo, hi], lo > 0 */
static inline double law_rng_logrange(law_rng *r, double lo, double hi)
{
    return exp(law_rng_range(r, log(lo), log(hi)));
}

#endif
