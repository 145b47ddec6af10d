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

    /* texts cut on a UTF-8 character boundary: a value quoted at 80 bytes, a pointer cut at
     * its 256 (they ended with the first byte of a character, which json_pack refuses: the
     * CLI printed "(null)" for --json-errors) */
    char long_value[128], long_key[512];
    memset(long_value, 'a', 79);
    strcpy(long_value + 79, "\xc3\xa9"); /* "é" across byte 80 */
    json_object_set_new(o, "mode3", json_string(long_value));
    CHECK(lub_spec_enum(o, "", "mode3", choices, NULL, &s, &err) == -1);
    CHECK(strstr(err.message, "aaaa\")") != NULL);
    json_t *js = json_string(err.message);
    CHECK(js != NULL);
    json_decref(js);
    strcpy(long_key, "a");
    for (int k = 0; k < 200; ++k)
        strcat(long_key, "\xc3\xa9");
    json_t *keyed = json_object();
    json_object_set_new(keyed, long_key, json_integer(1));
    CHECK(lub_spec_only_keys(keyed, "/law", allowed, &err) == -1);
    js = json_string(err.pointer);
    CHECK(js != NULL && strlen(err.pointer) >= 250);
    json_decref(js);
    json_decref(keyed);
    char jbuf[16];
    CHECK(strcmp(lub_pointer_join(jbuf, sizeof jbuf, "/x", "abc\xc3\xa9\xc3\xa9\xc3\xa9\xc3\xa9"),
                 "/x/abc\xc3\xa9\xc3\xa9\xc3\xa9") == 0);
    CHECK(lub_utf8_prefix("ab\xe2\x82\xac", 4) == 2 && lub_utf8_prefix("ab\xe2\x82\xac", 5) == 5);
    CHECK(lub_utf8_prefix("abc", 80) == 3);
    lub_fail(&err, "", "%s", long_key); /* a message cut at its 512 bytes */
    js = json_string(err.message);
    CHECK(js != NULL);
    json_decref(js);
    /* one line: control characters and stray bytes escaped, characters kept */
    char line[64];
    CHECK(strcmp(lub_text_one_line("/law/x\ny\t\x01\xc3 \xc3\xa9", line, sizeof line),
                 "/law/x\\ny\\t\\u0001\\xC3 \xc3\xa9") == 0);
    CHECK(strcmp(lub_text_one_line("\xc3\xa9\xc3\xa9", line, 4), "\xc3\xa9") == 0);

    json_decref(o);
    printf("spec_reader_failures=%d\n", failures);
    printf("%d passed, %d failed\n", failures ? 0 : 1, failures ? 1 : 0);
    return failures ? 1 : 0;
}
