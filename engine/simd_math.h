/* simd_math.h — LUB_VW-lane double-precision vectors (GCC/Clang vector extension) and the
 * elementary functions the batched contact law needs (contact_batch.c).
 *
 * The type is a plain vector of LUB_VW doubles: the compiler maps each operation onto the
 * widest instructions the file is compiled for (AVX-512, AVX2/FMA, or SSE2 pairs; same
 * results). All functions are pure and static inline; nothing here allocates or keeps state.
 *
 * Accuracy (tested against libm in tests/law/test_simd_math.c over the stated domains):
 *  - lub_v_exp(x), x in [-707, 707] (clamped to it): relative error < 4e-16;
 *  - lub_v_log(x), x a positive normal finite double (anything else is the caller's error:
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

/* Lanes per vector, 4 or 8, set by the build (CMakeLists.txt): 8 with AVX-512, 4 otherwise.
 * (8 lanes on AVX2 were measured 2x slower than 4: the compiler splits them into halves and
 * runs out of registers.) */
#ifndef LUB_VW
#define LUB_VW 4
#endif
#if LUB_VW == 8
#define LUB_LANES(F) F(0), F(1), F(2), F(3), F(4), F(5), F(6), F(7)
#elif LUB_VW == 4
#define LUB_LANES(F) F(0), F(1), F(2), F(3)
#else
#error "LUB_VW must be 4 or 8"
#endif

typedef double lub_vd __attribute__((vector_size(8 * LUB_VW)));
typedef int64_t lub_vi __attribute__((vector_size(8 * LUB_VW))); /* masks: all bits 1 = true */

static inline lub_vd lub_v_set1(double a)
{
#define LUB_SET1_LANE(l) a
    return (lub_vd){LUB_LANES(LUB_SET1_LANE)};
#undef LUB_SET1_LANE
}
static inline lub_vd lub_v_load(const double *p)
{
    lub_vd v;
    memcpy(&v, p, sizeof v);
    return v;
}
static inline void lub_v_store(double *p, lub_vd v) { memcpy(p, &v, sizeof v); }

/* m ? a : b, lane by lane (m a comparison result). */
static inline lub_vd lub_v_sel(lub_vi m, lub_vd a, lub_vd b)
{
    return (lub_vd)(((lub_vi)a & m) | ((lub_vi)b & ~m));
}
/* 1 if any lane of the mask m is true (for branches that skip work no lane needs). */
static inline int lub_v_any(lub_vi m)
{
#if defined(__AVX512F__) && LUB_VW == 8
    return _mm512_test_epi64_mask((__m512i)m, (__m512i)m) != 0;
#elif defined(__AVX__) && LUB_VW == 4
    return !_mm256_testz_si256((__m256i)m, (__m256i)m);
#else
    int64_t r = 0;
    for (int l = 0; l < LUB_VW; ++l)
        r |= m[l];
    return r != 0;
#endif
}
static inline lub_vd lub_v_abs(lub_vd a) { return (lub_vd)((lub_vi)a & INT64_MAX); }
static inline lub_vd lub_v_min(lub_vd a, lub_vd b) { return lub_v_sel(a < b, a, b); }
static inline lub_vd lub_v_max(lub_vd a, lub_vd b) { return lub_v_sel(a > b, a, b); }
/* correctly rounded square root, 8 (AVX-512), 4 (AVX) or 2 (SSE2) lanes per instruction */
static inline lub_vd lub_v_sqrt(lub_vd a)
{
#if defined(__AVX512F__) && LUB_VW == 8
    return (lub_vd)_mm512_sqrt_pd((__m512d)a);
#elif defined(__AVX__) && LUB_VW == 4
    return (lub_vd)_mm256_sqrt_pd((__m256d)a);
#elif defined(__SSE2__) /* two lanes per instruction (also 8 lanes without AVX-512) */
    double t[LUB_VW];
    memcpy(t, &a, sizeof t);
    for (int k = 0; k < LUB_VW; k += 2)
        _mm_storeu_pd(t + k, _mm_sqrt_pd(_mm_loadu_pd(t + k)));
    memcpy(&a, t, sizeof t);
    return a;
#else
    for (int k = 0; k < LUB_VW; ++k)
        a[k] = __builtin_sqrt(a[k]);
    return a;
#endif
}
/* 1 where |a| is finite (not inf, not NaN). */
static inline lub_vi lub_v_isfinite(lub_vd a) { return lub_v_abs(a) <= 1.79769313486231570e308; }

/* e^x for x in [-707, 707] (clamped): x = k ln2 + r, |r| <= ln2/2, e^r by its Taylor series to
 * r^13 (truncation 4e-18), 2^k built in the exponent bits (k in [-1020, 1021]: normal). */
static inline lub_vd lub_v_exp(lub_vd x)
{
    const double shift = 0x1.8p52; /* adding it rounds to an integer held in the low bits */
    x = lub_v_min(lub_v_max(x, lub_v_set1(-707.0)), lub_v_set1(707.0));
    const lub_vd t = x * 1.4426950408889634074 + shift;
    const lub_vd kd = t - shift;
    const lub_vi ki = (lub_vi)t - (lub_vi)lub_v_set1(shift);
    /* Cody-Waite: ln2 = LN2_HI + LN2_LO, LN2_HI with 11 trailing zero bits (kd*LN2_HI exact) */
    const lub_vd r = (x - kd * 0x1.62e42fefa3800p-1) - kd * 0x1.ef35793c76730p-45;
    lub_vd p = lub_v_set1(1.0 / 6227020800.0); /* 1/13! */
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
    const lub_vd two_k = (lub_vd)((ki + 1023) << 52);
    return (p + 1.0) * two_k;
}

/* ln x for positive normal finite x: x = 2^e m, m in [sqrt(1/2), sqrt(2)), ln m = 2 atanh(s),
 * s = (m - 1)/(m + 1), |s| <= 0.1716, series in s^2 to s^21 (truncation 2e-17 relative). */
static inline lub_vd lub_v_log(lub_vd x)
{
    const lub_vi bits = (lub_vi)x;
    const int64_t mant_mask = INT64_C(0x000fffffffffffff);
    const int64_t one_bits = INT64_C(0x3ff0000000000000);
    lub_vi e = (bits >> 52) - 1023;
    lub_vd m = (lub_vd)((bits & mant_mask) | one_bits); /* [1, 2) */
    const lub_vi big = m > 1.41421356237309504880;
    m = lub_v_sel(big, m * 0.5, m);
    e = e + (big & 1);
    const lub_vd f = m - 1.0; /* exact (Sterbenz) */
    const lub_vd s = f / (f + 2.0);
    const lub_vd z = s * s;
    lub_vd p = lub_v_set1(1.0 / 21.0);
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
    const lub_vd lnm = f - s * f + 2.0 * s * z * p;
    const lub_vd ed = __builtin_convertvector(e, lub_vd);
    return ed * 0x1.62e42fefa3800p-1 + (lnm + ed * 0x1.ef35793c76730p-45);
}

#endif
