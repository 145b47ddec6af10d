/* json_text.h — JSON text whose reals are exact and as short as the document allows.
 *
 * jansson prints every real with a fixed number of significant digits (17 by default), so a
 * value read as 0.3 comes back as 0.29999999999999999 and one read from a 10-digit summary as
 * 0.88912216990000004. lub_json_dumps() prints the whole document with the smallest precision
 * (1..17 significant digits) at which every real in it reads back to the same double: each real
 * then prints as its shortest exact decimal, except that a document holding a real that needs
 * 16 or 17 digits prints all its reals at that precision (exact, not always shortest).
 *
 * flags: jansson's json_dumps flags without JSON_REAL_PRECISION (which is replaced).
 * Returns what json_dumps returns: a NUL-terminated string the caller frees with free(), or
 * NULL (v NULL, or out of memory). Thread-safe; does not modify v. */
#ifndef LUBDEM_JSON_TEXT_H
#define LUBDEM_JSON_TEXT_H

#include <jansson.h>

char *lub_json_dumps(const json_t *v, size_t flags);

/* The smallest number of significant digits (1..17) at which "%.*g" of x reads back as x and
 * does not write a number below 1e15 in exponent form (20.0 needs 2 digits, not the 1 of
 * "2e+01"; 1e6 needs 7). */
int lub_real_digits(double x);

#endif
