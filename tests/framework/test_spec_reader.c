/* Unit tests of spec_reader.c: types, ranges, defaults, unknown fields, JSON pointers. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "framework_check.h"
#include "spec_reader.h"

int main(void)
{
    lub_error err;
    json_error_t je;
    json_t *o = json_loads("{\"eps\": -0.1, \"n\": 2.5, \"flag\": 1, \"mode\": \"x\", "
                           "\"v\": [1, 2], \"a/b\": 3, \"ok\": 0.5, \"big\": 1e3, "
                           "\"huge\": 1e30}",
                           0, &je);
    double d;
    long long i;
    int b;
    const char *s;

    CHECK(lub_spec_number(o, "", "eps", LUB_NONNEGATIVE, 0, 0, &d, &err) == -1);
    CHECK(strcmp(err.pointer, "/eps") == 0);
    CHECK(strstr(err.message, ">= 0") != NULL);

    CHECK(lub_spec_number(o, "/law", "ok", (lub_range){0, 1, 0, 1}, 0, 0, &d, &err) == 0);
    CHECK(d == 0.5);
    CHECK(lub_spec_number(o, "", "ok", (lub_range){0.5, 1, 1, 0}, 0, 0, &d, &err) == -1);
    CHECK(strstr(err.message, "> 0.5") != NULL);
    /* bounds and values quoted as the user wrote them, not as 17-digit doubles */
    CHECK(lub_spec_number(o, "", "eps", (lub_range){0.1, 0.6, 0, 0}, 0, 0, &d, &err) == -1);
    CHECK(strcmp(err.message, "must be >= 0.1 (got -0.1)") == 0);
    CHECK(lub_spec_number(o, "", "ok", (lub_range){0, 0.3, 0, 0}, 0, 0, &d, &err) == -1);
    CHECK(strcmp(err.message, "must be <= 0.3 (got 0.5)") == 0);

    CHECK(lub_spec_number(o, "", "missing", LUB_POSITIVE, 1, 7.0, &d, &err) == 0);
    CHECK(d == 7.0 && json_number_value(json_object_get(o, "missing")) == 7.0);
    CHECK(lub_spec_number(o, "", "absent", LUB_POSITIVE, 0, 0, &d, &err) == -1);
    CHECK(strstr(err.message, "required") != NULL);

    CHECK(lub_spec_integer(o, "", "n", 0, 10, 0, 0, &i, &err) == -1);
    CHECK(strstr(err.message, "integer") != NULL);
    CHECK(lub_spec_integer(o, "", "big", 0, 10000, 0, 0, &i, &err) == 0 && i == 1000);
    /* the resolved spec states it as an integer, not 1000.0 */
    CHECK(json_is_integer(json_object_get(o, "big")));
    /* an integral real beyond the range names the range, not the type */
    CHECK(lub_spec_integer(o, "", "huge", 0, 10, 0, 0, &i, &err) == -1);
    CHECK(strstr(err.message, "<= 10 (got 1e+30)") != NULL);
    CHECK(lub_spec_integer(o, "", "big", 0, 999, 0, 0, &i, &err) == -1);

    CHECK(lub_spec_bool(o, "", "flag", 0, 0, &b, &err) == -1);
    CHECK(strstr(err.message, "boolean") != NULL);

    const char *choices[] = {"a", "b", NULL};
    CHECK(lub_spec_enum(o, "", "mode", choices, NULL, &s, &err) == -1);
    CHECK(strstr(err.message, "\"a\", \"b\"") != NULL);
    CHECK(lub_spec_enum(o, "", "mode2", choices, "b", &s, &err) == 0 && strcmp(s, "b") == 0);

    double v[3];
    CHECK(lub_spec_vector(o, "", "v", 3, LUB_UNBOUNDED, NULL, v, &err) == -1);
    CHECK(strcmp(err.pointer, "/v") == 0);
    json_object_set_new(o, "w", json_pack("[f, s, f]", 1.0, "x", 2.0));
    CHECK(lub_spec_vector(o, "", "w", 3, LUB_UNBOUNDED, NULL, v, &err) == -1);
    CHECK(strcmp(err.pointer, "/w/1") == 0);

    /* RFC 6901 escaping of '/' in keys */
    CHECK(lub_spec_number(o, "", "a/b", (lub_range){0, 1, 0, 0}, 0, 0, &d, &err) == -1);
    CHECK(strcmp(err.pointer, "/a~1b") == 0);

    const char *allowed[] = {"eps", "n", NULL};
    json_t *small = json_pack("{s:f, s:f}", "eps", 1.0, "epz", 2.0);
    CHECK(lub_spec_only_keys(small, "/law", allowed, &err) == -1);
    CHECK(strcmp(err.pointer, "/law/epz") == 0);
    CHECK(strstr(err.message, "eps, n") != NULL);
    json_decref(small);

    CHECK(lub_spec_object(o, "", "eps", &err) == NULL);
    CHECK(lub_spec_object(o, "", "sub", &err) != NULL);

    /* non-finite numbers never pass (jansson rejects NaN on parse; INFINITY via API) */
    json_object_set_new(o, "inf", json_real(INFINITY));
    CHECK(json_object_get(o, "inf") == NULL ||
          lub_spec_number(o, "", "inf", LUB_UNBOUNDED, 0, 0, &d, &err) == -1);

    json_decref(o);
    printf("spec_reader_failures=%d\n", failures);
    printf("%d passed, %d failed\n", failures ? 0 : 1, failures ? 1 : 0);
    return failures ? 1 : 0;
}
