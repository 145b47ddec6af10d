/* state_checkpoint.h — the parts of a particle system's state that several systems share (the
 * periodic cell, the pair store), into a checkpoint file (checkpoint_file.h) and back, bit for
 * bit. Used by shear_checkpoint.h and resuspension_checkpoint.h.
 *
 * Names: "<prefix>/cell" (H, its inverse, L, volume), "<prefix>/i", "/j", "/c", "/state",
 * "/active", "/near", "/allow", "/bounds" for a pair store; "<name>_f64" and "<name>_i64" for
 * a step control (step_stiffness.h) and an event schedule (step_schedule.h). The pairs' img codes
 * are rebuilt from their image shifts; the merge buffers are not saved (lub_pairs_adopt refills
 * them). Units: as stored. Ownership: nothing is kept. Errors: 0 or -1 with the message in
 * lub_ckpt_error (a write failed, a dataset missing or of another size, a pair index outside
 * [0, n_particles), no memory for the pairs).
 */
#ifndef LUBDEM_STATE_CHECKPOINT_H
#define LUBDEM_STATE_CHECKPOINT_H

#include <jansson.h>

#include "checkpoint_file.h"
#include "pair_store.h"
#include "periodic_cell.h"
#include "step_schedule.h"
#include "step_stiffness.h"

/* A new checkpoint at path for a run of `scene` at `step` (the steps done: "step", which the
 * service names in its messages), its resolved spec (text "spec_resolved", which --resume
 * compares) and the file that holds its rows (text "output_file"). NULL with why[len] on
 * failure (nothing left open). */
lub_ckpt *lub_run_checkpoint_create(const char *path, const char *scene, int64_t step,
                                    const json_t *resolved, const char *output_file, char *why,
                                    size_t len);
/* The steps done of the checkpoint at path (its "step"), or -1 when the file cannot be read or
 * has none (written before 2026-12-06). */
int64_t lub_run_checkpoint_step(const char *path);
/* Closes a checkpoint made by lub_run_checkpoint_create; 0, or -1 when `failed` (a put of the
 * caller's failed) or the close failed, with why[len] the first failed write. */
int lub_run_checkpoint_close(lub_ckpt *c, int failed, char *why, size_t len);

_Static_assert(sizeof(vec3) == 3 * sizeof(double), "vec3 arrays are stored as doubles");

int lub_cell_save(lub_ckpt *c, const char *name, const lub_cell *cell);
int lub_cell_load(lub_ckpt *c, const char *name, lub_cell *cell);

int lub_pairs_save(lub_ckpt *c, const char *prefix, const lub_pairs *ps);
/* Replaces the pairs of ps (made by lub_pairs_init, possibly used) by the saved ones, for
 * n_particles particles; keeps the saved balanced split when it was made for `threads` parts
 * (else the system balances at its first step). */
int lub_pairs_load(lub_ckpt *c, const char *prefix, lub_pairs *ps, int n_particles, int threads);

int lub_step_control_save(lub_ckpt *c, const char *name, const lub_step_control *ctl);
int lub_step_control_load(lub_ckpt *c, const char *name, lub_step_control *ctl);
int lub_schedule_save(lub_ckpt *c, const char *name, const lub_schedule *sc);
/* -1 also for a schedule that cannot be one (event count, step, nsteps out of range) */
int lub_schedule_load(lub_ckpt *c, const char *name, lub_schedule *sc);

#endif
