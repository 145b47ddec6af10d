/* worker.h — one worker process: claims jobs and runs the engine for each.
 *
 * Started by the supervisor as `lubdemd worker <options>` (a fresh exec, so no database
 * connection or thread crosses fork()). Loop: claim (lease + fencing token), run
 * `lubdem run spec.json --out <job>/attempt-<n>/out` (engine_child.h), stream progress into
 * the job row with each heartbeat, stop the engine (SIGTERM, then SIGKILL after grace_s) when
 * the lease is lost or the job is dismissed, and finish with a fenced transaction (lease.h).
 * An engine crash fails the job with its diagnostic and is not retried. SIGTERM to the
 * worker: stop the engine and give the job back. Returns the process exit code. */
#ifndef LUBD_WORKER_H
#define LUBD_WORKER_H

#include <sqlite3.h>

#include "config.h"

int lubd_worker_main(const lubd_config *cfg, const char *name);

/* At the service's start, before the reaper (lubd_queue_reap_orphans): each job a service that
 * died left running on its last attempt whose engine had written a checkpoint fails with that
 * checkpoint kept as its files (checkpoint.h5, and the file holding its rows), so that it can
 * be continued ("continue_from"), as after an engine killed from outside on its last attempt.
 * The reaper fails the others. Returns how many were failed so, or -1 on a database error. */
int lubd_worker_keep_orphan_checkpoints(const lubd_config *cfg, sqlite3 *db);

/* The same while the service runs, for the jobs of one worker process that died (its name as
 * the jobs' worker column holds it, "w<slot>-pid<pid>"; its engine is killed with it,
 * PR_SET_PDEATHSIG): those on their last attempt whose engine had written a checkpoint fail at
 * once with it, their message saying "its worker process died (<how>)". The reaper requeues
 * the others, or fails them, when their leases expire. Returns how many were failed so, or -1
 * on a database error. Checksums the kept files (blocks for as long). */
int lubd_worker_keep_dead_worker_checkpoints(const lubd_config *cfg, sqlite3 *db,
                                             const char *worker, const char *how);

/* `lubdemd keep-checkpoints --worker NAME --how HOW <worker options>` (internal): the process
 * the supervisor starts when a worker process died holding jobs on their last attempt, so that
 * it does not itself wait while their files are checksummed (supervisor.h). Opens its own
 * connection to cfg->db_path, runs lubd_worker_keep_dead_worker_checkpoints for NAME (which
 * heartbeats each lease while it checksums, and records the files' sha256 in the transaction
 * that fails the job: a job's files are listed only once checksummed), prints how many jobs
 * failed with their checkpoint unless cfg->quiet, and dies with the service
 * (PR_SET_PDEATHSIG). Returns the exit code: 0, or 1 when the database cannot be used. */
int lubd_worker_keep_main(const lubd_config *cfg, const char *worker, const char *how);

#endif
