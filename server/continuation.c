/* continuation.c — checks of a "continue_from" submission (see continuation.h). */
#include "continuation.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "fsutil.h"
#include "queue.h"
#include "resume_spec.h"
#include "scene.h"
#include "spec_reader.h"

#define BAD_FROM(f, ...)                                                                           \
    lubd_fail(f, 400, LUBD_PT_BASE "invalid-request", "Invalid request", "/continue_from",         \
              __VA_ARGS__)

static int has_checkpoint(sqlite3 *db, const char *id, int *found)
{
    lubd_result_file *files;
    int n;
    if (lubd_queue_results(db, id, &files, &n) != 0)
        return -1;
    *found = 0;
    for (int i = 0; i < n; ++i)
        if (strcmp(files[i].name, "checkpoint.h5") == 0)
            *found = 1;
    free(files);
    return 0;
}

/* The earlier job's spec against the new one, by the engine's rule. */
static int same_run(sqlite3 *db, const lubd_continuation *c, const lub_scene *scene, lubd_fault *f)
{
    char *text = NULL;
    if (lubd_queue_spec(db, c->source_id, &text) != 1)
        return lubd_fail(f, 500, LUBD_PT_BASE "internal", "Internal error", NULL, "database error");
    json_t *spec = json_loads(text, 0, NULL), *saved = NULL;
    free(text);
    lub_error err;
    memset(&err, 0, sizeof err);
    int rc = 0;
    if (!spec || lub_spec_resolve(spec, &saved, &err) != 0) {
        rc = BAD_FROM(f,
                      "/continue_from: the spec of job %s no longer resolves (%s: %s); "
                      "submit without continue_from",
                      c->source_id, err.pointer, err.message);
    } else {
        char why[700], at[512], free_members[200];
        const int d = lub_resume_spec_mismatch(c->resolved, saved, scene->resume_may_differ, why,
                                               sizeof why, at, sizeof at);
        lub_resume_free_members(scene->resume_may_differ, free_members, sizeof free_members);
        if (d < 0) {
            rc =
                lubd_fail(f, 500, LUBD_PT_BASE "internal", "Internal error", NULL, "out of memory");
        } else if (d > 0) {
            char ptr[600];
            snprintf(ptr, sizeof ptr, "/inputs%.*s", lub_utf8_prefix(at, 500), at);
            rc = lubd_fail(f, 400, LUBD_PT_BASE "invalid-input", "Invalid input", ptr,
                           "/inputs%s (job %s being the stopped run): a continuation takes the "
                           "inputs of the job it continues, defaults included%s",
                           why, c->source_id, free_members);
        }
    }
    json_decref(spec);
    json_decref(saved);
    return rc;
}

int lubd_continuation_check(sqlite3 *db, const lubd_continuation *c, lubd_fault *f)
{
    const lub_scene *scene = lub_scene_find(c->process_id);
    lubd_job j;
    const int found = lubd_queue_get(db, c->source_id, &j);
    if (found < 0)
        return lubd_fail(f, 500, LUBD_PT_BASE "internal", "Internal error", NULL, "database error");
    if (found == 0 || (j.user_id != c->user_id && !c->is_admin))
        return BAD_FROM(f, "/continue_from: job %s does not exist (or belongs to another user)",
                        c->source_id);
    if (strcmp(j.process_id, c->process_id) != 0)
        return BAD_FROM(f, "/continue_from: job %s ran %s, not %s", c->source_id, j.process_id,
                        c->process_id);
    if (j.purged)
        return BAD_FROM(f, "/continue_from: job %s was deleted, with its checkpoint", c->source_id);
    const int successful = strcmp(j.state, "successful") == 0;
    if (!successful && strcmp(j.state, "failed") != 0)
        return BAD_FROM(f,
                        "/continue_from: job %s is %s; a job can be continued once it has "
                        "ended (successful, or failed with a checkpoint)",
                        c->source_id, j.state);
    if (successful && !scene->resume_may_differ)
        return BAD_FROM(f,
                        "/continue_from: job %s completed its run, and a %s run cannot be "
                        "extended",
                        c->source_id, c->process_id);
    int kept = 0;
    if (has_checkpoint(db, c->source_id, &kept) != 0)
        return lubd_fail(f, 500, LUBD_PT_BASE "internal", "Internal error", NULL, "database error");
    if (!kept)
        return BAD_FROM(f,
                        "/continue_from: job %s kept no checkpoint (a run keeps one when it "
                        "is stopped, e.g. at the CPU time limit, or completes on a service "
                        "with --keep-checkpoints 1)",
                        c->source_id);
    return same_run(db, c, scene, f);
}

int lubd_continuation_link_files(const char *from_dir, const char *to_dir, char *why,
                                 size_t why_len)
{
    static const char *const names[] = {"checkpoint.h5", "result.h5", "checkpoint-result.h5"};
    if (lubd_mkdir_p(to_dir, 0750) != 0) {
        const int e = errno;
        lubd_pathf(why, why_len, "cannot create %s: %s", to_dir, strerror(e));
        errno = e;
        return -1;
    }
    for (int k = 0; k < 3; ++k) {
        char src[1400], dst[1400];
        if (lubd_pathf(src, sizeof src, "%s/%s", from_dir, names[k]) != 0 ||
            lubd_pathf(dst, sizeof dst, "%s/%s", to_dir, names[k]) != 0) {
            lubd_pathf(why, why_len, "path too long under %s", from_dir);
            errno = ENAMETOOLONG;
            return -1;
        }
        if (k > 0 && access(src, F_OK) != 0)
            continue; /* the engine names what it misses */
        if (lubd_link_or_copy(src, dst) != 0) {
            const int e = errno;
            lubd_pathf(why, why_len, "its %s: %s", names[k], strerror(e));
            errno = e;
            return -1;
        }
    }
    return 0;
}

int lubd_continuation_hand_over(sqlite3 *db, const char *jobs_dir, const char *source_id, char *why,
                                size_t why_len)
{
    sqlite3_stmt *st = NULL;
    if (sqlite3_prepare_v2(db,
                           "SELECT id FROM jobs WHERE state IN ('accepted', 'running') AND "
                           "json_extract(request_json, '$.continue_from') = ?1",
                           -1, &st, NULL) != SQLITE_OK) {
        lubd_pathf(why, why_len, "database error: %s", sqlite3_errmsg(db));
        return -1;
    }
    sqlite3_bind_text(st, 1, source_id, -1, SQLITE_STATIC);
    char from[1200];
    lubd_pathf(from, sizeof from, "%s/%s/result", jobs_dir, source_id);
    int n = 0, rc;
    while ((rc = sqlite3_step(st)) == SQLITE_ROW) {
        const char *dep = (const char *)sqlite3_column_text(st, 0);
        char tmp[1300], dst[1300], err[600] = "";
        lubd_pathf(tmp, sizeof tmp, "%s/%s/." LUBD_CONTINUED_FROM ".tmp", jobs_dir, dep);
        lubd_pathf(dst, sizeof dst, "%s/%s/" LUBD_CONTINUED_FROM, jobs_dir, dep);
        if (access(dst, F_OK) == 0) { /* handed over before (a retried delete) */
            ++n;
            continue;
        }
        if (lubd_rm_rf(tmp) != 0 || lubd_continuation_link_files(from, tmp, err, sizeof err) != 0 ||
            rename(tmp, dst) != 0) {
            lubd_pathf(why, why_len,
                       "cannot keep the files of job %s for job %s, which continues it: %s",
                       source_id, dep, err[0] ? err : strerror(errno));
            lubd_rm_rf(tmp);
            sqlite3_finalize(st);
            return -1;
        }
        ++n;
    }
    if (rc != SQLITE_DONE) {
        lubd_pathf(why, why_len, "database error: %s", sqlite3_errmsg(db));
        n = -1;
    }
    sqlite3_finalize(st);
    return n;
}
