/* continuation.h — may a submitted job continue another job's checkpoint?
 *
 * A POST .../execution body with "continue_from": <jobID> asks for a job that continues the
 * run of that earlier job (lubdem run --resume on a copy of its result.h5 and checkpoint.h5)
 * instead of starting afresh: a run stopped at the service's CPU time limit goes on, a
 * completed simple_shear run is extended to a larger /strain or a smaller /target_rel_error.
 * Checked at submission, so that a continuation that cannot work is a 400 naming the member at
 * fault, never a queued job that fails: the earlier job is visible to the user, of the same
 * process, finished, not deleted, kept a checkpoint, and its spec agrees with this one but for
 * the members the scene lets a continuation change (engine/resume_spec.h, the engine's own
 * rule). The engine checks again when it runs (the strain already done, the files). */
#ifndef LUBD_CONTINUATION_H
#define LUBD_CONTINUATION_H

#include <jansson.h>
#include <sqlite3.h>

#include "problem.h"

typedef struct {
    const char *source_id;  /* the job to continue */
    long long user_id;      /* the submitter */
    int is_admin;           /* admins may continue any user's job */
    const char *process_id; /* of the new job */
    const json_t *resolved; /* the new job's resolved spec */
} lubd_continuation;

/* 0 when the job may be submitted; -1 with *f set: 400 at /continue_from (unknown, another
 * user's, another process, not finished, deleted, no checkpoint) or at /inputs/... (a member
 * that must be the earlier job's), 500 on a database error. */
int lubd_continuation_check(sqlite3 *db, const lubd_continuation *c, lubd_fault *f);

#endif
