/* test_server_units.c — unit tests of the server's pure parts and of the queue/lease SQL on a
 * scratch database: SHA-256 vectors, Range parsing, progress lines, execution-request
 * validation, the memory check of submissions, claim order/fencing/reaping, hard link or
 * copy of a continuation's files, their hand-over when the job they continue is deleted, and
 * the freeing of what deletions left on disk (a service stopped between their steps, a
 * hand-over that failed), the serialisation of two frees of one job, and a results list
 * whose reading fails part-way; the OpenAPI 3.0 translation of the draft-07 input schemas.
 * Usage:
 * test_server_units SCRATCH_DIR */
#include <fcntl.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

#include "config.h"
#include "continuation.h"
#include "db.h"
#include "deletion.h"
#include "exec_request.h"
#include "fsutil.h"
#include "http_range.h"
#include "job_limits.h"
#include "lease.h"
#include "oas_schema.h"
#include "processors.h"
#include "progress_line.h"
#include "queue.h"
#include "sha256.h"
#include "status_json.h"
#include "tokens.h"
#include "worker.h"

static int failures = 0;
#define CHECK(c)                                                                                   \
    do {                                                                                           \
        if (!(c)) {                                                                                \
            fprintf(stderr, "%s:%d: CHECK failed: %s\n", __FILE__, __LINE__, #c);                  \
            ++failures;                                                                            \
        }                                                                                          \
    } while (0)

static void test_sha256(void)
{
    char hex[65];
    lubd_sha256_hex("", 0, hex);
    CHECK(strcmp(hex, "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855") == 0);
    lubd_sha256_hex("abc", 3, hex);
    CHECK(strcmp(hex, "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad") == 0);
    const char *two = "abcdbcdecdefdefgefghfghighijhijkijkljklmklmnlmnomnopnopq";
    lubd_sha256_hex(two, strlen(two), hex);
    CHECK(strcmp(hex, "248d6a61d20638b8e5c026930c3e6039a33ce45964ff2167f6ecedd419db06c1") == 0);
    /* one million 'a', fed in uneven pieces */
    lubd_sha256 c;
    lubd_sha256_init(&c);
    char block[997];
    memset(block, 'a', sizeof block);
    size_t left = 1000000;
    while (left) {
        size_t n = left < sizeof block ? left : sizeof block;
        lubd_sha256_update(&c, block, n);
        left -= n;
    }
    uint8_t d[32];
    lubd_sha256_final(&c, d);
    lubd_hex_encode(d, 32, hex);
    CHECK(strcmp(hex, "cdc76e5c9914fb9281a1c7e284d73e67f1809a48a497200e046d39ccc7112cd0") == 0);
    CHECK(lubd_ct_equal("abc", "abc", 3) && !lubd_ct_equal("abc", "abd", 3));
    CHECK(lubd_is_hex("0123456789abcdef0123456789abcdef", 16));
    CHECK(!lubd_is_hex("0123456789abcdef0123456789abcde", 16));   /* one short */
    CHECK(!lubd_is_hex("0123456789abcdef0123456789abcdef0", 16)); /* one long */
    CHECK(!lubd_is_hex("0123456789ABCDEF0123456789abcdef", 16));  /* upper case */
    CHECK(!lubd_is_hex("0123456789abcdeg0123456789abcdef", 16));
    CHECK(lubd_is_hex("", 0) && !lubd_is_hex("a", 0));
}

static void test_range(void)
{
    uint64_t f = 0, l = 0;
    CHECK(lubd_range_parse(NULL, 100, &f, &l) == LUBD_RANGE_NONE);
    CHECK(lubd_range_parse("bytes=0-9", 100, &f, &l) == LUBD_RANGE_OK && f == 0 && l == 9);
    CHECK(lubd_range_parse("bytes=90-", 100, &f, &l) == LUBD_RANGE_OK && f == 90 && l == 99);
    CHECK(lubd_range_parse("bytes=90-1000", 100, &f, &l) == LUBD_RANGE_OK && l == 99);
    CHECK(lubd_range_parse("bytes=-10", 100, &f, &l) == LUBD_RANGE_OK && f == 90 && l == 99);
    CHECK(lubd_range_parse("bytes=-1000", 100, &f, &l) == LUBD_RANGE_OK && f == 0);
    CHECK(lubd_range_parse("bytes=100-", 100, &f, &l) == LUBD_RANGE_UNSATISFIABLE);
    CHECK(lubd_range_parse("bytes=-0", 100, &f, &l) == LUBD_RANGE_UNSATISFIABLE);
    CHECK(lubd_range_parse("bytes=5-1", 100, &f, &l) == LUBD_RANGE_NONE);
    CHECK(lubd_range_parse("bytes=0-1,5-6", 100, &f, &l) == LUBD_RANGE_NONE);
    CHECK(lubd_range_parse("items=0-1", 100, &f, &l) == LUBD_RANGE_NONE);
    CHECK(lubd_range_parse("bytes=99999999999999999999-", 100, &f, &l) == LUBD_RANGE_NONE);
    CHECK(lubd_range_parse("bytes=-", 100, &f, &l) == LUBD_RANGE_NONE);
}

static void test_progress(void)
{
    lubd_progress p;
    CHECK(lubd_progress_parse("progress fraction=0.2500 step=1200 steps_per_s=3.1e+05 eta_s=12.0",
                              &p) == 1);
    CHECK(p.fraction == 0.25 && p.step == 1200 && p.eta_s == 12.0 && p.steps_per_s == 3.1e5);
    CHECK(lubd_progress_parse("progress fraction=7", &p) == 1 && p.fraction == 1.0);
    CHECK(lubd_progress_parse("progress fraction=nan", &p) == 0);
    CHECK(lubd_progress_parse("progress step=3", &p) == 0);
    CHECK(lubd_progress_parse("info: hello", &p) == 0);
}

static void test_exec(void)
{
    lubd_exec_request r, r2;
    lubd_fault f;
    const char *ok = "{\"inputs\": {\"duration\": 1.5}, \"priority\": -2}";
    CHECK(lubd_exec_parse(ok, strlen(ok), "falling_sphere", &r, &f) == 0);
    CHECK(r.priority == -2);
    CHECK(strcmp(json_string_value(json_object_get(r.spec, "scene")), "falling_sphere") == 0);
    CHECK(json_object_get(r.resolved, "St") != NULL); /* defaults filled in */
    const char *reordered = "{\"priority\": -2, \"inputs\": {\"duration\": 1.5}}";
    CHECK(lubd_exec_parse(reordered, strlen(reordered), "falling_sphere", &r2, &f) == 0);
    CHECK(strcmp(r.fingerprint, r2.fingerprint) == 0);
    lubd_exec_free(&r2);
    CHECK(lubd_exec_parse(ok, strlen(ok), "two_spheres_shear", &r2, &f) == 0);
    CHECK(strcmp(r.fingerprint, r2.fingerprint) != 0); /* process id is part of it */
    lubd_exec_free(&r2);
    lubd_exec_free(&r);
    /* numbers compare by value: an integer and a real of equal value, a real's spellings, -0.0
     * and 0, in objects and arrays, are one request; other values are not (until 2026-12-06
     * "stiffness": 1e5 then 100000 under one Idempotency-Key was a 409) */
    static const char *const same[][2] = {
        {"{\"inputs\": {\"stiffness\": 1e5, \"phi\": 0.5}}",
         "{\"inputs\": {\"phi\": 0.50, \"stiffness\": 100000}}"},
        {"{\"inputs\": {\"stiffness\": 100000.0, \"strain\": 2}}",
         "{\"inputs\": {\"stiffness\": 1.0e5, \"strain\": 2.0}}"},
        {"{\"inputs\": {\"law\": {\"eps\": 0}}, \"priority\": 0}",
         "{\"inputs\": {\"law\": {\"eps\": -0.0}}, \"priority\": 0}"},
        {"{\"inputs\": {}, \"outputs\": {\"x\": [1, 2.5, 3e0]}}",
         "{\"inputs\": {}, \"outputs\": {\"x\": [1.0, 2.50, 3]}}"}};
    for (size_t k = 0; k < sizeof same / sizeof same[0]; ++k) {
        CHECK(lubd_exec_parse(same[k][0], strlen(same[k][0]), "simple_shear", &r, &f) == 0);
        CHECK(lubd_exec_parse(same[k][1], strlen(same[k][1]), "simple_shear", &r2, &f) == 0);
        CHECK(strcmp(r.fingerprint, r2.fingerprint) == 0);
        lubd_exec_free(&r);
        lubd_exec_free(&r2);
    }
    static const char *const differ[][2] = {
        {"{\"inputs\": {\"stiffness\": 1e5}}", "{\"inputs\": {\"stiffness\": 100001}}"},
        {"{\"inputs\": {\"phi\": 0.5}}", "{\"inputs\": {\"phi\": 0.5000000000000001}}"},
        {"{\"inputs\": {\"strain\": 2}}", "{\"inputs\": {\"strain\": \"2\"}}"}};
    for (size_t k = 0; k < sizeof differ / sizeof differ[0]; ++k) {
        CHECK(lubd_exec_parse(differ[k][0], strlen(differ[k][0]), "simple_shear", &r, &f) == 0);
        const int parsed =
            lubd_exec_parse(differ[k][1], strlen(differ[k][1]), "simple_shear", &r2, &f) == 0;
        CHECK(!parsed || strcmp(r.fingerprint, r2.fingerprint) != 0);
        lubd_exec_free(&r);
        if (parsed)
            lubd_exec_free(&r2);
    }
    const char *bad = "{\"inputs\": {\"duration\": -1}}";
    CHECK(lubd_exec_parse(bad, strlen(bad), "falling_sphere", &r, &f) == -1);
    CHECK(f.status == 400 && strcmp(f.pointer, "/inputs/duration") == 0);
    CHECK(lubd_exec_parse(bad, strlen(bad), "nope", &r, &f) == -1 && f.status == 404);
    CHECK(lubd_exec_parse("{", 1, "falling_sphere", &r, &f) == -1 && f.status == 400);
    CHECK(lubd_exec_parse("", 0, "falling_sphere", &r, &f) == -1 && f.status == 400);
    /* a number beyond a double or an int64 is named at its member, not at the body's root */
    const char *huge = "{\"inputs\": {\"law\": {\"eps\": 1e400}}}";
    CHECK(lubd_exec_parse(huge, strlen(huge), "falling_sphere", &r, &f) == -1);
    CHECK(f.status == 400 && strcmp(f.pointer, "/inputs/law/eps") == 0 &&
          strstr(f.type, "invalid-input") && strstr(f.detail, "1e400") &&
          strstr(f.detail, "double"));
    const char *prio = "{\"inputs\": {}, \"priority\": 99999999999999999999}";
    CHECK(lubd_exec_parse(prio, strlen(prio), "falling_sphere", &r, &f) == -1);
    CHECK(f.status == 400 && strcmp(f.pointer, "/priority") == 0 &&
          strstr(f.type, "invalid-request") && strstr(f.detail, "64-bit integer"));
    /* not NUL-terminated at len: the text after len is not read */
    const char cut[] = "{\"inputs\": {\"duration\": 1e400}}XYZ";
    CHECK(lubd_exec_parse(cut, strlen(cut) - 3, "falling_sphere", &r, &f) == -1);
    CHECK(f.status == 400 && strcmp(f.pointer, "/inputs/duration") == 0);
    const char nul[] = "{\"inputs\": {\"duration\": 1e400}}\0x";
    CHECK(lubd_exec_parse(nul, sizeof nul - 1, "falling_sphere", &r, &f) == -1);
    CHECK(f.status == 400 && strcmp(f.pointer, "") == 0 && strstr(f.type, "malformed-json"));
}

/* Submissions whose lower bound of memory cannot fit what a job may use are refused
 * (job_limits.h): against --mem-mb, and against the machine when --mem-mb is 0. */
static void test_job_limits(void)
{
    lubd_config cfg;
    lubd_config_defaults(&cfg, "lubdemd");
    cfg.mem_mb = 8192;
    lubd_exec_request r;
    lubd_fault f;
    const char *big = "{\"inputs\": {\"n_particles\": 10000000}}"; /* >= 34 GiB */
    CHECK(lubd_exec_parse(big, strlen(big), "simple_shear", &r, &f) == 0);
    memset(&f, 0, sizeof f);
    CHECK(lubd_job_fits(&r, &cfg, &f) == -1);
    CHECK(f.status == 400 && strstr(f.type, "job-too-large") &&
          strcmp(f.pointer, "/inputs/n_particles") == 0);
    CHECK(strstr(f.detail, "10000000 particles at phi 0.5") && strstr(f.detail, "8 GiB") &&
          strstr(f.detail, "--mem-mb") && strstr(f.detail, "lower /inputs/n_particles"));
    cfg.mem_mb = 65536; /* 34 GiB fit in 64 GiB of address space (if the machine has them) */
    const int fits = lubd_job_fits(&r, &cfg, &f);
    CHECK(fits == 0 || strstr(f.detail, "machine") || strstr(f.detail, "control group"));
    lubd_exec_free(&r);
    const char *small = "{\"inputs\": {\"n_particles\": 1000}}";
    CHECK(lubd_exec_parse(small, strlen(small), "simple_shear", &r, &f) == 0);
    cfg.mem_mb = 8192;
    CHECK(lubd_job_fits(&r, &cfg, &f) == 0);
    lubd_exec_free(&r);
    /* --threads beyond the processors: the engine runs on the processors, so the bound counts
     * their per-thread sums, not 256 (1.5e6 particles: 5.1 GiB with 1 thread, 25 GiB with 256) */
    const char *mid = "{\"inputs\": {\"n_particles\": 1500000}}";
    CHECK(lubd_exec_parse(mid, strlen(mid), "simple_shear", &r, &f) == 0);
    cfg.engine_threads = 256;
    if (lub_processors_available() <= 32)
        CHECK(lubd_job_fits(&r, &cfg, &f) == 0);
    cfg.engine_threads = 0;
    lubd_exec_free(&r);
    /* no --mem-mb: about 1 TiB (cut-off 10 a) fits no machine this runs on */
    cfg.mem_mb = 0;
    const char *huge = "{\"inputs\": {\"n_particles\": 10000000, \"cutoff\": 10}}";
    CHECK(lubd_exec_parse(huge, strlen(huge), "simple_shear", &r, &f) == 0);
    CHECK(lubd_job_fits(&r, &cfg, &f) == -1 && f.status == 400 && !strstr(f.detail, "--mem-mb"));
    lubd_exec_free(&r);
    /* scenes without an estimate are never refused */
    const char *fall = "{\"inputs\": {\"duration\": 1.5}}";
    cfg.mem_mb = 1;
    CHECK(lubd_exec_parse(fall, strlen(fall), "falling_sphere", &r, &f) == 0);
    CHECK(lubd_job_fits(&r, &cfg, &f) == 0);
    lubd_exec_free(&r);
}

static void test_queue(const char *dir)
{
    char path[1024];
    snprintf(path, sizeof path, "%s/units.db", dir);
    unlink(path);
    sqlite3 *db = lubd_db_open(path, 1);
    CHECK(db != NULL);
    if (!db)
        return;
    char tok[LUBD_TOKEN_MAX];
    CHECK(lubd_token_create(db, "u", 0, tok) == 0);
    char auth[200];
    snprintf(auth, sizeof auth, "Bearer %s", tok);
    lubd_user u;
    CHECK(lubd_auth_bearer(db, auth, &u) == 0 && strcmp(u.name, "u") == 0 && !u.is_admin);
    auth[strlen(auth) - 1] ^= 1; /* flip the last hex digit */
    CHECK(lubd_auth_bearer(db, auth, &u) == 1);
    CHECK(lubd_auth_bearer(db, "Basic abc", &u) == 1);
    /* Submit three jobs; the highest priority is claimed first, then FIFO. */
    const char *ids_prio[3] = {"0", "5", "0"};
    char ids[3][33];
    for (int i = 0; i < 3; ++i) {
        lubd_submit s = {
            u.id,        10,   "falling_sphere",  "{}", "{\"scene\":\"falling_sphere\"}",
            ids_prio[i], NULL, atoi(ids_prio[i]), 2,    NULL};
        int replayed;
        lubd_fault f;
        CHECK(lubd_queue_submit(db, &s, ids[i], &replayed, &f) == 0 && !replayed);
    }
    lubd_claim c1, c2;
    CHECK(lubd_lease_claim(db, "t1", 60, &c1) == 1 && strcmp(c1.id, ids[1]) == 0);
    CHECK(lubd_lease_claim(db, "t2", 0, &c2) == 1 && strcmp(c2.id, ids[0]) == 0);
    lubd_claim stale = c1;
    strcpy(stale.token, "00000000000000000000000000000000");
    CHECK(lubd_lease_heartbeat(db, &stale, 60, 10, "x", 0) == 0); /* fenced */
    CHECK(lubd_lease_heartbeat(db, &c1, 60, 10, "running: 10%", 1234) == 1);
    CHECK(lubd_lease_fail(db, &stale, "executor", "no") == 0);
    /* c2's lease (0 s) has expired: the reaper requeues it and its token is dead. */
    struct timespec ts = {0, 20000000L};
    nanosleep(&ts, NULL);
    int rq, fl;
    CHECK(lubd_queue_reap(db, &rq, &fl) == 0 && rq == 1 && fl == 0);
    CHECK(lubd_lease_heartbeat(db, &c2, 60, 20, NULL, 0) == 0);
    CHECK(lubd_lease_fail(db, &c2, "executor", "late") == 0);
    lubd_job j;
    CHECK(lubd_queue_get(db, ids[0], &j) == 1 && strcmp(j.state, "accepted") == 0 &&
          j.attempt == 1);
    /* Second attempt also dies (lease 0 s): max_attempts = 2 is reached -> failed/system. */
    lubd_claim c3;
    CHECK(lubd_lease_claim(db, "t3", 0, &c3) == 1 && strcmp(c3.id, ids[0]) == 0 && c3.attempt == 2);
    nanosleep(&ts, NULL);
    CHECK(lubd_queue_reap(db, &rq, &fl) == 0 && rq == 0 && fl == 1);
    CHECK(lubd_queue_get(db, ids[0], &j) == 1 && strcmp(j.state, "failed") == 0 &&
          strcmp(j.failure_kind, "system") == 0);
    CHECK(lubd_lease_fail(db, &c3, "executor", "late") == 0);
    lubd_lease_clear(&c3);
    /* A full database (here its page limit; on a full disk SQLite says the same) refuses a
     * submission with 507 and a Retry-After, and leaves nothing behind; lifting the limit lets
     * the same submission through. (It was a 500 "database error".) */
    {
        sqlite3_stmt *st = NULL;
        long pages = 0;
        if (sqlite3_prepare_v2(db, "PRAGMA page_count", -1, &st, NULL) == SQLITE_OK &&
            sqlite3_step(st) == SQLITE_ROW)
            pages = (long)sqlite3_column_int64(st, 0);
        sqlite3_finalize(st);
        char pragma[64];
        snprintf(pragma, sizeof pragma, "PRAGMA max_page_count = %ld", pages);
        CHECK(pages > 0 && sqlite3_exec(db, pragma, NULL, NULL, NULL) == SQLITE_OK);
        static char big[200000]; /* a spec that needs new pages */
        memset(big, ' ', sizeof big - 3);
        big[0] = '{';
        big[sizeof big - 3] = '}';
        lubd_submit s = {u.id, 10, "falling_sphere", "{}", big, "fp-full", NULL, 0, 3, NULL};
        char id_full[33];
        int rep;
        lubd_fault f;
        memset(&f, 0, sizeof f);
        CHECK(lubd_queue_submit(db, &s, id_full, &rep, &f) == -1 && f.status == 507 &&
              f.retry_after > 0);
        int acc = -1, run = -1;
        CHECK(lubd_queue_counts(db, &acc, &run) == 0 && acc == 1 && run == 1);
        CHECK(sqlite3_exec(db, "PRAGMA max_page_count = 1073741823", NULL, NULL, NULL) ==
              SQLITE_OK);
        CHECK(lubd_queue_submit(db, &s, id_full, &rep, &f) == 0 && !rep);
        CHECK(lubd_queue_dismiss(db, id_full, &j, NULL, &rep) == 0); /* back to the counts above */
    }
    /* Idempotency: same key + same fingerprint -> same job; other fingerprint -> 409. */
    {
        lubd_submit s = {u.id, 10, "falling_sphere", "{}", "{}", "fp-a", "key-1", 0, 3, NULL};
        char a1[33], a2[33];
        int rep;
        lubd_fault f;
        CHECK(lubd_queue_submit(db, &s, a1, &rep, &f) == 0 && !rep);
        CHECK(lubd_queue_submit(db, &s, a2, &rep, &f) == 0 && rep && strcmp(a1, a2) == 0);
        s.fingerprint = "fp-b";
        CHECK(lubd_queue_submit(db, &s, a2, &rep, &f) == -1 && f.status == 409);
        /* cap: u has ids[2] + a1 active = 2; a cap of 2 refuses the next one */
        s.idempotency_key = NULL;
        s.user_cap = 2;
        CHECK(lubd_queue_submit(db, &s, a2, &rep, &f) == -1 && f.status == 429 &&
              f.retry_after > 0);
    }
    /* The reaper judges every lease against one instant T: a lease ending 1 ms before T is
     * requeued with exactly one event stamped T, one ending 1 ms after T is left alone and
     * gets none. (SQLite's own 'now' moves between the reaper's statements; judged against it,
     * a lease expiring between the event INSERT and the UPDATE lost its event; server.kill9
     * caught that once as a job claimed twice without a requeue.) */
    {
        lubd_submit s = {u.id, 10, "falling_sphere", "{}", "{}", "fp-reap", NULL, 10, 3, NULL};
        char ra[33], rb[33];
        int rep;
        lubd_fault f;
        CHECK(lubd_queue_submit(db, &s, ra, &rep, &f) == 0);
        s.fingerprint = "fp-reap-2";
        CHECK(lubd_queue_submit(db, &s, rb, &rep, &f) == 0);
        lubd_claim ca, cb;
        CHECK(lubd_lease_claim(db, "ra", 100, &ca) == 1 && strcmp(ca.id, ra) == 0);
        CHECK(lubd_lease_claim(db, "rb", 100, &cb) == 1 && strcmp(cb.id, rb) == 0);
        /* T: 30 s from now, inside the 60 s lease of the job still running from above */
        double T = 0.0;
        {
            sqlite3_stmt *st;
            CHECK(sqlite3_prepare_v2(db, "SELECT " LUBD_SQL_NOW " + 30", -1, &st, NULL) ==
                  SQLITE_OK);
            CHECK(sqlite3_step(st) == SQLITE_ROW);
            T = sqlite3_column_double(st, 0);
            sqlite3_finalize(st);
        }
        const char *ids_ab[2] = {ra, rb};
        for (int k = 0; k < 2; ++k) {
            sqlite3_stmt *st;
            CHECK(sqlite3_prepare_v2(db, "UPDATE jobs SET lease_until = ?2 WHERE id = ?1", -1, &st,
                                     NULL) == SQLITE_OK);
            sqlite3_bind_text(st, 1, ids_ab[k], -1, SQLITE_STATIC);
            sqlite3_bind_double(st, 2, k == 0 ? T - 1e-3 : T + 1e-3);
            CHECK(sqlite3_step(st) == SQLITE_DONE);
            sqlite3_finalize(st);
        }
        int rq2, fl2;
        CHECK(lubd_queue_reap_at(db, T, &rq2, &fl2) == 0 && rq2 == 1 && fl2 == 0);
        lubd_job ja, jb;
        CHECK(lubd_queue_get(db, ra, &ja) == 1 && strcmp(ja.state, "accepted") == 0);
        CHECK(lubd_queue_get(db, rb, &jb) == 1 && strcmp(jb.state, "running") == 0);
        for (int k = 0; k < 2; ++k) {
            sqlite3_stmt *st;
            CHECK(sqlite3_prepare_v2(db,
                                     "SELECT count(*), coalesce(min(at), 0) FROM job_events "
                                     "WHERE job_id = ?1 AND event = 'requeued'",
                                     -1, &st, NULL) == SQLITE_OK);
            sqlite3_bind_text(st, 1, ids_ab[k], -1, SQLITE_STATIC);
            CHECK(sqlite3_step(st) == SQLITE_ROW);
            const int n_ev = sqlite3_column_int(st, 0);
            const double at = sqlite3_column_double(st, 1);
            CHECK(k == 0 ? (n_ev == 1 && at == T) : n_ev == 0);
            sqlite3_finalize(st);
        }
        CHECK(lubd_lease_heartbeat(db, &ca, 60, 5, NULL, 0) == 0); /* requeued: fenced */
        CHECK(lubd_lease_heartbeat(db, &cb, 60, 5, NULL, 0) == 1);
        lubd_lease_clear(&ca);
        lubd_lease_clear(&cb);
    }
    /* A job read queued and claimed by a worker before it is dismissed: the dismissal says
     * it dismissed a running job (the state read in its own transaction, what the request acts
     * on), not the queued one read before it. */
    int purge;
    lubd_job after;
    char was[16];
    {
        lubd_submit s = {u.id, 10, "falling_sphere", "{}", "{}", "fp-race", NULL, 10, 3, NULL};
        char rid[33];
        int rep;
        lubd_fault f;
        CHECK(lubd_queue_submit(db, &s, rid, &rep, &f) == 0);
        lubd_job seen;
        CHECK(lubd_queue_get(db, rid, &seen) == 1 && strcmp(seen.state, "accepted") == 0);
        lubd_claim cr; /* the jobs queued before it are claimed first */
        int claimed = 0;
        for (int k = 0; k < 8 && !claimed; ++k) {
            CHECK(lubd_lease_claim(db, "racer", 60, &cr) == 1);
            claimed = strcmp(cr.id, rid) == 0;
            if (!claimed)
                lubd_lease_clear(&cr);
        }
        CHECK(claimed);
        CHECK(lubd_queue_dismiss(db, rid, &after, was, &purge) == 0 && !purge &&
              strcmp(was, "running") == 0 && strcmp(after.state, "dismissed") == 0 &&
              strncmp(after.message, "stopped while it ran", 20) == 0);
        /* ... and one that ended in between is deleted as the ended job it is */
        CHECK(lubd_queue_dismiss(db, rid, &after, was, &purge) == 0 && purge &&
              strcmp(was, "dismissed") == 0 && after.purged);
        CHECK(lubd_queue_dismiss(db, rid, &after, was, &purge) == 1 && was[0] == '\0');
        lubd_lease_clear(&cr);
    }
    /* Dismissing the running job makes its holder's heartbeat fail. */
    CHECK(lubd_queue_dismiss(db, ids[1], &after, was, &purge) == 0 && !purge &&
          strcmp(was, "running") == 0 && strcmp(after.state, "dismissed") == 0);
    CHECK(lubd_lease_heartbeat(db, &c1, 60, 30, NULL, 0) == 0);
    /* ... and the failure its holder then reports is not recorded, but drops the lease the
     * dismissal kept (it stayed set until 2026-12-06) */
    CHECK(lubd_lease_fail(db, &c1, "executor", "late") == 0);
    {
        sqlite3_stmt *st = NULL;
        CHECK(sqlite3_prepare_v2(db,
                                 "SELECT state, lease_token IS NULL, lease_until IS NULL, "
                                 "failure_kind FROM jobs WHERE id = ?1",
                                 -1, &st, NULL) == SQLITE_OK);
        sqlite3_bind_text(st, 1, ids[1], -1, SQLITE_STATIC);
        CHECK(sqlite3_step(st) == SQLITE_ROW &&
              strcmp((const char *)sqlite3_column_text(st, 0), "dismissed") == 0 &&
              sqlite3_column_int(st, 1) == 1 && sqlite3_column_int(st, 2) == 1 &&
              strcmp((const char *)sqlite3_column_text(st, 3), "cancelled") == 0);
        sqlite3_finalize(st);
    }
    CHECK(lubd_queue_dismiss(db, ids[1], &after, NULL, &purge) == 0 && purge && after.purged);
    CHECK(lubd_queue_dismiss(db, ids[1], &after, NULL, &purge) == 1);
    lubd_lease_clear(&c1);
    lubd_lease_clear(&c2);
    lubd_db_close(db);
}

/* A run whose results cannot be recorded (the database refuses the rows: a full disk at
 * COMMIT, here a trigger) stays running with its files back in out/, not in a result/ the
 * database does not list; once the database takes them, the job succeeds with them. */
static void test_finish_refused(const char *dir)
{
    char path[1024], out[1100], res[1100], file[1200];
    snprintf(path, sizeof path, "%s/finish.db", dir);
    snprintf(out, sizeof out, "%s/finish-out", dir);
    snprintf(res, sizeof res, "%s/finish-result", dir);
    unlink(path);
    lubd_rm_rf(out);
    lubd_rm_rf(res);
    sqlite3 *db = lubd_db_open(path, 1);
    CHECK(db != NULL);
    if (!db)
        return;
    char tok[LUBD_TOKEN_MAX], id[33];
    CHECK(lubd_token_create(db, "f", 0, tok) == 0);
    char auth[200];
    snprintf(auth, sizeof auth, "Bearer %s", tok);
    lubd_user u;
    CHECK(lubd_auth_bearer(db, auth, &u) == 0);
    lubd_submit s = {
        u.id, 10, "falling_sphere", "{}", "{\"scene\":\"falling_sphere\"}", "0", NULL, 0, 2, NULL};
    int replayed;
    lubd_fault f;
    CHECK(lubd_queue_submit(db, &s, id, &replayed, &f) == 0);
    lubd_claim c;
    CHECK(lubd_lease_claim(db, "w", 60, &c) == 1);
    CHECK(mkdir(out, 0755) == 0);
    snprintf(file, sizeof file, "%s/summary.json", out);
    FILE *fp = fopen(file, "w");
    CHECK(fp != NULL);
    if (fp)
        fclose(fp);
    lubd_output_file files[1] = {{"summary.json", "application/json", 0, ""}};
    memset(files[0].sha256, 'a', 64);
    files[0].sha256[64] = '\0';
    CHECK(sqlite3_exec(db,
                       "CREATE TEMP TRIGGER refuse BEFORE INSERT ON results "
                       "BEGIN SELECT RAISE(ABORT, 'database or disk is full'); END",
                       NULL, NULL, NULL) == SQLITE_OK);
    CHECK(lubd_lease_succeed(db, &c, out, res, files, 1, "completed") == -1);
    struct stat sb;
    CHECK(stat(file, &sb) == 0 && stat(res, &sb) != 0);
    lubd_job j;
    CHECK(lubd_queue_get(db, id, &j) == 1 && strcmp(j.state, "running") == 0);
    CHECK(sqlite3_exec(db, "DROP TRIGGER refuse", NULL, NULL, NULL) == SQLITE_OK);
    CHECK(lubd_lease_succeed(db, &c, out, res, files, 1, "completed") == 1);
    snprintf(file, sizeof file, "%s/summary.json", res);
    CHECK(stat(file, &sb) == 0 && stat(out, &sb) != 0);
    CHECK(lubd_queue_get(db, id, &j) == 1 && strcmp(j.state, "successful") == 0);
    lubd_lease_clear(&c);
    lubd_db_close(db);
    lubd_rm_rf(res);
    unlink(path);
}

/* Reads a whole small file into buf (NUL-terminated); its length, or -1. */
static long slurp(const char *path, char *buf, size_t n)
{
    FILE *f = fopen(path, "rb");
    if (!f)
        return -1;
    size_t got = fread(buf, 1, n - 1, f);
    fclose(f);
    buf[got] = '\0';
    return (long)got;
}

/* lubd_link_or_copy: a hard link on one file system, a copy across two (/dev/shm, where it
 * is another file system than dir), never over an existing file. */
static void test_link_or_copy(const char *dir)
{
    char src[600], dst[600], text[64];
    snprintf(src, sizeof src, "%s/link_src", dir);
    snprintf(dst, sizeof dst, "%s/link_dst", dir);
    unlink(dst);
    CHECK(lubd_write_file_atomic(src, "state\n", 6) == 0);
    CHECK(lubd_link_or_copy(src, dst) == 0);
    struct stat a, b;
    CHECK(stat(src, &a) == 0 && stat(dst, &b) == 0 && a.st_ino == b.st_ino);
    CHECK(lubd_link_or_copy(src, dst) != 0); /* dst exists: refused, not replaced */
    char shm[600];
    snprintf(shm, sizeof shm, "/dev/shm/lubd_link_test_%ld", (long)getpid());
    struct stat d, m;
    if (lubd_write_file_atomic(shm, "other fs\n", 9) == 0 && stat(shm, &m) == 0 &&
        stat(dir, &d) == 0 && m.st_dev != d.st_dev) {
        unlink(dst);
        CHECK(lubd_link_or_copy(shm, dst) == 0);
        CHECK(slurp(dst, text, sizeof text) == 9 && strcmp(text, "other fs\n") == 0);
        CHECK(stat(dst, &b) == 0 && b.st_ino != m.st_ino);
    } else {
        printf("link_or_copy: no second file system at /dev/shm; the copy is not exercised\n");
    }
    unlink(shm);
    CHECK(lubd_link_or_copy("/nonexistent/lubd", dst) != 0);
    unlink(dst);
    unlink(src);
}

/* A deleted job hands its files over to the continuations that have not ended: hard links in
 * jobs/<id>/continued-from/ (no temporary folder left), none to a continuation that ended,
 * once only; a continuation of a deleted (purged) or unknown job is refused by the submission
 * itself, in its write transaction, unless it is the replay of one made before. */
/* A new scratch queue DIR/<name>.db (path) with one user (*u), and the path of its jobs folder
 * DIR/<name>-jobs (removed if there). NULL when the database cannot be made. */
static sqlite3 *scratch_queue(const char *dir, const char *name, char path[1024], char jobs[1024],
                              lubd_user *u)
{
    snprintf(path, 1024, "%s/%s.db", dir, name);
    snprintf(jobs, 1024, "%s/%s-jobs", dir, name);
    unlink(path);
    lubd_rm_rf(jobs);
    sqlite3 *db = lubd_db_open(path, 1);
    CHECK(db != NULL);
    if (!db)
        return NULL;
    char tok[LUBD_TOKEN_MAX], auth[200];
    CHECK(lubd_token_create(db, name, 0, tok) == 0);
    snprintf(auth, sizeof auth, "Bearer %s", tok);
    CHECK(lubd_auth_bearer(db, auth, u) == 0);
    return db;
}

static void test_hand_over(const char *dir)
{
    char path[1024], jobs[1024], f[1400];
    lubd_user u;
    sqlite3 *db = scratch_queue(dir, "handover", path, jobs, &u);
    if (!db)
        return;
    lubd_submit s = {u.id, 10, "simple_shear", "{}", "{}", "fp-src", NULL, 0, 3, NULL};
    char src[33], queued[33], ended[33], other[33];
    int rep;
    lubd_fault fault;
    CHECK(lubd_queue_submit(db, &s, src, &rep, &fault) == 0);
    char req[200];
    snprintf(req, sizeof req, "{\"continue_from\": \"%s\"}", src);
    s.request_json = req;
    s.continue_from = src;
    s.fingerprint = "fp-q";
    s.idempotency_key = "key-q";
    CHECK(lubd_queue_submit(db, &s, queued, &rep, &fault) == 0);
    s.idempotency_key = NULL;
    s.fingerprint = "fp-e";
    CHECK(lubd_queue_submit(db, &s, ended, &rep, &fault) == 0);
    s.request_json = "{}";
    s.continue_from = NULL;
    s.fingerprint = "fp-o";
    CHECK(lubd_queue_submit(db, &s, other, &rep, &fault) == 0);
    char sql[300];
    snprintf(sql, sizeof sql, "UPDATE jobs SET state = 'successful' WHERE id IN ('%s', '%s')", src,
             ended);
    CHECK(sqlite3_exec(db, sql, NULL, NULL, NULL) == SQLITE_OK);
    snprintf(f, sizeof f, "%s/%s/result", jobs, src);
    CHECK(lubd_mkdir_p(f, 0750) == 0);
    snprintf(f, sizeof f, "%s/%s/result/checkpoint.h5", jobs, src);
    CHECK(lubd_write_file_atomic(f, "ckpt\n", 5) == 0);
    snprintf(f, sizeof f, "%s/%s/result/result.h5", jobs, src);
    CHECK(lubd_write_file_atomic(f, "rows\n", 5) == 0);
    char why[900] = "";
    CHECK(lubd_continuation_hand_over(db, jobs, src, why, sizeof why) == 1);
    struct stat a, b;
    char g[1400];
    snprintf(g, sizeof g, "%s/%s/" LUBD_CONTINUED_FROM "/result.h5", jobs, queued);
    CHECK(stat(f, &a) == 0 && stat(g, &b) == 0 && a.st_ino == b.st_ino);
    snprintf(g, sizeof g, "%s/%s/" LUBD_CONTINUED_FROM "/checkpoint.h5", jobs, queued);
    CHECK(access(g, F_OK) == 0);
    snprintf(g, sizeof g, "%s/%s/" LUBD_CONTINUED_FROM "/checkpoint-result.h5", jobs, queued);
    CHECK(access(g, F_OK) != 0); /* not in the source: not made up */
    snprintf(g, sizeof g, "%s/%s/." LUBD_CONTINUED_FROM ".tmp", jobs, queued);
    CHECK(access(g, F_OK) != 0);
    snprintf(g, sizeof g, "%s/%s", jobs, ended);
    CHECK(access(g, F_OK) != 0);
    CHECK(lubd_continuation_hand_over(db, jobs, src, why, sizeof why) == 1); /* again: kept */
    CHECK(lubd_continuation_hand_over(db, jobs, other, why, sizeof why) == 0);
    /* a source without its checkpoint cannot be handed over: -1 and the reason */
    CHECK(unlink(f) == 0);
    snprintf(f, sizeof f, "%s/%s/result/checkpoint.h5", jobs, src);
    CHECK(unlink(f) == 0);
    snprintf(g, sizeof g, "%s/%s/" LUBD_CONTINUED_FROM, jobs, queued);
    CHECK(lubd_rm_rf(g) == 0);
    CHECK(lubd_continuation_hand_over(db, jobs, src, why, sizeof why) == -1 &&
          strstr(why, "checkpoint.h5") != NULL && strstr(why, queued) != NULL);
    CHECK(access(g, F_OK) != 0);
    /* once the source is purged, or for an unknown job, a continuation is refused */
    lubd_job j;
    CHECK(lubd_queue_dismiss(db, src, &j, NULL, &rep) == 0 && rep == 1);
    s.continue_from = src;
    s.fingerprint = "fp-late";
    memset(&fault, 0, sizeof fault);
    CHECK(lubd_queue_submit(db, &s, other, &rep, &fault) == -1 && fault.status == 400 &&
          strstr(fault.detail, "deleted") != NULL);
    s.continue_from = "0123456789abcdef0123456789abcdef";
    CHECK(lubd_queue_submit(db, &s, other, &rep, &fault) == -1 && fault.status == 400);
    /* ... but a retried submission (the same key and request) gets its job again */
    CHECK(lubd_queue_is_replay(db, u.id, "key-q", "fp-q") == 1);
    CHECK(lubd_queue_is_replay(db, u.id, "key-q", "fp-other") == 0);
    CHECK(lubd_queue_is_replay(db, u.id, "key-none", "fp-q") == 0);
    CHECK(lubd_queue_is_replay(db, u.id + 1, "key-q", "fp-q") == 0);
    s.continue_from = src;
    s.idempotency_key = "key-q";
    s.fingerprint = "fp-q";
    CHECK(lubd_queue_submit(db, &s, other, &rep, &fault) == 0 && rep && strcmp(other, queued) == 0);
    /* a key older than its day goes at the next keyed submission, whichever its key: a client
     * that never reuses one does not grow the table without end */
    CHECK(lubd_db_exec(db, "UPDATE idempotency SET created = created - 90000") == 0);
    s.continue_from = NULL;
    s.request_json = "{}";
    s.idempotency_key = "key-new";
    s.fingerprint = "fp-new";
    CHECK(lubd_queue_submit(db, &s, other, &rep, &fault) == 0 && !rep);
    sqlite3_stmt *count;
    CHECK(lubd_db_prepare(db, "SELECT count(*) FROM idempotency", &count) == 0);
    CHECK(sqlite3_step(count) == SQLITE_ROW && sqlite3_column_int(count, 0) == 1);
    sqlite3_finalize(count);
    CHECK(lubd_queue_is_replay(db, u.id, "key-new", "fp-new") == 1);
    lubd_db_close(db);
    lubd_rm_rf(jobs);
    unlink(path);
}

/* a file with some bytes at jobs/<id>/<rel> (folders made) */
static void put_file(const char *jobs, const char *id, const char *rel)
{
    char f[1400], d[1400];
    snprintf(f, sizeof f, "%s/%s/%s", jobs, id, rel);
    snprintf(d, sizeof d, "%s", f);
    *strrchr(d, '/') = '\0';
    CHECK(lubd_mkdir_p(d, 0750) == 0);
    CHECK(lubd_write_file_atomic(f, "data\n", 5) == 0);
}

static int exists(const char *jobs, const char *id, const char *rel)
{
    char f[1400];
    snprintf(f, sizeof f, "%s/%s%s%s", jobs, id, rel[0] ? "/" : "", rel);
    return access(f, F_OK) == 0;
}

/* a new simple_shear job of user_id (a continuation of `from` unless NULL) */
static void submit_job(sqlite3 *db, long long user_id, char id[33], const char *from)
{
    static int k = 0;
    char fp[40], req[200];
    snprintf(fp, sizeof fp, "fp-%d", k++);
    snprintf(req, sizeof req, "{\"continue_from\": \"%s\"}", from ? from : "");
    lubd_submit s = {user_id, 20, "simple_shear", from ? req : "{}", "{}", fp, NULL, 0, 3, from};
    int rep;
    lubd_fault fault;
    CHECK(lubd_queue_submit(db, &s, id, &rep, &fault) == 0);
}

static void test_deletion_sweep(const char *dir)
{
    char path[1024], jobs[1024];
    lubd_user u;
    sqlite3 *db = scratch_queue(dir, "sweep", path, jobs, &u);
    if (!db)
        return;
    CHECK(lubd_deletion_sweep(db, jobs, 1) == 0); /* no jobs folder yet: nothing to do */
    /* cut: deleted when the service stopped before its hand-over; q_cut continues it.
     * nockpt: its hand-over fails (no checkpoint); q_nockpt continues it.
     * e_old: an ended continuation that still holds handed-over files; r_req: one requeued
     * (accepted again), which keeps them. live: an ended job nobody deleted. */
    char cut[33], q_cut[33], nockpt[33], q_nockpt[33], e_old[33], r_req[33], live[33];
    int rep;
    submit_job(db, u.id, cut, NULL);
    submit_job(db, u.id, nockpt, NULL);
    submit_job(db, u.id, live, NULL);
    submit_job(db, u.id, q_cut, cut);
    submit_job(db, u.id, q_nockpt, nockpt);
    submit_job(db, u.id, e_old, live);
    submit_job(db, u.id, r_req, live);
    char sql[400];
    snprintf(sql, sizeof sql,
             "UPDATE jobs SET state = 'successful' WHERE id IN ('%s', '%s', '%s');"
             "UPDATE jobs SET state = 'failed' WHERE id = '%s'",
             cut, nockpt, live, e_old);
    CHECK(sqlite3_exec(db, sql, NULL, NULL, NULL) == SQLITE_OK);
    put_file(jobs, cut, "result/checkpoint.h5");
    put_file(jobs, cut, "result/result.h5");
    put_file(jobs, nockpt, "result/result.h5");
    put_file(jobs, live, "result/checkpoint.h5");
    put_file(jobs, e_old, LUBD_CONTINUED_FROM "/checkpoint.h5");
    put_file(jobs, r_req, LUBD_CONTINUED_FROM "/checkpoint.h5");
    put_file("", jobs, "notes/readme.txt");                            /* not a job's folder */
    put_file(jobs, "0123456789abcdef0123456789abcdef", "result/x.h5"); /* no such job */
    lubd_job j;
    CHECK(lubd_queue_dismiss(db, cut, &j, NULL, &rep) == 0 && rep == 1);
    CHECK(lubd_queue_dismiss(db, nockpt, &j, NULL, &rep) == 0 && rep == 1);
    /* nockpt's deletion: the hand-over fails, the folder is kept for q_nockpt */
    char why[1400] = "";
    CHECK(lubd_deletion_free(db, jobs, nockpt, why, sizeof why) == 1 &&
          strstr(why, q_nockpt) != NULL && strstr(why, "is kept") != NULL);
    CHECK(exists(jobs, nockpt, "result/result.h5"));
    /* the service starts again: cut's folder is handed over and freed, e_old's handed files
     * go; nockpt's stays (q_nockpt has not ended), and so does every other folder */
    CHECK(lubd_deletion_sweep(db, jobs, 1) == 2);
    CHECK(!exists(jobs, cut, ""));
    CHECK(exists(jobs, q_cut, LUBD_CONTINUED_FROM "/checkpoint.h5") &&
          exists(jobs, q_cut, LUBD_CONTINUED_FROM "/result.h5"));
    CHECK(!exists(jobs, e_old, LUBD_CONTINUED_FROM) && exists(jobs, e_old, ""));
    CHECK(exists(jobs, r_req, LUBD_CONTINUED_FROM "/checkpoint.h5"));
    CHECK(exists(jobs, nockpt, "result/result.h5"));
    CHECK(exists(jobs, live, "result/checkpoint.h5"));
    CHECK(exists(jobs, "notes", "readme.txt"));
    CHECK(exists(jobs, "0123456789abcdef0123456789abcdef", "result/x.h5"));
    CHECK(lubd_deletion_sweep(db, jobs, 1) == 0); /* nothing left to do: nothing freed */
    /* q_nockpt ends (it could not start without the checkpoint): nockpt's folder goes with it */
    snprintf(sql, sizeof sql, "UPDATE jobs SET state = 'failed' WHERE id = '%s'", q_nockpt);
    CHECK(sqlite3_exec(db, sql, NULL, NULL, NULL) == SQLITE_OK);
    CHECK(lubd_deletion_continuation_ended(db, jobs, q_nockpt, nockpt, why, sizeof why) == 0);
    CHECK(!exists(jobs, nockpt, ""));
    /* q_cut ends: its handed-over files go; live (not deleted) is not touched */
    CHECK(lubd_deletion_continuation_ended(db, jobs, q_cut, cut, why, sizeof why) == 0);
    CHECK(!exists(jobs, q_cut, LUBD_CONTINUED_FROM));
    CHECK(lubd_deletion_continuation_ended(db, jobs, r_req, live, why, sizeof why) == 0);
    CHECK(exists(jobs, live, "result/checkpoint.h5"));
    lubd_db_close(db);
    lubd_rm_rf(jobs);
    unlink(path);
}

/* lubd_deletion_free run in a thread of its own (the other party holds the folder's lock) */
typedef struct {
    sqlite3 *db;
    const char *jobs, *id;
    int rc;
    char why[1400];
} free_call;

/* lubd_queue_results reports a step that fails after the first rows as an error, not as a
 * shorter list (until 2026-12-07 it answered 0 with the rows read so far). A temporary view
 * named results shadows the table and fails at the second row (an integer overflow). */
static void test_results_step_error(const char *dir)
{
    char path[1024], jobs[1024];
    lubd_user u;
    sqlite3 *db = scratch_queue(dir, "resstep", path, jobs, &u);
    if (!db)
        return;
    CHECK(sqlite3_exec(db,
                       "INSERT INTO results VALUES "
                       "('j', 'a.json', 'application/json', 1, 'x'), "
                       "('j', 'b.json', 'application/json', 2, 'y')",
                       NULL, NULL, NULL) == SQLITE_OK);
    lubd_result_file *files;
    int n;
    CHECK(lubd_queue_results(db, "j", &files, &n) == 0 && n == 2);
    free(files);
    CHECK(sqlite3_exec(db,
                       "CREATE TEMP VIEW results AS SELECT job_id, name, media_type, "
                       "CASE WHEN name = 'b.json' THEN abs(-9223372036854775807 - 1) ELSE size "
                       "END AS size, sha256 FROM main.results",
                       NULL, NULL, NULL) == SQLITE_OK);
    CHECK(lubd_queue_results(db, "j", &files, &n) == -1 && files == NULL && n == 0);
    lubd_db_close(db);
    unlink(path);
}

static void *free_in_thread(void *arg)
{
    free_call *c = arg;
    c->rc = lubd_deletion_free(c->db, c->jobs, c->id, c->why, sizeof c->why);
    return NULL;
}

/* Two frees of one purged job (a DELETE's request thread and the worker that ends the job, two
 * processes) take turns on the folder's lock: while one holds it the other does not touch the
 * folder, and afterwards it finds the folder gone or frees what is there. */
static void test_deletion_free_serialised(const char *dir)
{
    char path[1024], jobs[1024];
    lubd_user u;
    sqlite3 *db = scratch_queue(dir, "freelock", path, jobs, &u);
    if (!db)
        return;
    char src[33], dep[33], folder[1200];
    int rep;
    submit_job(db, u.id, src, NULL);
    submit_job(db, u.id, dep, src);
    char sql[200];
    snprintf(sql, sizeof sql, "UPDATE jobs SET state = 'successful' WHERE id = '%s'", src);
    CHECK(sqlite3_exec(db, sql, NULL, NULL, NULL) == SQLITE_OK);
    lubd_job j;
    CHECK(lubd_queue_dismiss(db, src, &j, NULL, &rep) == 0 && rep == 1);
    const struct timespec pause = {0, 300000000L};
    for (int other_frees = 0; other_frees <= 1; ++other_frees) {
        put_file(jobs, src, "result/checkpoint.h5");
        put_file(jobs, src, "result/result.h5");
        lubd_pathf(folder, sizeof folder, "%s/%s", jobs, src);
        const int fd = open(folder, O_RDONLY | O_DIRECTORY | O_CLOEXEC);
        CHECK(fd >= 0 && flock(fd, LOCK_EX) == 0);
        free_call call = {db, jobs, src, -2, ""};
        pthread_t t;
        CHECK(pthread_create(&t, NULL, free_in_thread, &call) == 0);
        nanosleep(&pause, NULL);
        /* the lock is held: the folder and its files are untouched, nothing handed over */
        CHECK(exists(jobs, src, "result/result.h5") && !exists(jobs, dep, LUBD_CONTINUED_FROM));
        if (other_frees) { /* the holder frees the folder itself, handing over first */
            char why[1400] = "";
            CHECK(lubd_continuation_hand_over(db, jobs, src, why, sizeof why) == 1);
            CHECK(lubd_rm_rf(folder) == 0);
        }
        close(fd);
        pthread_join(t, NULL);
        CHECK(call.rc == 0 && !exists(jobs, src, ""));
        CHECK(exists(jobs, dep, LUBD_CONTINUED_FROM "/checkpoint.h5") &&
              exists(jobs, dep, LUBD_CONTINUED_FROM "/result.h5"));
        char handed[1300];
        lubd_pathf(handed, sizeof handed, "%s/%s/" LUBD_CONTINUED_FROM, jobs, dep);
        CHECK(lubd_rm_rf(handed) == 0);
    }
    lubd_db_close(db);
    lubd_rm_rf(jobs);
    unlink(path);
}

/* draft-07 text in, the expected OpenAPI 3.0 text out (NULL: an error naming `why`) */
/* More than 256 jobs left running on their last attempt by a service that died, each with
 * the checkpoint its engine left in attempt-1/out: at the next start every one of them fails
 * with its checkpoint kept as its files (until 2026-12-07 the first 256 only: the others were
 * failed by the reaper, their checkpoints left behind). */
static void test_many_orphans(const char *dir)
{
    enum { N_ORPHANS = 300 };
    char path[1024], jobs[1024];
    lubd_user u;
    sqlite3 *db = scratch_queue(dir, "orphans", path, jobs, &u);
    if (!db)
        return;
    lubd_config cfg;
    lubd_config_defaults(&cfg, "lubdemd");
    snprintf(cfg.jobs_dir, sizeof cfg.jobs_dir, "%s", jobs);
    snprintf(cfg.db_path, sizeof cfg.db_path, "%s", path);
    cfg.lease_s = 60;
    for (int k = 0; k < N_ORPHANS; ++k) {
        char fp[32], id[33];
        snprintf(fp, sizeof fp, "fp-orphan-%d", k);
        lubd_submit s = {u.id, N_ORPHANS, "simple_shear", "{}", "{}", fp, NULL, 0, 1, NULL};
        int rep;
        lubd_fault f;
        CHECK(lubd_queue_submit(db, &s, id, &rep, &f) == 0);
    }
    for (int k = 0; k < N_ORPHANS; ++k) {
        lubd_claim c;
        CHECK(lubd_lease_claim(db, "w0-pid1", 60, &c) == 1 && c.attempt == 1 &&
              c.max_attempts == 1);
        char rel[64];
        snprintf(rel, sizeof rel, "attempt-%d/out/checkpoint.h5", c.attempt);
        put_file(jobs, c.id, rel);
        lubd_lease_clear(&c);
    }
    CHECK(lubd_worker_keep_orphan_checkpoints(&cfg, db) == N_ORPHANS);
    sqlite3_stmt *st;
    CHECK(lubd_db_prepare(db,
                          "SELECT count(*), sum(state = 'failed' AND failure_kind = 'system' AND "
                          "EXISTS (SELECT 1 FROM results r WHERE r.job_id = jobs.id AND "
                          "r.name = 'checkpoint.h5')) FROM jobs",
                          &st) == 0);
    CHECK(sqlite3_step(st) == SQLITE_ROW && sqlite3_column_int(st, 0) == N_ORPHANS &&
          sqlite3_column_int(st, 1) == N_ORPHANS);
    sqlite3_finalize(st);
    int rq = -1, fl = -1; /* the reaper that follows at the start finds none left */
    CHECK(lubd_queue_reap_orphans(db, &rq, &fl) == 0 && rq == 0 && fl == 0);
    lubd_db_close(db);
    lubd_rm_rf(jobs);
    unlink(path);
}

static void oas_case(const char *in, const char *want, const char *why)
{
    json_t *draft = json_loads(in, JSON_DECODE_ANY, NULL), *before = json_deep_copy(draft);
    char err[300];
    json_t *got = lubd_oas_schema(draft, err, sizeof err);
    CHECK(draft && json_equal(draft, before)); /* the input is untouched */
    if (want) {
        json_t *w = json_loads(want, 0, NULL);
        CHECK(w && got && json_equal(got, w));
        if (!(got && json_equal(got, w))) {
            char *t = got ? json_dumps(got, JSON_COMPACT) : NULL;
            fprintf(stderr, "  %s\n  gave %s (%s)\n", in, t ? t : "NULL", err);
            free(t);
        }
        json_decref(w);
    } else {
        CHECK(!got && strstr(err, why) != NULL);
        if (got || !strstr(err, why))
            fprintf(stderr, "  %s\n  error \"%s\", wanted one with \"%s\"\n", in, err, why);
    }
    json_decref(got);
    json_decref(before);
    json_decref(draft);
}

static void test_oas_schema(void)
{
    /* exclusive bounds: the OpenAPI flag, the tighter of the two forms kept */
    oas_case("{\"type\":\"number\",\"exclusiveMinimum\":0,\"maximum\":1}",
             "{\"type\":\"number\",\"minimum\":0,\"exclusiveMinimum\":true,\"maximum\":1}", NULL);
    oas_case("{\"exclusiveMaximum\":1,\"minimum\":1e-34}",
             "{\"maximum\":1,\"exclusiveMaximum\":true,\"minimum\":1e-34}", NULL);
    oas_case("{\"minimum\":2,\"exclusiveMinimum\":1,\"maximum\":5,\"exclusiveMaximum\":6}",
             "{\"minimum\":2,\"maximum\":5}", NULL);
    oas_case("{\"minimum\":1,\"exclusiveMinimum\":1.5,\"exclusiveMaximum\":5,\"maximum\":5}",
             "{\"minimum\":1.5,\"exclusiveMinimum\":true,\"maximum\":5,\"exclusiveMaximum\":true}",
             NULL);
    oas_case("{\"minimum\":0,\"exclusiveMinimum\":true}",
             "{\"minimum\":0,\"exclusiveMinimum\":true}", NULL);
    /* const, type arrays, an untyped enum of mixed types, boolean schemas */
    oas_case("{\"const\":\"m4\",\"default\":\"m4\"}", "{\"enum\":[\"m4\"],\"default\":\"m4\"}",
             NULL);
    oas_case("{\"type\":[\"number\",\"null\"],\"minimum\":0}",
             "{\"type\":\"number\",\"nullable\":true,\"minimum\":0}", NULL);
    oas_case("{\"type\":[\"string\"]}", "{\"type\":\"string\"}", NULL);
    oas_case("{\"type\":[\"string\",\"boolean\",\"null\"]}",
             "{\"anyOf\":[{\"type\":\"string\",\"nullable\":true},"
             "{\"type\":\"boolean\",\"nullable\":true}]}",
             NULL);
    oas_case("{\"type\":[\"string\",\"integer\"],\"anyOf\":[{\"minimum\":1},{\"minLength\":2}]}",
             "{\"anyOf\":[{\"minimum\":1},{\"minLength\":2}],"
             "\"allOf\":[{\"anyOf\":[{\"type\":\"string\"},{\"type\":\"integer\"}]}]}",
             NULL);
    oas_case("{\"enum\":[\"none\",\"final\",false,true],\"default\":\"none\"}",
             "{\"enum\":[\"none\",\"final\",false,true],\"default\":\"none\"}", NULL);
    oas_case("{\"properties\":{\"a\":true,\"b\":false},\"additionalProperties\":false}",
             "{\"properties\":{\"a\":{},\"b\":{\"not\":{}}},\"additionalProperties\":false}", NULL);
    /* recursion into properties, items, additionalProperties, not, allOf/anyOf/oneOf;
     * $schema, $id, $comment dropped */
    oas_case(
        "{\"$schema\":\"http://json-schema.org/draft-07/schema#\",\"$id\":\"x\","
        "\"$comment\":\"c\",\"type\":\"object\",\"properties\":{\"p\":{\"type\":\"array\","
        "\"items\":{\"oneOf\":[{\"properties\":{\"m\":{\"const\":\"rate\"},\"r\":{\"not\":"
        "{\"const\":0}}}},{\"exclusiveMinimum\":0}]}},\"q\":{\"additionalProperties\":{"
        "\"exclusiveMaximum\":3}},\"s\":{\"allOf\":[{\"const\":1}],\"anyOf\":[{\"const\":2}]}}}",
        "{\"type\":\"object\",\"properties\":{\"p\":{\"type\":\"array\",\"items\":{\"oneOf\":"
        "[{\"properties\":{\"m\":{\"enum\":[\"rate\"]},\"r\":{\"not\":{\"enum\":[0]}}}},"
        "{\"minimum\":0,\"exclusiveMinimum\":true}]}},\"q\":{\"additionalProperties\":{"
        "\"maximum\":3,\"exclusiveMaximum\":true}},\"s\":{\"allOf\":[{\"enum\":[1]}],"
        "\"anyOf\":[{\"enum\":[2]}]}}}",
        NULL);
    /* if/then/else: dropped, the condition in words appended to the description */
    oas_case("{\"description\":\"a segment\",\"if\":{\"required\":[\"strain\"],\"description\":"
             "\"With strain, stress must not be 0.\"},\"then\":{\"properties\":{\"stress\":"
             "{\"not\":{\"const\":0}}}},\"else\":{}}",
             "{\"description\":\"a segment. With strain, stress must not be 0.\"}", NULL);
    oas_case("{\"if\":{\"required\":[\"a\"]},\"then\":{\"required\":[\"b\"]}}",
             "{\"description\":\"A further condition applies (a draft-07 if/then/else, which "
             "OpenAPI 3.0 cannot state): see the process's inputsSchema.\"}",
             NULL);
    /* errors: what has no rule, with the JSON Pointer of where it is */
    oas_case("{\"properties\":{\"a/b\":{\"$ref\":\"#/definitions/x\"}}}", NULL,
             "/properties/a~1b: keyword \"$ref\"");
    oas_case("{\"items\":[{\"type\":\"string\"}]}", NULL, "(root): keyword \"items\"");
    oas_case("{\"anyOf\":[{\"type\":\"null\"}]}", NULL, "/anyOf/0: type null alone");
    oas_case("{\"const\":1,\"enum\":[1,2]}", NULL, "const beside enum");
    oas_case("{\"exclusiveMinimum\":\"0\"}", NULL, "neither a number nor a boolean");
    oas_case("{\"type\":\"null\"}", NULL, "(root): type null alone");
    oas_case("{\"type\":1}", NULL, "neither a string nor an array");
    oas_case("3", NULL, "must be an object or a boolean");
}

/* RFC 3339 date-times of GET /jobs?datetime=: the inverse of lubd_rfc3339, to the millisecond */
static void test_rfc3339(void)
{
    long long lo = 0, hi = 0;
    char shown[40];
    lubd_rfc3339(1796645522.125, shown, sizeof shown); /* exact in binary */
    CHECK(lubd_parse_rfc3339(shown, &lo, &hi) == 0 && lo == 1796645522125LL && hi == lo);
    CHECK(lubd_parse_rfc3339("1970-01-01T00:00:00Z", &lo, &hi) == 0 && lo == 0 && hi == 0);
    CHECK(lubd_parse_rfc3339("2024-02-29t23:59:59.5z", &lo, &hi) == 0 && lo == 1709251199500LL &&
          hi == lo);
    /* a digit after the milliseconds: cut down (lo), the next millisecond up (hi) */
    CHECK(lubd_parse_rfc3339("1970-01-01T00:00:00.0011Z", &lo, &hi) == 0 && lo == 1 && hi == 2);
    CHECK(lubd_parse_rfc3339("1970-01-01T01:00:00+01:00", &lo, &hi) == 0 && lo == 0);
    CHECK(lubd_parse_rfc3339("1970-01-01T00:00:00 01:00", &lo, &hi) == 0 && lo == -3600000LL);
    CHECK(lubd_parse_rfc3339("1969-12-31T23:00:00-01:00", &lo, &hi) == 0 && lo == 0);
    static const char *const bad[] = {"",
                                      "2026-12-07",
                                      "2026-12-07T10:00:00",
                                      "2026-13-01T00:00:00Z",
                                      "2023-02-29T00:00:00Z",
                                      "2026-12-07T24:00:00Z",
                                      "2026-12-07T10:00:00.Z",
                                      "2026-12-07T10:00:00Zx",
                                      "2026-12-07T10:00:00+1:00",
                                      "..",
                                      NULL};
    for (const char *const *b = bad; *b; ++b)
        CHECK(lubd_parse_rfc3339(*b, &lo, &hi) == -1);
}

int main(int argc, char **argv)
{
    test_rfc3339();
    test_sha256();
    test_range();
    test_progress();
    test_exec();
    test_job_limits();
    test_oas_schema();
    test_queue(argc > 1 ? argv[1] : ".");
    test_finish_refused(argc > 1 ? argv[1] : ".");
    test_link_or_copy(argc > 1 ? argv[1] : ".");
    test_hand_over(argc > 1 ? argv[1] : ".");
    test_deletion_sweep(argc > 1 ? argv[1] : ".");
    test_deletion_free_serialised(argc > 1 ? argv[1] : ".");
    test_results_step_error(argc > 1 ? argv[1] : ".");
    test_many_orphans(argc > 1 ? argv[1] : ".");
    if (failures)
        fprintf(stderr, "%d check(s) failed\n", failures);
    else
        printf("PASS\n");
    return failures ? 1 : 0;
}
