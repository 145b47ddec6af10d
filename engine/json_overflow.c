/* json_overflow.c — the member holding a number jansson refused as too large, or a duplicate
 * key (json_overflow.h). */
#include "json_overflow.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* The markers put in place of the refused number (a string value) or duplicate key; each is
 * put in one of two copies, and the member is where the copies differ, so that a spec string
 * or key equal to a marker is not taken for it. */
static const char *const value_mark[2] = {"\001number", "\002number"};
static const char *const value_mark_json[2] = {"\"\\u0001number\"", "\"\\u0002number\""};
static const char *const key_mark[2] = {"\001key", "\002key"};
static const char *const key_mark_json[2] = {"\"\\u0001key\"", "\"\\u0002key\""};

/* Appends "/" and key, escaped (RFC 6901: "~" as "~0", "/" as "~1"), to at[len]; cut where at is
 * full (lub_fail cuts a character cut in two). */
static void append_key(char *at, size_t len, const char *key)
{
    size_t n = strlen(at);
    if (n + 1 < len)
        at[n++] = '/';
    for (const char *c = key; *c && n + 2 < len; ++c) {
        if (*c == '~' || *c == '/') {
            at[n++] = '~';
            at[n++] = *c == '~' ? '0' : '1';
        } else {
            at[n++] = *c;
        }
    }
    at[n] = '\0';
}

/* The JSON pointer of the marker within a (the copy with marker 0) and b (marker 1), appended to
 * at[len] (which holds their pointer); 1 when found. keys: the markers are keys, and the pointer
 * ends with `key` in place of the marker; otherwise string values. */
static int find_mark(const json_t *a, const json_t *b, int keys, const char *key, char *at,
                     size_t len)
{
    const size_t used = strlen(at);
    if (!b)
        return 0;
    if (!keys && json_is_string(a) && json_is_string(b))
        return strcmp(json_string_value(a), value_mark[0]) == 0 &&
               strcmp(json_string_value(b), value_mark[1]) == 0;
    if (json_is_array(a) && json_is_array(b)) {
        for (size_t k = 0; k < json_array_size(a); ++k) {
            snprintf(at + used, len - used, "/%zu", k);
            if (find_mark(json_array_get(a, k), json_array_get(b, k), keys, key, at, len))
                return 1;
        }
    } else if (json_is_object(a) && json_is_object(b)) {
        if (keys && json_object_get(a, key_mark[0]) && !json_object_get(b, key_mark[0]) &&
            json_object_get(b, key_mark[1]) && !json_object_get(a, key_mark[1])) {
            append_key(at, len, key);
            return 1;
        }
        const char *k;
        json_t *member;
        json_object_foreach ((json_t *)a, k, member) {
            append_key(at, len, k);
            if (find_mark(member, json_object_get(b, k), keys, key, at, len))
                return 1;
            at[used] = '\0';
        }
    }
    at[used] = '\0';
    return 0;
}

/* The number jansson refused as beyond a double ("real number overflow") or an int64 ("too big
 * integer"): text[*start, error position) (the position is the byte after it); 1 when found. */
static int overflow_token(const char *text, const json_error_t *jerr, size_t *start, size_t *end)
{
    if (!strstr(jerr->text, "real number overflow") && !strstr(jerr->text, "too big"))
        return 0;
    *end = (size_t)jerr->position;
    if (jerr->position < 0 || *end > strlen(text))
        return 0;
    for (*start = *end; *start > 0 && strchr("0123456789+-.eE", text[*start - 1]);)
        --*start;
    return *start < *end && *end - *start <= 400;
}

/* text with text[start, end) replaced by with, or NULL when out of memory (caller frees). */
static char *splice(const char *text, size_t start, size_t end, const char *with)
{
    const size_t len = strlen(text), wlen = strlen(with);
    char *out = malloc(len - (end - start) + wlen + 1);
    if (out) {
        memcpy(out, text, start);
        memcpy(out + start, with, wlen);
        memcpy(out + start + wlen, text + end, len - end + 1);
    }
    return out;
}

/* The key jansson refused as a duplicate: text[*start, *end), the quoted key that ends at the
 * error position; 1 when found. */
static int duplicate_token(const char *text, const json_error_t *jerr, size_t *start, size_t *end)
{
    if (json_error_code(jerr) != json_error_duplicate_key || jerr->position < 2)
        return 0;
    *end = (size_t)jerr->position;
    if (*end > strlen(text) || text[*end - 1] != '"')
        return 0;
    for (size_t i = *end - 1; i-- > 0;) {
        if (text[i] != '"')
            continue;
        size_t slashes = 0;
        while (i > slashes && text[i - 1 - slashes] == '\\')
            ++slashes;
        if (slashes % 2 == 0) {
            *start = i;
            return 1;
        }
    }
    return 0;
}

/* text with text[start, end) replaced by with and parsed again: any later number beyond the
 * range as 0, any later duplicate key renamed (at most 100 parses). NULL when it still does
 * not parse, or out of memory. */
static json_t *parse_with(const char *text, size_t start, size_t end, const char *with)
{
    char *again = splice(text, start, end, with);
    json_t *doc = NULL;
    for (int k = 0; again && !doc && k < 100; ++k) {
        json_error_t later;
        size_t s0, e0;
        char renamed[32];
        doc = json_loads(again, JSON_REJECT_DUPLICATES, &later);
        if (doc)
            break;
        char *next = NULL;
        if (overflow_token(again, &later, &s0, &e0)) {
            next = splice(again, s0, e0, "0");
        } else if (duplicate_token(again, &later, &s0, &e0)) {
            snprintf(renamed, sizeof renamed, "\"\\u0003%d\"", k);
            next = splice(again, s0, e0, renamed);
        }
        free(again);
        again = next;
    }
    free(again);
    return doc;
}

/* The pointer of the member text[start, end) is in (keys: the key, named `key`), into at. */
static int find_member(const char *text, size_t start, size_t end, int keys, const char *key,
                       char *at, size_t len)
{
    const char *const *marks = keys ? key_mark_json : value_mark_json;
    json_t *a = parse_with(text, start, end, marks[0]);
    json_t *b = a ? parse_with(text, start, end, marks[1]) : NULL;
    at[0] = '\0';
    const int found = a && b && find_mark(a, b, keys, key, at, len);
    json_decref(a);
    json_decref(b);
    return found;
}

int lub_json_overflow_member(const char *text, const json_error_t *jerr, lub_error *err)
{
    size_t start, end;
    if (!overflow_token(text, jerr, &start, &end))
        return -1;
    char at[sizeof err->pointer];
    if (!find_member(text, start, end, 0, NULL, at, sizeof at))
        return -1;
    lub_fail(err, at, "the number %.*s (line %d column %d) is beyond the range of %s",
             (int)(end - start), text + start, jerr->line, jerr->column,
             strstr(jerr->text, "real") ? "a double (magnitude above 1.8e308)"
                                        : "a 64-bit integer (magnitude above 9.2e18)");
    return 0;
}

int lub_json_duplicate_member(const char *text, const json_error_t *jerr, lub_error *err)
{
    size_t start, end;
    if (!duplicate_token(text, jerr, &start, &end))
        return -1;
    json_error_t kerr;
    json_t *k = json_loadb(text + start, end - start, JSON_DECODE_ANY, &kerr);
    char at[sizeof err->pointer];
    const int found =
        json_is_string(k) && find_member(text, start, end, 1, json_string_value(k), at, sizeof at);
    json_decref(k);
    if (!found)
        return -1;
    lub_fail(err, at,
             "the member appears twice in its object (again at line %d column %d): "
             "give it once",
             jerr->line, jerr->column);
    return 0;
}

int lub_json_underflow_member(const char *text, lub_error *err)
{
    int in_string = 0, line = 1;
    const char *line_start = text;
    for (const char *c = text; *c; ++c) {
        if (in_string) {
            if (*c == '\\' && c[1])
                ++c;
            else if (*c == '"')
                in_string = 0;
            continue;
        }
        if (*c == '"') {
            in_string = 1;
        } else if (*c == '\n') {
            ++line;
            line_start = c + 1;
        } else if (*c == '-' || (*c >= '0' && *c <= '9')) {
            const char *e = c;
            int nonzero = 0, in_exponent = 0;
            for (; *e && strchr("0123456789+-.eE", *e); ++e) {
                if (*e == 'e' || *e == 'E')
                    in_exponent = 1;
                else if (!in_exponent && *e >= '1' && *e <= '9')
                    nonzero = 1;
            }
            const size_t start = (size_t)(c - text), end = (size_t)(e - text);
            if (nonzero && end - start <= 400 && strtod(c, NULL) == 0.0) {
                char at[sizeof err->pointer];
                if (!find_member(text, start, end, 0, NULL, at, sizeof at))
                    return -1;
                lub_fail(err, at,
                         "the number %.*s (line %d column %d) is below the range of a double "
                         "(magnitude below 4.9e-324): it would be read as 0",
                         (int)(end - start), c, line, (int)(c - line_start) + 1);
                return 0;
            }
            c = e - 1;
        }
    }
    return -1;
}
