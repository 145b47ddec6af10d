/* shear_test.h — tiny assertion helpers for the tests/shear programs (no framework needed). */
#ifndef LUBDEM_SHEAR_TEST_H
#define LUBDEM_SHEAR_TEST_H

#include <stdio.h>

static int st_failures = 0;

#define ST_CHECK(cond, ...)                                                                        \
    do {                                                                                           \
        if (!(cond)) {                                                                             \
            fprintf(stderr, "FAIL %s:%d: %s: ", __FILE__, __LINE__, #cond);                        \
            fprintf(stderr, __VA_ARGS__);                                                          \
            fprintf(stderr, "\n");                                                                 \
            st_failures++;                                                                         \
        }                                                                                          \
    } while (0)

#define ST_DONE()                                                                                  \
    do {                                                                                           \
        if (st_failures)                                                                           \
            fprintf(stderr, "%d check(s) failed\n", st_failures);                                  \
        return st_failures ? 1 : 0;                                                                \
    } while (0)

#endif
