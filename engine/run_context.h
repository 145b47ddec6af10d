/* run_context.h — what a running scene can use: output writer, progress, stop request,
 * summary. Owned by the CLI driver (run_driver.c); scenes only borrow it during run().
 */
#ifndef LUBDEM_RUN_CONTEXT_H
#define LUBDEM_RUN_CONTEXT_H

#include <jansson.h>
#include <signal.h>
#include <stdint.h>

#include "h5md_writer.h"
#include "memory_budget.h"
#include "periodic_checkpoint.h"
#include "progress.h"

typedef struct lub_run_ctx {
    lub_h5 *out;                           /* result.h5 being written (never NULL in run) */
    lub_progress *progress;                /* progress reporter (stdout) */
    volatile sig_atomic_t *stop_requested; /* set by SIGTERM/SIGINT: stop at the next step,
                                              write what you have, return LUB_EXIT_INTERRUPTED */
    json_t *summary_results;               /* object: scene puts headline numbers here, each as
                                              {"value": v, "stderr": e (or null), "unit": "...", "ref": ...} */
    json_t *summary_extra; /* object: anything else (active_terms, units, diagnostics) */
    int threads;           /* OpenMP threads to use (>= 1): --threads, at most the processors
                              the process may run on and the OpenMP thread limit */
    int threads_used;      /* set by a scene whose steps run OpenMP teams: the smallest team
                              they got (below `threads` when OpenMP gave fewer); 0: not known,
                              the summary states `threads` */
    char diagnostic[1024]; /* on LUB_EXIT_NUMERICAL: what failed, where, when; on
                              LUB_EXIT_BAD_SPEC: "<JSON pointer>: <constraint>" (the driver
                              prints it as a spec error, --json-errors included) */
    /* Continuation of a stopped run (scenes with `resumable`, scene.h; README "Stopping and
     * resuming"). The driver sets the paths; the scene sets the flags. */
    const char *checkpoint_path;  /* where the scene writes its checkpoint when a stop request
                                     ends its time loop (a temporary name the driver renames to
                                     DIR/checkpoint.h5); NULL: none */
    int checkpoint_always;        /* 1 (--keep-checkpoint): also when the run completes, so
                                     that a continuation can extend it */
    int checkpoint_written;       /* 1: checkpoint_path holds a complete checkpoint */
    char checkpoint_failure[400]; /* why the checkpoint at the stop could not be written (the
                                     driver removes it and warns); "" otherwise */
    const char *resume_path;      /* checkpoint to continue from (NULL: start afresh) */
    const char *resume_result;    /* the file holding the checkpoint's rows and snapshots (the
                                     stopped run's result.h5, or a periodic checkpoint's copy),
                                     copied into the new result.h5 */
    int resume_rejected;          /* 1: the checkpoint or the old result.h5 cannot be used
                                     (diagnostic says why); the driver keeps the old files and
                                     discards the new ones, exit 2 */
    long long resumed_from_step;  /* steps the stopped run had done (0: not continued) */
    int resume_begun;             /* 1 once a continuation has taken up the stopped run's
                                     state; a continuation that fails before (the memory
                                     check, say) ran nothing, and the driver keeps the stopped
                                     run's files as for a refusal (with the failure's exit) */
    lub_periodic_ckpt *periodic;  /* checkpoints while the run goes on (--checkpoint-every);
                                     NULL: none. The scene takes one when lub_periodic_due
                                     says so, between two steps */
} lub_run_ctx;

/* Helpers for summary entries. stderr_value < 0 or NaN means "no error bar" (null). */
void lub_summary_put(lub_run_ctx *ctx, const char *name, double value, double stderr_value,
                     const char *unit);
/* Appends text (copied) to the summary's "warnings" array, created when absent. */
void lub_summary_warn(lub_run_ctx *ctx, const char *text);

/* The warning for a time step fixed by /dt at `ratio` times the scene's stability bound
 * `bound_name` (simple_shear: dt_elastic; resuspension and the two-sphere scenes: dt_critical)
 * into out[len]. */
void lub_fixed_dt_warning(char *out, size_t len, double ratio, const char *bound_name);

/* The warning for a fixed /dt within the single-pair bound but `ratio` (> limit) times the
 * step the pairs' summed stiffness allows (step_stiffness.h), into out (len bytes). */
void lub_fixed_dt_stiffness_warning(char *out, size_t len, double ratio, double limit);

/* The same warning appended to the JSON array `warnings` when dt_spec > dt_bound (a fixed /dt
 * above the bound); nothing otherwise. */
void lub_warn_fixed_dt(json_t *warnings, double dt_spec, double dt_bound, const char *bound_name);

/* lub_fixed_dt_stiffness_warning appended to the JSON array `warnings` when a fixed /dt
 * (dt_spec > 0) within the single-pair bound dt_bound ran at more than `limit` times the pairs'
 * summed-stiffness step (`ratio`, the largest met); nothing otherwise. */
void lub_warn_fixed_dt_stiffness(json_t *warnings, double dt_spec, double dt_bound, double ratio,
                                 double limit);

/* After a numerical failure: appends to ctx->diagnostic what set the time step and what to
 * change. The spec fixed it (/dt = dt_spec > 0): how it compares with the scene's stability
 * bound dt_bound (same units; summary name bound_name) and to lower /dt or leave it at 0;
 * otherwise the step was dt_safety * dt_bound and a smaller /dt_safety is the remedy (the
 * single-pair bound does not see how many neighbours act on a particle at once). Does nothing
 * when the diagnostic is full. */
void lub_diagnostic_dt_hint(lub_run_ctx *ctx, double dt_spec, double dt_safety, double dt_bound,
                            const char *bound_name);

/* The same for a step that followed the pairs' summed stiffness (step_stiffness.h): appends the
 * step in use dt, how it came from /dt_safety times the bound and how many times it changed,
 * /dt_stiffness_safety and the largest ratio met, and the advice to lower
 * /dt_stiffness_safety. */
void lub_diagnostic_adapted_dt_hint(lub_run_ctx *ctx, double dt, double dt_safety, double dt_bound,
                                    const char *bound_name, long changes, double stiffness_safety,
                                    double ratio_max);

/* Both of the above for a scene that finished with exit_code: the hint after a numerical
 * failure, the warning (appended to the JSON array `warnings`) after a completed run whose
 * fixed /dt exceeds dt_bound. */
void lub_report_time_step(lub_run_ctx *ctx, int exit_code, double dt_spec, double dt_safety,
                          double dt_bound, const char *bound_name, json_t *warnings);

/* After an allocation failed: writes into ctx->diagnostic "out of memory (<what>)", the
 * particle count (n_particles > 0) and the bytes the scene held (bytes_in_use > 0), the
 * address-space limit the process runs under when there is one (RLIMIT_AS: ulimit -v,
 * lubdemd --mem-mb), and the advice to lower `member` (a JSON pointer; NULL: none). */
void lub_diagnostic_out_of_memory(lub_run_ctx *ctx, const char *what, long long n_particles,
                                  double bytes_in_use, const char *member);

/* Before allocating `bytes` more (a lower bound) for `what` (e.g. "the time series of 1000000
 * samples"): 1 when they fit in what this process may still take (memory_budget.h: its
 * address-space limit, memory control group, the machine), otherwise 0 with ctx->diagnostic
 * "not enough memory: <what> need at least ..., but this process may use ...; lower <member>
 * (nothing was run)". A cgroup kills a process that touches more than its limit (exit 137,
 * no message) where the allocation itself succeeds; this check is what names the member. */
int lub_memory_fits(lub_run_ctx *ctx, double bytes, const char *what, const char *member);
/* The same for a need the scene states in full (scene.h: memory_need). */
int lub_memory_need_fits(lub_run_ctx *ctx, const lub_memory_need *need);

/* 1 when a stopped run has a checkpoint --resume goes on from: the one it wrote at the stop,
 * or, when that failed, the one it continued from or its last periodic one (which the run
 * driver keeps then). For the scenes' advice; call after the stop's checkpoint. */
int lub_run_resumable(const lub_run_ctx *ctx);
/* The scenes' advice to a stopped run that lub_run_resumable says can be continued, ending a
 * summary warning. The checkpoint may still be lost afterwards (result.h5 or the checkpoint
 * cannot be put in place): the run driver then replaces it with LUB_RERUN_ADVICE in every
 * warning (summary and stderr), so that no warning advises --resume beside its own "no
 * checkpoint was kept". */
#define LUB_RESUME_ADVICE "lubdem run --resume continues it"
#define LUB_RERUN_ADVICE "its checkpoint was not kept: run it again"
/* Replaces LUB_RESUME_ADVICE by LUB_RERUN_ADVICE in the warnings of `summary_extra` (its
 * "warnings" array of strings); returns how many were replaced. */
int lub_run_withdraw_resume_advice(json_t *summary_extra);

#endif
