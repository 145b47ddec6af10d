/* h5md_continue.h — the output of a stopped run carried into the result.h5 of its continuation:
 * the first rows of a time-series table, the first particle snapshots and the first frames of
 * a frame set of the old file (h5md_reader.h) appended, unchanged, to a new file
 * (h5md_writer.h), after which the continued run appends its own.
 *
 * Units: as stored. Ownership: borrows the reader and the writer. Memory: one chunk of
 * LUB_H5_CONTINUE_ROWS rows of every series, or one frame, at a time (a frame set: the
 * largest of the copied frames). Error behaviour: 0, or -1
 * with err[len] naming the series or frame that could not be read or written (the old file
 * holds fewer rows or frames than asked for, another shape, an HDF5 error).
 */
#ifndef LUBDEM_H5MD_CONTINUE_H
#define LUBDEM_H5MD_CONTINUE_H

#include <stddef.h>
#include <stdint.h>

#include "h5md_reader.h"
#include "h5md_writer.h"

enum { LUB_H5_CONTINUE_ROWS = 1024 };

/* Appends rows [0, rows) of the table of nseries series (names, ncomp as given to
 * lub_h5_table_create) read from `from` to `to`. expect_first (NULL: unchecked) holds the values
 * rows [0, rows) of the first series (one component) must have, bit for bit: the checkpoint's
 * own copy, so that a file other than the one the checkpoint was taken with is refused (err
 * names the first row that differs) before anything of it is used. */
int lub_h5_continue_table(lub_h5_reader *from, lub_h5_table *to, int nseries,
                          const char *const *names, const int *ncomp, int64_t rows,
                          const double *expect_first, char *err, size_t len);

/* Appends particle snapshots [0, frames) of n particles read from `from` to `to` (whose
 * particle group is defined); the old file's angular velocities when it has them. */
int lub_h5_continue_snapshots(lub_h5_reader *from, lub_h5 *to, int64_t n, int64_t frames, char *err,
                              size_t len);

/* Both of the above from the file at `path` (opened and closed here): rows [0, rows) of the
 * table (first checking that its first series holds them; expect_first as for
 * lub_h5_continue_table), then, when frames > 0, snapshots [0, frames) of n particles into `to`
 * (whose particle group the caller has defined). */
int lub_h5_continue_output(const char *path, lub_h5_table *to_table, int nseries,
                           const char *const *names, const int *ncomp, int64_t rows,
                           const double *expect_first, lub_h5 *to, int64_t n, int64_t frames,
                           char *err, size_t len);

/* Frames [0, frames) of the file at `path`'s frame set of `to`'s group and columns
 * (lub_h5_frames_layout) appended to `to`; frames 0 copies nothing and opens nothing. The
 * old frames must be numbered as written (row_start of each = the rows before it). */
int lub_h5_continue_frames(const char *path, lub_h5_frames *to, int64_t frames, char *err,
                           size_t len);

#endif
