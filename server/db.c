/* db.c — connection set-up, schema application, transactions, connection pool. */
#include "db.h"

#include <stdio.h>
#include <stdlib.h>

#include "queue_sql.h" /* generated from schema/queue.sql: lubd_queue_sql[] */

int lubd_db_exec(sqlite3 *db, const char *sql)
{
    char *msg = NULL;
    if (sqlite3_exec(db, sql, NULL, NULL, &msg) != SQLITE_OK) {
        fprintf(stderr, "lubdemd: sqlite: %s\n", msg ? msg : sqlite3_errmsg(db));
        sqlite3_free(msg);
        return -1;
    }
    return 0;
}

sqlite3 *lubd_db_open(const char *path, int create)
{
    sqlite3 *db = NULL;
    int flags = SQLITE_OPEN_READWRITE | SQLITE_OPEN_NOMUTEX | (create ? SQLITE_OPEN_CREATE : 0);
    if (sqlite3_open_v2(path, &db, flags, NULL) != SQLITE_OK) {
        fprintf(stderr, "lubdemd: cannot open database %s: %s\n", path,
                db ? sqlite3_errmsg(db) : "out of memory");
        sqlite3_close(db);
        return NULL;
    }
    sqlite3_busy_timeout(db, 10000);
    if (lubd_db_exec(db, "PRAGMA synchronous=NORMAL; PRAGMA foreign_keys=ON;") != 0)
        goto fail;
    if (create) {
        if (lubd_db_exec(db, "PRAGMA journal_mode=WAL;") != 0)
            goto fail;
        if (lubd_db_exec(db, "BEGIN IMMEDIATE;") != 0)
            goto fail;
        if (lubd_db_exec(db, lubd_queue_sql) != 0) {
            lubd_db_rollback(db);
            goto fail;
        }
        if (lubd_db_exec(db, "COMMIT;") != 0)
            goto fail;
    }
    return db;
fail:
    sqlite3_close(db);
    return NULL;
}

void lubd_db_close(sqlite3 *db) { sqlite3_close(db); }

int lubd_db_begin(sqlite3 *db) { return lubd_db_exec(db, "BEGIN IMMEDIATE"); }
int lubd_db_commit(sqlite3 *db) { return lubd_db_exec(db, "COMMIT"); }
void lubd_db_rollback(sqlite3 *db)
{
    if (!sqlite3_get_autocommit(db))
        sqlite3_exec(db, "ROLLBACK", NULL, NULL, NULL);
}

int lubd_db_prepare(sqlite3 *db, const char *sql, sqlite3_stmt **st)
{
    if (sqlite3_prepare_v2(db, sql, -1, st, NULL) != SQLITE_OK) {
        fprintf(stderr, "lubdemd: sqlite prepare: %s\n", sqlite3_errmsg(db));
        return -1;
    }
    return 0;
}

int lubd_db_pool_init(lubd_db_pool *p, const char *path, int n)
{
    p->n = n;
    pthread_mutex_init(&p->mu, NULL);
    pthread_cond_init(&p->cv, NULL);
    pthread_mutex_init(&p->write_mu, NULL);
    p->conns = calloc((size_t)n, sizeof *p->conns);
    p->busy = calloc((size_t)n, sizeof *p->busy);
    if (!p->conns || !p->busy)
        return -1;
    for (int i = 0; i < n; ++i)
        if (!(p->conns[i] = lubd_db_open(path, 0)))
            return -1;
    return 0;
}

void lubd_db_pool_destroy(lubd_db_pool *p)
{
    if (p->conns)
        for (int i = 0; i < p->n; ++i)
            sqlite3_close(p->conns[i]);
    free(p->conns);
    free(p->busy);
    p->conns = NULL;
    p->busy = NULL;
    pthread_mutex_destroy(&p->mu);
    pthread_cond_destroy(&p->cv);
    pthread_mutex_destroy(&p->write_mu);
}

sqlite3 *lubd_db_acquire(lubd_db_pool *p)
{
    pthread_mutex_lock(&p->mu);
    for (;;) {
        for (int i = 0; i < p->n; ++i)
            if (!p->busy[i]) {
                p->busy[i] = 1;
                pthread_mutex_unlock(&p->mu);
                return p->conns[i];
            }
        pthread_cond_wait(&p->cv, &p->mu);
    }
}

void lubd_db_release(lubd_db_pool *p, sqlite3 *db)
{
    lubd_db_rollback(db); /* never hand on an open transaction */
    pthread_mutex_lock(&p->mu);
    for (int i = 0; i < p->n; ++i)
        if (p->conns[i] == db)
            p->busy[i] = 0;
    pthread_cond_signal(&p->cv);
    pthread_mutex_unlock(&p->mu);
}

sqlite3 *lubd_db_acquire_writer(lubd_db_pool *p)
{
    pthread_mutex_lock(&p->write_mu);
    return lubd_db_acquire(p);
}

void lubd_db_release_writer(lubd_db_pool *p, sqlite3 *db)
{
    lubd_db_release(p, db);
    pthread_mutex_unlock(&p->write_mu);
}
