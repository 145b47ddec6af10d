/* http_range.h — parsing a single HTTP byte range (RFC 9110 §14.1.2) against a file size.
 * Pure; fuzzed. Multi-range and malformed headers are ignored (whole file, 200) as RFC 9110
 * allows; only a syntactically valid but unsatisfiable single range yields 416. */
#ifndef LUBD_HTTP_RANGE_H
#define LUBD_HTTP_RANGE_H

#include <stdint.h>

enum { LUBD_RANGE_NONE = 0, LUBD_RANGE_OK = 1, LUBD_RANGE_UNSATISFIABLE = 2 };

/* header may be NULL. On LUBD_RANGE_OK, [*first, *last] is inclusive and within size. */
int lubd_range_parse(const char *header, uint64_t size, uint64_t *first, uint64_t *last);

#endif
