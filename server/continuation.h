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
#include <stddef.h>

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

/* The folder, inside a continuation's job folder, that holds the earlier job's files once
 * that job has been deleted: jobs/<id>/continued-from/. */
#define LUBD_CONTINUED_FROM "continued-from"

/* Puts the files a continuation starts from (checkpoint.h5, and result.h5 and, after a periodic
 * checkpoint, checkpoint-result.h5 where from_dir has them) of from_dir into to_dir (created
 * when missing): hard links, or copies across file systems (lubd_link_or_copy). The engine
 * never writes to them in place (it writes new files under temporary names and renames them),
 * so the earlier job's files stay as they were. 0, or -1 with errno set and *why naming the
 * file (to_dir may then hold some of them). */
int lubd_continuation_link_files(const char *from_dir, const char *to_dir, char *why,
                                 size_t why_len);

/* A job being deleted hands its kept files over to the jobs that continue it and have not
 * ended (accepted or running): each gets hard links in jobs/<id>/continued-from/ (built under a
 * temporary name and renamed, so that the folder, when there, is complete), which its worker
 * takes instead of the deleted job's. Called once the source job is marked purged (no
 * continuation of it can be submitted after that: lubd_queue_submit checks it in its write
 * transaction) and before its folder is removed. Returns the number of jobs handed the files,
 * or -1 with *why set (the caller then keeps the source's folder, where the worker finds the
 * files). */
int lubd_continuation_hand_over(sqlite3 *db, const char *jobs_dir, const char *source_id, char *why,
                                size_t why_len);

#endif
