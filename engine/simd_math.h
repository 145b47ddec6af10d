/* simd_math.h — four-lane double-precision vectors (GCC/Clang vector extension) and the
 * elementary functions the batched contact law needs (contact_batch.c).
 *
 * The type is a plain vector of 4 doubles: compiled with AVX2/FMA each operation is one
 * instruction, without them the compiler splits it into SSE2 pairs (same results). All
 * functions are pure and static inline; nothing here allocates or keeps state.
 *
 * Accuracy (tested against libm in tests/law/test_simd_math.c over the stated domains):
 *  - lub_v4_exp(x), x in [-707, 707] (clamped to it): relative error < 4e-16;
 *  - lub_v4_log(x), x a positive normal finite double (anything else is the caller's error:
 *    the result is then meaningless, never a trap): error < 4e-16 max(1, |ln x|) absolute.
 * Both are written here (range reduction + polynomial) because glibc's vector math entry points
 * are declared only under -ffast-math, which the engine does not use.
 */
#ifndef LUBDEM_SIMD_MATH_H
#define LUBDEM_SIMD_MATH_H

#include <stdint.h>
#include <string.h>
#if defined(__AVX__) || defined(__SSE2__)
#include <immintrin.h>
#endif

typedef double lub_v4d __attribute__((vector_size(32)));
typedef int64_t lub_v4i __attribute__((vector_size(32))); /* masks: all bits 1 = true */

static inline lub_v4d lub_v4_set1(double a) { return (lub_v4d){a, a, a, a}; }
static inline lub_v4d lub_v4_load(const double *p)
{
    lub_v4d v;
    memcpy(&v, p, sizeof v);
    return v;
}
static inline void lub_v4_store(double *p, lub_v4d v) { memcpy(p, &v, sizeof v); }

/* m ? a : b, lane by lane (m a comparison result). */
static inline lub_v4d lub_v4_sel(lub_v4i m, lub_v4d a, lub_v4d b)
{
    return (lub_v4d)(((lub_v4i)a & m) | ((lub_v4i)b & ~m));
}
static inline lub_v4d lub_v4_abs(lub_v4d a)
{
    return (lub_v4d)((lub_v4i)a & (lub_v4i){INT64_MAX, INT64_MAX, INT64_MAX, INT64_MAX});
}
static inline lub_v4d lub_v4_min(lub_v4d a, lub_v4d b) { return lub_v4_sel(a < b, a, b); }
static inline lub_v4d lub_v4_max(lub_v4d a, lub_v4d b) { return lub_v4_sel(a > b, a, b); }
/* correctly rounded square root (one vsqrtpd with AVX, two sqrtpd with SSE2) */
static inline lub_v4d lub_v4_sqrt(lub_v4d a)
{
#if defined(__AVX__)
    return (lub_v4d)_mm256_sqrt_pd((__m256d)a);
#elif defined(__SSE2__)
    const __m128d lo = _mm_sqrt_pd((__m128d){a[0], a[1]});
    const __m128d hi = _mm_sqrt_pd((__m128d){a[2], a[3]});
    return (lub_v4d){lo[0], lo[1], hi[0], hi[1]};
#else
    return (lub_v4d){__builtin_sqrt(a[0]), __builtin_sqrt(a[1]), __builtin_sqrt(a[2]),
                     __builtin_sqrt(a[3])};
#endif
}
/* 1 where |a| is finite (not inf, not NaN). */
static inline lub_v4i lub_v4_isfinite(lub_v4d a)
{
    return lub_v4_abs(a) <= 1.79769313486231570e308;
}

/* e^x for x in [-707, 707] (clamped): x = k ln2 + r, |r| <= ln2/2, e^r by its Taylor series to
 * r^13 (truncation 4e-18), 2^k built in the exponent bits (k in [-1020, 1021]: normal). */
static inline lub_v4d lub_v4_exp(lub_v4d x)
{
    const double shift = 0x1.8p52; /* adding it rounds to an integer held in the low bits */
    x = lub_v4_min(lub_v4_max(x, lub_v4_set1(-707.0)), lub_v4_set1(707.0));
    const lub_v4d t = x * 1.4426950408889634074 + shift;
    const lub_v4d kd = t - shift;
    const lub_v4i ki = (lub_v4i)t - (lub_v4i)lub_v4_set1(shift);
    /* Cody-Waite: ln2 = LN2_HI + LN2_LO, LN2_HI with 11 trailing zero bits (kd*LN2_HI exact) */
    const lub_v4d r = (x - kd * 0x1.62e42fefa3800p-1) - kd * 0x1.ef35793c76730p-45;
    lub_v4d p = lub_v4_set1(1.0 / 6227020800.0); /* 1/13! */
    p = p * r + 1.0 / 479001600.0;
    p = p * r + 1.0 / 39916800.0;
    p = p * r + 1.0 / 3628800.0;
    p = p * r + 1.0 / 362880.0;
    p = p * r + 1.0 / 40320.0;
    p = p * r + 1.0 / 5040.0;
    p = p * r + 1.0 / 720.0;
    p = p * r + 1.0 / 120.0;
    p = p * r + 1.0 / 24.0;
    p = p * r + 1.0 / 6.0;
    p = p * r + 0.5;
    p = p * (r * r) + r; /* e^r - 1, kept separate from the 1 for accuracy */
    const lub_v4d two_k = (lub_v4d)((ki + 1023) << 52);
    return (p + 1.0) * two_k;
}

/* ln x for positive normal finite x: x = 2^e m, m in [sqrt(1/2), sqrt(2)), ln m = 2 atanh(s),
 * s = (m - 1)/(m + 1), |s| <= 0.1716, series in s^2 to s^21 (truncation 2e-17 relative). */
static inline lub_v4d lub_v4_log(lub_v4d x)
{
    const lub_v4i bits = (lub_v4i)x;
    const int64_t mant_mask = INT64_C(0x000fffffffffffff);
    const int64_t one_bits = INT64_C(0x3ff0000000000000);
    lub_v4i e = (bits >> 52) - 1023;
    lub_v4d m = (lub_v4d)((bits & mant_mask) | one_bits); /* [1, 2) */
    const lub_v4i big = m > 1.41421356237309504880;
    m = lub_v4_sel(big, m * 0.5, m);
    e = e + (big & 1);
    const lub_v4d f = m - 1.0; /* exact (Sterbenz) */
    const lub_v4d s = f / (f + 2.0);
    const lub_v4d z = s * s;
    lub_v4d p = lub_v4_set1(1.0 / 21.0);
    p = p * z + 1.0 / 19.0;
    p = p * z + 1.0 / 17.0;
    p = p * z + 1.0 / 15.0;
    p = p * z + 1.0 / 13.0;
    p = p * z + 1.0 / 11.0;
    p = p * z + 1.0 / 9.0;
    p = p * z + 1.0 / 7.0;
    p = p * z + 1.0 / 5.0;
    p = p * z + 1.0 / 3.0;
    /* ln m = 2s + 2s z p = f - s f + 2 s z p  (2s = f - s f exactly in real arithmetic; the
     * form f - s*f keeps the leading term f exact) */
    const lub_v4d lnm = f - s * f + 2.0 * s * z * p;
    const lub_v4d ed = __builtin_convertvector(e, lub_v4d);
    return ed * 0x1.62e42fefa3800p-1 + (lnm + ed * 0x1.ef35793c76730p-45);
}

#endif
