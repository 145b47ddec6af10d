/* queue.c — HTTP-side queue operations. */
#include "queue.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "db.h"
#include "fsutil.h"

static const char *const state_names[] = {"accepted", "running", "successful", "failed",
                                          "dismissed"};

int lubd_state_bit(const char *name)
{
    for (int i = 0; i < 5; ++i)
        if (strcmp(name, state_names[i]) == 0)
            return 1 << i;
    return 0;
}

/* A full disk (SQLITE_FULL: the file system, or the database's page limit) is the operator's
 * to fix and the client's to retry: 507 Insufficient Storage with a Retry-After, nothing
 * changed (the transaction is rolled back). Any other database error is a 500. */
static int db_fault(sqlite3 *db, lubd_fault *f)
{
    fprintf(stderr, "lubdemd: sqlite: %s\n", sqlite3_errmsg(db));
    if (sqlite3_errcode(db) == SQLITE_FULL) {
        lubd_fail(f, 507, LUBD_PT_BASE "storage-full", "Insufficient storage", NULL,
                  "the service's storage is full (%s): nothing was queued or changed; retry "
                  "once space has been freed",
                  sqlite3_errmsg(db));
        f->retry_after = 60;
        return -1;
    }
    return lubd_fail(f, 500, LUBD_PT_BASE "internal", "Internal error", NULL, "database error: %s",
                     sqlite3_errmsg(db));
}

#define JOB_COLUMNS                                                                                \
    "j.seq, j.id, j.user_id, u.name, j.process_id, j.state, j.priority, j.created, "               \
    "coalesce(j.started, -1), coalesce(j.finished, -1), j.updated, j.progress, "                   \
    "coalesce(j.message, ''), coalesce(j.failure_kind, ''), j.attempt, j.max_attempts, "           \
    "j.purged, coalesce(json_extract(j.request_json, '$.continue_from'), '')"

static void copy_text(char *dst, size_t n, sqlite3_stmt *st, int col)
{
    const unsigned char *t = sqlite3_column_text(st, col);
    snprintf(dst, n, "%s", t ? (const char *)t : "");
}

static void read_job(sqlite3_stmt *st, lubd_job *j)
{
    j->seq = sqlite3_column_int64(st, 0);
    copy_text(j->id, sizeof j->id, st, 1);
    j->user_id = sqlite3_column_int64(st, 2);
    copy_text(j->user, sizeof j->user, st, 3);
    copy_text(j->process_id, sizeof j->process_id, st, 4);
    copy_text(j->state, sizeof j->state, st, 5);
    j->priority = sqlite3_column_int(st, 6);
    j->created = sqlite3_column_double(st, 7);
    j->started = sqlite3_column_double(st, 8);
    j->finished = sqlite3_column_double(st, 9);
    j->updated = sqlite3_column_double(st, 10);
    j->progress = sqlite3_column_int(st, 11);
    copy_text(j->message, sizeof j->message, st, 12);
    copy_text(j->failure_kind, sizeof j->failure_kind, st, 13);
    j->attempt = sqlite3_column_int(st, 14);
    j->max_attempts = sqlite3_column_int(st, 15);
    j->purged = sqlite3_column_int(st, 16);
    copy_text(j->continue_from, sizeof j->continue_from, st, 17);
}

/* An Idempotency-Key names its request for a day. */
#define IDEMPOTENCY_WINDOW_S "86400"

/* The job an earlier request of this user with this key made (within the window), into
 * job_id: 1 when it was the same request (fingerprint), 2 when another one, 0 when there is
 * none, -1 on a database error. */
static int idempotent_job(sqlite3 *db, long long user_id, const char *key, const char *fingerprint,
                          char job_id[33])
{
    sqlite3_stmt *st;
    if (lubd_db_prepare(db,
                        "SELECT request_sha256 = ?3, job_id FROM idempotency WHERE user_id = ?1 "
                        "AND key = ?2 AND created >= " LUBD_SQL_NOW " - " IDEMPOTENCY_WINDOW_S,
                        &st) != 0)
        return -1;
    sqlite3_bind_int64(st, 1, user_id);
    sqlite3_bind_text(st, 2, key, -1, SQLITE_STATIC);
    sqlite3_bind_text(st, 3, fingerprint, -1, SQLITE_STATIC);
    const int rc = sqlite3_step(st);
    int found = rc == SQLITE_DONE ? 0 : -1;
    if (rc == SQLITE_ROW) {
        found = sqlite3_column_int(st, 0) ? 1 : 2;
        copy_text(job_id, 33, st, 1);
    }
    sqlite3_finalize(st);
    return found;
}

int lubd_queue_submit(sqlite3 *db, const lubd_submit *in, char job_id[33], int *replayed,
                      lubd_fault *f)
{
    sqlite3_stmt *st = NULL;
    *replayed = 0;
    if (lubd_db_begin(db) != 0)
        return db_fault(db, f);
    if (in->idempotency_key) {
        /* every expired key goes, not only this one: clients that never reuse a key (a CI
         * pipeline's run ids) would otherwise grow the table without end */
        if (lubd_db_prepare(db,
                            "DELETE FROM idempotency WHERE created < " LUBD_SQL_NOW
                            " - " IDEMPOTENCY_WINDOW_S,
                            &st) != 0)
            goto dberr;
        if (sqlite3_step(st) != SQLITE_DONE)
            goto dberr;
        sqlite3_finalize(st);
        st = NULL;
        const int found =
            idempotent_job(db, in->user_id, in->idempotency_key, in->fingerprint, job_id);
        if (found < 0)
            goto dberr;
        if (found > 0) {
            lubd_db_rollback(db);
            if (found == 2)
                return lubd_fail(f, 409, LUBD_PT_BASE "idempotency-key-reused",
                                 "Idempotency-Key reused", NULL,
                                 "Idempotency-Key was already used for a different request "
                                 "(job %s); use a new key for a new request",
                                 job_id);
            *replayed = 1;
            return 0;
        }
    }
    if (lubd_db_prepare(db,
                        "SELECT count(*) FROM jobs WHERE user_id = ?1 AND state IN "
                        "('accepted','running')",
                        &st) != 0)
        goto dberr;
    sqlite3_bind_int64(st, 1, in->user_id);
    if (sqlite3_step(st) != SQLITE_ROW)
        goto dberr;
    long long active = sqlite3_column_int64(st, 0);
    sqlite3_finalize(st);
    st = NULL;
    if (active >= in->user_cap) {
        lubd_db_rollback(db);
        lubd_fail(f, 429, LUBD_PT_BASE "quota-exceeded", "Too many active jobs", NULL,
                  "you have %lld queued or running jobs (limit %d); retry when some finish", active,
                  in->user_cap);
        f->retry_after = 10;
        return -1;
    }
    if (in->continue_from && in->continue_from[0]) {
        if (lubd_db_prepare(db, "SELECT purged FROM jobs WHERE id = ?1", &st) != 0)
            goto dberr;
        sqlite3_bind_text(st, 1, in->continue_from, -1, SQLITE_STATIC);
        const int rc = sqlite3_step(st);
        if (rc != SQLITE_ROW && rc != SQLITE_DONE)
            goto dberr;
        const int deleted = rc == SQLITE_DONE || sqlite3_column_int(st, 0) != 0;
        sqlite3_finalize(st);
        st = NULL;
        if (deleted) {
            lubd_db_rollback(db);
            return lubd_fail(
                f, 400, LUBD_PT_BASE "invalid-request", "Invalid request", "/continue_from",
                "/continue_from: job %s was deleted, with its checkpoint", in->continue_from);
        }
    }
    if (lubd_random_hex(job_id, 16) != 0) {
        lubd_db_rollback(db);
        return lubd_fail(f, 500, LUBD_PT_BASE "internal", "Internal error", NULL,
                         "no randomness for the job id");
    }
    if (lubd_db_prepare(
            db,
            "INSERT INTO jobs(id, user_id, process_id, state, priority, "
            "request_json, spec_json, request_sha256, created, updated, "
            "max_attempts, message) VALUES (?1, ?2, ?3, 'accepted', ?4, ?5, ?6, ?7, " LUBD_SQL_NOW
            ", " LUBD_SQL_NOW ", ?8, 'queued')",
            &st) != 0)
        goto dberr;
    sqlite3_bind_text(st, 1, job_id, -1, SQLITE_STATIC);
    sqlite3_bind_int64(st, 2, in->user_id);
    sqlite3_bind_text(st, 3, in->process_id, -1, SQLITE_STATIC);
    sqlite3_bind_int(st, 4, in->priority);
    sqlite3_bind_text(st, 5, in->request_json, -1, SQLITE_STATIC);
    sqlite3_bind_text(st, 6, in->spec_json, -1, SQLITE_STATIC);
    sqlite3_bind_text(st, 7, in->fingerprint, -1, SQLITE_STATIC);
    sqlite3_bind_int(st, 8, in->max_attempts);
    if (sqlite3_step(st) != SQLITE_DONE)
        goto dberr;
    sqlite3_finalize(st);
    st = NULL;
    if (lubd_db_prepare(
            db,
            "INSERT INTO job_events(job_id, at, event, attempt) VALUES (?1, " LUBD_SQL_NOW
            ", 'submitted', 0)",
            &st) != 0)
        goto dberr;
    sqlite3_bind_text(st, 1, job_id, -1, SQLITE_STATIC);
    if (sqlite3_step(st) != SQLITE_DONE)
        goto dberr;
    sqlite3_finalize(st);
    st = NULL;
    if (in->idempotency_key) {
        if (lubd_db_prepare(db,
                            "INSERT INTO idempotency(user_id, key, request_sha256, job_id, "
                            "created) VALUES (?1, ?2, ?3, ?4, " LUBD_SQL_NOW ")",
                            &st) != 0)
            goto dberr;
        sqlite3_bind_int64(st, 1, in->user_id);
        sqlite3_bind_text(st, 2, in->idempotency_key, -1, SQLITE_STATIC);
        sqlite3_bind_text(st, 3, in->fingerprint, -1, SQLITE_STATIC);
        sqlite3_bind_text(st, 4, job_id, -1, SQLITE_STATIC);
        if (sqlite3_step(st) != SQLITE_DONE)
            goto dberr;
        sqlite3_finalize(st);
        st = NULL;
    }
    if (lubd_db_commit(db) != 0)
        goto dberr;
    return 0;
dberr:
    db_fault(db, f);
    sqlite3_finalize(st);
    lubd_db_rollback(db);
    return -1;
}

int lubd_queue_is_replay(sqlite3 *db, long long user_id, const char *key, const char *fingerprint)
{
    char job_id[33];
    const int found = idempotent_job(db, user_id, key, fingerprint, job_id);
    return found < 0 ? -1 : found == 1;
}

int lubd_queue_get(sqlite3 *db, const char *id, lubd_job *j)
{
    sqlite3_stmt *st;
    if (lubd_db_prepare(db,
                        "SELECT " JOB_COLUMNS " FROM jobs j JOIN users u ON u.id = j.user_id "
                        "WHERE j.id = ?1",
                        &st) != 0)
        return -1;
    sqlite3_bind_text(st, 1, id, -1, SQLITE_STATIC);
    int rc = sqlite3_step(st), result;
    if (rc == SQLITE_ROW) {
        read_job(st, j);
        result = 1;
    } else if (rc == SQLITE_DONE) {
        result = 0;
    } else {
        fprintf(stderr, "lubdemd: sqlite: %s\n", sqlite3_errmsg(db));
        result = -1;
    }
    sqlite3_finalize(st);
    return result;
}

/* a job's created time in ms since the epoch as its status shows it (lubd_rfc3339: whole
 * seconds, then the fraction's milliseconds cut, at most 999) */
#define CREATED_MS                                                                                 \
    "(CAST(j.created AS INTEGER) * 1000 + min(999, CAST((j.created - CAST(j.created AS "           \
    "INTEGER)) * 1000.0 AS INTEGER)))"

int lubd_queue_list(sqlite3 *db, const lubd_list_query *q, lubd_job **jobs, int *n, int *more)
{
    *jobs = NULL;
    *n = 0;
    *more = 0;
    sqlite3_stmt *st;
    if (lubd_db_prepare(db,
                        "SELECT " JOB_COLUMNS " FROM jobs j JOIN users u ON u.id = j.user_id "
                        "WHERE j.purged = 0 AND (?1 < 0 OR j.user_id = ?1) AND (?2 = 0 OR "
                        "(?2 >> (CASE j.state WHEN 'accepted' THEN 0 WHEN 'running' THEN 1 "
                        "WHEN 'successful' THEN 2 WHEN 'failed' THEN 3 ELSE 4 END)) & 1) AND "
                        "(?3 IS NULL OR j.process_id IN (SELECT value FROM json_each(?3))) "
                        "AND (?4 = 0 OR j.seq < ?4) AND (?6 < 0 OR " CREATED_MS " >= ?6) AND "
                        "(?7 < 0 OR " CREATED_MS " <= ?7) AND (?8 < 0 OR (j.started IS NOT NULL "
                        "AND coalesce(j.finished, " LUBD_SQL_NOW ") - j.started >= ?8)) AND "
                        "(?9 < 0 OR (j.started IS NOT NULL AND coalesce(j.finished, " LUBD_SQL_NOW
                        ") - j.started <= ?9)) ORDER BY j.seq DESC LIMIT ?5",
                        &st) != 0)
        return -1;
    sqlite3_bind_int64(st, 1, q->user_id);
    sqlite3_bind_int(st, 2, q->state_mask);
    if (q->process_ids)
        sqlite3_bind_text(st, 3, q->process_ids, -1, SQLITE_STATIC);
    else
        sqlite3_bind_null(st, 3);
    sqlite3_bind_int64(st, 4, q->before_seq);
    sqlite3_bind_int(st, 5, q->limit + 1);
    sqlite3_bind_int64(st, 6, q->created_from_ms);
    sqlite3_bind_int64(st, 7, q->created_to_ms);
    sqlite3_bind_double(st, 8, q->min_duration);
    sqlite3_bind_double(st, 9, q->max_duration);
    lubd_job *arr = calloc((size_t)q->limit + 1, sizeof *arr);
    if (!arr) {
        sqlite3_finalize(st);
        return -1;
    }
    int rc, count = 0;
    while ((rc = sqlite3_step(st)) == SQLITE_ROW)
        read_job(st, &arr[count++]);
    sqlite3_finalize(st);
    if (rc != SQLITE_DONE) {
        fprintf(stderr, "lubdemd: sqlite: %s\n", sqlite3_errmsg(db));
        free(arr);
        return -1;
    }
    if (count > q->limit) {
        *more = 1;
        count = q->limit;
    }
    *jobs = arr;
    *n = count;
    return 0;
}

static int exec_bound(sqlite3 *db, const char *sql, const char *id)
{
    sqlite3_stmt *st;
    if (lubd_db_prepare(db, sql, &st) != 0)
        return -1;
    sqlite3_bind_text(st, 1, id, -1, SQLITE_STATIC);
    int rc = sqlite3_step(st);
    sqlite3_finalize(st);
    if (rc != SQLITE_DONE) {
        fprintf(stderr, "lubdemd: sqlite: %s\n", sqlite3_errmsg(db));
        return -1;
    }
    return 0;
}

int lubd_queue_dismiss(sqlite3 *db, const char *id, lubd_job *after, char *was, int *purge_files)
{
    *purge_files = 0;
    if (was)
        was[0] = '\0';
    if (lubd_db_begin(db) != 0)
        return -1;
    lubd_job j;
    int found = lubd_queue_get(db, id, &j);
    if (found <= 0) {
        lubd_db_rollback(db);
        return found == 0 ? 1 : -1;
    }
    if (j.purged) {
        lubd_db_rollback(db);
        return 1;
    }
    int rc = 0;
    if (strcmp(j.state, "accepted") == 0 || strcmp(j.state, "running") == 0) {
        /* The lease (if any) is kept so the worker's fenced heartbeat sees the change. */
        rc = exec_bound(db,
                        "UPDATE jobs SET state = 'dismissed', failure_kind = 'cancelled', "
                        "message = CASE state WHEN 'running' THEN 'stopped while it ran "
                        "(DELETE): its engine is stopped and the files it wrote are removed "
                        "(its log stays)' ELSE 'taken out of the queue (DELETE) before it "
                        "started' END, finished = " LUBD_SQL_NOW ", updated = " LUBD_SQL_NOW
                        " WHERE id = ?1",
                        id);
        if (rc == 0)
            rc = exec_bound(db,
                            "INSERT INTO job_events(job_id, at, event, attempt, worker, token) "
                            "SELECT id, " LUBD_SQL_NOW ", 'dismissed', attempt, worker, "
                            "lease_token FROM jobs WHERE id = ?1",
                            id);
    } else {
        rc = exec_bound(db,
                        "UPDATE jobs SET purged = 1, state = 'dismissed', message = CASE state "
                        "WHEN 'dismissed' THEN 'deleted: its files and log are removed (it had "
                        "been dismissed)' ELSE 'deleted: its results, files and log are removed "
                        "(it had ended ' || state || coalesce(': ' || substr(message, 1, 400), '') "
                        "|| ')' END, updated = " LUBD_SQL_NOW " WHERE id = ?1",
                        id);
        if (rc == 0)
            rc = exec_bound(db, "DELETE FROM results WHERE job_id = ?1", id);
        if (rc == 0)
            rc = exec_bound(
                db,
                "INSERT INTO job_events(job_id, at, event, attempt) SELECT id, " LUBD_SQL_NOW
                ", 'purged', attempt FROM jobs WHERE id = ?1",
                id);
        *purge_files = 1;
    }
    if (rc != 0 || lubd_queue_get(db, id, after) != 1 || lubd_db_commit(db) != 0) {
        lubd_db_rollback(db);
        *purge_files = 0;
        return -1;
    }
    if (was)
        snprintf(was, sizeof j.state, "%s", j.state);
    return 0;
}

/* SQLite's clock (LUBD_SQL_NOW) into *now: 0, or -1 after printing the error. */
static int sql_now(sqlite3 *db, double *now)
{
    sqlite3_stmt *st;
    if (lubd_db_prepare(db, "SELECT " LUBD_SQL_NOW, &st) != 0)
        return -1;
    const int have_now = sqlite3_step(st) == SQLITE_ROW;
    *now = have_now ? sqlite3_column_double(st, 0) : 0.0;
    sqlite3_finalize(st);
    if (!have_now) {
        fprintf(stderr, "lubdemd: sqlite: %s\n", sqlite3_errmsg(db));
        return -1;
    }
    return 0;
}

int lubd_queue_reap(sqlite3 *db, int *requeued, int *failed)
{
    *requeued = *failed = 0;
    double now;
    return sql_now(db, &now) != 0 ? -1 : lubd_queue_reap_at(db, now, requeued, failed);
}

/* The reaper's pass: every running lease that ends before `expired_before` is requeued (its
 * message `why`) or, after its last attempt, failed (its message `fail_why`, a printf format
 * given the attempt and max_attempts); `now` stamps the changes. */
static int reap_leases(sqlite3 *db, double now, double expired_before, const char *why,
                       const char *fail_why, int *requeued, int *failed)
{
    *requeued = *failed = 0;
    if (lubd_db_begin(db) != 0)
        return -1;
    sqlite3_stmt *st;
    const char *ev =
        "INSERT INTO job_events(job_id, at, event, attempt, worker, token) SELECT id, ?1, ?2, "
        "attempt, worker, lease_token FROM jobs WHERE state = 'running' AND lease_until < ?4 "
        "AND (attempt < max_attempts) = ?3";
    for (int retry = 1; retry >= 0; --retry) {
        if (lubd_db_prepare(db, ev, &st) != 0)
            goto fail;
        sqlite3_bind_double(st, 1, now);
        sqlite3_bind_text(st, 2, retry ? "requeued" : "failed", -1, SQLITE_STATIC);
        sqlite3_bind_int(st, 3, retry);
        sqlite3_bind_double(st, 4, expired_before);
        int rc = sqlite3_step(st);
        sqlite3_finalize(st);
        if (rc != SQLITE_DONE)
            goto fail;
    }
    int changed[2];
    const char *update[2] = {
        "UPDATE jobs SET state = 'accepted', worker = NULL, lease_token = NULL, lease_until = "
        "NULL, engine_pid = NULL, progress = 0, message = ?3, updated = ?1 WHERE state = "
        "'running' AND lease_until < ?2 AND attempt < max_attempts",
        "UPDATE jobs SET state = 'failed', failure_kind = 'system', worker = NULL, lease_token = "
        "NULL, lease_until = NULL, message = printf(?3, attempt, max_attempts), finished = ?1, "
        "updated = ?1 WHERE state = 'running' AND lease_until < ?2"};
    for (int k = 0; k < 2; ++k) {
        if (lubd_db_prepare(db, update[k], &st) != 0)
            goto fail;
        sqlite3_bind_double(st, 1, now);
        sqlite3_bind_double(st, 2, expired_before);
        sqlite3_bind_text(st, 3, k == 0 ? why : fail_why, -1, SQLITE_STATIC);
        const int rc = sqlite3_step(st);
        sqlite3_finalize(st);
        if (rc != SQLITE_DONE)
            goto fail;
        changed[k] = sqlite3_changes(db);
    }
    if (lubd_db_commit(db) != 0)
        goto fail;
    *requeued = changed[0];
    *failed = changed[1];
    return 0;
fail:
    fprintf(stderr, "lubdemd: sqlite: %s\n", sqlite3_errmsg(db));
    lubd_db_rollback(db);
    return -1;
}

int lubd_queue_reap_at(sqlite3 *db, double now, int *requeued, int *failed)
{
    return reap_leases(db, now, now, "requeued: the worker stopped heartbeating (lease expired)",
                       "failed: its worker stopped heartbeating during attempt %d, the last of "
                       "%d (lease expired)",
                       requeued, failed);
}

int lubd_queue_reap_orphans(sqlite3 *db, int *requeued, int *failed)
{
    *requeued = *failed = 0;
    double now;
    if (sql_now(db, &now) != 0)
        return -1;
    return reap_leases(db, now, 1e300, /* every lease */
                       "requeued: the service stopped without releasing it (crash or kill -9) "
                       "and was started again",
                       "failed: the service stopped without releasing it (crash or kill -9) "
                       "during attempt %d, the last of %d",
                       requeued, failed);
}

int lubd_queue_counts(sqlite3 *db, int *accepted, int *running)
{
    sqlite3_stmt *st;
    if (lubd_db_prepare(db,
                        "SELECT (SELECT count(*) FROM jobs WHERE state = 'accepted'), "
                        "(SELECT count(*) FROM jobs WHERE state = 'running')",
                        &st) != 0)
        return -1;
    int rc = sqlite3_step(st);
    if (rc == SQLITE_ROW) {
        *accepted = sqlite3_column_int(st, 0);
        *running = sqlite3_column_int(st, 1);
    }
    sqlite3_finalize(st);
    return rc == SQLITE_ROW ? 0 : -1;
}

int lubd_queue_spec(sqlite3 *db, const char *id, char **spec_json)
{
    *spec_json = NULL;
    sqlite3_stmt *st;
    if (lubd_db_prepare(db, "SELECT spec_json FROM jobs WHERE id = ?1", &st) != 0)
        return -1;
    sqlite3_bind_text(st, 1, id, -1, SQLITE_STATIC);
    int rc = sqlite3_step(st), result = 0;
    if (rc == SQLITE_ROW) {
        *spec_json = strdup((const char *)sqlite3_column_text(st, 0));
        result = *spec_json ? 1 : -1;
    } else if (rc != SQLITE_DONE) {
        result = -1;
    }
    sqlite3_finalize(st);
    return result;
}

int lubd_queue_results(sqlite3 *db, const char *id, lubd_result_file **files, int *n)
{
    *files = NULL;
    *n = 0;
    sqlite3_stmt *st;
    if (lubd_db_prepare(db,
                        "SELECT name, media_type, size, sha256 FROM results WHERE job_id = ?1 "
                        "ORDER BY name LIMIT 64",
                        &st) != 0)
        return -1;
    sqlite3_bind_text(st, 1, id, -1, SQLITE_STATIC);
    lubd_result_file *arr = calloc(64, sizeof *arr);
    int rc = SQLITE_DONE, count = 0;
    while (arr && (rc = sqlite3_step(st)) == SQLITE_ROW) {
        copy_text(arr[count].name, sizeof arr[count].name, st, 0);
        copy_text(arr[count].media_type, sizeof arr[count].media_type, st, 1);
        arr[count].size = sqlite3_column_int64(st, 2);
        copy_text(arr[count].sha256, sizeof arr[count].sha256, st, 3);
        ++count;
    }
    sqlite3_finalize(st);
    if (!arr || rc != SQLITE_DONE) { /* a failed step: the list may be partial */
        free(arr);
        return -1;
    }
    *files = arr;
    *n = count;
    return 0;
}
