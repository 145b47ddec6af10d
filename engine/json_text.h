/* json_text.h — text of reals that is exact and as short as possible (JSON and messages).
 *
 * jansson prints every real with a fixed number of significant digits (17 by default), so a
 * value read as 0.3 comes back as 0.29999999999999999 and one read from a 10-digit summary as
 * 0.88912216990000004. lub_json_dumps() prints each real with the fewest significant digits
 * (1..17) that read back to the same double, in jansson's style otherwise (always a '.' or an
 * exponent; 20.0 and 1e6 as 20.0 and 1000000.0, exponents from 1e15 and below 1e-4).
 *
 * flags: jansson's json_dumps flags; a JSON_REAL_PRECISION among them is ignored.
 * Returns a NUL-terminated string the caller frees with free(), or NULL (v NULL, or out of
 * memory). Thread-safe; does not modify v. */
#ifndef LUBDEM_JSON_TEXT_H
#define LUBDEM_JSON_TEXT_H

#include <jansson.h>

char *lub_json_dumps(const json_t *v, size_t flags);

/* Every real within v (objects and arrays, recursively) replaced in place by the double nearest
 * its "%.*g" text at `digits` significant digits (1..17), so that lub_json_dumps prints it with
 * at most that many. For readable results; not for a spec, which must stay exact. */
void lub_json_round_reals(json_t *v, int digits);

/* x as its shortest exact decimal ("%.*g" with lub_real_digits(x) digits: 0.6, 1e+30,
 * 1000000) into out, for messages that quote a spec's numbers; returns out. */
const char *lub_real_text(double x, char out[40]);

/* The smallest number of significant digits (1..17) at which "%.*g" of x reads back as x and
 * does not write a number below 1e15 in exponent form (20.0 needs 2 digits, not the 1 of
 * "2e+01"; 1e6 needs 7). */
int lub_real_digits(double x);

#endif
