/* test_run_checks.c — the advisory checks of a finished simple_shear run: each check fires
 * just beyond its threshold, stays silent just inside it and for NaN, and names the spec
 * member to change. */
#include <math.h>
#include <string.h>

#include "shear_run_checks.h"
#include "shear_test.h"

/* a run that passes every check */
static lub_shear_run_state clean(void)
{
    lub_shear_run_state st = {.elastic_number = 1e4,
                              .kinetic_share = 1e-4,
                              .crushed_fraction = 0.0,
                              .bond_order_q6 = 0.05,
                              .lost_pairs = 0.0,
                              .steady = 1};
    return st;
}

static char text[LUB_SHEAR_WARNINGS_MAX][LUB_SHEAR_WARNING_LEN];

/* number of warnings for st; *first gets the first one (or "") */
static int count(const lub_shear_run_state *st, const char **first)
{
    memset(text, 0, sizeof text);
    int n = lub_shear_run_warnings(st, text);
    *first = n > 0 ? text[0] : "";
    return n;
}

int main(void)
{
    const char *w;
    lub_shear_run_state st = clean();
    ST_CHECK(count(&st, &w) == 0, "clean run warns: %s", w);

    /* elastic number: 5e3 is the floor */
    st = clean();
    st.elastic_number = 4.9e3;
    ST_CHECK(count(&st, &w) == 1 && strstr(w, "/stiffness") && strstr(w, "4.9e+03"), "El 4.9e3: %s",
             w);
    st.elastic_number = 5.1e3;
    ST_CHECK(count(&st, &w) == 0, "El 5.1e3 warns: %s", w);
    st.elastic_number = NAN;
    ST_CHECK(count(&st, &w) == 0, "El NaN warns: %s", w);
    /* the factor by which to raise it: 5e3 / 1e3 = 5 */
    st.elastic_number = 1e3;
    ST_CHECK(count(&st, &w) == 1 && strstr(w, "by 5 or more"), "El 1e3: %s", w);

    /* kinetic stress: 1 % of sigma_xy */
    st = clean();
    st.kinetic_share = 0.011;
    ST_CHECK(count(&st, &w) == 1 && strstr(w, "/St") && strstr(w, "1.1 %"), "kinetic 1.1 %%: %s",
             w);
    st.kinetic_share = 0.009;
    ST_CHECK(count(&st, &w) == 0, "kinetic 0.9 %% warns: %s", w);

    /* crushed asperities: 1 % of the contacts */
    st = clean();
    st.crushed_fraction = 0.02;
    ST_CHECK(count(&st, &w) == 1 && strstr(w, "crushed in 2 %") && strstr(w, "/stiffness"),
             "crushed 2 %%: %s", w);
    st.crushed_fraction = 0.005;
    ST_CHECK(count(&st, &w) == 0, "crushed 0.5 %% warns: %s", w);

    /* ordering: Q6 above 0.1 */
    st = clean();
    st.bond_order_q6 = 0.153;
    ST_CHECK(count(&st, &w) == 1 && strstr(w, "0.153") && strstr(w, "/n_particles"), "Q6 0.153: %s",
             w);
    st.bond_order_q6 = 0.092;
    ST_CHECK(count(&st, &w) == 0, "Q6 0.092 warns: %s", w);

    /* lost pair states: any */
    st = clean();
    st.lost_pairs = 1.0;
    ST_CHECK(count(&st, &w) == 1 && strstr(w, "1 active pair"), "1 lost pair: %s", w);

    /* no steady state */
    st = clean();
    st.steady = 0;
    ST_CHECK(count(&st, &w) == 1 && strstr(w, "/strain"), "not steady: %s", w);

    /* everything at once: six messages, each naming the spec member to change (a JSON
     * pointer after "; raise " or "; lower "), none truncated */
    st.elastic_number = 1e2;
    st.kinetic_share = 0.5;
    st.crushed_fraction = 0.3;
    st.bond_order_q6 = 0.5;
    st.lost_pairs = 12345.0;
    int n = count(&st, &w);
    ST_CHECK(n == LUB_SHEAR_WARNINGS_MAX, "all checks: %d warnings", n);
    for (int k = 0; k < n; ++k) {
        size_t len = strlen(text[k]);
        ST_CHECK(len + 1 < LUB_SHEAR_WARNING_LEN, "warning %d may be truncated (%zu chars)", k,
                 len);
        ST_CHECK(strstr(text[k], "; raise /") || strstr(text[k], "; lower /"),
                 "warning %d names no spec member to change: %s", k, text[k]);
    }
    ST_DONE();
}
