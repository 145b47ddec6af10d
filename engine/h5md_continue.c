/* h5md_continue.c — a stopped run's time series and snapshots into its continuation's file
 * (see h5md_continue.h). */
#include "h5md_continue.h"

#include <stdio.h>
#include <stdlib.h>

int lub_h5_continue_table(lub_h5_reader *from, lub_h5_table *to, int nseries,
                          const char *const *names, const int *ncomp, int64_t rows, char *err,
                          size_t len)
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
    int rc = 0;
    if (!pos || !vel || !omega) {
        snprintf(err, len, "out of memory (snapshots of the stopped run)");
        rc = -1;
    }
    for (int64_t k = 0; k < frames && rc == 0; ++k) {
        int64_t step = 0;
        double time = 0.0, edges[9];
        if (lub_h5r_frame_read(from, k, &step, &time, edges, pos, vel, omega)) {
            snprintf(err, len, "cannot read snapshot %lld: %s", (long long)k, lub_h5r_error(from));
            rc = -1;
        } else if (lub_h5_particles_snapshot(to, step, time, edges, pos, vel, omega)) {
            snprintf(err, len, "cannot copy snapshot %lld: %s", (long long)k,
                     lub_h5_last_error(to));
            rc = -1;
        }
    }
    free(pos);
    free(vel);
    free(omega);
    return rc;
}

int lub_h5_continue_output(const char *path, lub_h5_table *to_table, int nseries,
                           const char *const *names, const int *ncomp, int64_t rows, lub_h5 *to,
                           int64_t n, int64_t frames, char *err, size_t len)
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
        rc = lub_h5_continue_table(from, to_table, nseries, names, ncomp, rows, err, len);
    if (rc == 0)
        rc = lub_h5_continue_snapshots(from, to, n, frames, err, len);
    lub_h5r_close(from);
    return rc;
}
