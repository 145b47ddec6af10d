/* exec_request.h — parsing and validating a POST /processes/{id}/execution body.
 *
 * Body: {"inputs": {...scene parameters...}, "priority"?: -10..10, "outputs"?: {},
 *        "response"?: "document", "subscriber"?: {}, "continue_from"?: jobID}. Unknown members
 * are rejected. continue_from is checked for its form and the scene here (resumable scenes
 * only); whether that job can be continued with this spec is server/continuation.h.
 * The engine spec is the "inputs" object plus "scene": <process id>; it is validated with the
 * engine's own lub_spec_resolve(), and engine error pointers are re-rooted under "/inputs".
 * Pure (no I/O); the lubFuzzer target drives this function directly.
 * On success the caller owns the json_t references in *r (free with lubd_exec_free). */
#ifndef LUBD_EXEC_REQUEST_H
#define LUBD_EXEC_REQUEST_H

#include <jansson.h>
#include <stddef.h>

#include "problem.h"

typedef struct {
    json_t *body;     /* parsed body */
    json_t *spec;     /* inputs + scene, as submitted */
    json_t *resolved; /* spec with every default filled in */
    int priority;
    char fingerprint[65];   /* sha256 of process id + canonical body (sorted, compact, reals
                             * of integral value as integers: numbers compare by value) */
    char continue_from[33]; /* "continue_from" of the body ("" = none) */
} lubd_exec_request;

/* Returns 0, or -1 with *f set (400 malformed/invalid, 404 unknown process). */
int lubd_exec_parse(const char *body, size_t len, const char *process_id, lubd_exec_request *r,
                    lubd_fault *f);
void lubd_exec_free(lubd_exec_request *r);

#endif
