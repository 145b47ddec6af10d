/* scene_harness.h — runs a scene spec in-process (resolve + run) for the scene tests and
 * benchmarks, with a throw-away result.h5. Test support code, not part of the engine. */
#ifndef LUBDEM_SCENE_HARNESS_H
#define LUBDEM_SCENE_HARNESS_H

#include <jansson.h>

typedef struct {
    int rc;             /* LUB_EXIT_* returned by run(), or 2 if the spec was rejected */
    json_t *results;    /* summary "results" (owned; NULL if rejected) */
    json_t *extra;      /* summary extras: active_terms, units, ... (owned) */
    double wall_s;      /* wall time of run() */
    char message[1024]; /* spec error "pointer: message" or run diagnostic */
} scene_outcome;

/* Runs spec_text; returns o->rc. keep_h5 != NULL: keep the result file under that path. */
int scene_run_text(const char *spec_text, const char *keep_h5, scene_outcome *o);
void scene_outcome_free(scene_outcome *o);
/* results[name].value, NAN if absent or null */
double scene_value(const scene_outcome *o, const char *name);

/* Tiny check helpers: print "ok"/"FAIL" lines, count failures. */
int scene_check(int cond, const char *what, double got, double want);

#endif
