/* resuspension_checkpoint.h — the state of a resuspension system (resuspension_system.h) into
 * a checkpoint file (checkpoint_file.h) and back, so that a stopped run continues as if it had
 * not stopped.
 *
 * Saved under "system/": positions (wrapped), the images removed by wrapping, velocities,
 * spins, the positions of the last neighbour-list rebuild and its time, the interaction counts
 * and inverse inertia shares of the spin-torque stabilisation, the cell, time, step, step size,
 * the counters (rebuilds, flips, lid hits), whether a rebuild is due, the listing distance, the
 * last step's largest speed and contact counts; under "pairs/" every listed pair with its law
 * state (state_checkpoint.h). Floor spheres included: the system's particle count n counts
 * them. What is rebuilt rather than stored: radii, masses, weights and the mean flow (from the
 * spec and the bed, which the scene rebuilds from its seed), the cell lists, the per-thread sums.
 *
 * Units: those of the system. Ownership: nothing is kept; restore writes into a system made by
 * lub_rs_init from the same spec. Errors: 0 or -1 with the message in lub_ckpt_error (or none
 * for a pair index out of range, or another particle count).
 */
#ifndef LUBDEM_RESUSPENSION_CHECKPOINT_H
#define LUBDEM_RESUSPENSION_CHECKPOINT_H

#include "checkpoint_file.h"
#include "resuspension_system.h"

int lub_rs_save(lub_ckpt *c, const lub_rs_system *s);
int lub_rs_restore(lub_ckpt *c, lub_rs_system *s);

#endif
