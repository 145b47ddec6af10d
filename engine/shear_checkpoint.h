/* shear_checkpoint.h — the state of a sheared system (shear_system.h) into a checkpoint file
 * (checkpoint_file.h) and back, so that a stopped run continues as if it had not stopped.
 *
 * Saved under "system/": the particles' radii, positions (unwrapped), velocities, spins, the
 * positions and cell of the last neighbour-list rebuild, the inverse inertia shares of the
 * spin-torque stabilisation, the cell (H, its inverse, L, volume), time, step, the counters
 * (rebuilds, flips, lost pairs), the skin consumed and whether a rebuild is due, the listing
 * distance of the last rebuild, every listed pair with its image shift, law state and flags
 * (active, near, allowed), the balanced split of the pairs over the threads, the Delaunay
 * update statistics, the step whose positions the Delaunay set was last computed from (a
 * network frame may have computed the set of the step that follows it; a checkpoint written
 * before 2026-12-06 has none, and its first step computes the set again, counted once more
 * in delaunay_updates) and the microstructure sums. Values are stored bit for bit, so a run
 * continued with the same binary and thread count gives the same numbers as one that never
 * stopped (1 and 2 threads; tests/shear/test_resume.py). What is rebuilt rather than stored:
 * the cell lists and the Delaunay candidate sites (recomputed at every update from positions),
 * the per-thread sums (zeroed at every step), masses and inertias (from the radii and the
 * density of the spec).
 *
 * Units: those of the system. Ownership: nothing is kept; restore writes into a system made by
 * lub_shear_init (and lub_shear_use_delaunay when the run uses it) with the same particle
 * count, law, density, cut-off, skin and microstructure bins. Error behaviour: 0 or -1 with
 * the message in lub_ckpt_error (save: a write failed; restore: a dataset missing or of another
 * size, or no memory for the pairs).
 */
#ifndef LUBDEM_SHEAR_CHECKPOINT_H
#define LUBDEM_SHEAR_CHECKPOINT_H

#include "checkpoint_file.h"
#include "shear_system.h"

int lub_shear_save(lub_ckpt *c, const lub_shear_system *s);

/* The particle count and radii stored in c: *n, then radius[*n] (malloc'd, caller frees); -1
 * when missing. For lub_shear_init before lub_shear_restore. */
int lub_shear_saved_particles(lub_ckpt *c, int *n, double **radius);

int lub_shear_restore(lub_ckpt *c, lub_shear_system *s);

#endif
