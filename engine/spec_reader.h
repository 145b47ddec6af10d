/* spec_reader.h — reading and validating a JSON job spec with errors that name the field.
 *
 * Every accessor takes the parent object and its JSON pointer, checks type and range, and on
 * failure fills a lub_error with the JSON pointer of the offending field and the constraint
 * it violates. Accessors with a default insert the default into the object (so the object
 * becomes the "resolved" spec). Ownership: the json_t objects belong to the caller; nothing
 * here keeps a reference. Pure except for writing the error and the defaulted fields.
 */
#ifndef LUBDEM_SPEC_READER_H
#define LUBDEM_SPEC_READER_H

#include <jansson.h>
#include <math.h>
#include <stddef.h>

typedef struct {
    char pointer[256]; /* JSON pointer of the offending field, "" for the document root */
    char message[512]; /* the constraint, in words, including the value received */
} lub_error;

/* Sets the error and returns -1 (for "return lub_fail(...)"). printf-style message. A pointer
 * or message longer than its buffer is cut on a UTF-8 character boundary (lub_utf8_trim_tail),
 * so that both stay valid UTF-8 when what was put in them was. */
int lub_fail(lub_error *err, const char *pointer, const char *fmt, ...)
    __attribute__((format(printf, 3, 4)));

/* Builds "parent/key" into buf (escaping ~ and / per RFC 6901). Returns buf. A pointer longer
 * than size - 1 bytes is cut, on a UTF-8 character boundary. */
const char *lub_pointer_join(char *buf, size_t size, const char *parent, const char *key);

/* The length of the longest prefix of s of at most max bytes that does not end inside a UTF-8
 * character: for quoting a user's string cut to a length ("%.*s"). */
int lub_utf8_prefix(const char *s, size_t max);

/* Cuts an incomplete UTF-8 character off the end of s (what a full buffer leaves of a
 * multi-byte character). */
void lub_utf8_trim_tail(char *s);

/* s for a one-line message into out[size]: control characters as \n, \t, \r or \u00XX and
 * bytes that are not valid UTF-8 as \xNN (a backslash stays as it is), cut on a character
 * boundary when out is too small. Returns out. */
const char *lub_text_one_line(const char *s, char *out, size_t size);

/* Rejects any member of obj not in the NULL-terminated list `allowed`. */
int lub_spec_only_keys(const json_t *obj, const char *ptr, const char *const *allowed,
                       lub_error *err);

/* Numbers. Range: [min, max] inclusive unless the *_excl flag says exclusive. NaN bounds mean
 * unbounded. If the key is absent: with has_default, the default is stored and returned;
 * otherwise it is an error ("required"). Integers in JSON are accepted as numbers. */
typedef struct {
    double min, max;
    int min_excl, max_excl;
} lub_range;
int lub_spec_number(json_t *obj, const char *ptr, const char *key, lub_range range, int has_default,
                    double def, double *out, lub_error *err);
int lub_spec_integer(json_t *obj, const char *ptr, const char *key, long long min, long long max,
                     int has_default, long long def, long long *out, lub_error *err);
int lub_spec_bool(json_t *obj, const char *ptr, const char *key, int has_default, int def, int *out,
                  lub_error *err);
/* String that must be one of the NULL-terminated `choices` (NULL choices = any string). */
int lub_spec_enum(json_t *obj, const char *ptr, const char *key, const char *const *choices,
                  const char *def, const char **out, lub_error *err);
/* Fixed-length array of numbers (e.g. a 3-vector), each in range. */
int lub_spec_vector(json_t *obj, const char *ptr, const char *key, int len, lub_range range,
                    const double *def, double *out, lub_error *err);
/* Optional sub-object: returns it (creating an empty one if absent); error if not an object. */
json_t *lub_spec_object(json_t *obj, const char *ptr, const char *key, lub_error *err);
/* A run that samples every `sample_strain` up to `strain` keeps strain / sample_strain samples:
 * more than max_samples is an error at /sample_strain that says what each sample costs (`cost`,
 * e.g. "232 bytes of memory each") and the smallest sample_strain allowed. 0 or -1. */
int lub_spec_sample_count(double strain, double sample_strain, double max_samples, const char *cost,
                          lub_error *err);

#define LUB_UNBOUNDED ((lub_range){-INFINITY, INFINITY, 0, 0})
#define LUB_POSITIVE ((lub_range){0.0, INFINITY, 1, 0})
#define LUB_NONNEGATIVE ((lub_range){0.0, INFINITY, 0, 0})

#endif
