/* check.h — tiny assertion helpers for the continuum tests: every check prints a
 * name=value line (figures for the README) and counts failures; main returns the count. */
#ifndef LUBDEM_TESTS_CONTINUUM_CHECK_H
#define LUBDEM_TESTS_CONTINUUM_CHECK_H

#include <math.h>
#include <stdio.h>

static int g_failures = 0;

/* |got - want| <= tol (tol = half a unit of the last digit printed by the reference) */
static void check_near(const char *name, double got, double want, double tol)
{
    int ok = isfinite(got) && fabs(got - want) <= tol;
    printf("%s=%.10g ref=%.10g tol=%.3g %s\n", name, got, want, tol, ok ? "ok" : "FAIL");
    if (!ok)
        ++g_failures;
}

static void check_true(const char *name, int cond)
{
    printf("%s=%s\n", name, cond ? "ok" : "FAIL");
    if (!cond)
        ++g_failures;
}

static int check_report(void)
{
    printf("failures=%d\n", g_failures);
    return g_failures ? 1 : 0;
}

#endif
