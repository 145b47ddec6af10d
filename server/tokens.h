/* tokens.h — users and bearer tokens.
 *
 * A token reads "lub_<16 hex id>_<64 hex secret>". Only SHA-256(secret) (server/sha256.c) is
 * stored; authentication looks the row up by id and compares hashes in constant time.
 * The plaintext is shown once, by lubd_token_create. Functions take a caller-owned
 * connection; they return 0 on success, -1 on database error (message on stderr). */
#ifndef LUBD_TOKENS_H
#define LUBD_TOKENS_H

#include <sqlite3.h>
#include <stdio.h>

typedef struct {
    long long id;
    char name[64];
    int is_admin;
    long long max_active; /* -1 = server default */
} lubd_user;

#define LUBD_TOKEN_MAX 96

/* Creates the user if needed (admin=1 also promotes an existing user) and a new token. */
int lubd_token_create(sqlite3 *db, const char *user, int admin, char token[LUBD_TOKEN_MAX]);
/* Revokes a token given in full or by its id. Returns 1 if revoked, 0 if unknown, -1 error. */
int lubd_token_revoke(sqlite3 *db, const char *token_or_id);
/* Prints id, user, admin, created, revoked (one line per token). */
int lubd_token_list(sqlite3 *db, FILE *out);
/* Sets the per-user cap (max accepted+running jobs); cap < 0 = server default. */
int lubd_user_set_cap(sqlite3 *db, const char *user, long long cap);
/* Parses "Bearer <token>" and fills *u. Returns 0 ok, 1 missing/malformed/unknown/revoked,
 * -1 database error. */
int lubd_auth_bearer(sqlite3 *db, const char *authorization, lubd_user *u);
/* Number of non-revoked tokens (to decide whether to print the first-token hint). */
int lubd_token_count(sqlite3 *db);

#endif
