/* resume_spec.c — the spec comparison of a continuation (see resume_spec.h). */
#include "resume_spec.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "json_text.h"
#include "spec_reader.h"

/* a and b hold the same values: numbers by value (a spec may write 12 or 12.0, and a client or
 * an older service may print the one the other wrote as the other), the rest as json_equal. */
static int same_values(const json_t *a, const json_t *b)
{
    if (json_is_number(a) && json_is_number(b))
        return json_number_value(a) == json_number_value(b);
    if (json_is_object(a) && json_is_object(b)) {
        if (json_object_size(a) != json_object_size(b))
            return 0;
        const char *key;
        json_t *value;
        json_object_foreach ((json_t *)a, key, value) {
            const json_t *other = json_object_get(b, key);
            if (!other || !same_values(value, other))
                return 0;
        }
        return 1;
    }
    if (json_is_array(a) && json_is_array(b)) {
        if (json_array_size(a) != json_array_size(b))
            return 0;
        for (size_t k = 0; k < json_array_size(a); ++k)
            if (!same_values(json_array_get(a, k), json_array_get(b, k)))
                return 0;
        return 1;
    }
    return json_equal(a, b);
}

/* The first place where a and b differ, as a JSON pointer under `at` into out[len] (the two
 * values there into va/vb, compact JSON, truncated); 0 when they are equal. */
static int first_difference(const json_t *a, const json_t *b, const char *at, char *out, size_t len,
                            char *va, char *vb, size_t vlen)
{
    if (same_values(a, b))
        return 0;
    if (json_is_object(a) && json_is_object(b)) {
        const char *key;
        json_t *value;
        json_object_foreach ((json_t *)a, key, value) {
            char sub[512];
            lub_pointer_join(sub, sizeof sub, at, key);
            const json_t *other = json_object_get(b, key);
            if (!other) {
                snprintf(out, len, "%s", sub);
                snprintf(vb, vlen, "absent");
                char *t = lub_json_dumps(value, JSON_COMPACT | JSON_ENCODE_ANY);
                snprintf(va, vlen, "%s", t ? t : "?");
                lub_utf8_trim_tail(va);
                free(t);
                return 1;
            }
            if (first_difference(value, other, sub, out, len, va, vb, vlen))
                return 1;
        }
        json_object_foreach ((json_t *)b, key, value) {
            if (!json_object_get(a, key))
                return first_difference(b, a, at, out, len, vb, va, vlen);
        }
    }
    snprintf(out, len, "%s", at[0] ? at : "(root)");
    char *ta = lub_json_dumps(a, JSON_COMPACT | JSON_ENCODE_ANY);
    char *tb = lub_json_dumps(b, JSON_COMPACT | JSON_ENCODE_ANY);
    snprintf(va, vlen, "%s", ta ? ta : "?");
    snprintf(vb, vlen, "%s", tb ? tb : "?");
    lub_utf8_trim_tail(va); /* a value cut inside a character */
    lub_utf8_trim_tail(vb);
    free(ta);
    free(tb);
    return 1;
}

int lub_resume_spec_mismatch(const json_t *here, const json_t *saved, const char *const *may_differ,
                             char *why, size_t len, char *at_out, size_t at_len)
{
    json_t *a = json_deep_copy(here), *b = json_deep_copy(saved);
    int rc = 0;
    if (!a || !b) {
        snprintf(why, len, "out of memory");
        rc = -1;
    } else {
        for (int k = 0; may_differ && may_differ[k]; ++k) {
            json_object_del(a, may_differ[k]);
            json_object_del(b, may_differ[k]);
        }
        char at[512], was[160], now[160];
        /* another scene's checkpoint is refused at /scene, whatever member comes first */
        const json_t *scene_a = json_object_get(a, "scene"), *scene_b = json_object_get(b, "scene");
        const int other_scene =
            scene_a && scene_b && !json_equal(scene_a, scene_b) &&
            first_difference(scene_a, scene_b, "/scene", at, sizeof at, now, was, sizeof now);
        if (other_scene || first_difference(a, b, "", at, sizeof at, now, was, sizeof now)) {
            snprintf(why, len, "%s: %s here, %s in the stopped run's spec", at, now, was);
            lub_utf8_trim_tail(why);
            if (at_out) {
                snprintf(at_out, at_len, "%s", at);
                lub_utf8_trim_tail(at_out);
            }
            rc = 1;
        }
    }
    json_decref(a);
    json_decref(b);
    return rc;
}

void lub_resume_free_members(const char *const *may_differ, char *out, size_t len)
{
    out[0] = '\0';
    for (int k = 0; may_differ && may_differ[k]; ++k) {
        const size_t used = strlen(out);
        snprintf(out + used, len - used, "%s/%s", k ? ", " : "; only ", may_differ[k]);
    }
    if (out[0]) {
        const size_t used = strlen(out);
        snprintf(out + used, len - used, " may change");
    }
}
