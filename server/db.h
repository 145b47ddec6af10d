/* db.h — SQLite connections for the queue database.
 *
 * lubd_db_open() opens one connection and sets the per-connection pragmas (busy_timeout,
 * synchronous=NORMAL, foreign_keys); with create=1 it also switches the file to WAL and
 * applies the embedded schema (schema/queue.sql). A connection is used by one thread at a
 * time and never crosses fork(). lubd_db_pool hands out connections to HTTP threads.
 * Errors: functions return -1 (or NULL) and print one line to stderr. */
#ifndef LUBD_DB_H
#define LUBD_DB_H

#include <pthread.h>
#include <sqlite3.h>

/* Seconds since the Unix epoch with sub-second resolution, evaluated by SQLite
 * (unixepoch('subsec') needs 3.42; Debian 12 has 3.40). */
#define LUBD_SQL_NOW "((julianday('now') - 2440587.5) * 86400.0)"

sqlite3 *lubd_db_open(const char *path, int create);
void lubd_db_close(sqlite3 *db);
int lubd_db_exec(sqlite3 *db, const char *sql); /* no result rows */
/* BEGIN IMMEDIATE (takes the write lock up front; busy_timeout applies). */
int lubd_db_begin(sqlite3 *db);
int lubd_db_commit(sqlite3 *db);
void lubd_db_rollback(sqlite3 *db);
/* Prepare or return -1 after printing the error. */
int lubd_db_prepare(sqlite3 *db, const char *sql, sqlite3_stmt **st);

typedef struct {
    sqlite3 **conns;
    int *busy;
    int n;
    pthread_mutex_t mu;
    pthread_cond_t cv;
    pthread_mutex_t write_mu; /* one in-process writer at a time (see acquire_writer) */
} lubd_db_pool;

int lubd_db_pool_init(lubd_db_pool *p, const char *path, int n);
void lubd_db_pool_destroy(lubd_db_pool *p);
sqlite3 *lubd_db_acquire(lubd_db_pool *p); /* blocks until one is free */
void lubd_db_release(lubd_db_pool *p, sqlite3 *db);
/* For handlers that write: also serialises writers of this process, so that they queue on a
 * mutex instead of in SQLite's busy handler (which sleeps in steps of up to 100 ms).
 * Writers in other processes (workers) are still arbitrated by BEGIN IMMEDIATE. */
sqlite3 *lubd_db_acquire_writer(lubd_db_pool *p);
void lubd_db_release_writer(lubd_db_pool *p, sqlite3 *db);

#endif
