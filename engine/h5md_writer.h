/* h5md_writer.h — result.h5 in the H5MD 1.1 layout (../shared/spec/service-conventions.md §2).
 *
 *   /h5md                      version [1,1], author, creator (lubdem + version)
 *   /observables/<name>        {step int64[T], time f64[T], value f64[T] | [T][3] | [T][3][3]}
 *                              series in one table hard-link one shared step/time pair
 *   /particles/all/...         optional snapshots: box, position, velocity, angular_velocity,
 *                              radius, id, optional image (positions as the scene passes
 *                              them: wrapped into the cell with their images by simple_shear,
 *                              unwrapped by resuspension)
 *   /profiles/<name>           free-form arrays (profiles, distributions), attribute "unit"
 *   /<group> (frame sets)      records of a varying count per frame (an interaction network):
 *                              step int64[F], time f64[F], row_start int64[F], row_count
 *                              int64[F]; columns <name> [R] | [R][ncomp], frame k's rows
 *                              row_start[k] .. row_start[k] + row_count[k] - 1
 *   /parameters                spec_verbatim, spec_resolved (JSON strings), units, build
 *   root attribute "status"    "running" | "complete" | "partial" | "failed"
 *
 * Ownership: lub_h5 owns the HDF5 handles and its row buffers (allocated when a table or the
 * particle group is defined, never during appends except when a buffer of 1024 rows is
 * flushed to disk). All functions return 0 on success and -1 on an HDF5 error (message in
 * lub_h5_last_error), except the writes an output failure stops (lub_h5_output_lost). Not
 * thread-safe: call from one thread.
 */
#ifndef LUBDEM_H5MD_WRITER_H
#define LUBDEM_H5MD_WRITER_H

#include <stddef.h>
#include <stdint.h>

typedef struct lub_h5 lub_h5;
typedef struct lub_h5_table lub_h5_table;

/* Creates path (truncating a file of that name). NULL on failure, with the reason in errbuf:
 * "HDF5: cannot create PATH: <the system's reason>" when the file cannot be made (what it may
 * have begun stays: the caller removes it). */
lub_h5 *lub_h5_create(const char *path, char *errbuf, int errlen);
/* 1 if errno value e is an output failure a user can act on (no space, file too large, quota,
 * I/O error, read-only file system): what a failed HDF5 write or close leaves in errno when
 * the system refused it. HDF5 itself does not report it; other values may be stale. */
int lub_h5_output_failure(int e);
const char *lub_h5_last_error(const lub_h5 *f);
/* A write the system refuses with an output failure (lub_h5_output_failure: a full disk, the
 * file-size limit, ...) gives the file up: that call and every later write (time series,
 * particle group and snapshots, arrays, parameters, flush) do nothing and return 0, so that the run
 * goes on and its results still reach the summary; lub_h5_close then returns -1 and the caller
 * removes the file (a file whose write failed part-way cannot be trusted). Other HDF5 errors return
 * -1 as before. lub_h5_output_lost returns 1 once the file is given up, with why[len] (may be NULL)
 * the system's reason, what failed and from which step ("File too large (append to the time
 * series from step 4999 on)"); 0 otherwise. */
int lub_h5_output_lost(const lub_h5 *f, char *why, size_t len);

/* /parameters: verbatim and resolved spec (JSON text), unit system description (JSON text),
 * and build provenance (version, git commit, compiler, flags, HDF5 version) added inside. */
int lub_h5_write_parameters(lub_h5 *f, const char *spec_verbatim, const char *spec_resolved,
                            const char *units_json);

/* Units of the datasets the scene's scales give (strings as the observables' units: "1/gd",
 * "a", "a*gd", "gd"; NULL or "" for none), written as their "unit" attribute: `time` on the
 * `time` datasets of the tables and of the particle snapshots, `length` on the particles'
 * position, radius and box edges, `velocity` and `angular_velocity` on theirs (the image
 * element is a count and has none; frame sets take their time unit in lub_h5_frames_define).
 * Before any table, particle group or frame set is defined (-1 after, or for a unit of
 * LUB_H5_UNIT_MAX characters or more; lub_h5_last_error). */
#define LUB_H5_UNIT_MAX 48
int lub_h5_set_units(lub_h5 *f, const char *time, const char *length, const char *velocity,
                     const char *angular_velocity);

/* A table of time series sampled together. ncomp[i] is 1 (scalar), 3 (vector) or 9 (3x3
 * tensor, row-major, sigma_ij = value[3*i + j]). Names may contain '/' for subgroups under
 * /observables. The table keeps pointers to nothing passed in (names are copied). */
lub_h5_table *lub_h5_table_create(lub_h5 *f, int nseries, const char *const *names,
                                  const int *ncomp, const char *const *units);
/* row: the values of all series concatenated in definition order. */
int lub_h5_table_append(lub_h5_table *t, int64_t step, double time, const double *row);

/* Particle snapshots. boundary: 3 strings "periodic" or "none". radius[n], id implicit 0..n-1. */
int lub_h5_particles_define(lub_h5 *f, int64_t n, const double *radius,
                            const char *const *boundary);
/* edges: 3x3 cell matrix (rows = edge vectors) or NULL for an unbounded scene. Arrays are
 * interleaved [n][3]; omega may be NULL.
 * Room: a snapshot that would bring the file within LUB_H5_SNAPSHOT_RESERVE_BYTES of the
 * file-size limit (RLIMIT_FSIZE, e.g. lubdemd's --fsize-mb; or lub_h5_set_byte_limit), or
 * leave less than that free on the file's file system, is not written, nor is any later one;
 * the call still returns 0, so the run and its time series go on (a write beyond RLIMIT_FSIZE
 * would kill the process with SIGXFSZ, or fail with EFBIG, and lose the whole file). The
 * reserve covers the rest of a run's output (time series, distributions, parameters).
 * lub_h5_snapshots_skipped tells how many were skipped, from which step, and why. */
int lub_h5_particles_snapshot(lub_h5 *f, int64_t step, double time, const double *edges,
                              const double *pos, const double *vel, const double *omega,
                              const int32_t *image);
/* H5MD's image element, /particles/all/image {step, time: the position's; value int32
 * [F][n][3]}: the cell images a position was wrapped by, so that position + image . edges (the
 * same frame's edge vectors) is the unwrapped one. After lub_h5_particles_define, before the
 * first snapshot; every snapshot then passes image[n][3] (NULL for a file without it). */
int lub_h5_particles_define_image(lub_h5 *f);
/* 1 when lub_h5_particles_define_image has made the image element. */
int lub_h5_particles_has_image(const lub_h5 *f);
#define LUB_H5_SNAPSHOT_RESERVE_BYTES ((uint64_t)64 << 20)
/* Snapshots not written for lack of room (0: none); *first_step (may be NULL) gets the step of
 * the first, why[len] (may be NULL) the reason (limit or free space, with the sizes in MiB). */
int64_t lub_h5_snapshots_skipped(const lub_h5 *f, int64_t *first_step, char *why, size_t len);
/* Lowers the file-size limit the snapshot room check uses to `bytes` (tests; a limit above
 * RLIMIT_FSIZE is ignored). */
void lub_h5_set_byte_limit(lub_h5 *f, uint64_t bytes);

/* Value types of the frame sets' columns (below). */
typedef enum { LUB_H5_F64, LUB_H5_I64, LUB_H5_I8 } lub_h5_type;

/* Frame sets: records whose number changes from frame to frame, all frames' rows
 * concatenated in each column (layout above; columns chunked by 4096 rows and compressed).
 * lub_h5_frames_define makes the group and its empty datasets, each with its "unit"
 * attribute; the set belongs to f (freed by lub_h5_finish; at most 4 sets of at most 24
 * columns); NULL on an HDF5 error (lub_h5_last_error). Nothing passed in is kept. */
typedef struct {
    const char *name;
    lub_h5_type type;
    int ncomp; /* 1: a column [R]; 2 to 9: [R][ncomp] */
    const char *unit;
} lub_h5_column;
typedef struct lub_h5_frames lub_h5_frames;
enum { LUB_H5_FRAME_COLUMNS_MAX = 24 };
lub_h5_frames *lub_h5_frames_define(lub_h5 *f, const char *group, int ncol,
                                    const lub_h5_column *cols, const char *time_unit);
/* Appends one frame of `rows` records: columns[c] holds rows * ncomp values of column c, of
 * its type (rows may be 0). Room: as for particle snapshots (LUB_H5_SNAPSHOT_RESERVE_BYTES),
 * a frame that would not fit is not written, nor is any later one of the set, and the call
 * returns 0 (lub_h5_frames_skipped). Errors as the other writes (lub_h5_output_lost). */
int lub_h5_frames_append(lub_h5_frames *fr, int64_t step, double time, int64_t rows,
                         const void *const *columns);
/* Frames written so far; *last_step (may be NULL) the step of the last (-1: none). A NULL fr
 * (no set defined) has written none. */
int64_t lub_h5_frames_written(const lub_h5_frames *fr, int64_t *last_step);
/* The set's group (owned by fr) and columns as defined (names owned by fr, units NULL); returns
 * the column count. */
int lub_h5_frames_layout(const lub_h5_frames *fr, const char **group,
                         lub_h5_column cols[LUB_H5_FRAME_COLUMNS_MAX]);
/* Frames not written for lack of room, as lub_h5_snapshots_skipped. */
int64_t lub_h5_frames_skipped(const lub_h5_frames *fr, int64_t *first_step, char *why, size_t len);

/* Free-form dataset under /profiles (rank 1 or 2, row-major), with a "unit" attribute. */
int lub_h5_write_array(lub_h5 *f, const char *name, int rank, const int64_t *dims,
                       const double *data, const char *unit);

/* A string attribute `key` = text on the /profiles dataset `name` written before (a
 * convention the numbers need to be read). */
int lub_h5_profile_note(lub_h5 *f, const char *name, const char *key, const char *text);

/* Flushes buffers and HDF5 metadata (used at checkpoints and before a partial exit). */
int lub_h5_flush(lub_h5 *f);
/* Flushes, writes the root "status" attribute, closes everything and frees f. Returns -1 when
 * the file is not complete (an error, or given up: lub_h5_output_lost) and the caller must
 * remove it. */
int lub_h5_close(lub_h5 *f, const char *status);
/* lub_h5_close that says why it failed: why[len] (may be NULL) gets the system's reason and
 * what failed ("No space left on device (append to the time series from step 120 on)"),
 * or the HDF5 error; empty on success. */
int lub_h5_finish(lub_h5 *f, const char *status, char *why, size_t len);

#endif
