/* lease.c — claim, heartbeat and fenced completion. */
#include "lease.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "db.h"
#include "fsutil.h"

static int sql_err(sqlite3 *db)
{
    fprintf(stderr, "lubdemd worker: sqlite: %s\n", sqlite3_errmsg(db));
    return -1;
}

/* Records `event` ("claimed", a final state, "requeued") of claim c in job_events: 0, or -1
 * (sql_err) on an SQLite error. Inside the caller's transaction. */
static int add_claim_event(sqlite3 *db, const lubd_claim *c, const char *event)
{
    sqlite3_stmt *st;
    if (lubd_db_prepare(db,
                        "INSERT INTO job_events(job_id, at, event, attempt, worker, token) "
                        "VALUES (?1, " LUBD_SQL_NOW ", ?2, ?3, ?4, ?5)",
                        &st) != 0)
        return -1;
    sqlite3_bind_text(st, 1, c->id, -1, SQLITE_STATIC);
    sqlite3_bind_text(st, 2, event, -1, SQLITE_STATIC);
    sqlite3_bind_int(st, 3, c->attempt);
    sqlite3_bind_text(st, 4, c->worker, -1, SQLITE_STATIC);
    sqlite3_bind_text(st, 5, c->token, -1, SQLITE_STATIC);
    const int rc = sqlite3_step(st);
    sqlite3_finalize(st);
    return rc == SQLITE_DONE ? 0 : sql_err(db);
}

int lubd_lease_claim(sqlite3 *db, const char *worker, int lease_s, lubd_claim *c)
{
    memset(c, 0, sizeof *c);
    if (lubd_random_hex(c->token, 16) != 0)
        return -1;
    snprintf(c->worker, sizeof c->worker, "%s", worker);
    if (lubd_db_begin(db) != 0)
        return -1;
    sqlite3_stmt *st;
    if (lubd_db_prepare(db,
                        "UPDATE jobs SET state = 'running', worker = ?1, lease_token = ?2, "
                        "attempt = attempt + 1, started = coalesce(started, " LUBD_SQL_NOW "), "
                        "lease_until = " LUBD_SQL_NOW " + ?3, heartbeat = " LUBD_SQL_NOW ", "
                        "updated = " LUBD_SQL_NOW ", progress = 0, message = 'running', "
                        "engine_pid = NULL WHERE id = (SELECT id FROM jobs WHERE state = "
                        "'accepted' ORDER BY priority DESC, seq LIMIT 1) "
                        "RETURNING id, attempt, spec_json, process_id, "
                        "coalesce(json_extract(request_json, '$.continue_from'), ''), "
                        "max_attempts",
                        &st) != 0) {
        lubd_db_rollback(db);
        return -1;
    }
    sqlite3_bind_text(st, 1, c->worker, -1, SQLITE_STATIC);
    sqlite3_bind_text(st, 2, c->token, -1, SQLITE_STATIC);
    sqlite3_bind_int(st, 3, lease_s);
    int rc = sqlite3_step(st), result = 0;
    if (rc == SQLITE_ROW) {
        snprintf(c->id, sizeof c->id, "%s", (const char *)sqlite3_column_text(st, 0));
        c->attempt = sqlite3_column_int(st, 1);
        c->spec_json = strdup((const char *)sqlite3_column_text(st, 2));
        snprintf(c->process_id, sizeof c->process_id, "%s",
                 (const char *)sqlite3_column_text(st, 3));
        snprintf(c->continue_from, sizeof c->continue_from, "%s",
                 (const char *)sqlite3_column_text(st, 4));
        c->max_attempts = sqlite3_column_int(st, 5);
        result = c->spec_json ? 1 : -1;
        rc = sqlite3_step(st); /* finish the statement */
    }
    if (rc != SQLITE_DONE)
        result = sql_err(db);
    sqlite3_finalize(st);
    if (result == 1 && add_claim_event(db, c, "claimed") != 0)
        result = -1;
    if (result < 0 || lubd_db_commit(db) != 0) {
        lubd_db_rollback(db);
        lubd_lease_clear(c);
        return -1;
    }
    if (result == 0)
        lubd_lease_clear(c);
    return result;
}

void lubd_lease_clear(lubd_claim *c)
{
    free(c->spec_json);
    c->spec_json = NULL;
}

int lubd_lease_heartbeat(sqlite3 *db, const lubd_claim *c, int lease_s, int progress,
                         const char *message, long engine_pid)
{
    sqlite3_stmt *st;
    /* A single UPDATE is atomic; no explicit transaction needed (no read-then-write). */
    if (lubd_db_prepare(db,
                        "UPDATE jobs SET lease_until = " LUBD_SQL_NOW
                        " + ?3, heartbeat = " LUBD_SQL_NOW
                        ", progress = CASE WHEN ?4 < 0 THEN progress ELSE ?4 END, "
                        "message = coalesce(?5, message), engine_pid = CASE WHEN ?6 > 0 THEN "
                        "?6 ELSE engine_pid END, updated = CASE WHEN ?4 >= 0 OR ?5 IS NOT NULL "
                        "THEN " LUBD_SQL_NOW " ELSE updated END "
                        "WHERE id = ?1 AND lease_token = ?2 AND state = 'running'",
                        &st) != 0)
        return -1;
    sqlite3_bind_text(st, 1, c->id, -1, SQLITE_STATIC);
    sqlite3_bind_text(st, 2, c->token, -1, SQLITE_STATIC);
    sqlite3_bind_int(st, 3, lease_s);
    sqlite3_bind_int(st, 4, progress);
    if (message)
        sqlite3_bind_text(st, 5, message, -1, SQLITE_TRANSIENT);
    else
        sqlite3_bind_null(st, 5);
    sqlite3_bind_int64(st, 6, engine_pid);
    int rc = sqlite3_step(st);
    sqlite3_finalize(st);
    if (rc != SQLITE_DONE)
        return sql_err(db);
    return sqlite3_changes(db) > 0 ? 1 : 0;
}

/* Inside an open transaction: 1 if (id, token) still holds a running lease. */
static int still_ours(sqlite3 *db, const lubd_claim *c)
{
    sqlite3_stmt *st;
    if (lubd_db_prepare(db,
                        "SELECT 1 FROM jobs WHERE id = ?1 AND lease_token = ?2 AND state = "
                        "'running'",
                        &st) != 0)
        return -1;
    sqlite3_bind_text(st, 1, c->id, -1, SQLITE_STATIC);
    sqlite3_bind_text(st, 2, c->token, -1, SQLITE_STATIC);
    int rc = sqlite3_step(st);
    sqlite3_finalize(st);
    if (rc == SQLITE_ROW)
        return 1;
    return rc == SQLITE_DONE ? 0 : sql_err(db);
}

static int finish_row(sqlite3 *db, const lubd_claim *c, const char *state, const char *kind,
                      const char *message)
{
    sqlite3_stmt *st;
    if (lubd_db_prepare(db,
                        "UPDATE jobs SET state = ?3, failure_kind = ?4, message = ?5, "
                        "progress = CASE WHEN ?3 = 'successful' THEN 100 ELSE progress END, "
                        "finished = " LUBD_SQL_NOW ", updated = " LUBD_SQL_NOW ", "
                        "lease_until = NULL, engine_pid = NULL "
                        "WHERE id = ?1 AND lease_token = ?2 AND state = 'running'",
                        &st) != 0)
        return -1;
    sqlite3_bind_text(st, 1, c->id, -1, SQLITE_STATIC);
    sqlite3_bind_text(st, 2, c->token, -1, SQLITE_STATIC);
    sqlite3_bind_text(st, 3, state, -1, SQLITE_STATIC);
    if (kind)
        sqlite3_bind_text(st, 4, kind, -1, SQLITE_STATIC);
    else
        sqlite3_bind_null(st, 4);
    sqlite3_bind_text(st, 5, message, -1, SQLITE_TRANSIENT);
    int rc = sqlite3_step(st);
    sqlite3_finalize(st);
    if (rc != SQLITE_DONE)
        return sql_err(db);
    return add_claim_event(db, c, state);
}

/* The answer of a finish whose lease is no longer this worker's: 0. A job dismissed while it
 * ran still carries this worker's token (queue.c keeps it for the fenced heartbeat); it is
 * dropped here, so that an ended job shows no lease (until 2026-12-06 a failure reported to
 * a dismissed job left it set). */
static int lease_lost(sqlite3 *db, const lubd_claim *c)
{
    lubd_lease_drop(db, c);
    return 0;
}

/* Moves out_dir to result_dir, registers its files and finishes the row in `state`, in one
 * transaction under the lease. */
static int finish_with_outputs(sqlite3 *db, const lubd_claim *c, const char *state,
                               const char *kind, const char *message, const char *out_dir,
                               const char *result_dir, const lubd_output_file *files, int n)
{
    if (lubd_db_begin(db) != 0)
        return -1;
    int ours = still_ours(db, c);
    if (ours <= 0) {
        lubd_db_rollback(db);
        return ours < 0 ? ours : lease_lost(db, c);
    }
    /* A result_dir can only be a leftover of an attempt that crashed between its rename and
     * its COMMIT (never served: the job had not finished). Replace it. */
    struct stat sb;
    if (stat(result_dir, &sb) == 0 && lubd_rm_rf(result_dir) != 0) {
        fprintf(stderr, "lubdemd worker: cannot remove %s: %s\n", result_dir, strerror(errno));
        lubd_db_rollback(db);
        return -1;
    }
    if (rename(out_dir, result_dir) != 0) {
        fprintf(stderr, "lubdemd worker: rename %s: %s\n", out_dir, strerror(errno));
        lubd_db_rollback(db);
        return -1;
    }
    sqlite3_stmt *st = NULL;
    if (lubd_db_prepare(db, "DELETE FROM results WHERE job_id = ?1", &st) != 0)
        goto fail;
    sqlite3_bind_text(st, 1, c->id, -1, SQLITE_STATIC);
    if (sqlite3_step(st) != SQLITE_DONE)
        goto fail;
    sqlite3_finalize(st);
    st = NULL;
    for (int i = 0; i < n; ++i) {
        if (lubd_db_prepare(db,
                            "INSERT INTO results(job_id, name, media_type, size, sha256) "
                            "VALUES (?1, ?2, ?3, ?4, ?5)",
                            &st) != 0)
            goto fail;
        sqlite3_bind_text(st, 1, c->id, -1, SQLITE_STATIC);
        sqlite3_bind_text(st, 2, files[i].name, -1, SQLITE_STATIC);
        sqlite3_bind_text(st, 3, files[i].media_type, -1, SQLITE_STATIC);
        sqlite3_bind_int64(st, 4, files[i].size);
        sqlite3_bind_text(st, 5, files[i].sha256, -1, SQLITE_STATIC);
        if (sqlite3_step(st) != SQLITE_DONE)
            goto fail;
        sqlite3_finalize(st);
        st = NULL;
    }
    if (finish_row(db, c, state, kind, message) != 0 || lubd_db_commit(db) != 0)
        goto fail;
    return 1;
fail:
    if (st)
        sql_err(db);
    sqlite3_finalize(st);
    lubd_db_rollback(db);
    /* The job is still running in the database: its files go back where they were, so that
     * nothing stands in result_dir that the database does not list (a full disk at COMMIT) */
    if (rename(result_dir, out_dir) != 0)
        fprintf(stderr, "lubdemd worker: cannot move %s back to %s: %s\n", result_dir, out_dir,
                strerror(errno));
    return -1;
}

int lubd_lease_succeed(sqlite3 *db, const lubd_claim *c, const char *out_dir,
                       const char *result_dir, const lubd_output_file *files, int n,
                       const char *message)
{
    return finish_with_outputs(db, c, "successful", NULL, message, out_dir, result_dir, files, n);
}

int lubd_lease_fail_with_outputs(sqlite3 *db, const lubd_claim *c, const char *kind,
                                 const char *message, const char *out_dir, const char *result_dir,
                                 const lubd_output_file *files, int n)
{
    return finish_with_outputs(db, c, "failed", kind, message, out_dir, result_dir, files, n);
}

int lubd_lease_fail(sqlite3 *db, const lubd_claim *c, const char *kind, const char *message)
{
    if (lubd_db_begin(db) != 0)
        return -1;
    int ours = still_ours(db, c);
    if (ours <= 0) {
        lubd_db_rollback(db);
        return ours < 0 ? ours : lease_lost(db, c);
    }
    if (finish_row(db, c, "failed", kind, message) != 0 || lubd_db_commit(db) != 0) {
        lubd_db_rollback(db);
        return -1;
    }
    return 1;
}

static int exec_claim(sqlite3 *db, const lubd_claim *c, const char *sql)
{
    sqlite3_stmt *st;
    if (lubd_db_prepare(db, sql, &st) != 0)
        return -1;
    sqlite3_bind_text(st, 1, c->id, -1, SQLITE_STATIC);
    sqlite3_bind_text(st, 2, c->token, -1, SQLITE_STATIC);
    int rc = sqlite3_step(st);
    sqlite3_finalize(st);
    return rc == SQLITE_DONE ? sqlite3_changes(db) : sql_err(db);
}

int lubd_lease_requeue(sqlite3 *db, const lubd_claim *c, const char *message)
{
    if (lubd_db_begin(db) != 0)
        return -1;
    sqlite3_stmt *st;
    int n = -1;
    if (lubd_db_prepare(db,
                        "UPDATE jobs SET state = 'accepted', worker = NULL, lease_token = NULL, "
                        "lease_until = NULL, engine_pid = NULL, progress = 0, message = ?3, "
                        "updated = " LUBD_SQL_NOW " WHERE id = ?1 AND lease_token = ?2 AND "
                        "state = 'running' AND attempt < max_attempts",
                        &st) == 0) {
        sqlite3_bind_text(st, 1, c->id, -1, SQLITE_STATIC);
        sqlite3_bind_text(st, 2, c->token, -1, SQLITE_STATIC);
        sqlite3_bind_text(st, 3, message, -1, SQLITE_TRANSIENT);
        const int rc = sqlite3_step(st);
        sqlite3_finalize(st);
        n = rc == SQLITE_DONE ? sqlite3_changes(db) : sql_err(db);
    }
    if (n > 0 && add_claim_event(db, c, "requeued") != 0)
        n = -1;
    if (n < 0 || lubd_db_commit(db) != 0) {
        lubd_db_rollback(db);
        return -1;
    }
    return n > 0 ? 1 : 0;
}

int lubd_lease_release(sqlite3 *db, const lubd_claim *c)
{
    if (lubd_db_begin(db) != 0)
        return -1;
    int n = exec_claim(db, c,
                       "UPDATE jobs SET state = 'accepted', attempt = max(attempt - 1, 0), "
                       "worker = NULL, lease_token = NULL, lease_until = NULL, engine_pid = "
                       "NULL, progress = 0, message = 'requeued: the service is shutting down', "
                       "updated = " LUBD_SQL_NOW
                       " WHERE id = ?1 AND lease_token = ?2 AND state = 'running'");
    if (n > 0)
        n = exec_claim(
            db, c,
            "INSERT INTO job_events(job_id, at, event, attempt, token) SELECT ?1, " LUBD_SQL_NOW
            ", 'released', attempt, ?2 FROM jobs WHERE id = ?1");
    if (n < 0 || lubd_db_commit(db) != 0) {
        lubd_db_rollback(db);
        return -1;
    }
    return n > 0 ? 1 : 0;
}

int lubd_lease_drop(sqlite3 *db, const lubd_claim *c)
{
    int n = exec_claim(db, c,
                       "UPDATE jobs SET lease_token = NULL, lease_until = NULL, engine_pid = "
                       "NULL WHERE id = ?1 AND lease_token = ?2 AND state <> 'running'");
    return n < 0 ? -1 : 0;
}

int lubd_lease_extend_last_attempts(sqlite3 *db, const char *worker, int lease_s)
{
    sqlite3_stmt *st;
    if (lubd_db_prepare(db,
                        "UPDATE jobs SET lease_until = max(lease_until, " LUBD_SQL_NOW
                        " + ?2) WHERE worker = ?1 AND state = 'running' AND lease_token IS NOT "
                        "NULL AND attempt >= max_attempts",
                        &st) != 0)
        return -1;
    sqlite3_bind_text(st, 1, worker, -1, SQLITE_STATIC);
    sqlite3_bind_int(st, 2, lease_s);
    const int rc = sqlite3_step(st);
    sqlite3_finalize(st);
    return rc == SQLITE_DONE ? sqlite3_changes(db) : sql_err(db);
}
