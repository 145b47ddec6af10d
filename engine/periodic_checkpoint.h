/* periodic_checkpoint.h — checkpoints taken while a run goes on (lubdem run --checkpoint-every
 * S), so that a run killed without warning (kill -9, the OOM killer, a node failure, a service
 * whose worker died) continues from the last one with --resume instead of from the start.
 *
 * A periodic checkpoint is two files in DIR, each written under a temporary name and renamed:
 *   checkpoint-result.h5  a copy of the result.h5 being written, flushed first, so that it is a
 *                         consistent HDF5 file with the time series and snapshots so far (the
 *                         file being written is not one after a kill);
 *   checkpoint.h5         the scene's state, which names that copy as the file holding its rows
 *                         (text "output_file", LUB_PERIODIC_OUTPUT).
 * Both are on disk (fsync) before they are renamed, and DIR after, so a crash of the machine
 * leaves the last checkpoint or the new one, whole. The copy is renamed first, so a
 * checkpoint.h5 always has an output file with at least its rows (the continuation copies the
 * first rows it needs). A checkpoint written when a stop request ends the run names result.h5
 * instead (run_driver.h).
 *
 * Cost: the copy is the size of result.h5 so far (snapshots included), made by lub_file_copy
 * (file_copy.h: inside the kernel, or no data moved where the file system shares blocks), the
 * state ~2 kB per particle; both are written while the run waits. Units: wall-clock seconds.
 * Ownership: the paths are borrowed (the driver's). Errors: a failed checkpoint is recorded once
 * (failure) and the run goes on; the next is tried at the next interval. Not thread-safe.
 */
#ifndef LUBDEM_PERIODIC_CHECKPOINT_H
#define LUBDEM_PERIODIC_CHECKPOINT_H

#include <stdint.h>

#include "h5md_writer.h"

#define LUB_PERIODIC_OUTPUT "checkpoint-result.h5"

typedef struct lub_periodic_ckpt {
    double every_s;                  /* wall-clock seconds between checkpoints (> 0) */
    double next_at;                  /* lub_wall_seconds() of the next one */
    const char *live_path;           /* the result.h5 being written (its temporary name) */
    const char *copy_tmp, *copy_dst; /* DIR/.checkpoint-result.h5.tmp, DIR/checkpoint-result.h5 */
    const char *ckpt_tmp, *ckpt_dst; /* DIR/.checkpoint.h5.tmp, DIR/checkpoint.h5 */
    int notes;                       /* notes set on each checkpoint before it is published */
    const char *const *note_names;   /* (lub_ckpt_set_notes: the builds of the run; borrowed) */
    const char *const *note_texts;
    long written;      /* checkpoints published by this run */
    char failure[400]; /* the first failure, "" when none */
} lub_periodic_ckpt;

/* Sets the paths and the first due time (now + every_s). */
void lub_periodic_init(lub_periodic_ckpt *pc, double every_s, const char *live_path,
                       const char *copy_tmp, const char *copy_dst, const char *ckpt_tmp,
                       const char *ckpt_dst);

/* 1 when a checkpoint is due: the clock is read only every 64 steps (step & 63 == 0). */
int lub_periodic_due(lub_periodic_ckpt *pc, int64_t step);

/* First part of a checkpoint: flushes `out` and copies the live file to copy_tmp. 0, or -1 with
 * the failure recorded (also when `out` has been given up, lub_h5_output_lost). */
int lub_periodic_copy_output(lub_periodic_ckpt *pc, lub_h5 *out);

/* Last part, once the scene has written ckpt_tmp: sets its notes (if any), puts it on disk
 * (fsync), renames the copy,
 * then the checkpoint, puts the folder's new names on disk (fsync of DIR) and schedules the
 * next. 0 when the checkpoint is in place (a failed fsync of DIR is recorded all the same), or
 * -1 with the failure recorded. */
int lub_periodic_publish(lub_periodic_ckpt *pc);

/* The scene could not write ckpt_tmp (why): removes the temporaries, records it, schedules the
 * next. */
void lub_periodic_failed(lub_periodic_ckpt *pc, const char *why);

#endif
