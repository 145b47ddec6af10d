/* scene_harness.c — in-process scene runs for tests and benchmarks (scene_harness.h). */
#include "scene_harness.h"

#include <math.h>
#include <stdio.h>
#include <string.h>
#include <unistd.h>

#include "progress.h"
#include "run_context.h"
#include "scene.h"

int scene_run_text(const char *spec_text, const char *keep_h5, scene_outcome *o)
{
    static int counter = 0;
    memset(o, 0, sizeof *o);
    json_error_t jerr;
    json_t *spec = json_loads(spec_text, 0, &jerr);
    if (!spec) {
        snprintf(o->message, sizeof o->message, "invalid JSON: %s", jerr.text);
        return o->rc = 2;
    }
    json_t *resolved = NULL;
    lub_error err;
    int r = lub_spec_resolve(spec, &resolved, &err);
    json_decref(spec);
    if (r) {
        snprintf(o->message, sizeof o->message, "%s: %s", err.pointer, err.message);
        return o->rc = 2;
    }
    char path[512];
    if (keep_h5)
        snprintf(path, sizeof path, "%s", keep_h5);
    else
        snprintf(path, sizeof path, "scene_harness_%ld_%d.h5", (long)getpid(), counter++);
    char errbuf[256];
    lub_h5 *h5 = lub_h5_create(path, errbuf, sizeof errbuf);
    if (!h5) {
        snprintf(o->message, sizeof o->message, "%s", errbuf);
        json_decref(resolved);
        return o->rc = 4;
    }
    lub_progress prog;
    lub_progress_init(&prog, NULL, 1e9);
    static volatile sig_atomic_t stop = 0;
    lub_run_ctx ctx;
    memset(&ctx, 0, sizeof ctx);
    ctx.out = h5;
    ctx.progress = &prog;
    ctx.stop_requested = &stop;
    ctx.summary_results = json_object();
    ctx.summary_extra = json_object();
    ctx.threads = 1;
    const lub_scene *sc = lub_scene_find(json_string_value(json_object_get(resolved, "scene")));
    double t0 = lub_wall_seconds();
    o->rc = sc->run(resolved, &ctx);
    o->wall_s = lub_wall_seconds() - t0;
    lub_h5_close(h5, o->rc == 0 ? "complete" : "failed");
    if (!keep_h5)
        unlink(path);
    snprintf(o->message, sizeof o->message, "%s", ctx.diagnostic);
    o->results = ctx.summary_results;
    o->extra = ctx.summary_extra;
    json_decref(resolved);
    return o->rc;
}

void scene_outcome_free(scene_outcome *o)
{
    json_decref(o->results);
    json_decref(o->extra);
    o->results = o->extra = NULL;
}

double scene_value(const scene_outcome *o, const char *name)
{
    json_t *e = o->results ? json_object_get(o->results, name) : NULL;
    json_t *v = e ? json_object_get(e, "value") : NULL;
    return (v && json_is_number(v)) ? json_number_value(v) : NAN;
}

int scene_check(int cond, const char *what, double got, double want)
{
    printf("%s %s: got %.10g, limit %.10g\n", cond ? "ok  " : "FAIL", what, got, want);
    fflush(stdout);
    return cond ? 0 : 1;
}
