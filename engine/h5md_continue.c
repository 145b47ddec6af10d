/* h5md_continue.c — a stopped run's time series, snapshots and frame sets into its continuation's
 * file (see h5md_continue.h). */
#include "h5md_continue.h"

#include <stdio.h>
#include <stdlib.h>

int lub_h5_continue_table(lub_h5_reader *from, lub_h5_table *to, int nseries,
                          const char *const *names, const int *ncomp, int64_t rows,
                          const double *expect_first, char *err, size_t len)
{
    int width = 0;
    for (int s = 0; s < nseries; ++s)
        width += ncomp[s];
    const int64_t chunk = LUB_H5_CONTINUE_ROWS;
    double *values = malloc((size_t)chunk * (size_t)width * sizeof *values);
    double *row = malloc((size_t)width * sizeof *row);
    double *time = malloc((size_t)chunk * sizeof *time);
    int64_t *step = malloc((size_t)chunk * sizeof *step);
    int rc = 0;
    if (!values || !row || !time || !step) {
        snprintf(err, len, "out of memory (time series of the stopped run)");
        rc = -1;
    }
    for (int64_t row0 = 0; row0 < rows && rc == 0; row0 += chunk) {
        const int64_t count = rows - row0 < chunk ? rows - row0 : chunk;
        /* series s occupies values[offset * count ...] for this chunk */
        size_t offset = 0;
        for (int s = 0; s < nseries && rc == 0; ++s) {
            if (lub_h5r_series_read(from, names[s], ncomp[s], row0, count,
                                    values + offset * (size_t)count, s == 0 ? step : NULL,
                                    s == 0 ? time : NULL)) {
                snprintf(err, len, "cannot read rows %lld to %lld of %s: %s", (long long)row0,
                         (long long)(row0 + count - 1), names[s], lub_h5r_error(from));
                rc = -1;
            }
            offset += (size_t)ncomp[s];
        }
        /* values[0, count) is the first series of this chunk */
        for (int64_t k = 0; k < count && rc == 0 && expect_first && ncomp[0] == 1; ++k)
            if (values[k] != expect_first[row0 + k]) {
                snprintf(err, len,
                         "row %lld of %s is %.17g in the file and %.17g in the checkpoint: it is "
                         "not the file the checkpoint was taken with",
                         (long long)(row0 + k), names[0], values[k], expect_first[row0 + k]);
                rc = -1;
            }
        for (int64_t k = 0; k < count && rc == 0; ++k) {
            size_t col = 0, base = 0;
            for (int s = 0; s < nseries; ++s) {
                const double *src = values + base * (size_t)count + (size_t)k * (size_t)ncomp[s];
                for (int c = 0; c < ncomp[s]; ++c)
                    row[col++] = src[c];
                base += (size_t)ncomp[s];
            }
            if (lub_h5_table_append(to, step[k], time[k], row)) {
                snprintf(err, len, "cannot copy row %lld of the time series",
                         (long long)(row0 + k));
                rc = -1;
            }
        }
    }
    free(values);
    free(row);
    free(time);
    free(step);
    return rc;
}

int lub_h5_continue_snapshots(lub_h5_reader *from, lub_h5 *to, int64_t n, int64_t frames, char *err,
                              size_t len)
{
    if (frames <= 0)
        return 0;
    int64_t have = 0, n_file = 0;
    if (lub_h5r_frames(from, &have, &n_file) || n_file != n || have < frames) {
        snprintf(err, len,
                 "the stopped run's file holds %lld snapshots of %lld particles, not %lld of %lld",
                 (long long)have, (long long)n_file, (long long)frames, (long long)n);
        return -1;
    }
    double *pos = malloc((size_t)n * 3 * sizeof *pos);
    double *vel = malloc((size_t)n * 3 * sizeof *vel);
    double *omega = malloc((size_t)n * 3 * sizeof *omega);
    /* the images, where the new file has them (the scene defines them only when the stopped
     * run's file has them too) */
    const int with_image = lub_h5_particles_has_image(to);
    int32_t *image = with_image ? malloc((size_t)n * 3 * sizeof *image) : NULL;
    int rc = 0;
    if (!pos || !vel || !omega || (with_image && !image)) {
        snprintf(err, len, "out of memory (snapshots of the stopped run)");
        rc = -1;
    }
    for (int64_t k = 0; k < frames && rc == 0; ++k) {
        int64_t step = 0;
        double time = 0.0, edges[9];
        const int irc = with_image ? lub_h5r_frame_image(from, k, image) : 0;
        if (lub_h5r_frame_read(from, k, &step, &time, edges, pos, vel, omega) || irc < 0) {
            snprintf(err, len, "cannot read snapshot %lld: %s", (long long)k, lub_h5r_error(from));
            rc = -1;
        } else if (irc > 0) {
            snprintf(err, len, "the stopped run's snapshots have no images");
            rc = -1;
        } else if (lub_h5_particles_snapshot(to, step, time, edges, pos, vel, omega, image)) {
            snprintf(err, len, "cannot copy snapshot %lld: %s", (long long)k,
                     lub_h5_last_error(to));
            rc = -1;
        }
    }
    free(pos);
    free(vel);
    free(omega);
    free(image);
    return rc;
}

int lub_h5_continue_output(const char *path, lub_h5_table *to_table, int nseries,
                           const char *const *names, const int *ncomp, int64_t rows,
                           const double *expect_first, lub_h5 *to, int64_t n, int64_t frames,
                           char *err, size_t len)
{
    lub_h5_reader *from = lub_h5r_open(path, err, len);
    if (!from)
        return -1;
    int64_t have = 0;
    int rc = 0;
    if (lub_h5r_series_rows(from, names[0], &have) || have < rows) {
        snprintf(err, len, "%s holds %lld rows of the time series, the checkpoint needs %lld", path,
                 (long long)have, (long long)rows);
        rc = -1;
    }
    if (rc == 0)
        rc = lub_h5_continue_table(from, to_table, nseries, names, ncomp, rows, expect_first, err,
                                   len);
    if (rc == 0)
        rc = lub_h5_continue_snapshots(from, to, n, frames, err, len);
    lub_h5r_close(from);
    return rc;
}

/* The frame index (step, time, row_start, row_count of frames [0, frames)) of group into the
 * arrays; 0, or -1 with err[len]. */
static int read_frame_index(lub_h5_reader *from, const char *group, int64_t frames, int64_t *step,
                            double *time, int64_t *start, int64_t *count, char *err, size_t len)
{
    const char *names[4] = {"step", "time", "row_start", "row_count"};
    void *outs[4] = {step, time, start, count};
    for (int k = 0; k < 4; ++k) {
        char path[160];
        snprintf(path, sizeof path, "/%s/%s", group, names[k]);
        if (lub_h5r_rows(from, path, k == 1 ? LUB_H5_F64 : LUB_H5_I64, 1, 0, frames, outs[k],
                         NULL)) {
            snprintf(err, len, "the stopped run's file does not hold %lld frames of /%s: %s",
                     (long long)frames, group, lub_h5r_error(from));
            return -1;
        }
    }
    for (int64_t k = 0, rows = 0; k < frames; rows += count[k], ++k)
        if (start[k] != rows || count[k] < 0) {
            snprintf(err, len,
                     "frame %lld of /%s in the stopped run's file: rows from %lld, "
                     "%lld of them (expected from %lld)",
                     (long long)k, group, (long long)start[k], (long long)count[k],
                     (long long)rows);
            return -1;
        }
    return 0;
}

int lub_h5_continue_frames(const char *path, lub_h5_frames *to, int64_t frames, char *err,
                           size_t len)
{
    if (frames <= 0)
        return 0;
    const char *group = NULL;
    lub_h5_column cols[LUB_H5_FRAME_COLUMNS_MAX];
    const int ncol = lub_h5_frames_layout(to, &group, cols);
    lub_h5_reader *from = lub_h5r_open(path, err, len);
    if (!from)
        return -1;
    int64_t *step = malloc((size_t)frames * sizeof *step);
    double *time = malloc((size_t)frames * sizeof *time);
    int64_t *start = malloc((size_t)frames * sizeof *start);
    int64_t *count = malloc((size_t)frames * sizeof *count);
    void **columns = calloc((size_t)ncol, sizeof *columns);
    int rc = 0;
    if (!step || !time || !start || !count || !columns) {
        snprintf(err, len, "out of memory (frames of /%s of the stopped run)", group);
        rc = -1;
    }
    if (rc == 0)
        rc = read_frame_index(from, group, frames, step, time, start, count, err, len);
    int64_t largest = 0;
    for (int64_t k = 0; k < frames && rc == 0; ++k)
        largest = count[k] > largest ? count[k] : largest;
    for (int c = 0; c < ncol && rc == 0; ++c) {
        const size_t bytes = cols[c].type == LUB_H5_I8 ? 1u : 8u;
        columns[c] = malloc((size_t)(largest > 0 ? largest : 1) * (size_t)cols[c].ncomp * bytes);
        if (!columns[c]) {
            snprintf(err, len, "out of memory (frames of /%s of the stopped run)", group);
            rc = -1;
        }
    }
    for (int64_t k = 0; k < frames && rc == 0; ++k) {
        for (int c = 0; c < ncol && rc == 0; ++c) {
            char col_path[160];
            snprintf(col_path, sizeof col_path, "/%s/%s", group, cols[c].name);
            if (lub_h5r_rows(from, col_path, (int)cols[c].type, cols[c].ncomp, start[k], count[k],
                             columns[c], NULL)) {
                snprintf(err, len, "cannot read frame %lld of /%s: %s", (long long)k, group,
                         lub_h5r_error(from));
                rc = -1;
            }
        }
        if (rc == 0 &&
            lub_h5_frames_append(to, step[k], time[k], count[k], (const void *const *)columns)) {
            snprintf(err, len, "cannot copy frame %lld of /%s", (long long)k, group);
            rc = -1;
        }
    }
    for (int c = 0; c < ncol && columns; ++c)
        free(columns[c]);
    free(columns);
    free(step);
    free(time);
    free(start);
    free(count);
    lub_h5r_close(from);
    return rc;
}
