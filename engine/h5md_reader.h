/* h5md_reader.h — reads back, in chunks, the time series and particle snapshots that
 * h5md_writer.c wrote into a result.h5 (layout in h5md_writer.h):
 *
 *   /observables/<name>/{step int64[T], time f64[T], value f64[T] | [T][3] | [T][3][3]}
 *   /particles/all/position/{step, time, value f64[F][n][3]}
 *   /particles/all/{velocity, angular_velocity}/value f64[F][n][3]
 *   /particles/all/box/edges/value f64[F][3][3]   (zeros for an unbounded scene)
 *
 * Units: those of the file (the writer's "unit" attributes); values come back as stored, bit
 * for bit. Rows and frames are counted from 0. Every read selects only the rows asked for
 * (hyperslabs): a chunk of a large file costs the chunk, not the file.
 * A file closed by lub_h5_close holds every row appended; one read while it is still being
 * written holds the rows flushed so far (lub_h5_flush), as HDF5 allows.
 *
 * Ownership: lub_h5_reader owns its HDF5 handles (it keeps the datasets of the series and of
 * the particles last read open); it keeps no pointer to anything passed in; the caller owns
 * every output array. Errors: functions return 0 / -1 (or NULL), with a message naming the
 * dataset in lub_h5r_error; HDF5's own error printing is silenced. Not thread-safe. */
#ifndef LUBDEM_H5MD_READER_H
#define LUBDEM_H5MD_READER_H

#include <stddef.h>
#include <stdint.h>

typedef struct lub_h5_reader lub_h5_reader;

/* Opens path read-only. NULL on failure with err[len] set (missing file, not HDF5, not H5MD:
 * no /h5md group). */
lub_h5_reader *lub_h5r_open(const char *path, char *err, size_t len);
/* Closes and frees r (NULL: nothing). */
void lub_h5r_close(lub_h5_reader *r);
/* The last error message ("" when none). */
const char *lub_h5r_error(const lub_h5_reader *r);

/* Rows of series /observables/<name> (its value's first dimension) into *rows; -1 when
 * missing. */
int lub_h5r_series_rows(lub_h5_reader *r, const char *name, int64_t *rows);
/* Rows [row0, row0 + count) of /observables/<name>/value into out (count * ncomp doubles,
 * row-major; ncomp 1, 3 or 9 must match the dataset's shape [T], [T][3] or [T][3][3], else -1
 * with a message), and of its step and time into step[count], time[count]. out, step and time
 * may each be NULL (not read). -1 when rows are out of range; count 0 reads nothing. */
int lub_h5r_series_read(lub_h5_reader *r, const char *name, int ncomp, int64_t row0, int64_t count,
                        double *out, int64_t *step, double *time);

/* Number of particle frames and particles (either pointer may be NULL): -1 when the file has
 * no /particles/all. */
int lub_h5r_frames(lub_h5_reader *r, int64_t *frames, int64_t *n_particles);
/* Frame k (0 <= k < frames): step, time, edges[9] (rows = edge vectors, as written), pos, vel,
 * omega [n][3]. Every output may be NULL (not read); -1 when k is out of range, or when vel or
 * omega is requested but the file has none for every frame (written without them). */
int lub_h5r_frame_read(lub_h5_reader *r, int64_t k, int64_t *step, double *time, double *edges,
                       double *pos, double *vel, double *omega);
/* The images of frame k (/particles/all/image, [n][3]): 0 read, 1 when the file has none (then
 * image is untouched), -1 on an error (k out of range, images in only some frames). */
int lub_h5r_frame_image(lub_h5_reader *r, int64_t k, int32_t *image);
/* 1 when the file's particle snapshots have an image element, 0 when not, -1 on an error (no
 * snapshots). */
int lub_h5r_has_image(lub_h5_reader *r);

/* Rows [row0, row0 + count) of the dataset at `path` (from the root; rank 1 with ncomp 1,
 * or [R][ncomp]) into out (count * ncomp values of `type`, a lub_h5_type of h5md_writer.h:
 * the frame sets' columns); *total (may be NULL) gets its row count. -1 when it is absent,
 * of another shape, or the rows are out of range; count 0 reads nothing. */
int lub_h5r_rows(lub_h5_reader *r, const char *path, int type, int ncomp, int64_t row0,
                 int64_t count, void *out, int64_t *total);

#endif
