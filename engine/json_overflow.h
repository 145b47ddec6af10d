/* json_overflow.h — the member of a spec that holds a number beyond a double or an int64.
 *
 * jansson refuses such a number ("real number overflow", "too big integer") with the position
 * after it but no member. lub_json_overflow_member() replaces it by a marker string (and any
 * later such number by 0), parses the text again and looks the marker up, so that the refusal
 * names the member like every other spec error: "/phi: the number 1e400 (line 1 column 35) is
 * beyond the range of a double ...". It parses two copies with two markers and takes the place
 * where they differ, so that a string of the spec equal to a marker is not taken for it (until
 * 2026-12-07 one marker, and a spec string "\u0001number" before the number was named).
 *
 * text: the spec text jansson refused with *jerr. Returns 0 with *err naming the member, or -1
 * when the refusal was for another reason or the member cannot be found (*err untouched).
 * Allocates copies of text while it works (at most 100 parses); no state. */
#ifndef LUBDEM_JSON_OVERFLOW_H
#define LUBDEM_JSON_OVERFLOW_H

#include <jansson.h>

#include "spec_reader.h"

int lub_json_overflow_member(const char *text, const json_error_t *jerr, lub_error *err);

/* The same for a key jansson refused as a duplicate (JSON_REJECT_DUPLICATES gives its position,
 * not its object): the key is renamed to a marker in two copies, and the refusal names the
 * member, "/law/eps: the member appears twice in its object (again at line 1 column 35): give
 * it once". 0 with *err, or -1 (another reason, or not found; *err untouched). */
int lub_json_duplicate_member(const char *text, const json_error_t *jerr, lub_error *err);

/* A number in text (which jansson parsed) that is not 0 as written but below the smallest
 * double, which jansson reads as 0 without a word (1e-400: a "dt" of 0 would be taken as the
 * automatic step, an "St" refused as "got 0"): 0 with *err naming the member, "/dt: the number
 * 1e-400 (line 1 column 32) is below the range of a double ...", or -1 when there is none (or it
 * cannot be found). */
int lub_json_underflow_member(const char *text, lub_error *err);

#endif
