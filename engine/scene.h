/* scene.h — the scene registry: every job type the engine runs (DEM or continuum).
 *
 * A spec is a JSON object {"scene": "<name>", ...scene fields...}. A scene provides:
 *  - resolve(): validate the spec IN PLACE (type, range, unknown fields), inserting every
 *    default so that the object becomes the fully resolved spec. On error it fills *err
 *    (JSON pointer + constraint) and returns -1; it never runs anything. The server calls
 *    this same function to reject bad submissions before queuing (one set of rules).
 *  - run(): run the resolved spec, writing observables through ctx->out and headline
 *    numbers into ctx->summary_results. Returns a LUB_EXIT_* code.
 * Each scene lives in its own scene_<name>.c and is listed in scene_registry.c.
 */
#ifndef LUBDEM_SCENE_H
#define LUBDEM_SCENE_H

#include <jansson.h>

#include "memory_budget.h"
#include "spec_reader.h"

struct lub_run_ctx;

/* Exit codes of the CLI and return codes of scene run() (README "CLI contract"). */
enum {
    LUB_EXIT_OK = 0,         /* completed; summary status "complete" */
    LUB_EXIT_INTERNAL = 1,   /* unexpected internal error */
    LUB_EXIT_BAD_SPEC = 2,   /* usage or invalid spec; nothing written. From run(): a refusal
                                only the run can make (the step count once the packing gives
                                the step, step_count.h), before any step; status "failed",
                                diagnostic "<JSON pointer>: <constraint>" */
    LUB_EXIT_NUMERICAL = 3,  /* numerical failure (NaN, blow-up); status "failed" + diagnostic */
    LUB_EXIT_IO = 4,         /* cannot write the output */
    LUB_EXIT_INTERRUPTED = 5 /* SIGTERM/SIGINT: valid partial result, status "partial" */
};

typedef struct {
    const char *name;        /* scene id, e.g. "falling_sphere" (also the service process id) */
    const char *title;       /* one line */
    const char *description; /* a paragraph: what it computes, units, reference */
    int (*resolve)(json_t *spec, lub_error *err);
    int (*run)(const json_t *resolved, struct lub_run_ctx *ctx);
    /* Optional (NULL: no estimate): a lower bound of the memory run() will hold with
     * `threads` threads, into *need (memory_budget.h); 0, or -1 when it has none. Pure; the
     * run driver refuses a run that cannot fit before run() and the service a submission. */
    int (*memory_need)(const json_t *resolved, int threads, lub_memory_need *need);
    /* 1: run() writes a checkpoint when stopped and continues from one (lub_run_ctx
     * checkpoint_path, resume_path); 0: a stopped run of this scene starts afresh. */
    int resumable;
    /* NULL-terminated top-level spec members a continuation may change (those that only decide
     * when the run ends, e.g. "strain"); NULL: none. run() checks the new values. */
    const char *const *resume_may_differ;
} lub_scene;

/* NULL-terminated table of all scenes. */
const lub_scene *const *lub_scene_list(void);
const lub_scene *lub_scene_find(const char *name);

/* Validate a whole spec document: checks "scene" and dispatches to the scene's resolve().
 * On success *resolved is a new reference to the fully resolved spec (a deep copy of the
 * input with defaults). Returns 0 or -1 with *err set. Used by the CLI and by the server. */
int lub_spec_resolve(const json_t *spec, json_t **resolved, lub_error *err);

#endif
