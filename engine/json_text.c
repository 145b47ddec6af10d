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

/* The largest lub_real_digits over the reals of v (0 when it holds none). */
static int max_real_digits(const json_t *v)
{
    int most = 0;
    if (json_is_real(v)) {
        most = lub_real_digits(json_real_value(v));
    } else if (json_is_object(v)) {
        const char *key;
        json_t *member;
        json_object_foreach ((json_t *)v, key, member) {
            const int d = max_real_digits(member);
            most = d > most ? d : most;
            if (most == 17)
                break;
        }
    } else if (json_is_array(v)) {
        for (size_t i = 0; i < json_array_size(v) && most < 17; ++i) {
            const int d = max_real_digits(json_array_get(v, i));
            most = d > most ? d : most;
        }
    }
    return most;
}

char *lub_json_dumps(const json_t *v, size_t flags)
{
    if (!v)
        return NULL;
    const int digits = max_real_digits(v);
    flags &= ~(size_t)JSON_REAL_PRECISION(31);
    return json_dumps(v, flags | JSON_REAL_PRECISION(digits > 0 ? digits : 17));
}
