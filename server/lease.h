/* lease.h — worker-side queue operations with leases and fencing tokens.
 *
 * A claim takes the highest-priority oldest accepted job and stamps it with a fresh random
 * lease_token (the fencing token) and lease_until = now + lease_s. Every later write by the
 * worker matches on (id, lease_token, state='running'); zero matched rows means the lease was
 * lost (reaped after expiry) or the job was dismissed, and the worker must stop the engine
 * and write nothing. All writes run in BEGIN IMMEDIATE. Return codes per function;
 * database errors print on stderr and return -1. */
#ifndef LUBD_LEASE_H
#define LUBD_LEASE_H

#include <sqlite3.h>

typedef struct {
    char id[33];
    char token[33];
    char worker[64];
    char process_id[64];
    int attempt;
    int max_attempts;       /* the job's --max-attempts when it was submitted */
    char *spec_json;        /* malloc'd, owned by the claim; free with lubd_lease_clear */
    char continue_from[33]; /* the job whose checkpoint this one continues ("" = none) */
} lubd_claim;

/* 1 claimed, 0 queue empty, -1 error. */
int lubd_lease_claim(sqlite3 *db, const char *worker, int lease_s, lubd_claim *c);
void lubd_lease_clear(lubd_claim *c);

/* Extends the lease and records progress (progress < 0 = unchanged, message NULL = unchanged,
 * engine_pid <= 0 = unchanged). 1 = still ours, 0 = lost or dismissed, -1 = error. */
int lubd_lease_heartbeat(sqlite3 *db, const lubd_claim *c, int lease_s, int progress,
                         const char *message, long engine_pid);

typedef struct {
    const char *name;
    const char *media_type;
    long long size;
    char sha256[65];
} lubd_output_file;

/* Success: inside one transaction, checks the lease, moves out_dir to result_dir (replacing
 * a leftover from a crashed earlier attempt), registers the files and marks the job
 * successful. 1 done, 0 lease lost (nothing moved; as lubd_lease_fail), -1 error (rolled back and
 * the files moved back to out_dir, e.g. a full disk at COMMIT). */
int lubd_lease_succeed(sqlite3 *db, const lubd_claim *c, const char *out_dir,
                       const char *result_dir, const lubd_output_file *files, int n,
                       const char *message);
/* Failure (not retried). kind: "executor" or "system". 1 done, 0 lease lost (a job dismissed
 * meanwhile: the lease fields the dismissal kept are dropped), -1 error. */
int lubd_lease_fail(sqlite3 *db, const lubd_claim *c, const char *kind, const char *message);
/* Failure that keeps what the engine wrote (its summary, a partial or failed result.h5, the
 * checkpoint of a stopped run): as lubd_lease_succeed, but the job ends failed; the files
 * are served like a successful job's. Same returns. */
int lubd_lease_fail_with_outputs(sqlite3 *db, const lubd_claim *c, const char *kind,
                                 const char *message, const char *out_dir, const char *result_dir,
                                 const lubd_output_file *files, int n);
/* Gives the job back to the queue as its next attempt (the attempt is used up) when
 * attempt < max_attempts: its engine was killed from outside (SIGKILL: the kernel's OOM
 * killer, an operator), and the next attempt continues from the periodic checkpoint the engine
 * left, as after a worker's death. `message` becomes the job's message and is the reason the
 * job log states. 1 requeued, 0 lease lost, dismissed or no attempt left (nothing changed),
 * -1 error. */
int lubd_lease_requeue(sqlite3 *db, const lubd_claim *c, const char *message);
/* Gives the job back to the queue without consuming an attempt (graceful shutdown). */
int lubd_lease_release(sqlite3 *db, const lubd_claim *c);
/* After a dismissal: drops the lease fields if the job still carries our token. */
int lubd_lease_drop(sqlite3 *db, const lubd_claim *c);
/* After the worker process `worker` died (its name as the jobs' worker column holds it): extends
 * the leases of its jobs on their last attempt to lease_s from now (never shortens one), so that
 * the reaper leaves them to the process that keeps their checkpoints until it heartbeats them
 * (lubd_worker_keep_main). A single UPDATE. Returns how many jobs, or -1 on an error. */
int lubd_lease_extend_last_attempts(sqlite3 *db, const char *worker, int lease_s);

#endif
