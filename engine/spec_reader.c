/* spec_reader.c — typed, range-checked access to JSON spec fields with JSON-pointer errors. */
#include "spec_reader.h"

#include <math.h>
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
    }
    return -1;
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

int lub_spec_only_keys(const json_t *obj, const char *ptr, const char *const *allowed,
                       lub_error *err)
{
    const char *key;
    const json_t *value;
    char buf[256];
    json_object_foreach ((json_t *)obj, key, value) {
        int ok = 0;
        for (const char *const *a = allowed; *a; ++a)
            if (strcmp(*a, key) == 0) {
                ok = 1;
                break;
            }
        if (!ok) {
            /* list the allowed names so the user sees the typo */
            char names[400];
            size_t n = 0;
            names[0] = '\0';
            for (const char *const *a = allowed; *a && n < sizeof names - 40; ++a)
                n += (size_t)snprintf(names + n, sizeof names - n, "%s%s", a == allowed ? "" : ", ",
                                      *a);
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
    if (choices) {
        int ok = 0;
        for (const char *const *c = choices; *c; ++c)
            if (strcmp(*c, s) == 0) {
                ok = 1;
                break;
            }
        if (!ok) {
            char names[400];
            size_t n = 0;
            names[0] = '\0';
            for (const char *const *c = choices; *c && n < sizeof names - 40; ++c)
                n += (size_t)snprintf(names + n, sizeof names - n, "%s\"%s\"",
                                      c == choices ? "" : ", ", *c);
            return lub_fail(err, p, "must be one of %s (got \"%.80s\")", names, s);
        }
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
