/* rng.h — small seeded pseudo-random generator (xoshiro256**, seeded through splitmix64).
 *
 * Pure value type, no global state: every user owns its lub_rng. Reproducible for a given
 * seed on every platform (integer arithmetic only; gaussian via Box–Muller with libm).
 * Not cryptographic. Not thread-safe per instance (give each thread its own).
 */
#ifndef LUBDEM_RNG_H
#define LUBDEM_RNG_H

#include <math.h>
#include <stdint.h>

typedef struct {
    uint64_t s[4];
} lub_rng;

static inline uint64_t lub_rng_splitmix(uint64_t *x)
{
    uint64_t z = (*x += 0x9e3779b97f4a7c15ULL);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
    return z ^ (z >> 31);
}

static inline void lub_rng_seed(lub_rng *r, uint64_t seed)
{
    uint64_t x = seed;
    for (int i = 0; i < 4; ++i)
        r->s[i] = lub_rng_splitmix(&x);
}

static inline uint64_t lub_rng_rotl(uint64_t x, int k) { return (x << k) | (x >> (64 - k)); }

static inline uint64_t lub_rng_next(lub_rng *r)
{
    uint64_t *s = r->s;
    uint64_t result = lub_rng_rotl(s[1] * 5, 7) * 9;
    uint64_t t = s[1] << 17;
    s[2] ^= s[0];
    s[3] ^= s[1];
    s[1] ^= s[2];
    s[0] ^= s[3];
    s[2] ^= t;
    s[3] = lub_rng_rotl(s[3], 45);
    return result;
}

/* Uniform in [0, 1). */
static inline double lub_rng_uniform(lub_rng *r)
{
    return (double)(lub_rng_next(r) >> 11) * 0x1.0p-53;
}

/* Standard normal (Box–Muller, one value per call; the second value is discarded so that the
 * stream stays a pure function of the number of calls). */
static inline double lub_rng_gauss(lub_rng *r)
{
    double u1 = lub_rng_uniform(r);
    double u2 = lub_rng_uniform(r);
    if (u1 < 1e-300)
        u1 = 1e-300;
    return sqrt(-2.0 * log(u1)) * cos(6.283185307179586 * u2);
}

#endif
