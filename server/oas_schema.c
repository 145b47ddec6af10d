/* oas_schema.c — draft-07 JSON Schema to OpenAPI 3.0 Schema Object (see oas_schema.h). */
#include "oas_schema.h"

#include <stdio.h>
#include <string.h>

typedef struct {
    char *err;
    size_t errlen;
} oas_ctx;

/* OpenAPI 3.0 Schema Object keywords that mean the same in draft-07: copied as they are */
static const char *const copied[] = {
    "title",         "description",   "default", "enum",     "required", "multipleOf",
    "maxLength",     "minLength",     "pattern", "maxItems", "minItems", "uniqueItems",
    "maxProperties", "minProperties", "format",  "nullable", "readOnly", "writeOnly",
    "example",       "deprecated",    NULL};
/* draft-07 identification and comments: no meaning for a client */
static const char *const dropped[] = {"$schema", "$id", "$comment", NULL};
/* translated into subschemas one by one */
static const char *const schema_lists[] = {"allOf", "anyOf", "oneOf", NULL};

static const char generic_condition[] =
    "A further condition applies (a draft-07 if/then/else, which OpenAPI 3.0 cannot state): "
    "see the process's inputsSchema.";

static int in_list(const char *k, const char *const *list)
{
    for (; *list; ++list)
        if (strcmp(k, *list) == 0)
            return 1;
    return 0;
}

static int fail(oas_ctx *c, const char *path, const char *fmt, const char *arg)
{
    char what[200];
    snprintf(what, sizeof what, fmt, arg);
    snprintf(c->err, c->errlen, "%s: %s", *path ? path : "(root)", what);
    return -1;
}

/* path + "/" + seg as a JSON Pointer (~ and / escaped), truncated to n bytes */
static void child_path(char *buf, size_t n, const char *path, const char *seg)
{
    size_t k = (size_t)snprintf(buf, n, "%s/", path);
    for (; *seg && k + 3 < n; ++seg) {
        if (*seg == '~' || *seg == '/') {
            buf[k++] = '~';
            buf[k++] = *seg == '~' ? '0' : '1';
        } else {
            buf[k++] = *seg;
        }
    }
    if (k < n)
        buf[k] = '\0';
}

static json_t *translate(json_t *s, const char *path, oas_ctx *c);

static int set_translated(json_t *out, const char *key, json_t *sub, const char *path, oas_ctx *c)
{
    char p[512];
    child_path(p, sizeof p, path, key);
    json_t *t = translate(sub, p, c);
    if (!t)
        return -1;
    json_object_set_new(out, key, t);
    return 0;
}

/* the bound of one side (lower: minimum/exclusiveMinimum, else maximum/exclusiveMaximum) */
static int put_bound(json_t *out, json_t *s, int lower, const char *path, oas_ctx *c)
{
    const char *bk = lower ? "minimum" : "maximum";
    const char *ek = lower ? "exclusiveMinimum" : "exclusiveMaximum";
    json_t *b = json_object_get(s, bk), *e = json_object_get(s, ek);
    if (b && !json_is_number(b))
        return fail(c, path, "%s is not a number", bk);
    if (e && !json_is_number(e) && !json_is_boolean(e))
        return fail(c, path, "%s is neither a number nor a boolean", ek);
    if (!e || json_is_boolean(e)) { /* no exclusive bound, or already the OpenAPI flag */
        if (b)
            json_object_set_new(out, bk, json_deep_copy(b));
        if (e)
            json_object_set_new(out, ek, json_deep_copy(e));
        return 0;
    }
    const double x = json_number_value(e);
    /* draft-07 requires both: the exclusive bound wins when it is at least as tight */
    if (!b || (lower ? x >= json_number_value(b) : x <= json_number_value(b))) {
        json_object_set_new(out, bk, json_deep_copy(e));
        json_object_set_new(out, ek, json_true());
    } else {
        json_object_set_new(out, bk, json_deep_copy(b));
    }
    return 0;
}

/* a type array: one type (with nullable), or (*alts) anyOf branches for two or more */
static int put_types(json_t *out, json_t *t, json_t **alts, const char *path, oas_ctx *c)
{
    size_t i, n = 0;
    int nullable = 0;
    json_t *v;
    json_array_foreach (t, i, v) {
        if (!json_is_string(v))
            return fail(c, path, "%s", "type array holds a non-string");
        if (strcmp(json_string_value(v), "null") == 0)
            nullable = 1;
        else
            ++n;
    }
    if (n == 0)
        return fail(c, path, "%s", "type null alone has no OpenAPI 3.0 form");
    if (n > 1)
        *alts = json_array();
    json_array_foreach (t, i, v) {
        if (strcmp(json_string_value(v), "null") == 0)
            continue;
        json_t *one = n == 1 ? out : json_object();
        json_object_set_new(one, "type", json_string(json_string_value(v)));
        if (nullable)
            json_object_set_new(one, "nullable", json_true());
        if (n > 1)
            json_array_append_new(*alts, one);
    }
    return 0;
}

/* every member of s but the bounds' second keyword and the if/then/else sentence */
static int put_members(json_t *out, json_t *s, json_t **alts, const char *path, oas_ctx *c)
{
    int lower_done = 0, upper_done = 0;
    const char *k;
    json_t *v;
    json_object_foreach (s, k, v) {
        if (in_list(k, copied) || strncmp(k, "x-", 2) == 0) {
            json_object_set_new(out, k, json_deep_copy(v));
        } else if (in_list(k, dropped) || strcmp(k, "if") == 0 || strcmp(k, "then") == 0 ||
                   strcmp(k, "else") == 0) {
            continue;
        } else if (strcmp(k, "minimum") == 0 || strcmp(k, "exclusiveMinimum") == 0) {
            if (!lower_done++ && put_bound(out, s, 1, path, c) != 0)
                return -1;
        } else if (strcmp(k, "maximum") == 0 || strcmp(k, "exclusiveMaximum") == 0) {
            if (!upper_done++ && put_bound(out, s, 0, path, c) != 0)
                return -1;
        } else if (strcmp(k, "const") == 0) {
            if (json_object_get(s, "enum"))
                return fail(c, path, "%s", "const beside enum");
            json_t *one = json_array();
            json_array_append_new(one, json_deep_copy(v));
            json_object_set_new(out, "enum", one);
        } else if (strcmp(k, "type") == 0) {
            if (json_is_array(v)) {
                if (put_types(out, v, alts, path, c) != 0)
                    return -1;
            } else if (!json_is_string(v)) {
                return fail(c, path, "%s", "type is neither a string nor an array");
            } else if (strcmp(json_string_value(v), "null") == 0) {
                return fail(c, path, "%s", "type null alone has no OpenAPI 3.0 form");
            } else {
                json_object_set_new(out, k, json_deep_copy(v));
            }
        } else if (strcmp(k, "properties") == 0) {
            if (!json_is_object(v))
                return fail(c, path, "%s", "properties is not an object");
            char p[512];
            child_path(p, sizeof p, path, k);
            json_t *props = json_object();
            json_object_set_new(out, k, props);
            const char *name;
            json_t *sub;
            json_object_foreach (v, name, sub)
                if (set_translated(props, name, sub, p, c) != 0)
                    return -1;
        } else if (strcmp(k, "additionalProperties") == 0 && json_is_boolean(v)) {
            json_object_set_new(out, k, json_deep_copy(v));
        } else if (strcmp(k, "additionalProperties") == 0 || strcmp(k, "not") == 0 ||
                   (strcmp(k, "items") == 0 && !json_is_array(v))) {
            if (set_translated(out, k, v, path, c) != 0)
                return -1;
        } else if (in_list(k, schema_lists)) {
            if (!json_is_array(v) || json_array_size(v) == 0)
                return fail(c, path, "%s is not a non-empty array", k);
            char p[512];
            child_path(p, sizeof p, path, k);
            json_t *list = json_array();
            json_object_set_new(out, k, list);
            size_t i;
            json_t *sub;
            json_array_foreach (v, i, sub) {
                char pi[540], idx[24];
                snprintf(idx, sizeof idx, "%zu", i);
                child_path(pi, sizeof pi, p, idx);
                json_t *t = translate(sub, pi, c);
                if (!t)
                    return -1;
                json_array_append_new(list, t);
            }
        } else {
            return fail(c, path, "keyword \"%.100s\" has no OpenAPI 3.0 translation here", k);
        }
    }
    return 0;
}

static json_t *translate(json_t *s, const char *path, oas_ctx *c)
{
    if (json_is_true(s))
        return json_object();
    if (json_is_false(s))
        return json_pack("{s:{}}", "not");
    if (!json_is_object(s)) {
        fail(c, path, "%s", "a schema must be an object or a boolean");
        return NULL;
    }
    json_t *out = json_object(), *alts = NULL;
    if (put_members(out, s, &alts, path, c) != 0) {
        json_decref(alts);
        json_decref(out);
        return NULL;
    }
    if (alts) { /* two or more types: anyOf, or a branch of allOf beside an anyOf of its own */
        if (json_object_get(out, "anyOf")) {
            json_t *all = json_object_get(out, "allOf");
            if (!all) {
                all = json_array();
                json_object_set_new(out, "allOf", all);
            }
            json_array_append_new(all, json_pack("{s:o}", "anyOf", alts));
        } else {
            json_object_set_new(out, "anyOf", alts);
        }
    }
    json_t *cond = json_object_get(s, "if");
    if (cond) {
        json_t *words = json_object_get(cond, "description");
        const char *sentence = json_is_string(words) ? json_string_value(words) : generic_condition;
        json_t *d = json_object_get(out, "description");
        if (json_is_string(d)) {
            const char *t = json_string_value(d);
            const size_t n = strlen(t);
            const char *sep = n && t[n - 1] == '.' ? " " : ". ";
            json_object_set_new(out, "description", json_sprintf("%s%s%s", t, sep, sentence));
        } else {
            json_object_set_new(out, "description", json_string(sentence));
        }
    }
    return out;
}

json_t *lubd_oas_schema(json_t *draft, char *err, size_t errlen)
{
    oas_ctx c = {err, errlen};
    if (errlen)
        err[0] = '\0';
    return translate(draft, "", &c);
}
