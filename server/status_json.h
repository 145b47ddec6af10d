/* status_json.h — OGC statusInfo documents for job rows.
 * Returns a new JSON object owned by the caller (NULL only on allocation failure).
 * `base` is the absolute URL prefix for links (e.g. "http://127.0.0.1:8080"). */
#ifndef LUBD_STATUS_JSON_H
#define LUBD_STATUS_JSON_H

#include <jansson.h>
#include <stddef.h>

#include "queue.h"

json_t *lubd_status_json(const lubd_job *j, const char *base, int with_user);
/* RFC 3339 UTC with milliseconds, e.g. 2026-11-22T00:41:52.123Z. */
void lubd_rfc3339(double epoch_s, char *buf, size_t n);
int lubd_job_finished(const lubd_job *j); /* successful, failed or dismissed */

/* An RFC 3339 date-time (YYYY-MM-DDTHH:MM:SS[.frac] then Z or +HH:MM/-HH:MM; t, z and a
 * space for T accepted, and a space for the offset's + as a query string may decode it) as
 * milliseconds since the epoch: *floor_ms its instant cut to the millisecond, *ceil_ms the
 * first millisecond at or after it. 0, or -1 when s is not one. */
int lubd_parse_rfc3339(const char *s, long long *floor_ms, long long *ceil_ms);

#endif
