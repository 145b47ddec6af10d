/* json_overflow.c — the member holding a number jansson refused as too large (json_overflow.h). */
#include "json_overflow.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* The JSON pointer of the first string equal to mark within node (RFC 6901: "~" as "~0", "/"
 * as "~1"), appended to at[len] (which holds node's pointer); 1 when found. */
static int find_string(const json_t *node, const char *mark, char *at, size_t len)
{
    const size_t used = strlen(at);
    if (json_is_string(node))
        return strcmp(json_string_value(node), mark) == 0;
    if (json_is_array(node)) {
        for (size_t k = 0; k < json_array_size(node); ++k) {
            snprintf(at + used, len - used, "/%zu", k);
            if (find_string(json_array_get(node, k), mark, at, len))
                return 1;
        }
    } else if (json_is_object(node)) {
        const char *key;
        json_t *member;
        json_object_foreach ((json_t *)node, key, member) {
            size_t n = used;
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
            if (find_string(member, mark, at, len))
                return 1;
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

int lub_json_overflow_member(const char *text, const json_error_t *jerr, lub_error *err)
{
    size_t start, end;
    if (!overflow_token(text, jerr, &start, &end))
        return -1;
    char *again = splice(text, start, end, "\"\\u0001number\"");
    json_t *doc = NULL;
    for (int k = 0; again && !doc && k < 100; ++k) {
        json_error_t later;
        size_t s0, e0;
        doc = json_loads(again, JSON_REJECT_DUPLICATES, &later);
        if (doc || !overflow_token(again, &later, &s0, &e0))
            break;
        char *next = splice(again, s0, e0, "0");
        free(again);
        again = next;
    }
    free(again);
    char at[sizeof err->pointer] = "";
    const int found = doc && find_string(doc, "\001number", at, sizeof at);
    json_decref(doc);
    if (!found)
        return -1;
    lub_fail(err, at, "the number %.*s (line %d column %d) is beyond the range of %s",
             (int)(end - start), text + start, jerr->line, jerr->column,
             strstr(jerr->text, "real") ? "a double (magnitude above 1.8e308)"
                                        : "a 64-bit integer (magnitude above 9.2e18)");
    return 0;
}
