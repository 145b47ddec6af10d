/* queue.h — the job queue as seen by the HTTP side: submit, read, list, dismiss, reap.
 *
 * Every read-then-write runs inside BEGIN IMMEDIATE (db.h). Functions take a caller-owned
 * connection; none keeps references. Return conventions are given per function; database
 * errors print one line on stderr and return -1. Worker-side operations are in lease.h. */
#ifndef LUBD_QUEUE_H
#define LUBD_QUEUE_H

#include <sqlite3.h>

#include "problem.h"

enum {
    LUBD_ST_ACCEPTED = 1,
    LUBD_ST_RUNNING = 2,
    LUBD_ST_SUCCESSFUL = 4,
    LUBD_ST_FAILED = 8,
    LUBD_ST_DISMISSED = 16
};
/* Bit of a state name, 0 if unknown. */
int lubd_state_bit(const char *name);

typedef struct {
    long long seq;
    char id[33];
    long long user_id;
    char user[64];
    char process_id[64];
    char state[16];
    int priority;
    double created, started, finished, updated; /* < 0 = not set */
    int progress;
    char message[600];
    char failure_kind[16];
    int attempt, max_attempts;
    int purged;
    char continue_from[33]; /* the job whose checkpoint this one continues ("" = none) */
} lubd_job;

typedef struct {
    long long user_id;
    int user_cap; /* max accepted+running jobs for this user */
    const char *process_id;
    const char *request_json;
    const char *spec_json;
    const char *fingerprint;
    const char *idempotency_key; /* NULL = none */
    int priority;
    int max_attempts;
    const char *continue_from; /* the job it continues; NULL or "" = none */
} lubd_submit;

/* Returns 0 with job_id set (*replayed = 1 if an Idempotency-Key matched an earlier
 * identical request), or -1 with *f set (409 key reused with a different body, 429 over the
 * per-user cap with retry_after, 400 at /continue_from when the job it continues was deleted
 * (checked in the write transaction, so that a deletion either comes first and refuses the
 * continuation, or comes after and hands its files over to it), 500 database error). */
int lubd_queue_submit(sqlite3 *db, const lubd_submit *in, char job_id[33], int *replayed,
                      lubd_fault *f);
/* 1 when lubd_queue_submit would answer (user_id, key, fingerprint) with the job it made for
 * the same request earlier (a replay), 0 when not, -1 on a database error. A replay is not
 * checked again: a retried continuation gets its job even after the job it continues has been
 * deleted. */
int lubd_queue_is_replay(sqlite3 *db, long long user_id, const char *key, const char *fingerprint);

/* 1 found, 0 not found, -1 error. */
int lubd_queue_get(sqlite3 *db, const char *id, lubd_job *j);

typedef struct {
    long long user_id;       /* -1 = every user (admin) */
    int state_mask;          /* 0 = every state */
    const char *process_ids; /* a JSON array of process ids (any of them); NULL = any */
    int limit;
    long long before_seq; /* cursor: only jobs with seq < before_seq; 0 = from the newest */
    /* created (as shown: cut to the millisecond) within [from, to], in ms since the epoch;
     * -1 = open */
    long long created_from_ms, created_to_ms;
    /* started to finished (or now, while running) within [min, max] seconds, which a job
     * that never started does not meet; < 0 = no bound */
    double min_duration, max_duration;
} lubd_list_query;

/* Fills a malloc'd array (caller frees) newest first; *more = 1 if more rows follow. */
int lubd_queue_list(sqlite3 *db, const lubd_list_query *q, lubd_job **jobs, int *n, int *more);

/* DELETE /jobs/{id}: accepted -> dismissed; running -> dismissed (the worker holding the lease
 * notices at its next heartbeat and stops the engine); finished -> purged (tombstone).
 * Returns 0 and the job after the change, with *purge_files = 1 when the caller must delete
 * the job directory and, in `was` (16 bytes; NULL: not wanted), the state the job was dismissed
 * from; 1 if the job is already purged; -1 error. The state is read in the transaction that
 * changes it: what the caller does to the job's files must follow `was`, never a state read
 * before the call, which a worker may have changed meanwhile (until 2026-12-07 the request
 * tidied a job it had seen queued as a queued one, removing the files of the engine a worker
 * had started for it in between). */
int lubd_queue_dismiss(sqlite3 *db, const char *id, lubd_job *after, char *was, int *purge_files);

/* Requeues running jobs whose lease expired (attempt < max_attempts) and fails the others,
 * each with its job_events row ('requeued' / 'failed'), in one transaction. Returns 0, or -1
 * (database error; nothing changed). */
int lubd_queue_reap(sqlite3 *db, int *requeued, int *failed);

/* lubd_queue_reap with every lease judged against the one instant `now` (s, the clock of
 * LUBD_SQL_NOW): a lease has expired when lease_until < now. Every statement of the reaper
 * uses this instant, so the jobs whose state changes and the jobs that get an event are the
 * same set (SQLite's own 'now' moves between statements). */
int lubd_queue_reap_at(sqlite3 *db, double now, int *requeued, int *failed);

/* At the start of the one service that may use the queue (main.c holds its lock): every
 * running lease is an orphan of a service that died (its workers and engines die with it,
 * PR_SET_PDEATHSIG), so each is requeued (or failed after its last attempt) now instead of
 * when its lease would have expired. The attempt counts, as for an expired lease. */
int lubd_queue_reap_orphans(sqlite3 *db, int *requeued, int *failed);

int lubd_queue_counts(sqlite3 *db, int *accepted, int *running);

typedef struct {
    char name[64];
    char media_type[64];
    long long size;
    char sha256[65];
} lubd_result_file;

/* The engine spec a job was submitted with (malloc'd, caller frees): 1 found, 0 no such job,
 * -1 error. */
int lubd_queue_spec(sqlite3 *db, const char *id, char **spec_json);

/* Registered files of a job (malloc'd array, caller frees). */
int lubd_queue_results(sqlite3 *db, const char *id, lubd_result_file **files, int *n);

#endif
