/* json_text.c — exact, short JSON reals (see json_text.h). */
#include "json_text.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

int lub_real_digits(double x)
{
    char buf[40];
    for (int p = 1; p < 17; ++p) {
        snprintf(buf, sizeof buf, "%.*g", p, x);
        const char *e = strchr(buf, 'e');
        if (e && atoi(e + 1) >= 0 && atoi(e + 1) < 15)
            continue; /* 20 as 2e+01: take the digits that print it as 20 */
        if (strtod(buf, NULL) == x)
            return p;
    }
    return 17; /* always exact for an IEEE 754 double */
}

const char *lub_real_text(double x, char out[40])
{
    snprintf(out, 40, "%.*g", lub_real_digits(x), x);
    return out;
}

/* x in jansson's style with lub_real_digits(x) digits: a '.' or an exponent always (so that it
 * reads back as a real), no '+' and no leading zeros in the exponent. Returns the length. */
static size_t format_real(double x, char out[40])
{
    char buf[40];
    lub_real_text(x, buf);
    size_t n = 0;
    for (const char *c = buf; *c; ++c) {
        out[n++] = *c;
        if (*c == 'e') {
            ++c;
            if (*c == '-' || *c == '+') {
                if (*c == '-')
                    out[n++] = '-';
                ++c;
            }
            while (*c == '0' && c[1])
                ++c;
            while (*c)
                out[n++] = *c++;
            break;
        }
    }
    out[n] = '\0';
    if (!strpbrk(out, ".e")) {
        out[n++] = '.';
        out[n++] = '0';
        out[n] = '\0';
    }
    return n;
}

char *lub_json_dumps(const json_t *v, size_t flags)
{
    if (!v)
        return NULL;
    flags &= ~(size_t)JSON_REAL_PRECISION(31);
    char *text = json_dumps(v, flags | JSON_REAL_PRECISION(17));
    if (!text)
        return NULL;
    /* Rewrite every real token (a number with '.' or an exponent, outside strings) in place:
     * the shortest exact form is never longer than the 17-digit one, and a longer one would be
     * left as it is. */
    size_t r = 0, w = 0;
    int in_string = 0;
    while (text[r]) {
        const char c = text[r];
        if (in_string) {
            text[w++] = text[r++];
            if (c == '\\' && text[r])
                text[w++] = text[r++];
            else if (c == '"')
                in_string = 0;
            continue;
        }
        if (c == '"')
            in_string = 1;
        if (c != '-' && (c < '0' || c > '9')) {
            text[w++] = text[r++];
            continue;
        }
        const size_t start = r;
        int real = 0;
        while (text[r] && strchr("+-0123456789.eE", text[r])) {
            real |= text[r] == '.' || text[r] == 'e' || text[r] == 'E';
            ++r;
        }
        const size_t len = r - start;
        char shortest[40];
        size_t n = 0;
        if (real && len < sizeof shortest) {
            char token[40];
            memcpy(token, text + start, len);
            token[len] = '\0';
            n = format_real(strtod(token, NULL), shortest);
        }
        if (n > 0 && n <= len) {
            memcpy(text + w, shortest, n);
            w += n;
        } else {
            memmove(text + w, text + start, len);
            w += len;
        }
    }
    text[w] = '\0';
    return text;
}

void lub_json_round_reals(json_t *v, int digits)
{
    if (json_is_real(v)) {
        char buf[40];
        snprintf(buf, sizeof buf, "%.*g", digits, json_real_value(v));
        json_real_set(v, strtod(buf, NULL));
    } else if (json_is_array(v)) {
        for (size_t k = 0; k < json_array_size(v); ++k)
            lub_json_round_reals(json_array_get(v, k), digits);
    } else if (json_is_object(v)) {
        const char *key;
        json_t *member;
        json_object_foreach (v, key, member)
            lub_json_round_reals(member, digits);
    }
}
