/* run_driver.h — runs one spec end to end: parse, validate, run the scene, write
 * DIR/result.h5 and DIR/summary.json atomically (temporary names + rename), and, for a run of a
 * resumable scene that a stop request ended, DIR/checkpoint.h5 (renamed into place after its
 * result.h5; removed when a later run of the folder ends otherwise).
 * On an invalid spec nothing is created. Returns a LUB_EXIT_* code; messages go to `diag`
 * (stderr in the CLI). */
#ifndef LUBDEM_RUN_DRIVER_H
#define LUBDEM_RUN_DRIVER_H

#include <signal.h>
#include <stdio.h>

#include "spec_reader.h"

typedef struct {
    const char *spec_text;                 /* the verbatim spec (JSON text) */
    const char *out_dir;                   /* created if missing */
    int threads;                           /* >= 1 */
    FILE *progress;                        /* progress lines (NULL = quiet) */
    FILE *diag;                            /* diagnostics */
    int json_errors;                       /* spec errors as one JSON object on diag */
    volatile sig_atomic_t *stop_requested; /* set asynchronously by signal handlers to the
                                              signal that asks the run to stop (SIGTERM,
                                              SIGINT, SIGXCPU); 0: none */
    int resume;          /* --resume: continue from DIR/checkpoint.h5 when there is one (README
                            "Stopping and resuming"); without one the run starts from the beginning */
    int keep_checkpoint; /* --keep-checkpoint: a completed run of a resumable scene keeps
                            DIR/checkpoint.h5 too, so that --resume can extend it */
    double checkpoint_every_s; /* --checkpoint-every: a checkpoint every so many wall-clock
                                  seconds while a resumable scene runs (periodic_checkpoint.h);
                                  0: only when stopped */
} lub_run_request;

int lub_run_spec(const lub_run_request *req);

/* Parses and validates only (CLI "validate"): prints the resolved spec on `out` and flushes it.
 * LUB_EXIT_BAD_SPEC on an invalid spec (reported on diag), LUB_EXIT_IO with a line on diag
 * when `out` cannot be written, LUB_EXIT_INTERNAL without memory. */
int lub_validate_spec(const char *spec_text, FILE *out, FILE *diag, int json_errors);

/* A spec error on diag: "error: <pointer or (root)>: <message>" on one line (control
 * characters and bytes that are not UTF-8 escaped, lub_text_one_line), or with json_errors one
 * line {"pointer": ..., "message": ...} (README, CLI contract), which is always valid JSON. */
void lub_report_spec_error(FILE *diag, int json_errors, const lub_error *err);

#endif
