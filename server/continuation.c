/* continuation.c — checks of a "continue_from" submission (see continuation.h). */
#include "continuation.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "queue.h"
#include "resume_spec.h"
#include "scene.h"

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
            snprintf(ptr, sizeof ptr, "/inputs%.500s", at);
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
