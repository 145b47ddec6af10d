/* spec_reader.c — typed, range-checked access to JSON spec fields with JSON-pointer errors. */
#include "spec_reader.h"

#include <math.h>
#include <stdint.h>
#include <stdarg.h>
#include <stdio.h>
#include <string.h>

#include "json_text.h"

int lub_fail(lub_error *err, const char *pointer, const char *fmt, ...)
{
    if (err) {
        snprintf(err->pointer, sizeof err->pointer, "%s", pointer ? pointer : "");
        va_list ap;
        va_start(ap, fmt);
        vsnprintf(err->message, sizeof err->message, fmt, ap);
        va_end(ap);
        lub_utf8_trim_tail(err->pointer);
        lub_utf8_trim_tail(err->message);
    }
    return -1;
}

/* The length of the valid UTF-8 character at s (1..4), 0 when s does not begin one. */
static size_t utf8_char_len(const unsigned char *s)
{
    const unsigned char c = s[0];
    if (c < 0x80)
        return 1;
    size_t n;
    unsigned char lo = 0x80, hi = 0xBF; /* the range of the second byte */
    if (c >= 0xC2 && c <= 0xDF) {
        n = 2;
    } else if (c >= 0xE0 && c <= 0xEF) {
        n = 3;
        if (c == 0xE0)
            lo = 0xA0; /* no overlong form */
        else if (c == 0xED)
            hi = 0x9F; /* no surrogate */
    } else if (c >= 0xF0 && c <= 0xF4) {
        n = 4;
        if (c == 0xF0)
            lo = 0x90;
        else if (c == 0xF4)
            hi = 0x8F; /* nothing beyond U+10FFFF */
    } else {
        return 0;
    }
    if (s[1] < lo || s[1] > hi)
        return 0;
    for (size_t i = 2; i < n; ++i)
        if ((s[i] & 0xC0) != 0x80)
            return 0;
    return n;
}

int lub_utf8_prefix(const char *s, size_t max)
{
    size_t n = 0;
    while (n < max && s[n])
        ++n;
    if (s[n]) /* cut: step back to the start of the character that would be cut */
        while (n > 0 && ((unsigned char)s[n] & 0xC0) == 0x80)
            --n;
    return n > INT32_MAX ? INT32_MAX : (int)n;
}

void lub_utf8_trim_tail(char *s)
{
    size_t n = strlen(s);
    if (n == 0)
        return;
    size_t lead = n - 1; /* the start of the last character */
    while (lead > 0 && ((unsigned char)s[lead] & 0xC0) == 0x80 && n - lead < 4)
        --lead;
    const unsigned char c = (unsigned char)s[lead];
    const size_t want = c < 0x80 ? 1 : c >= 0xF0 ? 4 : c >= 0xE0 ? 3 : c >= 0xC0 ? 2 : 1;
    if (n - lead < want)
        s[lead] = '\0';
}

const char *lub_text_one_line(const char *s, char *out, size_t size)
{
    if (size == 0)
        return out;
    size_t n = 0;
    const unsigned char *u = (const unsigned char *)s;
    while (*u) {
        char piece[8];
        size_t len = utf8_char_len(u);
        if (len == 1 && *u < 0x20) {
            const char *esc = *u == '\n' ? "\\n" : *u == '\t' ? "\\t" : *u == '\r' ? "\\r" : NULL;
            if (esc)
                snprintf(piece, sizeof piece, "%s", esc);
            else
                snprintf(piece, sizeof piece, "\\u%04X", *u);
        } else if (len == 1 && *u == 0x7F) {
            snprintf(piece, sizeof piece, "\\u007F");
        } else if (len == 0) {
            snprintf(piece, sizeof piece, "\\x%02X", *u);
            len = 1;
        } else {
            memcpy(piece, u, len);
            piece[len] = '\0';
        }
        const size_t plen = strlen(piece);
        if (n + plen >= size)
            break;
        memcpy(out + n, piece, plen);
        n += plen;
        u += len;
    }
    out[n] = '\0';
    return out;
}

const char *lub_pointer_join(char *buf, size_t size, const char *parent, const char *key)
{
    size_t n = (size_t)snprintf(buf, size, "%s/", parent ? parent : "");
    for (const char *c = key; *c && n + 3 < size; ++c) {
        if (*c == '~') {
            buf[n++] = '~';
            buf[n++] = '0';
        } else if (*c == '/') {
            buf[n++] = '~';
            buf[n++] = '1';
        } else {
            buf[n++] = *c;
        }
    }
    buf[n < size ? n : size - 1] = '\0';
    lub_utf8_trim_tail(buf); /* a key cut inside a character */
    return buf;
}

static const char *json_type_name(const json_t *v)
{
    switch (json_typeof(v)) {
    case JSON_OBJECT: return "an object";
    case JSON_ARRAY: return "an array";
    case JSON_STRING: return "a string";
    case JSON_INTEGER: return "an integer";
    case JSON_REAL: return "a number";
    case JSON_TRUE:
    case JSON_FALSE: return "a boolean";
    case JSON_NULL: return "null";
    }
    return "unknown";
}

/* 1 when name is one of the NULL-terminated list, 0 otherwise. */
static int name_listed(const char *const *list, const char *name)
{
    for (const char *const *a = list; *a; ++a)
        if (strcmp(*a, name) == 0)
            return 1;
    return 0;
}

/* The names of the NULL-terminated list into out[size] (size > 40), separated by ", ", each in
 * double quotes when quoted: for an error message. Names stop being added once fewer than 40
 * bytes are left; snprintf cuts the last one added at the end of out. */
static void list_names(const char *const *list, int quoted, char *out, size_t size)
{
    size_t n = 0;
    out[0] = '\0';
    for (const char *const *a = list; *a && n < size - 40; ++a)
        n += (size_t)snprintf(out + n, size - n, quoted ? "%s\"%s\"" : "%s%s",
                              a == list ? "" : ", ", *a);
}

int lub_spec_only_keys(const json_t *obj, const char *ptr, const char *const *allowed,
                       lub_error *err)
{
    const char *key;
    const json_t *value;
    char buf[256];
    json_object_foreach ((json_t *)obj, key, value) {
        if (!name_listed(allowed, key)) {
            /* list the allowed names so the user sees the typo */
            char names[400];
            list_names(allowed, 0, names, sizeof names);
            return lub_fail(err, lub_pointer_join(buf, sizeof buf, ptr, key),
                            "unknown field (allowed: %s)", names);
        }
    }
    (void)value;
    return 0;
}

static int range_check(double v, lub_range r, const char *p, lub_error *err)
{
    if (!isfinite(v))
        return lub_fail(err, p, "must be a finite number");
    char bound[40], got[40];
    if (!isnan(r.min) && (r.min_excl ? !(v > r.min) : !(v >= r.min)))
        return lub_fail(err, p, "must be %s %s (got %s)",
                        r.min_excl ? ">" : ">=", lub_real_text(r.min, bound),
                        lub_real_text(v, got));
    if (!isnan(r.max) && (r.max_excl ? !(v < r.max) : !(v <= r.max)))
        return lub_fail(err, p, "must be %s %s (got %s)",
                        r.max_excl ? "<" : "<=", lub_real_text(r.max, bound),
                        lub_real_text(v, got));
    return 0;
}

int lub_spec_number(json_t *obj, const char *ptr, const char *key, lub_range range, int has_default,
                    double def, double *out, lub_error *err)
{
    char p[256];
    lub_pointer_join(p, sizeof p, ptr, key);
    json_t *v = json_object_get(obj, key);
    if (!v) {
        if (!has_default)
            return lub_fail(err, p, "required number is missing");
        json_object_set_new(obj, key, json_real(def));
        *out = def;
        return 0;
    }
    if (!json_is_number(v))
        return lub_fail(err, p, "must be a number (got %s)", json_type_name(v));
    double x = json_number_value(v);
    if (range_check(x, range, p, err))
        return -1;
    *out = x;
    return 0;
}

int lub_spec_integer(json_t *obj, const char *ptr, const char *key, long long min, long long max,
                     int has_default, long long def, long long *out, lub_error *err)
{
    char p[256];
    lub_pointer_join(p, sizeof p, ptr, key);
    json_t *v = json_object_get(obj, key);
    if (!v) {
        if (!has_default)
            return lub_fail(err, p, "required integer is missing");
        json_object_set_new(obj, key, json_integer(def));
        *out = def;
        return 0;
    }
    long long x;
    const int written_as_real = json_is_real(v);
    if (json_is_integer(v)) {
        x = json_integer_value(v);
    } else if (written_as_real && json_real_value(v) == floor(json_real_value(v))) {
        const double r = json_real_value(v); /* 1e3 written as a real is still an integer */
        /* range first, and never convert beyond +-9e15 (exact in a double, no overflow) */
        char got[40];
        if (r < (double)min || r <= -9e15)
            return lub_fail(err, p, "must be >= %lld (got %s)", min, lub_real_text(r, got));
        if (r > (double)max || r >= 9e15)
            return lub_fail(err, p, "must be <= %lld (got %s)", max, lub_real_text(r, got));
        x = (long long)r;
    } else {
        return lub_fail(err, p, "must be an integer (got %s)", json_type_name(v));
    }
    if (x < min)
        return lub_fail(err, p, "must be >= %lld (got %lld)", min, x);
    if (x > max)
        return lub_fail(err, p, "must be <= %lld (got %lld)", max, x);
    if (written_as_real) /* the resolved spec states the integer as an integer */
        json_object_set_new(obj, key, json_integer(x));
    *out = x;
    return 0;
}

int lub_spec_bool(json_t *obj, const char *ptr, const char *key, int has_default, int def, int *out,
                  lub_error *err)
{
    char p[256];
    lub_pointer_join(p, sizeof p, ptr, key);
    json_t *v = json_object_get(obj, key);
    if (!v) {
        if (!has_default)
            return lub_fail(err, p, "required boolean is missing");
        json_object_set_new(obj, key, json_boolean(def));
        *out = def;
        return 0;
    }
    if (!json_is_boolean(v))
        return lub_fail(err, p, "must be a boolean (got %s)", json_type_name(v));
    *out = json_is_true(v);
    return 0;
}

int lub_spec_enum(json_t *obj, const char *ptr, const char *key, const char *const *choices,
                  const char *def, const char **out, lub_error *err)
{
    char p[256];
    lub_pointer_join(p, sizeof p, ptr, key);
    json_t *v = json_object_get(obj, key);
    if (!v) {
        if (!def)
            return lub_fail(err, p, "required string is missing");
        json_object_set_new(obj, key, json_string(def));
        v = json_object_get(obj, key);
    }
    if (!json_is_string(v))
        return lub_fail(err, p, "must be a string (got %s)", json_type_name(v));
    const char *s = json_string_value(v);
    if (choices && !name_listed(choices, s)) {
        char names[400];
        list_names(choices, 1, names, sizeof names);
        return lub_fail(err, p, "must be one of %s (got \"%.*s\")", names, lub_utf8_prefix(s, 80),
                        s);
    }
    *out = s; /* borrowed from obj: valid while obj lives */
    return 0;
}

int lub_spec_vector(json_t *obj, const char *ptr, const char *key, int len, lub_range range,
                    const double *def, double *out, lub_error *err)
{
    char p[256];
    lub_pointer_join(p, sizeof p, ptr, key);
    json_t *v = json_object_get(obj, key);
    if (!v) {
        if (!def)
            return lub_fail(err, p, "required array of %d numbers is missing", len);
        json_t *a = json_array();
        for (int i = 0; i < len; ++i) {
            json_array_append_new(a, json_real(def[i]));
            out[i] = def[i];
        }
        json_object_set_new(obj, key, a);
        return 0;
    }
    if (!json_is_array(v) || (int)json_array_size(v) != len)
        return lub_fail(err, p, "must be an array of %d numbers", len);
    for (int i = 0; i < len; ++i) {
        char pi[272];
        snprintf(pi, sizeof pi, "%s/%d", p, i);
        json_t *e = json_array_get(v, (size_t)i);
        if (!json_is_number(e))
            return lub_fail(err, pi, "must be a number (got %s)", json_type_name(e));
        out[i] = json_number_value(e);
        if (range_check(out[i], range, pi, err))
            return -1;
    }
    return 0;
}

json_t *lub_spec_object(json_t *obj, const char *ptr, const char *key, lub_error *err)
{
    char p[256];
    lub_pointer_join(p, sizeof p, ptr, key);
    json_t *v = json_object_get(obj, key);
    if (!v) {
        json_object_set_new(obj, key, json_object());
        return json_object_get(obj, key);
    }
    if (!json_is_object(v)) {
        lub_fail(err, p, "must be an object (got %s)", json_type_name(v));
        return NULL;
    }
    return v;
}

int lub_spec_sample_count(double strain, double sample_strain, double max_samples, const char *cost,
                          lub_error *err)
{
    if (!(strain / sample_strain > max_samples))
        return 0;
    char least[40], got[40];
    return lub_fail(err, "/sample_strain",
                    "the run would keep strain / sample_strain = %.3g samples, more than %.0e "
                    "(%s): raise /sample_strain to at least %s or lower /strain (got %s)",
                    strain / sample_strain, max_samples, cost,
                    lub_real_text(strain / max_samples, least), lub_real_text(sample_strain, got));
}
