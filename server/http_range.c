/* http_range.c — "bytes=a-b", "bytes=a-", "bytes=-n". */
#include "http_range.h"

#include <string.h>
#include <strings.h>

/* Parses decimal digits; returns number of digits (0 = none), -1 on overflow. */
static int parse_u64(const char **s, uint64_t *out)
{
    uint64_t v = 0;
    int n = 0;
    while (**s >= '0' && **s <= '9') {
        unsigned d = (unsigned)(**s - '0');
        if (v > (UINT64_MAX - d) / 10)
            return -1;
        v = v * 10 + d;
        ++*s;
        ++n;
    }
    *out = v;
    return n;
}

int lubd_range_parse(const char *h, uint64_t size, uint64_t *first, uint64_t *last)
{
    if (!h)
        return LUBD_RANGE_NONE;
    while (*h == ' ')
        ++h;
    if (strncasecmp(h, "bytes=", 6) != 0)
        return LUBD_RANGE_NONE;
    h += 6;
    while (*h == ' ')
        ++h;
    if (strchr(h, ','))
        return LUBD_RANGE_NONE; /* multiple ranges: serve the whole representation */
    uint64_t a = 0, b = 0;
    int na = parse_u64(&h, &a);
    if (na < 0 || *h != '-')
        return LUBD_RANGE_NONE;
    ++h;
    int nb = parse_u64(&h, &b);
    if (nb < 0)
        return LUBD_RANGE_NONE;
    while (*h == ' ')
        ++h;
    if (*h != '\0' || (na == 0 && nb == 0))
        return LUBD_RANGE_NONE;
    if (na == 0) { /* suffix: last b bytes */
        if (b == 0 || size == 0)
            return LUBD_RANGE_UNSATISFIABLE;
        *first = b >= size ? 0 : size - b;
        *last = size - 1;
        return LUBD_RANGE_OK;
    }
    if (nb > 0 && b < a)
        return LUBD_RANGE_NONE; /* invalid syntax per RFC: ignore */
    if (a >= size)
        return LUBD_RANGE_UNSATISFIABLE;
    *first = a;
    *last = (nb == 0 || b >= size) ? size - 1 : b;
    return LUBD_RANGE_OK;
}
