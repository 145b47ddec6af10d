/* h5md_writer.c — H5MD 1.1 result files (layout in h5md_writer.h). */
#include "h5md_writer.h"

#include <errno.h>
#include <hdf5.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/statvfs.h>

#include "build_info.h"
#include "contact_batch.h"

#define ROWS_PER_CHUNK 1024
#define MAX_TABLES 32
#define MAX_FRAME_SETS 4
#define MAX_FRAME_COLUMNS LUB_H5_FRAME_COLUMNS_MAX
#define FRAME_CHUNK_ROWS 4096 /* rows of a frame set's column per chunk */
#define FRAME_INDEX_CHUNK 64  /* frames of its step, time, row_start, row_count per chunk */

struct lub_h5_table {
    lub_h5 *file;
    int nseries;
    int *ncomp;
    int row_len;
    hid_t step_ds, time_ds;
    hid_t *value_ds;
    int64_t *step_buf;
    double *time_buf;
    double *row_buf;
    double *col_buf; /* one series' columns of a flush (ROWS_PER_CHUNK x 9): no allocation in a
                        run's time loop */
    int nbuf;
    int64_t nwritten;
};

struct lub_h5_frames {
    lub_h5 *file;
    char group[64];
    int ncol;
    char name[MAX_FRAME_COLUMNS][48];
    lub_h5_type type[MAX_FRAME_COLUMNS];
    int ncomp[MAX_FRAME_COLUMNS];
    hid_t col_ds[MAX_FRAME_COLUMNS];
    hid_t step_ds, time_ds, start_ds, count_ds;
    int64_t frames, rows, last_step;
    /* room (lub_h5_frames_skipped) */
    int64_t skipped, first_skipped_step;
    char skip_reason[256];
};

struct lub_h5 {
    hid_t file;
    lub_h5_frames *frame_sets[MAX_FRAME_SETS];
    int nframe_sets;
    char err[256];
    lub_h5_table *tables[MAX_TABLES];
    int ntables;
    /* particle snapshots */
    int64_t np;
    int64_t nframes;
    hid_t p_step, p_time, p_pos, p_vel, p_omega, p_edges;
    hid_t p_image; /* H5MD image [F][n][3] int32, or invalid when the scene writes none */
    /* units of the time and particle datasets (lub_h5_set_units; empty: no attribute) */
    char unit_time[LUB_H5_UNIT_MAX], unit_length[LUB_H5_UNIT_MAX];
    char unit_velocity[LUB_H5_UNIT_MAX], unit_angular_velocity[LUB_H5_UNIT_MAX];
    /* room for snapshots (lub_h5_snapshots_skipped) */
    char *path;          /* the file's path, for the free space of its file system */
    uint64_t byte_limit; /* RLIMIT_FSIZE (soft) at creation, or lub_h5_set_byte_limit */
    int64_t frames_skipped;
    int64_t first_skipped_step;
    char skip_reason[256];
    /* given up after an output failure (lub_h5_output_lost) */
    int lost;
    char lost_reason[320];
};

int lub_h5_output_failure(int e)
{
    return e == ENOSPC || e == EFBIG || e == EDQUOT || e == EIO || e == EROFS;
}

static int set_err(lub_h5 *f, const char *what, const char *name)
{
    /* the system's reason, where it is one of the output failures a user can act on */
    const int e = errno;
    const int known = lub_h5_output_failure(e);
    snprintf(f->err, sizeof f->err, "HDF5: cannot %.80s %.120s%s%s", what, name ? name : "",
             known ? ": " : "", known ? strerror(e) : "");
    return -1;
}

const char *lub_h5_last_error(const lub_h5 *f) { return f ? f->err : "no file"; }

/* A write that failed: an output failure (errno: no space, file too large, ...) gives the file
 * up and returns 0, so that the run goes on to its summary (lub_h5_output_lost); any other
 * failure returns -1 as set_err does. step: the first step not written (< 0: none). */
static int write_failed(lub_h5 *f, const char *what, const char *name, int64_t step)
{
    const int e = errno;
    set_err(f, what, name);
    if (!lub_h5_output_failure(e))
        return -1;
    if (!f->lost) {
        f->lost = 1;
        char from[64] = "";
        if (step >= 0)
            snprintf(from, sizeof from, " from step %lld on", (long long)step);
        snprintf(f->lost_reason, sizeof f->lost_reason, "%s (%.80s %.120s%s)", strerror(e), what,
                 name ? name : "", from);
    }
    return 0;
}

int lub_h5_output_lost(const lub_h5 *f, char *why, size_t len)
{
    if (why && len > 0)
        snprintf(why, len, "%s", f->lost ? f->lost_reason : "");
    return f->lost;
}

static hid_t vlen_string_type(void)
{
    hid_t t = H5Tcopy(H5T_C_S1);
    H5Tset_size(t, H5T_VARIABLE);
    H5Tset_cset(t, H5T_CSET_UTF8);
    return t;
}

static int write_string_attr(hid_t loc, const char *name, const char *value)
{
    hid_t t = vlen_string_type();
    hid_t sp = H5Screate(H5S_SCALAR);
    if (H5Aexists(loc, name) > 0)
        H5Adelete(loc, name);
    hid_t a = H5Acreate2(loc, name, t, sp, H5P_DEFAULT, H5P_DEFAULT);
    herr_t rc = a < 0 ? -1 : H5Awrite(a, t, &value);
    if (a >= 0)
        H5Aclose(a);
    H5Sclose(sp);
    H5Tclose(t);
    return rc < 0 ? -1 : 0;
}

static int write_string_array_attr(hid_t loc, const char *name, const char *const *values, int n)
{
    hid_t t = vlen_string_type();
    hsize_t dim = (hsize_t)n;
    hid_t sp = H5Screate_simple(1, &dim, NULL);
    hid_t a = H5Acreate2(loc, name, t, sp, H5P_DEFAULT, H5P_DEFAULT);
    herr_t rc = a < 0 ? -1 : H5Awrite(a, t, values);
    if (a >= 0)
        H5Aclose(a);
    H5Sclose(sp);
    H5Tclose(t);
    return rc < 0 ? -1 : 0;
}

static int write_int_attr(hid_t loc, const char *name, const int *values, int n)
{
    hsize_t dim = (hsize_t)n;
    hid_t sp = n == 1 ? H5Screate(H5S_SCALAR) : H5Screate_simple(1, &dim, NULL);
    hid_t a = H5Acreate2(loc, name, H5T_STD_I32LE, sp, H5P_DEFAULT, H5P_DEFAULT);
    herr_t rc = a < 0 ? -1 : H5Awrite(a, H5T_NATIVE_INT, values);
    if (a >= 0)
        H5Aclose(a);
    H5Sclose(sp);
    return rc < 0 ? -1 : 0;
}

static int write_string_dataset(hid_t loc, const char *name, const char *value)
{
    hid_t t = vlen_string_type();
    hid_t sp = H5Screate(H5S_SCALAR);
    hid_t d = H5Dcreate2(loc, name, t, sp, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
    herr_t rc = d < 0 ? -1 : H5Dwrite(d, t, H5S_ALL, H5S_ALL, H5P_DEFAULT, &value);
    if (d >= 0)
        H5Dclose(d);
    H5Sclose(sp);
    H5Tclose(t);
    return rc < 0 ? -1 : 0;
}

/* Link-creation property list that creates missing intermediate groups. */
static hid_t lcpl_intermediate(void)
{
    hid_t l = H5Pcreate(H5P_LINK_CREATE);
    H5Pset_create_intermediate_group(l, 1);
    return l;
}

static hid_t make_group(hid_t loc, const char *path)
{
    if (H5Lexists(loc, path, H5P_DEFAULT) > 0)
        return H5Gopen2(loc, path, H5P_DEFAULT);
    hid_t l = lcpl_intermediate();
    hid_t g = H5Gcreate2(loc, path, l, H5P_DEFAULT, H5P_DEFAULT);
    H5Pclose(l);
    return g;
}

/* Extendible dataset [0][extra dims...] chunked along time. */
static hid_t create_extendible(hid_t loc, const char *name, hid_t type, int rank,
                               const hsize_t *frame_dims, hsize_t chunk_rows, int compress)
{
    hsize_t dims[4] = {0, 0, 0, 0}, maxd[4], chunk[4];
    dims[0] = 0;
    maxd[0] = H5S_UNLIMITED;
    chunk[0] = chunk_rows;
    for (int i = 1; i < rank; ++i) {
        dims[i] = maxd[i] = chunk[i] = frame_dims[i - 1];
    }
    hid_t sp = H5Screate_simple(rank, dims, maxd);
    hid_t pl = H5Pcreate(H5P_DATASET_CREATE);
    H5Pset_chunk(pl, rank, chunk);
    if (compress && H5Zfilter_avail(H5Z_FILTER_DEFLATE) > 0) {
        H5Pset_shuffle(pl);
        H5Pset_deflate(pl, 1);
    }
    hid_t d = H5Dcreate2(loc, name, type, sp, H5P_DEFAULT, pl, H5P_DEFAULT);
    H5Pclose(pl);
    H5Sclose(sp);
    return d;
}

/* Append `rows` rows (each of frame size) at row offset `at`. */
static int append_rows(hid_t ds, hid_t memtype, int rank, const hsize_t *frame_dims, int64_t at,
                       int64_t rows, const void *data)
{
    hsize_t newdims[4], start[4] = {0, 0, 0, 0}, count[4];
    newdims[0] = (hsize_t)(at + rows);
    count[0] = (hsize_t)rows;
    start[0] = (hsize_t)at;
    for (int i = 1; i < rank; ++i)
        newdims[i] = count[i] = frame_dims[i - 1];
    if (H5Dset_extent(ds, newdims) < 0)
        return -1;
    hid_t fs = H5Dget_space(ds);
    H5Sselect_hyperslab(fs, H5S_SELECT_SET, start, NULL, count, NULL);
    hid_t ms = H5Screate_simple(rank, count, NULL);
    herr_t rc = H5Dwrite(ds, memtype, ms, fs, H5P_DEFAULT, data);
    H5Sclose(ms);
    H5Sclose(fs);
    return rc < 0 ? -1 : 0;
}

lub_h5 *lub_h5_create(const char *path, char *errbuf, int errlen)
{
    /* No HDF5 exit handler: a close that fails (disk full: ENOSPC while flushing) leaves the
     * file in HDF5's table, and the handler's second close segfaulted in H5F__close_cb
     * (HDF5 1.10.8, Debian 12) after we had reported the error, turning exit 4 into a crash.
     * Every file is closed explicitly; this must precede any other HDF5 call (it does: the
     * engine's first HDF5 call is here) and is a no-op afterwards. */
    H5dont_atexit();
    H5Eset_auto2(H5E_DEFAULT, NULL, NULL); /* we report errors ourselves */
    lub_h5 *f = calloc(1, sizeof *f);
    if (!f) {
        snprintf(errbuf, (size_t)errlen, "out of memory");
        return NULL;
    }
    f->p_step = f->p_time = f->p_pos = f->p_vel = f->p_omega = f->p_edges = H5I_INVALID_HID;
    f->p_image = H5I_INVALID_HID;
    f->path = strdup(path);
    f->byte_limit = UINT64_MAX;
    struct rlimit fsize;
    if (getrlimit(RLIMIT_FSIZE, &fsize) == 0 && fsize.rlim_cur != RLIM_INFINITY)
        f->byte_limit = (uint64_t)fsize.rlim_cur;
    hid_t fapl = H5Pcreate(H5P_FILE_ACCESS);
    /* H5MD implementation note: file format readable by HDF5 >= 1.8 */
    H5Pset_libver_bounds(fapl, H5F_LIBVER_V18, H5F_LIBVER_V18);
    errno = 0;
    f->file = H5Fcreate(path, H5F_ACC_TRUNC, H5P_DEFAULT, fapl);
    const int create_errno = errno;
    H5Pclose(fapl);
    if (f->file < 0) {
        snprintf(errbuf, (size_t)errlen, "HDF5: cannot create %s: %s", path,
                 create_errno ? strerror(create_errno) : "HDF5 error");
        free(f->path);
        free(f);
        return NULL;
    }
    hid_t h5md = make_group(f->file, "h5md");
    int version[2] = {1, 1};
    int rc = write_int_attr(h5md, "version", version, 2);
    hid_t author = make_group(h5md, "author");
    const char *user = getenv("LUBDEM_AUTHOR");
    if (!user)
        user = getenv("USER");
    rc |= write_string_attr(author, "name", user && *user ? user : "lubdem user");
    H5Gclose(author);
    hid_t creator = make_group(h5md, "creator");
    rc |= write_string_attr(creator, "name", "lubdem");
    rc |= write_string_attr(creator, "version", lub_build_version());
    H5Gclose(creator);
    H5Gclose(h5md);
    rc |= write_string_attr(f->file, "status", "running");
    if (rc) {
        snprintf(errbuf, (size_t)errlen, "HDF5: cannot write /h5md metadata in %s", path);
        H5Fclose(f->file);
        free(f->path);
        free(f);
        return NULL;
    }
    return f;
}

static void copy_unit(char dst[LUB_H5_UNIT_MAX], const char *src)
{
    snprintf(dst, LUB_H5_UNIT_MAX, "%s", src ? src : "");
}

int lub_h5_set_units(lub_h5 *f, const char *time, const char *length, const char *velocity,
                     const char *angular_velocity)
{
    const char *u[4] = {time, length, velocity, angular_velocity};
    for (int k = 0; k < 4; ++k)
        if (u[k] && strlen(u[k]) >= LUB_H5_UNIT_MAX)
            return set_err(f, "use a unit this long:", u[k]);
    if (f->ntables > 0 || f->p_pos >= 0 || f->nframe_sets > 0)
        return set_err(f, "set the units after", "a table, particles or a frame set is defined");
    copy_unit(f->unit_time, time);
    copy_unit(f->unit_length, length);
    copy_unit(f->unit_velocity, velocity);
    copy_unit(f->unit_angular_velocity, angular_velocity);
    return 0;
}

/* The "unit" attribute of dataset d, when the unit is set; 0 on success or nothing to do. */
static int unit_attr(hid_t d, const char *unit)
{
    return d < 0 || !unit[0] ? 0 : write_string_attr(d, "unit", unit);
}

int lub_h5_write_parameters(lub_h5 *f, const char *spec_verbatim, const char *spec_resolved,
                            const char *units_json)
{
    if (f->lost)
        return 0;
    hid_t g = make_group(f->file, "parameters");
    if (g < 0)
        return write_failed(f, "create", "/parameters", -1);
    int rc = write_string_dataset(g, "spec_verbatim", spec_verbatim ? spec_verbatim : "");
    rc |= write_string_dataset(g, "spec_resolved", spec_resolved ? spec_resolved : "");
    rc |= write_string_dataset(g, "units", units_json ? units_json : "{}");
    hid_t b = make_group(g, "build");
    rc |= write_string_attr(b, "version", lub_build_version());
    rc |= write_string_attr(b, "git_commit", lub_build_git());
    rc |= write_string_attr(b, "compiler", lub_build_compiler());
    rc |= write_string_attr(b, "cflags", lub_build_cflags());
    /* the batched law's instruction set: results of different sets agree to round-off only */
    rc |= write_string_attr(b, "contact_law_simd", lub_pair_batch_isa());
    char hv[64];
    unsigned maj, min, rel;
    H5get_libversion(&maj, &min, &rel);
    snprintf(hv, sizeof hv, "%u.%u.%u", maj, min, rel);
    rc |= write_string_attr(b, "hdf5_version", hv);
    H5Gclose(b);
    H5Gclose(g);
    return rc ? write_failed(f, "write", "/parameters", -1) : 0;
}

static int table_flush(lub_h5_table *t)
{
    lub_h5 *f = t->file;
    if (t->nbuf == 0 || f->lost) {
        t->nbuf = 0;
        return 0;
    }
    const int64_t first = t->step_buf[0];
    if (append_rows(t->step_ds, H5T_NATIVE_INT64, 1, NULL, t->nwritten, t->nbuf, t->step_buf) ||
        append_rows(t->time_ds, H5T_NATIVE_DOUBLE, 1, NULL, t->nwritten, t->nbuf, t->time_buf)) {
        t->nbuf = 0;
        return write_failed(f, "append to", "the time series", first);
    }
    /* gather each series' columns from the row buffer */
    double *col = t->col_buf;
    int off = 0;
    for (int s = 0; s < t->nseries; ++s) {
        int nc = t->ncomp[s];
        for (int r = 0; r < t->nbuf; ++r)
            memcpy(col + (size_t)r * nc, t->row_buf + (size_t)r * t->row_len + off,
                   sizeof(double) * (size_t)nc);
        hsize_t fd[2] = {3, 3};
        if (nc == 3)
            fd[0] = 3;
        int rank = nc == 1 ? 1 : (nc == 3 ? 2 : 3);
        if (append_rows(t->value_ds[s], H5T_NATIVE_DOUBLE, rank, fd, t->nwritten, t->nbuf, col)) {
            t->nbuf = 0;
            return write_failed(f, "append to", "the time series", first);
        }
        off += nc;
    }
    t->nwritten += t->nbuf;
    t->nbuf = 0;
    return 0;
}

/* Frees the buffers of t (those not allocated yet are NULL) and t itself; its datasets are the
 * caller's to close. */
static void table_release(lub_h5_table *t)
{
    free(t->ncomp);
    free(t->value_ds);
    free(t->step_buf);
    free(t->time_buf);
    free(t->row_buf);
    free(t->col_buf);
    free(t);
}

lub_h5_table *lub_h5_table_create(lub_h5 *f, int nseries, const char *const *names,
                                  const int *ncomp, const char *const *units)
{
    if (f->ntables >= MAX_TABLES) {
        set_err(f, "create more tables than", "32");
        return NULL;
    }
    lub_h5_table *t = calloc(1, sizeof *t);
    if (!t)
        return NULL;
    t->file = f;
    t->nseries = nseries;
    t->ncomp = malloc(sizeof(int) * (size_t)nseries);
    t->value_ds = malloc(sizeof(hid_t) * (size_t)nseries);
    if (nseries > 0 && (!t->ncomp || !t->value_ds)) { /* (until 2026-12-07 written unchecked) */
        set_err(f, "out of memory creating observables table starting with", names[0]);
        table_release(t);
        return NULL;
    }
    for (int s = 0; s < nseries; ++s) {
        if (ncomp[s] != 1 && ncomp[s] != 3 && ncomp[s] != 9) {
            set_err(f, "create series with ncomp not in {1,3,9}:", names[s]);
            table_release(t);
            return NULL;
        }
        t->ncomp[s] = ncomp[s];
        t->row_len += ncomp[s];
    }
    t->step_buf = malloc(sizeof(int64_t) * ROWS_PER_CHUNK);
    t->time_buf = malloc(sizeof(double) * ROWS_PER_CHUNK);
    t->row_buf = malloc(sizeof(double) * ROWS_PER_CHUNK * (size_t)t->row_len);
    t->col_buf = malloc(sizeof(double) * ROWS_PER_CHUNK * 9);
    int ok = t->ncomp && t->value_ds && t->step_buf && t->time_buf && t->row_buf && t->col_buf;
    char path[512];
    for (int s = 0; ok && s < nseries; ++s) {
        snprintf(path, sizeof path, "observables/%s", names[s]);
        hid_t g = make_group(f->file, path);
        if (g < 0) {
            ok = 0;
            break;
        }
        if (s == 0) {
            /* explicit-mode step/time, shared by the table through hard links */
            t->step_ds = create_extendible(g, "step", H5T_STD_I64LE, 1, NULL, ROWS_PER_CHUNK, 1);
            t->time_ds = create_extendible(g, "time", H5T_IEEE_F64LE, 1, NULL, ROWS_PER_CHUNK, 1);
            ok = t->step_ds >= 0 && t->time_ds >= 0 && unit_attr(t->time_ds, f->unit_time) == 0;
        } else {
            char src[512];
            snprintf(src, sizeof src, "/observables/%s/step", names[0]);
            ok = H5Lcreate_hard(f->file, src, g, "step", H5P_DEFAULT, H5P_DEFAULT) >= 0;
            snprintf(src, sizeof src, "/observables/%s/time", names[0]);
            ok = ok && H5Lcreate_hard(f->file, src, g, "time", H5P_DEFAULT, H5P_DEFAULT) >= 0;
        }
        hsize_t fd[2] = {3, 3};
        int rank = ncomp[s] == 1 ? 1 : (ncomp[s] == 3 ? 2 : 3);
        t->value_ds[s] = create_extendible(g, "value", H5T_IEEE_F64LE, rank, fd, ROWS_PER_CHUNK, 1);
        ok = ok && t->value_ds[s] >= 0;
        if (ok && units && units[s])
            ok = write_string_attr(t->value_ds[s], "unit", units[s]) == 0;
        H5Gclose(g);
    }
    if (!ok) {
        set_err(f, "create observables table starting with", names[0]);
        table_release(t);
        return NULL;
    }
    f->tables[f->ntables++] = t;
    return t;
}

int lub_h5_table_append(lub_h5_table *t, int64_t step, double time, const double *row)
{
    if (t->file->lost)
        return 0;
    t->step_buf[t->nbuf] = step;
    t->time_buf[t->nbuf] = time;
    memcpy(t->row_buf + (size_t)t->nbuf * t->row_len, row, sizeof(double) * (size_t)t->row_len);
    if (++t->nbuf == ROWS_PER_CHUNK)
        return table_flush(t);
    return 0;
}

static void table_free(lub_h5_table *t)
{
    H5Dclose(t->step_ds);
    H5Dclose(t->time_ds);
    for (int s = 0; s < t->nseries; ++s)
        H5Dclose(t->value_ds[s]);
    table_release(t);
}

int lub_h5_particles_define(lub_h5 *f, int64_t n, const double *radius, const char *const *boundary)
{
    if (f->lost)
        return 0;
    hid_t g = make_group(f->file, "particles/all");
    hid_t box = make_group(g, "box");
    int dim = 3;
    int rc = write_int_attr(box, "dimension", &dim, 1);
    rc |= write_string_array_attr(box, "boundary", boundary, 3);
    hsize_t nn = (hsize_t)n;
    hid_t sp = H5Screate_simple(1, &nn, NULL);
    hid_t d = H5Dcreate2(g, "radius", H5T_IEEE_F64LE, sp, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
    rc |= d < 0 || H5Dwrite(d, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, radius) < 0;
    rc |= unit_attr(d, f->unit_length);
    if (d >= 0)
        H5Dclose(d);
    int64_t *ids = malloc(sizeof(int64_t) * (size_t)(n > 0 ? n : 1));
    for (int64_t i = 0; ids && i < n; ++i)
        ids[i] = i;
    d = H5Dcreate2(g, "id", H5T_STD_I64LE, sp, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
    rc |= !ids || d < 0 || H5Dwrite(d, H5T_NATIVE_INT64, H5S_ALL, H5S_ALL, H5P_DEFAULT, ids) < 0;
    free(ids);
    if (d >= 0)
        H5Dclose(d);
    H5Sclose(sp);

    hsize_t frame[2] = {(hsize_t)n, 3};
    hid_t pos = make_group(g, "position");
    f->p_step = create_extendible(pos, "step", H5T_STD_I64LE, 1, NULL, 64, 0);
    f->p_time = create_extendible(pos, "time", H5T_IEEE_F64LE, 1, NULL, 64, 0);
    f->p_pos = create_extendible(pos, "value", H5T_IEEE_F64LE, 3, frame, 1, 0);
    rc |= unit_attr(f->p_time, f->unit_time) | unit_attr(f->p_pos, f->unit_length);
    H5Gclose(pos);
    const char *others[2] = {"velocity", "angular_velocity"};
    hid_t *ds[2] = {&f->p_vel, &f->p_omega};
    for (int k = 0; k < 2; ++k) {
        hid_t og = make_group(g, others[k]);
        rc |= H5Lcreate_hard(f->file, "/particles/all/position/step", og, "step", H5P_DEFAULT,
                             H5P_DEFAULT) < 0;
        rc |= H5Lcreate_hard(f->file, "/particles/all/position/time", og, "time", H5P_DEFAULT,
                             H5P_DEFAULT) < 0;
        *ds[k] = create_extendible(og, "value", H5T_IEEE_F64LE, 3, frame, 1, 0);
        rc |= unit_attr(*ds[k], k == 0 ? f->unit_velocity : f->unit_angular_velocity);
        H5Gclose(og);
    }
    hid_t edges = make_group(box, "edges");
    rc |= H5Lcreate_hard(f->file, "/particles/all/position/step", edges, "step", H5P_DEFAULT,
                         H5P_DEFAULT) < 0;
    rc |= H5Lcreate_hard(f->file, "/particles/all/position/time", edges, "time", H5P_DEFAULT,
                         H5P_DEFAULT) < 0;
    hsize_t ed[2] = {3, 3};
    f->p_edges = create_extendible(edges, "value", H5T_IEEE_F64LE, 3, ed, 64, 0);
    rc |= unit_attr(f->p_edges, f->unit_length);
    H5Gclose(edges);
    H5Gclose(box);
    H5Gclose(g);
    f->np = n;
    if (rc || f->p_step < 0 || f->p_pos < 0 || f->p_vel < 0 || f->p_omega < 0 || f->p_edges < 0)
        return write_failed(f, "create", "/particles/all", -1);
    return 0;
}

int lub_h5_particles_define_image(lub_h5 *f)
{
    if (f->lost)
        return 0;
    if (f->p_pos < 0)
        return set_err(f, "define /particles/all/image before", "lub_h5_particles_define");
    if (f->nframes > 0 || f->frames_skipped > 0) /* its rows would not line up */
        return set_err(f, "define /particles/all/image after", "a particle snapshot");
    hid_t g = H5Gcreate2(f->file, "/particles/all/image", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
    int rc = g < 0;
    if (g >= 0) {
        rc |= H5Lcreate_hard(f->file, "/particles/all/position/step", g, "step", H5P_DEFAULT,
                             H5P_DEFAULT) < 0;
        rc |= H5Lcreate_hard(f->file, "/particles/all/position/time", g, "time", H5P_DEFAULT,
                             H5P_DEFAULT) < 0;
        hsize_t frame[2] = {(hsize_t)f->np, 3};
        f->p_image = create_extendible(g, "value", H5T_STD_I32LE, 3, frame, 1, 0);
        H5Gclose(g);
    }
    if (rc || f->p_image < 0)
        return write_failed(f, "create", "/particles/all/image", -1);
    return 0;
}

int lub_h5_particles_has_image(const lub_h5 *f) { return f && f->p_image >= 0; }

/* 1 if `what` (a frame of frame_bytes: "a snapshot", "a frame of /pair_network") leaves
 * LUB_H5_SNAPSHOT_RESERVE_BYTES below the file-size limit and on the file system; otherwise 0
 * with reason[len] set. */
static int room_for(const lub_h5 *f, const char *what, uint64_t frame_bytes, char *reason,
                    size_t len)
{
    /* the chunks HDF5 still holds in its cache (1 MiB per dataset: 2.2 MiB of snapshots and
     * frames of 300 particles) are not in the file's size until they are written: a snapshot
     * was checked against a size that much too small (until 2026-12-06); a failed flush shows
     * again at the write that follows */
    H5Fflush(f->file, H5F_SCOPE_LOCAL);
    hsize_t size = 0;
    if (H5Fget_filesize(f->file, &size) < 0)
        size = 0;
    const uint64_t need = (uint64_t)size + frame_bytes + LUB_H5_SNAPSHOT_RESERVE_BYTES;
    const double mb = 1.0 / (1024.0 * 1024.0);
    if (need > f->byte_limit) {
        snprintf(reason, len,
                 "%s of %.3g MiB would bring result.h5 (%.4g MiB) within %.0f MiB of "
                 "the file-size limit of %.4g MiB this process runs under (RLIMIT_FSIZE: ulimit "
                 "-f, lubdemd --fsize-mb)",
                 what, frame_bytes * mb, size * mb, (double)LUB_H5_SNAPSHOT_RESERVE_BYTES * mb,
                 f->byte_limit * mb);
        return 0;
    }
    struct statvfs fs;
    if (f->path && statvfs(f->path, &fs) == 0) {
        const uint64_t avail = (uint64_t)fs.f_bavail * (uint64_t)fs.f_frsize;
        if (frame_bytes + LUB_H5_SNAPSHOT_RESERVE_BYTES > avail) {
            snprintf(reason, len,
                     "%s of %.3g MiB would leave less than %.0f MiB free on the output "
                     "file system (%.4g MiB free)",
                     what, frame_bytes * mb, (double)LUB_H5_SNAPSHOT_RESERVE_BYTES * mb,
                     avail * mb);
            return 0;
        }
    }
    return 1;
}

void lub_h5_set_byte_limit(lub_h5 *f, uint64_t bytes)
{
    if (bytes < f->byte_limit)
        f->byte_limit = bytes;
}

int64_t lub_h5_snapshots_skipped(const lub_h5 *f, int64_t *first_step, char *why, size_t len)
{
    if (first_step)
        *first_step = f->first_skipped_step;
    if (why && len > 0)
        snprintf(why, len, "%s", f->frames_skipped > 0 ? f->skip_reason : "");
    return f->frames_skipped;
}

int lub_h5_particles_snapshot(lub_h5 *f, int64_t step, double time, const double *edges,
                              const double *pos, const double *vel, const double *omega,
                              const int32_t *image)
{
    if (f->lost)
        return 0;
    if (f->p_pos < 0)
        return set_err(f, "write a snapshot before", "lub_h5_particles_define");
    const uint64_t frame_bytes =
        (uint64_t)f->np * 3u * sizeof(double) * (1u + (vel != NULL) + (omega != NULL)) +
        2u * sizeof(double) + 9u * sizeof(double) +
        (image ? (uint64_t)f->np * 3u * sizeof(int32_t) : 0u);
    if (image && f->p_image < 0)
        return set_err(f, "write an image before", "lub_h5_particles_define_image");
    if (!image && f->p_image >= 0) /* the image rows would fall behind the positions' */
        return set_err(f, "write a snapshot without its image after",
                       "lub_h5_particles_define_image");
    if (f->frames_skipped > 0 ||
        !room_for(f, "a snapshot", frame_bytes, f->skip_reason, sizeof f->skip_reason)) {
        if (f->frames_skipped++ == 0)
            f->first_skipped_step = step;
        return 0;
    }
    hsize_t frame[2] = {(hsize_t)f->np, 3};
    hsize_t ed[2] = {3, 3};
    static const double no_edges[9] = {0, 0, 0, 0, 0, 0, 0, 0, 0};
    int64_t at = f->nframes;
    int rc = append_rows(f->p_step, H5T_NATIVE_INT64, 1, NULL, at, 1, &step);
    rc |= append_rows(f->p_time, H5T_NATIVE_DOUBLE, 1, NULL, at, 1, &time);
    rc |= append_rows(f->p_edges, H5T_NATIVE_DOUBLE, 3, ed, at, 1, edges ? edges : no_edges);
    rc |= append_rows(f->p_pos, H5T_NATIVE_DOUBLE, 3, frame, at, 1, pos);
    if (vel)
        rc |= append_rows(f->p_vel, H5T_NATIVE_DOUBLE, 3, frame, at, 1, vel);
    if (omega)
        rc |= append_rows(f->p_omega, H5T_NATIVE_DOUBLE, 3, frame, at, 1, omega);
    if (image)
        rc |= append_rows(f->p_image, H5T_NATIVE_INT32, 3, frame, at, 1, image);
    if (rc)
        return write_failed(f, "append", "a particle snapshot", step);
    f->nframes++;
    return 0;
}

static hid_t file_type_of(lub_h5_type type)
{
    return type == LUB_H5_I64 ? H5T_STD_I64LE : type == LUB_H5_I8 ? H5T_STD_I8LE : H5T_IEEE_F64LE;
}

static hid_t mem_type_of(lub_h5_type type)
{
    return type == LUB_H5_I64  ? H5T_NATIVE_INT64
           : type == LUB_H5_I8 ? H5T_NATIVE_INT8
                               : H5T_NATIVE_DOUBLE;
}

static size_t value_bytes(lub_h5_type type) { return type == LUB_H5_I8 ? 1u : 8u; }

int lub_h5_write_array(lub_h5 *f, const char *name, int rank, const int64_t *dims,
                       const double *data, const char *unit)
{
    if (rank < 1 || rank > 2)
        return set_err(f, "write array of rank other than 1 or 2:", name);
    if (f->lost)
        return 0;
    char path[512];
    snprintf(path, sizeof path, "profiles/%s", name);
    hsize_t hd[2] = {(hsize_t)dims[0], rank > 1 ? (hsize_t)dims[1] : 1};
    hid_t sp = H5Screate_simple(rank, hd, NULL);
    hid_t l = lcpl_intermediate();
    hid_t d = H5Dcreate2(f->file, path, H5T_IEEE_F64LE, sp, l, H5P_DEFAULT, H5P_DEFAULT);
    H5Pclose(l);
    int rc = d < 0 || H5Dwrite(d, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, data) < 0;
    if (!rc && unit)
        rc = write_string_attr(d, "unit", unit);
    if (d >= 0)
        H5Dclose(d);
    H5Sclose(sp);
    return rc ? write_failed(f, "write", path, -1) : 0;
}

int lub_h5_profile_note(lub_h5 *f, const char *name, const char *key, const char *text)
{
    if (f->lost)
        return 0;
    char path[512];
    snprintf(path, sizeof path, "profiles/%s", name);
    hid_t d = H5Dopen2(f->file, path, H5P_DEFAULT);
    const int rc = d < 0 || write_string_attr(d, key, text);
    if (d >= 0)
        H5Dclose(d);
    return rc ? write_failed(f, "write an attribute of", path, -1) : 0;
}

static void frames_free(lub_h5_frames *fr)
{
    hid_t ids[4] = {fr->step_ds, fr->time_ds, fr->start_ds, fr->count_ds};
    for (int k = 0; k < 4; ++k)
        if (ids[k] >= 0)
            H5Dclose(ids[k]);
    for (int c = 0; c < fr->ncol; ++c)
        if (fr->col_ds[c] >= 0)
            H5Dclose(fr->col_ds[c]);
    free(fr);
}

/* An extendible dataset `name` of group g with a "unit" attribute; H5I_INVALID_HID on error. */
static hid_t frames_dataset(hid_t g, const char *name, lub_h5_type type, int ncomp,
                            hsize_t chunk_rows, int compress, const char *unit)
{
    const hsize_t width[1] = {(hsize_t)ncomp};
    hid_t d = create_extendible(g, name, file_type_of(type), ncomp > 1 ? 2 : 1, width, chunk_rows,
                                compress);
    if (d >= 0 && unit && write_string_attr(d, "unit", unit)) {
        H5Dclose(d);
        d = H5I_INVALID_HID;
    }
    return d;
}

lub_h5_frames *lub_h5_frames_define(lub_h5 *f, const char *group, int ncol,
                                    const lub_h5_column *cols, const char *time_unit)
{
    if (f->nframe_sets >= MAX_FRAME_SETS || ncol < 1 || ncol > MAX_FRAME_COLUMNS ||
        strlen(group) >= sizeof((lub_h5_frames *)0)->group) {
        set_err(f, "define the frame set (too many sets or columns, or a long name)", group);
        return NULL;
    }
    lub_h5_frames *fr = calloc(1, sizeof *fr);
    if (!fr) {
        set_err(f, "define (out of memory)", group);
        return NULL;
    }
    fr->file = f;
    snprintf(fr->group, sizeof fr->group, "%s", group);
    fr->ncol = ncol;
    fr->last_step = -1;
    fr->step_ds = fr->time_ds = fr->start_ds = fr->count_ds = H5I_INVALID_HID;
    for (int c = 0; c < MAX_FRAME_COLUMNS; ++c)
        fr->col_ds[c] = H5I_INVALID_HID;
    for (int c = 0; c < ncol; ++c) {
        if (cols[c].ncomp < 1 || cols[c].ncomp > 9 || strlen(cols[c].name) >= sizeof fr->name[c]) {
            set_err(f, "define a column of 1 to 9 components and a short name:", cols[c].name);
            free(fr);
            return NULL;
        }
        snprintf(fr->name[c], sizeof fr->name[c], "%s", cols[c].name);
        fr->type[c] = cols[c].type;
        fr->ncomp[c] = cols[c].ncomp;
    }
    f->frame_sets[f->nframe_sets++] = fr; /* freed by lub_h5_finish, also after an error */
    if (f->lost)
        return fr; /* appends do nothing */
    hid_t g = make_group(f->file, group);
    int bad = g < 0;
    if (!bad) {
        fr->step_ds = frames_dataset(g, "step", LUB_H5_I64, 1, FRAME_INDEX_CHUNK, 0, "1");
        fr->time_ds = frames_dataset(g, "time", LUB_H5_F64, 1, FRAME_INDEX_CHUNK, 0, time_unit);
        fr->start_ds = frames_dataset(g, "row_start", LUB_H5_I64, 1, FRAME_INDEX_CHUNK, 0, "1");
        fr->count_ds = frames_dataset(g, "row_count", LUB_H5_I64, 1, FRAME_INDEX_CHUNK, 0, "1");
        bad = fr->step_ds < 0 || fr->time_ds < 0 || fr->start_ds < 0 || fr->count_ds < 0;
        for (int c = 0; c < ncol && !bad; ++c) {
            fr->col_ds[c] = frames_dataset(g, cols[c].name, cols[c].type, cols[c].ncomp,
                                           FRAME_CHUNK_ROWS, 1, cols[c].unit);
            bad = fr->col_ds[c] < 0;
        }
        H5Gclose(g);
    }
    if (bad && write_failed(f, "create", group, -1))
        return NULL;
    return fr;
}

int lub_h5_frames_append(lub_h5_frames *fr, int64_t step, double time, int64_t rows,
                         const void *const *columns)
{
    lub_h5 *f = fr->file;
    if (f->lost)
        return 0;
    uint64_t frame_bytes = 4u * 8u;
    for (int c = 0; c < fr->ncol; ++c)
        frame_bytes += (uint64_t)rows * (uint64_t)fr->ncomp[c] * value_bytes(fr->type[c]);
    char what[96];
    snprintf(what, sizeof what, "a frame of /%s", fr->group);
    if (fr->skipped > 0 ||
        !room_for(f, what, frame_bytes, fr->skip_reason, sizeof fr->skip_reason)) {
        if (fr->skipped++ == 0)
            fr->first_skipped_step = step;
        return 0;
    }
    const int64_t at = fr->frames, start = fr->rows;
    int rc = append_rows(fr->step_ds, H5T_NATIVE_INT64, 1, NULL, at, 1, &step);
    rc |= append_rows(fr->time_ds, H5T_NATIVE_DOUBLE, 1, NULL, at, 1, &time);
    rc |= append_rows(fr->start_ds, H5T_NATIVE_INT64, 1, NULL, at, 1, &start);
    rc |= append_rows(fr->count_ds, H5T_NATIVE_INT64, 1, NULL, at, 1, &rows);
    for (int c = 0; c < fr->ncol && rows > 0; ++c) {
        const hsize_t width[1] = {(hsize_t)fr->ncomp[c]};
        rc |= append_rows(fr->col_ds[c], mem_type_of(fr->type[c]), fr->ncomp[c] > 1 ? 2 : 1, width,
                          start, rows, columns[c]);
    }
    /* to the file now: the room check of the next frame then sees its size (compressed chunks
     * otherwise wait in HDF5's chunk cache, up to 1 MiB a column) */
    for (int c = 0; c < fr->ncol && !rc; ++c)
        rc |= H5Dflush(fr->col_ds[c]) < 0;
    if (rc)
        return write_failed(f, "append a frame to", fr->group, step);
    fr->frames++;
    fr->rows += rows;
    fr->last_step = step;
    return 0;
}

int64_t lub_h5_frames_written(const lub_h5_frames *fr, int64_t *last_step)
{
    if (last_step)
        *last_step = fr ? fr->last_step : -1;
    return fr ? fr->frames : 0;
}

int lub_h5_frames_layout(const lub_h5_frames *fr, const char **group,
                         lub_h5_column cols[LUB_H5_FRAME_COLUMNS_MAX])
{
    *group = fr->group;
    for (int c = 0; c < fr->ncol; ++c)
        cols[c] = (lub_h5_column){fr->name[c], fr->type[c], fr->ncomp[c], NULL};
    return fr->ncol;
}

int64_t lub_h5_frames_skipped(const lub_h5_frames *fr, int64_t *first_step, char *why, size_t len)
{
    if (first_step)
        *first_step = fr->first_skipped_step;
    if (why && len > 0)
        snprintf(why, len, "%s", fr->skipped > 0 ? fr->skip_reason : "");
    return fr->skipped;
}

int lub_h5_flush(lub_h5 *f)
{
    int rc = 0;
    for (int i = 0; i < f->ntables; ++i)
        rc |= table_flush(f->tables[i]);
    if (!f->lost && H5Fflush(f->file, H5F_SCOPE_GLOBAL) < 0)
        rc = write_failed(f, "flush", "the file", -1);
    return rc ? -1 : 0;
}

int lub_h5_finish(lub_h5 *f, const char *status, char *why, size_t len)
{
    if (why && len > 0)
        why[0] = '\0';
    if (!f)
        return 0;
    int rc = 0;
    for (int i = 0; i < f->ntables; ++i) {
        rc |= table_flush(f->tables[i]);
        table_free(f->tables[i]);
    }
    for (int i = 0; i < f->nframe_sets; ++i)
        frames_free(f->frame_sets[i]);
    hid_t handles[7] = {f->p_step,  f->p_time,  f->p_pos,  f->p_vel,
                        f->p_omega, f->p_edges, f->p_image};
    for (int i = 0; i < 7; ++i)
        if (handles[i] >= 0)
            H5Dclose(handles[i]);
    if (!f->lost)
        rc |= write_string_attr(f->file, "status", status ? status : "complete");
    errno = 0;
    if (H5Fclose(f->file) < 0) {
        /* the final flush: what the system refused, where errno names an output failure */
        const int e = errno;
        rc = -1;
        if (!f->lost && lub_h5_output_failure(e))
            snprintf(f->lost_reason, sizeof f->lost_reason, "%s (closing the file)", strerror(e));
        else if (!f->lost)
            snprintf(f->lost_reason, sizeof f->lost_reason, "%s",
                     f->err[0] ? f->err : "HDF5 could not close the file");
    } else if (rc && !f->lost) {
        snprintf(f->lost_reason, sizeof f->lost_reason, "%s", f->err);
    }
    if (f->lost)
        rc = -1;
    if (rc && why && len > 0)
        snprintf(why, len, "%s", f->lost_reason);
    free(f->path);
    free(f);
    return rc ? -1 : 0;
}

int lub_h5_close(lub_h5 *f, const char *status) { return lub_h5_finish(f, status, NULL, 0); }
