/* h5md_reader.c — chunked reading of result.h5 (layout in h5md_reader.h and h5md_writer.h). */
#include "h5md_reader.h"

#include "h5_read.h"
#include "h5md_writer.h"

#include <errno.h>
#include <hdf5.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#define PARTICLES "/particles/all"

/* A dataset kept open with its extent. */
typedef struct {
    hid_t id;
    int rank;
    hsize_t dims[3];
} dataset;

struct lub_h5_reader {
    hid_t file;
    char *path;
    char err[512];
    /* the series last read (name NULL: none) */
    char *series;
    dataset s_step, s_time, s_value;
    int s_ncomp; /* from the value's shape; 0: none of [T], [T][3], [T][3][3] */
    /* particles: 0 not looked at yet, 1 open, -1 absent or unreadable (message in p_err) */
    int p_state;
    char p_err[400];
    dataset p_step, p_time, p_edges, p_pos, p_vel, p_omega; /* vel, omega: id < 0 when absent */
    dataset p_image;                                        /* id < 0 when absent */
    int64_t frames, np;
};

#if defined(__GNUC__)
__attribute__((format(printf, 2, 3)))
#endif
static int
fail(lub_h5_reader *r, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(r->err, sizeof r->err, fmt, ap);
    va_end(ap);
    return -1;
}

static void dataset_close(dataset *d)
{
    if (d->id >= 0)
        H5Dclose(d->id);
    d->id = H5I_INVALID_HID;
    d->rank = 0;
}

/* Opens path with its extent: 0, 1 when absent (d->id < 0), or -1 when present but not a
 * readable dataset of rank 1 to 3. */
static int dataset_open(hid_t file, const char *path, dataset *d)
{
    d->id = H5I_INVALID_HID;
    d->rank = 0;
    if (!lub_h5_path_exists(file, path))
        return 1;
    d->id = H5Dopen2(file, path, H5P_DEFAULT);
    if (d->id < 0)
        return -1;
    hid_t sp = H5Dget_space(d->id);
    d->rank = sp >= 0 ? H5Sget_simple_extent_ndims(sp) : -1;
    if (d->rank < 1 || d->rank > 3 || H5Sget_simple_extent_dims(sp, d->dims, NULL) < 0) {
        if (sp >= 0)
            H5Sclose(sp);
        dataset_close(d);
        return -1;
    }
    H5Sclose(sp);
    return 0;
}

/* Rows [row0, row0 + count) of d (whole rows) into out, of memory type mtype. */
static int read_rows(const dataset *d, hid_t mtype, int64_t row0, int64_t count, void *out)
{
    hsize_t start[3] = {(hsize_t)row0, 0, 0}, cnt[3] = {(hsize_t)count, 1, 1};
    for (int i = 1; i < d->rank; ++i)
        cnt[i] = d->dims[i];
    hid_t fs = H5Dget_space(d->id);
    hid_t ms = H5Screate_simple(d->rank, cnt, NULL);
    herr_t rc =
        fs < 0 || ms < 0 ? -1 : H5Sselect_hyperslab(fs, H5S_SELECT_SET, start, NULL, cnt, NULL);
    if (rc >= 0)
        rc = H5Dread(d->id, mtype, ms, fs, H5P_DEFAULT, out);
    if (ms >= 0)
        H5Sclose(ms);
    if (fs >= 0)
        H5Sclose(fs);
    return rc < 0 ? -1 : 0;
}

lub_h5_reader *lub_h5r_open(const char *path, char *err, size_t len)
{
    char dummy[8];
    if (!err || len == 0) {
        err = dummy;
        len = sizeof dummy;
    }
    err[0] = '\0';
    if (!path || !*path) {
        snprintf(err, len, "result file: no file name");
        return NULL;
    }
    lub_h5_reader *r = calloc(1, sizeof *r);
    if (!r || !(r->path = strdup(path))) {
        free(r);
        snprintf(err, len, "result file: out of memory opening %s", path);
        return NULL;
    }
    dataset *all[10] = {&r->s_step,  &r->s_time, &r->s_value, &r->p_step,  &r->p_time,
                        &r->p_edges, &r->p_pos,  &r->p_vel,   &r->p_omega, &r->p_image};
    for (int i = 0; i < 10; ++i)
        all[i]->id = H5I_INVALID_HID;
    r->file = lub_h5_open_read(path, "result file", err, len);
    if (r->file < 0) {
        free(r->path);
        free(r);
        return NULL;
    }
    if (!lub_h5_path_exists(r->file, "/h5md")) {
        snprintf(err, len, "result file: %s is not an H5MD file (no /h5md group)", path);
        H5Fclose(r->file);
        free(r->path);
        free(r);
        return NULL;
    }
    return r;
}

static void close_series(lub_h5_reader *r)
{
    dataset_close(&r->s_step);
    dataset_close(&r->s_time);
    dataset_close(&r->s_value);
    free(r->series);
    r->series = NULL;
    r->s_ncomp = 0;
}

static void close_particles(lub_h5_reader *r)
{
    dataset *p[7] = {&r->p_step, &r->p_time,  &r->p_edges, &r->p_pos,
                     &r->p_vel,  &r->p_omega, &r->p_image};
    for (int i = 0; i < 7; ++i)
        dataset_close(p[i]);
    r->p_state = 0;
}

void lub_h5r_close(lub_h5_reader *r)
{
    if (!r)
        return;
    close_series(r);
    close_particles(r);
    H5Fclose(r->file);
    free(r->path);
    free(r);
}

const char *lub_h5r_error(const lub_h5_reader *r) { return r ? r->err : "result file: no file"; }

/* Makes series name the open one: 0, or -1 with the message set. */
static int open_series(lub_h5_reader *r, const char *name)
{
    if (!name || !*name)
        return fail(r, "result file: no series name");
    while (*name == '/')
        ++name;
    if (r->series && strcmp(r->series, name) == 0)
        return 0;
    close_series(r);
    const size_t n = strlen(name) + 32;
    char *path = malloc(n);
    r->series = strdup(name);
    if (!path || !r->series) {
        free(path);
        free(r->series);
        r->series = NULL;
        return fail(r, "result file: out of memory");
    }
    int rc = 0;
    snprintf(path, n, "/observables/%s/value", name);
    int st = dataset_open(r->file, path, &r->s_value);
    if (st > 0)
        rc = fail(r, "result file: series /observables/%.200s is missing from %.200s", name,
                  r->path);
    else if (st < 0)
        rc = fail(r, "result file: %.240s is not a readable array of rank 1 to 3", path);
    const char *parts[2] = {"step", "time"};
    dataset *ds[2] = {&r->s_step, &r->s_time};
    for (int i = 0; rc == 0 && i < 2; ++i) {
        snprintf(path, n, "/observables/%s/%s", name, parts[i]);
        if (dataset_open(r->file, path, ds[i]) != 0 || ds[i]->rank != 1)
            rc = fail(r, "result file: %.240s is missing or not a 1-D array", path);
    }
    free(path);
    if (rc < 0) {
        close_series(r);
        return -1;
    }
    const dataset *v = &r->s_value;
    if (v->rank == 1)
        r->s_ncomp = 1;
    else if (v->rank == 2 && v->dims[1] == 3)
        r->s_ncomp = 3;
    else if (v->rank == 3 && v->dims[1] == 3 && v->dims[2] == 3)
        r->s_ncomp = 9;
    return 0;
}

int lub_h5r_series_rows(lub_h5_reader *r, const char *name, int64_t *rows)
{
    if (!r || open_series(r, name) < 0)
        return -1;
    if (rows)
        *rows = (int64_t)r->s_value.dims[0];
    return 0;
}

static const char *shape_name(int ncomp)
{
    return ncomp == 1 ? "scalars [T]" : ncomp == 3 ? "vectors [T][3]" : "tensors [T][3][3]";
}

int lub_h5r_series_read(lub_h5_reader *r, const char *name, int ncomp, int64_t row0, int64_t count,
                        double *out, int64_t *step, double *time)
{
    if (!r || open_series(r, name) < 0)
        return -1;
    const char *s = r->series;
    if (ncomp != 1 && ncomp != 3 && ncomp != 9)
        return fail(r, "result file: ncomp %d asked of /observables/%.200s (1, 3 or 9)", ncomp, s);
    if (r->s_ncomp == 0)
        return fail(r,
                    "result file: /observables/%.200s/value has a shape other than [T], [T][3] "
                    "and [T][3][3]",
                    s);
    if (ncomp != r->s_ncomp)
        return fail(r, "result file: /observables/%.200s/value holds %s, not ncomp %d", s,
                    shape_name(r->s_ncomp), ncomp);
    const int64_t rows = (int64_t)r->s_value.dims[0];
    if (row0 < 0 || count < 0 || row0 > rows || count > rows - row0)
        return fail(r,
                    "result file: %lld rows from row %lld of /observables/%.200s are out of "
                    "range: it has %lld rows",
                    (long long)count, (long long)row0, s, (long long)rows);
    if (count == 0)
        return 0;
    const char *parts[2] = {"step", "time"};
    const dataset *ds[2] = {&r->s_step, &r->s_time};
    const int wanted[2] = {step != NULL, time != NULL};
    for (int i = 0; i < 2; ++i)
        if (wanted[i] && (int64_t)ds[i]->dims[0] < row0 + count)
            return fail(r, "result file: /observables/%.200s/%s has %lld rows, value %lld", s,
                        parts[i], (long long)ds[i]->dims[0], (long long)rows);
    if (out && read_rows(&r->s_value, H5T_NATIVE_DOUBLE, row0, count, out) < 0)
        return fail(r, "result file: cannot read rows %lld to %lld of /observables/%.200s/value",
                    (long long)row0, (long long)(row0 + count - 1), s);
    if (step && read_rows(&r->s_step, H5T_NATIVE_INT64, row0, count, step) < 0)
        return fail(r, "result file: cannot read rows %lld to %lld of /observables/%.200s/step",
                    (long long)row0, (long long)(row0 + count - 1), s);
    if (time && read_rows(&r->s_time, H5T_NATIVE_DOUBLE, row0, count, time) < 0)
        return fail(r, "result file: cannot read rows %lld to %lld of /observables/%.200s/time",
                    (long long)row0, (long long)(row0 + count - 1), s);
    return 0;
}

/* A per-particle array [F][n][3]: 1 if its shape fits n. */
static int particle_shape(const dataset *d, hsize_t n)
{
    return d->rank == 3 && d->dims[1] == n && d->dims[2] == 3;
}

#if defined(__GNUC__)
__attribute__((format(printf, 2, 3)))
#endif
static int
particles_bad(lub_h5_reader *r, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(r->p_err, sizeof r->p_err, fmt, ap);
    va_end(ap);
    close_particles(r);
    r->p_state = -1;
    snprintf(r->err, sizeof r->err, "%s", r->p_err);
    return -1;
}

/* Opens the particle datasets once: 0, or -1 with the message set. */
static int open_particles(lub_h5_reader *r)
{
    if (r->p_state > 0)
        return 0;
    if (r->p_state < 0) {
        snprintf(r->err, sizeof r->err, "%s", r->p_err);
        return -1;
    }
    if (!lub_h5_path_exists(r->file, PARTICLES))
        return particles_bad(r, "result file: %.200s has no particle snapshots (no %s)", r->path,
                             PARTICLES);
    static const char *const paths[7] = {
        PARTICLES "/position/value", PARTICLES "/position/step",
        PARTICLES "/position/time",  PARTICLES "/box/edges/value",
        PARTICLES "/velocity/value", PARTICLES "/angular_velocity/value",
        PARTICLES "/image/value"};
    dataset *ds[7] = {&r->p_pos, &r->p_step,  &r->p_time, &r->p_edges,
                      &r->p_vel, &r->p_omega, &r->p_image};
    for (int i = 0; i < 7; ++i) {
        const int st = dataset_open(r->file, paths[i], ds[i]);
        if (st < 0 || (st > 0 && i < 4))
            return particles_bad(r, "result file: %s is missing or not a readable array", paths[i]);
    }
    if (r->p_pos.rank != 3 || r->p_pos.dims[2] != 3)
        return particles_bad(r, "result file: %s is not an array [F][n][3]", paths[0]);
    const hsize_t frames = r->p_pos.dims[0], n = r->p_pos.dims[1];
    if (r->p_step.rank != 1 || r->p_time.rank != 1 || r->p_step.dims[0] < frames ||
        r->p_time.dims[0] < frames)
        return particles_bad(r, "result file: %s or %s has fewer than the %llu frames of %s",
                             paths[1], paths[2], (unsigned long long)frames, paths[0]);
    if (r->p_edges.rank != 3 || r->p_edges.dims[0] < frames || r->p_edges.dims[1] != 3 ||
        r->p_edges.dims[2] != 3)
        return particles_bad(r, "result file: %s is not an array [F][3][3] of %llu frames",
                             paths[3], (unsigned long long)frames);
    for (int i = 4; i < 7; ++i)
        if (ds[i]->id >= 0 && !particle_shape(ds[i], n))
            return particles_bad(r, "result file: %s is not an array [F][%llu][3]", paths[i],
                                 (unsigned long long)n);
    r->frames = (int64_t)frames;
    r->np = (int64_t)n;
    r->p_state = 1;
    return 0;
}

int lub_h5r_frames(lub_h5_reader *r, int64_t *frames, int64_t *n_particles)
{
    if (!r || open_particles(r) < 0)
        return -1;
    if (frames)
        *frames = r->frames;
    if (n_particles)
        *n_particles = r->np;
    return 0;
}

/* The velocity or angular velocity of frame k: -1 (message set) when the file has none for
 * every frame (the writer appends them only with a snapshot that has them: their rows line up
 * with the frames only when every snapshot had them). */
static int read_particle_field(lub_h5_reader *r, const dataset *d, const char *what, int64_t k,
                               double *out)
{
    if (d->id < 0 || d->dims[0] == 0)
        return fail(r, "result file: %.200s has no %s in its particle snapshots", r->path, what);
    if ((int64_t)d->dims[0] != r->frames)
        return fail(r,
                    "result file: %.200s has %s in %llu of its %lld particle snapshots: which "
                    "frames they belong to is unknown",
                    r->path, what, (unsigned long long)d->dims[0], (long long)r->frames);
    if (read_rows(d, H5T_NATIVE_DOUBLE, k, 1, out) < 0)
        return fail(r, "result file: cannot read the %s of frame %lld", what, (long long)k);
    return 0;
}

int lub_h5r_frame_read(lub_h5_reader *r, int64_t k, int64_t *step, double *time, double *edges,
                       double *pos, double *vel, double *omega)
{
    if (!r || open_particles(r) < 0)
        return -1;
    if (k < 0 || k >= r->frames)
        return fail(r, "result file: frame %lld is out of range: %.200s has %lld frames",
                    (long long)k, r->path, (long long)r->frames);
    if (vel && read_particle_field(r, &r->p_vel, "velocities", k, vel) < 0)
        return -1;
    if (omega && read_particle_field(r, &r->p_omega, "angular velocities", k, omega) < 0)
        return -1;
    if ((step && read_rows(&r->p_step, H5T_NATIVE_INT64, k, 1, step) < 0) ||
        (time && read_rows(&r->p_time, H5T_NATIVE_DOUBLE, k, 1, time) < 0) ||
        (edges && read_rows(&r->p_edges, H5T_NATIVE_DOUBLE, k, 1, edges) < 0) ||
        (pos && read_rows(&r->p_pos, H5T_NATIVE_DOUBLE, k, 1, pos) < 0))
        return fail(r, "result file: cannot read frame %lld of %.200s", (long long)k, r->path);
    return 0;
}

int lub_h5r_has_image(lub_h5_reader *r)
{
    if (!r || open_particles(r) < 0)
        return -1;
    return r->p_image.id >= 0;
}

int lub_h5r_frame_image(lub_h5_reader *r, int64_t k, int32_t *image)
{
    if (!r || open_particles(r) < 0)
        return -1;
    if (k < 0 || k >= r->frames)
        return fail(r, "result file: frame %lld is out of range: %.200s has %lld frames",
                    (long long)k, r->path, (long long)r->frames);
    if (r->p_image.id < 0)
        return 1;
    if ((int64_t)r->p_image.dims[0] != r->frames)
        return fail(r, "result file: %.200s has images in %llu of its %lld particle snapshots",
                    r->path, (unsigned long long)r->p_image.dims[0], (long long)r->frames);
    if (read_rows(&r->p_image, H5T_NATIVE_INT32, k, 1, image) < 0)
        return fail(r, "result file: cannot read the images of frame %lld", (long long)k);
    return 0;
}

int lub_h5r_rows(lub_h5_reader *r, const char *path, int type, int ncomp, int64_t row0,
                 int64_t count, void *out, int64_t *total)
{
    dataset d;
    const int opened = dataset_open(r->file, path, &d);
    if (opened != 0)
        return fail(r, "%s: %s", path, opened > 0 ? "absent" : "not a readable dataset");
    const int rank_ok = ncomp == 1 ? d.rank == 1 : d.rank == 2 && d.dims[1] == (hsize_t)ncomp;
    const int64_t rows = (int64_t)d.dims[0];
    int rc = 0;
    if (!rank_ok) {
        rc = fail(r, "%s: not %d component%s per row", path, ncomp, ncomp == 1 ? "" : "s");
    } else if (row0 < 0 || count < 0 || row0 > rows || count > rows - row0) {
        rc = fail(r, "%s: %lld rows from row %lld asked for, %lld held", path, (long long)count,
                  (long long)row0, (long long)rows);
    } else if (count > 0) {
        const hid_t mtype = type == LUB_H5_I64  ? H5T_NATIVE_INT64
                            : type == LUB_H5_I8 ? H5T_NATIVE_INT8
                                                : H5T_NATIVE_DOUBLE;
        if (read_rows(&d, mtype, row0, count, out))
            rc = fail(r, "%s: cannot read rows %lld to %lld", path, (long long)row0,
                      (long long)(row0 + count - 1));
    }
    if (rc == 0 && total)
        *total = rows;
    dataset_close(&d);
    return rc;
}
