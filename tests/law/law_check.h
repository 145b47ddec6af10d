/* law_check.h — the assertion macro and small vector helpers shared by the law tests.
 * Header-only; each test program has its own failure counter (static, one per program).
 * CHECK(cond, fmt, ...) counts a failure and prints it (the first LAW_CHECK_PRINT_LIMIT ones)
 * to stderr with file and line; tests return failures ? 1 : 0. */
#ifndef LUBDEM_LAW_CHECK_H
#define LUBDEM_LAW_CHECK_H

#include <stdio.h>

#include "law_rng.h"
#include "vec3.h"

#ifndef LAW_CHECK_PRINT_LIMIT
#define LAW_CHECK_PRINT_LIMIT 30
#endif

static int failures = 0;
#define CHECK(cond, ...)                                                                           \
    do {                                                                                           \
        if (!(cond)) {                                                                             \
            ++failures;                                                                            \
            if (failures < LAW_CHECK_PRINT_LIMIT) {                                                \
                fprintf(stderr, "FAIL %s:%d: ", __FILE__, __LINE__);                               \
                fprintf(stderr, __VA_ARGS__);                                                      \
                fputc('\n', stderr);                                                               \
            }                                                                                      \
        }                                                                                          \
    } while (0)

/* uniform in the cube [-scale, scale]^3 */
static inline vec3 rand_vec(law_rng *r, double scale)
{
    return v3(law_rng_range(r, -scale, scale), law_rng_range(r, -scale, scale),
              law_rng_range(r, -scale, scale));
}
static inline vec3 unit(vec3 a) { return v3_scale(a, 1.0 / v3_norm(a)); }

#endif
