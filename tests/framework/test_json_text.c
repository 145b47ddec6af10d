/* Unit tests of json_text.c: reals print exact and as short as each one allows. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "framework_check.h"
#include "json_text.h"

/* Dumps v compact and compares with the expected text. */
static void check_text(json_t *v, const char *expected)
{
    char *text = lub_json_dumps(v, JSON_COMPACT | JSON_SORT_KEYS | JSON_REAL_PRECISION(3));
    if (!text || strcmp(text, expected) != 0) {
        fprintf(stderr, "expected %s\n     got %s\n", expected, text ? text : "(null)");
        ++failures;
    }
    free(text);
    json_decref(v);
}

/* Every real of v reads back bit for bit from lub_json_dumps' text. */
static int reals_equal(const json_t *a, const json_t *b)
{
    if (json_is_real(a))
        return json_is_real(b) && json_real_value(a) == json_real_value(b) &&
               signbit(json_real_value(a)) == signbit(json_real_value(b));
    if (json_is_array(a)) {
        if (!json_is_array(b) || json_array_size(a) != json_array_size(b))
            return 0;
        for (size_t i = 0; i < json_array_size(a); ++i)
            if (!reals_equal(json_array_get(a, i), json_array_get(b, i)))
                return 0;
        return 1;
    }
    return json_equal((json_t *)a, (json_t *)b);
}

int main(void)
{
    /* Shortest digits of single values. */
    CHECK(lub_real_digits(0.3) == 1);
    CHECK(lub_real_digits(0.1) == 1);
    CHECK(lub_real_digits(2.5e-7) == 2);
    CHECK(lub_real_digits(0.8891221699) == 10);
    CHECK(lub_real_digits(1.0 / 3.0) == 16);
    CHECK(lub_real_digits(0.1 + 0.2) == 17);
    CHECK(lub_real_digits(0.0) == 1);
    CHECK(lub_real_digits(-0.0) == 1);
    CHECK(lub_real_digits(20.0) == 2);
    CHECK(lub_real_digits(1e6) == 7);
    CHECK(lub_real_digits(1e14) == 15);
    CHECK(lub_real_digits(1e15) == 1);
    CHECK(lub_real_digits(1e-5) == 1);
    char t[40];
    CHECK(strcmp(lub_real_text(0.6, t), "0.6") == 0);
    CHECK(strcmp(lub_real_text(0.1 + 0.2, t), "0.30000000000000004") == 0);
    CHECK(strcmp(lub_real_text(1e30, t), "1e+30") == 0);
    CHECK(strcmp(lub_real_text(1e7, t), "10000000") == 0);

    /* Values a user types, and a summary's 10-digit values read back, print as written
     * (jansson alone prints 0.29999999999999999 and 0.88912216990000004); the caller's
     * JSON_REAL_PRECISION is ignored. */
    check_text(json_pack("{s:f, s:f, s:[f, {s:f}], s:i, s:f}", "dt_safety", 0.3, "phi", 0.55,
                         "list", 0.1, "eps", 2.5e-7, "n", 300, "big", 1e6),
               "{\"big\":1000000.0,\"dt_safety\":0.3,\"list\":[0.1,{\"eps\":2.5e-7}],\"n\":300,"
               "\"phi\":0.55}");
    check_text(json_pack("{s:f, s:f}", "mu", 0.8891221699, "St", 0.3),
               "{\"St\":0.3,\"mu\":0.8891221699}");
    check_text(json_pack("[f, f]", -0.0, 1e-300), "[-0.0,1e-300]");
    check_text(json_pack("[f, f, f]", 20.0, 1e30, 2.0), "[20.0,1e30,2.0]");
    check_text(json_pack("{s:s, s:i}", "no", "reals", "n", 1), "{\"n\":1,\"no\":\"reals\"}");

    /* Each real is as short as it can be, whatever the others need. */
    check_text(json_pack("{s:f, s:f, s:[f, f], s:s}", "a", 0.3, "b", 0.1 + 0.2, "c", 1.0 / 3.0, 9.3,
                         "s", "0.29999999999999999 1e+30 \\\" 2.50"),
               "{\"a\":0.3,\"b\":0.30000000000000004,\"c\":[0.3333333333333333,9.3],"
               "\"s\":\"0.29999999999999999 1e+30 \\\\\\\" 2.50\"}");
    json_t *doc = json_pack("[f, f, f]", -4.9406564584124654e-324, 1.7976931348623157e308,
                            -2.2250738585072014e-308);
    char *text = lub_json_dumps(doc, JSON_INDENT(2));
    json_t *back = text ? json_loads(text, 0, NULL) : NULL;
    CHECK(back != NULL);
    CHECK(back && reals_equal(doc, back));
    CHECK(text && strstr(text, "5e-324") && strstr(text, "1.7976931348623157e308"));
    free(text);
    json_decref(back);
    json_decref(doc);

    /* Exact on random doubles of every magnitude (the property the stored spec relies on). */
    unsigned long long s = 88172645463325252ULL;
    int inexact = 0;
    for (int i = 0; i < 20000; ++i) {
        s ^= s << 13;
        s ^= s >> 7;
        s ^= s << 17;
        double x;
        memcpy(&x, &s, sizeof x);
        if (!isfinite(x))
            continue;
        if (i % 2)
            x = (double)(s >> 11) / 9007199254740992.0 * pow(10.0, (double)(i % 41) - 20.0);
        json_t *one = json_pack("[f]", x);
        char *t = lub_json_dumps(one, JSON_COMPACT);
        json_t *r = t ? json_loads(t, 0, NULL) : NULL;
        if (!r || !reals_equal(one, r))
            ++inexact;
        free(t);
        json_decref(r);
        json_decref(one);
    }
    CHECK(inexact == 0);

    /* Rounded for a summary's results: at most 10 digits, nested members too, integers and
     * strings untouched. */
    json_t *res = json_pack("{s:f, s:[f, {s:f}], s:I, s:s, s:f}", "mu", 0.88912216993141, "list",
                            1.0 / 3.0, "deep", 2.0 / 3.0e-9, "n", (json_int_t)123456789012345, "s",
                            "0.123456789012", "exact", 0.25);
    lub_json_round_reals(res, 10);
    check_text(res, "{\"exact\":0.25,\"list\":[0.3333333333,{\"deep\":666666666.7}],"
                    "\"mu\":0.8891221699,\"n\":123456789012345,\"s\":\"0.123456789012\"}");

    CHECK(lub_json_dumps(NULL, 0) == NULL);
    if (failures)
        fprintf(stderr, "%d failure(s)\n", failures);
    return failures ? 1 : 0;
}
