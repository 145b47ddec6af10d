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

#endif
