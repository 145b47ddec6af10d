/* tokens.c — token creation, revocation and bearer authentication. */
#include "tokens.h"

#include <stdio.h>
#include <string.h>
#include <strings.h>

#include "db.h"
#include "fsutil.h"
#include "sha256.h"

static long long ensure_user(sqlite3 *db, const char *user, int admin)
{
    sqlite3_stmt *st;
    if (lubd_db_prepare(db,
                        "INSERT INTO users(name, is_admin, created) VALUES (?1, ?2, " LUBD_SQL_NOW
                        ") ON CONFLICT(name) DO UPDATE SET is_admin = max(is_admin, ?2) "
                        "RETURNING id",
                        &st) != 0)
        return -1;
    sqlite3_bind_text(st, 1, user, -1, SQLITE_TRANSIENT);
    sqlite3_bind_int(st, 2, admin ? 1 : 0);
    long long id = -1;
    if (sqlite3_step(st) == SQLITE_ROW)
        id = sqlite3_column_int64(st, 0);
    else
        fprintf(stderr, "lubdemd: sqlite: %s\n", sqlite3_errmsg(db));
    sqlite3_finalize(st);
    return id;
}

int lubd_token_create(sqlite3 *db, const char *user, int admin, char token[LUBD_TOKEN_MAX])
{
    char id[17], secret[65], hash[65];
    if (strlen(user) == 0 || strlen(user) >= 64) {
        fprintf(stderr, "lubdemd: user name must have 1..63 characters\n");
        return -1;
    }
    if (lubd_random_hex(id, 8) != 0 || lubd_random_hex(secret, 32) != 0) {
        perror("lubdemd: /dev/urandom");
        return -1;
    }
    lubd_sha256_hex(secret, 64, hash);
    if (lubd_db_begin(db) != 0)
        return -1;
    long long uid = ensure_user(db, user, admin);
    sqlite3_stmt *st = NULL;
    if (uid < 0 || lubd_db_prepare(db,
                                   "INSERT INTO tokens(id, user_id, secret_sha256, created) "
                                   "VALUES (?1, ?2, ?3, " LUBD_SQL_NOW ")",
                                   &st) != 0)
        goto fail;
    sqlite3_bind_text(st, 1, id, -1, SQLITE_STATIC);
    sqlite3_bind_int64(st, 2, uid);
    sqlite3_bind_text(st, 3, hash, -1, SQLITE_STATIC);
    if (sqlite3_step(st) != SQLITE_DONE)
        goto fail;
    sqlite3_finalize(st);
    if (lubd_db_commit(db) != 0)
        goto fail;
    snprintf(token, LUBD_TOKEN_MAX, "lub_%s_%s", id, secret);
    return 0;
fail:
    sqlite3_finalize(st);
    lubd_db_rollback(db);
    return -1;
}

int lubd_token_revoke(sqlite3 *db, const char *token_or_id)
{
    char id[17] = {0};
    const char *p = token_or_id;
    if (strncmp(p, "lub_", 4) == 0)
        p += 4;
    if (strlen(p) < 16)
        return 0;
    memcpy(id, p, 16);
    sqlite3_stmt *st;
    if (lubd_db_prepare(
            db, "UPDATE tokens SET revoked = " LUBD_SQL_NOW " WHERE id = ?1 AND revoked IS NULL",
            &st) != 0)
        return -1;
    sqlite3_bind_text(st, 1, id, -1, SQLITE_STATIC);
    int rc = sqlite3_step(st);
    sqlite3_finalize(st);
    if (rc != SQLITE_DONE)
        return -1;
    return sqlite3_changes(db) > 0 ? 1 : 0;
}

int lubd_token_list(sqlite3 *db, FILE *out)
{
    sqlite3_stmt *st;
    if (lubd_db_prepare(db,
                        "SELECT t.id, u.name, u.is_admin, datetime(t.created, 'unixepoch'), "
                        "CASE WHEN t.revoked IS NULL THEN '-' ELSE datetime(t.revoked, "
                        "'unixepoch') END FROM tokens t JOIN users u ON u.id = t.user_id "
                        "ORDER BY t.created",
                        &st) != 0)
        return -1;
    fprintf(out, "%-16s  %-16s  %-5s  %-19s  %s\n", "id", "user", "admin", "created", "revoked");
    while (sqlite3_step(st) == SQLITE_ROW)
        fprintf(out, "%-16s  %-16s  %-5s  %-19s  %s\n", sqlite3_column_text(st, 0),
                sqlite3_column_text(st, 1), sqlite3_column_int(st, 2) ? "yes" : "no",
                sqlite3_column_text(st, 3), sqlite3_column_text(st, 4));
    sqlite3_finalize(st);
    return 0;
}

int lubd_user_set_cap(sqlite3 *db, const char *user, long long cap)
{
    sqlite3_stmt *st;
    if (lubd_db_prepare(db, "UPDATE users SET max_active = ?2 WHERE name = ?1", &st) != 0)
        return -1;
    sqlite3_bind_text(st, 1, user, -1, SQLITE_STATIC);
    if (cap < 0)
        sqlite3_bind_null(st, 2);
    else
        sqlite3_bind_int64(st, 2, cap);
    int rc = sqlite3_step(st);
    sqlite3_finalize(st);
    if (rc != SQLITE_DONE)
        return -1;
    return sqlite3_changes(db) > 0 ? 0 : -1;
}

int lubd_token_count(sqlite3 *db)
{
    sqlite3_stmt *st;
    if (lubd_db_prepare(db, "SELECT count(*) FROM tokens WHERE revoked IS NULL", &st) != 0)
        return -1;
    int n = sqlite3_step(st) == SQLITE_ROW ? sqlite3_column_int(st, 0) : -1;
    sqlite3_finalize(st);
    return n;
}

static int is_hex(const char *s, size_t n)
{
    for (size_t i = 0; i < n; ++i)
        if (!((s[i] >= '0' && s[i] <= '9') || (s[i] >= 'a' && s[i] <= 'f')))
            return 0;
    return 1;
}

int lubd_auth_bearer(sqlite3 *db, const char *authorization, lubd_user *u)
{
    if (!authorization || strncasecmp(authorization, "Bearer ", 7) != 0)
        return 1;
    const char *t = authorization + 7;
    while (*t == ' ')
        ++t;
    /* lub_ + 16 + _ + 64 */
    if (strlen(t) != 4 + 16 + 1 + 64 || strncmp(t, "lub_", 4) != 0 || t[20] != '_' ||
        !is_hex(t + 4, 16) || !is_hex(t + 21, 64))
        return 1;
    char id[17], hash[65];
    memcpy(id, t + 4, 16);
    id[16] = '\0';
    lubd_sha256_hex(t + 21, 64, hash);
    sqlite3_stmt *st;
    if (lubd_db_prepare(db,
                        "SELECT t.secret_sha256, u.id, u.name, u.is_admin, "
                        "coalesce(u.max_active, -1) FROM tokens t JOIN users u ON u.id = "
                        "t.user_id WHERE t.id = ?1 AND t.revoked IS NULL",
                        &st) != 0)
        return -1;
    sqlite3_bind_text(st, 1, id, -1, SQLITE_STATIC);
    int rc = sqlite3_step(st), result = 1;
    if (rc == SQLITE_ROW) {
        const char *stored = (const char *)sqlite3_column_text(st, 0);
        if (stored && strlen(stored) == 64 && lubd_ct_equal(stored, hash, 64)) {
            u->id = sqlite3_column_int64(st, 1);
            snprintf(u->name, sizeof u->name, "%s", (const char *)sqlite3_column_text(st, 2));
            u->is_admin = sqlite3_column_int(st, 3);
            u->max_active = sqlite3_column_int64(st, 4);
            result = 0;
        }
    } else if (rc != SQLITE_DONE) {
        fprintf(stderr, "lubdemd: sqlite: %s\n", sqlite3_errmsg(db));
        result = -1;
    }
    sqlite3_finalize(st);
    return result;
}
