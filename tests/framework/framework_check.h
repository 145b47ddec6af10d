/* framework_check.h — the CHECK macro of the framework unit tests: a failed condition prints
 * file, line and expression on stderr and counts into `failures` (one counter per test file). */
#ifndef LUBDEM_FRAMEWORK_CHECK_H
#define LUBDEM_FRAMEWORK_CHECK_H

#include <stdio.h>

static int failures = 0;
#define CHECK(cond)                                                                                \
    do {                                                                                           \
        if (!(cond)) {                                                                             \
            fprintf(stderr, "%s:%d: CHECK failed: %s\n", __FILE__, __LINE__, #cond);               \
            ++failures;                                                                            \
        }                                                                                          \
    } while (0)

#endif
