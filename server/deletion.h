/* deletion.h — freeing the disk space of deleted jobs.
 *
 * A DELETE of an ended job marks it purged in the database first, then frees its folder
 * jobs/<id>: the jobs that continue it and have not ended are handed its kept files
 * (lubd_continuation_hand_over), then the folder is removed. Either step can be cut short: the
 * service killed between them, a hand-over that fails (the folder is then kept, and the
 * continuations read the files from it). What is left is taken up again when one of those
 * continuations ends (lubd_deletion_continuation_ended) and at every start of the service
 * (lubd_deletion_sweep), so that a deleted job's folder outlives neither the service's next
 * start nor its last continuation.
 *
 * The functions only read the database (one caller-owned connection) and remove files; none
 * of them changes a job's state. */
#ifndef LUBD_DELETION_H
#define LUBD_DELETION_H

#include <sqlite3.h>
#include <stddef.h>

#include "queue.h"

/* Frees the folder of the purged job `id`: hands its files over to the jobs that continue it
 * and have not ended, then removes jobs_dir/<id>. Returns 0 when the folder is gone (or was
 * not there), 1 when it is kept because the hand-over failed, -1 when it could not be
 * removed; *why says why for 1 and -1. Must not be called for a job that is not purged (its
 * folder would be removed all the same). Callers in any thread or process are serialised by an
 * exclusive flock on the folder: one that waited finds the folder gone and returns 0. Where the
 * file system refuses that lock (NFS: EBADF on a folder), the free goes on without it. */
int lubd_deletion_free(sqlite3 *db, const char *jobs_dir, const char *id, char *why,
                       size_t why_len);

/* A continuation `id` of `source_id` has ended (or was dismissed before it started): removes
 * the files handed over to it (jobs_dir/<id>/continued-from/), and, if `source_id` is purged
 * and its folder was kept, frees that folder too (lubd_deletion_free; it may be kept again
 * for another continuation that has not ended). Returns 0, or -1 with *why set when a folder
 * could not be removed or was kept. */
int lubd_deletion_continuation_ended(sqlite3 *db, const char *jobs_dir, const char *id,
                                     const char *source_id, char *why, size_t why_len);

/* What the engines of an ended (not purged) job wrote outside its result/ and is never served:
 * the out/ folders of its earlier attempts (a requeued attempt's partial files that the next
 * attempt did not take over) and, for a job dismissed while it ran, its last attempt's out/
 * too; the job's resume-out/. The attempts' logs stay (GET /jobs/{id}/log), and so does the
 * last out/ of a job that did not end dismissed (a failed job's summary may be read from it).
 * A job that has not ended is left alone. Returns the number of folders removed, or -1 with
 * *why set when one could not be. */
int lubd_deletion_tidy_ended(const char *jobs_dir, const lubd_job *j, char *why, size_t why_len);

/* Takes up what deletions and ended continuations left in jobs_dir: for every folder named
 * after a job, a purged job's folder is freed (lubd_deletion_free), an ended continuation's
 * continued-from/ is removed and an ended job is tidied (lubd_deletion_tidy_ended). Folders that
 * are no job's are left alone. Prints a line on stderr for every folder it frees unless quiet, and
 * for every one it cannot. Returns the number of folders freed, or -1 when jobs_dir or the database
 * cannot be read (a jobs_dir that does not exist yet is 0). */
int lubd_deletion_sweep(sqlite3 *db, const char *jobs_dir, int quiet);

#endif
