/* network_output.h — the interaction network (pair_network.h) as a frame set of result.h5:
 * the spec member that asks for it and the columns of /pair_network, shared by the scenes
 * that write it (simple_shear, resuspension).
 *
 *   /pair_network/{step, time, row_start, row_count}   one entry per frame
 *   /pair_network/<column>                              one row per pair, frames in order
 *
 * Units: forces and torques in the units the caller names (force_unit, torque_unit), time in
 * time_unit, lengths in a. Ownership: the frame set belongs to the file (h5md_writer.h);
 * nothing passed in is kept. Errors: as below.
 */
#ifndef LUBDEM_NETWORK_OUTPUT_H
#define LUBDEM_NETWORK_OUTPUT_H

#include <jansson.h>
#include <stdint.h>

#include "h5md_writer.h"
#include "pair_network.h"
#include "spec_reader.h"

/* When a scene writes the network: never, at the end of its run (also a stopped one), or
 * also with every particle snapshot. */
enum { LUB_NETWORK_NONE, LUB_NETWORK_FINAL, LUB_NETWORK_SNAPSHOTS };

/* The spec member /pair_network of obj: "none" (default), "final" or "snapshots"; false and
 * true (its first form) are read as "none" and "final" and replaced by them in place. 0 with
 * *mode a LUB_NETWORK_*, or -1 with err naming /pair_network and the choices. */
int lub_spec_pair_network(json_t *obj, int *mode, lub_error *err);

/* Defines /pair_network in out (lub_h5_frames_define); NULL on an HDF5 error. */
lub_h5_frames *lub_network_define(lub_h5 *out, const char *force_unit, const char *torque_unit,
                                  const char *time_unit);

/* Appends net as the frame of `step` at `time` (lub_h5_frames_append: 0, also when the frame
 * is skipped for lack of room; -1 on an HDF5 error, lub_h5_last_error). */
int lub_network_append(lub_h5_frames *frames, const lub_pair_network *net, int64_t step,
                       double time);

/* The summary warning for frames of /pair_network skipped for lack of room (lub_h5_frames_
 * skipped), appended to the JSON array `warnings`; nothing when none was (or frames is NULL). */
void lub_network_warn_skipped(const lub_h5_frames *frames, json_t *warnings);

#endif
