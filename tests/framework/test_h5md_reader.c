/* test_h5md_reader.c — what h5md_writer.c wrote, h5md_reader.c reads back bit for bit: a table
 * of a scalar, a vector and a tensor series (2500 rows: two full row buffers of 1024 and the
 * rest flushed by the close) read in chunks that cross the buffers' boundaries, and particle
 * snapshots (step, time, box, positions, velocities, angular velocities). Reads out of range,
 * of another ncomp, of a missing series, and of angular velocities a file does not hold fail
 * with a message. Usage: test_h5md_reader DIR (scratch files are written there). */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "framework_check.h"
#include "h5md_reader.h"
#include "h5md_writer.h"

enum { ROWS = 2500, N = 37, FRAMES = 3, ROW_LEN = 1 + 3 + 9 };

static const char *const names[3] = {"strain", "group/velocity_mean", "group/deep/stress"};
static const int ncomp[3] = {1, 3, 9};
static const int offset[3] = {0, 1, 4};

static int64_t step_of(int64_t r) { return 5 * r + 3; }
static double time_of(int64_t r) { return 0.001 * (double)r + 1e-17 * (double)(r % 7); }
/* component c of row r: irregular bit patterns, with -0.0 and a NaN here and there */
static double value_of(int64_t r, int c)
{
    if (r % 97 == 5 && c == 0)
        return -0.0;
    uint64_t x = (uint64_t)r * 0x9e3779b97f4a7c15u + (uint64_t)c * 0xbf58476d1ce4e5b9u;
    x ^= x >> 31;
    x *= 0x94d049bb133111ebu;
    x ^= x >> 29;
    double v = (double)(x >> 11) * 0x1.0p-40 - 4096.0;
    if (r % 211 == 17 && c == 1)
        memcpy(&v, &(uint64_t){0x7ff8000000012345u}, sizeof v);
    return v;
}
static double particle_of(int frame, int field, int i, int c)
{
    return (double)(frame + 1) * 1.25 + (double)field * 1000.0 + (double)i * 0.1 + c * 1e-9;
}

static int write_file(const char *path, int with_omega, int with_particles)
{
    char err[256];
    lub_h5 *f = lub_h5_create(path, err, sizeof err);
    CHECK(f != NULL);
    if (!f) {
        fprintf(stderr, "%s\n", err);
        return -1;
    }
    const char *units[3] = {"1", "m/s", "Pa"};
    lub_h5_table *t = lub_h5_table_create(f, 3, names, ncomp, units);
    CHECK(t != NULL);
    for (int64_t r = 0; t && r < ROWS; ++r) {
        double row[ROW_LEN];
        for (int c = 0; c < ROW_LEN; ++c)
            row[c] = value_of(r, c);
        CHECK(lub_h5_table_append(t, step_of(r), time_of(r), row) == 0);
    }
    if (with_particles) {
        double radius[N];
        for (int i = 0; i < N; ++i)
            radius[i] = 0.5 + 0.01 * i;
        const char *boundary[3] = {"periodic", "periodic", "none"};
        CHECK(lub_h5_particles_define(f, N, radius, boundary) == 0);
        /* images with the angular velocities (the file without them has none either) */
        if (with_omega)
            CHECK(lub_h5_particles_define_image(f) == 0 && lub_h5_particles_has_image(f));
        static double fields[3][N * 3];
        static int32_t image[N * 3];
        for (int k = 0; k < FRAMES; ++k) {
            for (int field = 0; field < 3; ++field)
                for (int i = 0; i < N; ++i)
                    for (int c = 0; c < 3; ++c)
                        fields[field][3 * i + c] = particle_of(k, field, i, c);
            for (int j = 0; j < N * 3; ++j)
                image[j] = 100 * k + j - 50;
            const double box[9] = {10 + k, 0, 0, 0.5 * k, 11, 0, 0, 0, 12};
            /* the last frame of an unbounded scene: no edges (zeros) */
            CHECK(lub_h5_particles_snapshot(f, 100 * k, 0.5 * k, k == 2 ? NULL : box, fields[0],
                                            fields[1], with_omega ? fields[2] : NULL,
                                            with_omega ? image : NULL) == 0);
        }
        if (with_omega) { /* refused: rows that would not line up with the positions' */
            CHECK(lub_h5_particles_define_image(f) == -1);
            CHECK(lub_h5_particles_snapshot(f, 900, 9.0, NULL, fields[0], fields[1], fields[2],
                                            NULL) == -1);
        }
    }
    CHECK(lub_h5_close(f, "complete") == 0);
    return 0;
}

/* rows [row0, row0 + count) of series s compared with what was written */
static void check_chunk(lub_h5_reader *r, int s, int64_t row0, int64_t count)
{
    double *v = malloc(sizeof(double) * (size_t)(count * ncomp[s]) + 1);
    int64_t *st = malloc(sizeof(int64_t) * (size_t)count + 1);
    double *tm = malloc(sizeof(double) * (size_t)count + 1);
    CHECK(v && st && tm);
    if (v && st && tm) {
        CHECK(lub_h5r_series_read(r, names[s], ncomp[s], row0, count, v, st, tm) == 0);
        int bad = 0;
        for (int64_t k = 0; k < count; ++k) {
            const int64_t row = row0 + k;
            const double t = time_of(row);
            bad += st[k] != step_of(row) || memcmp(&tm[k], &t, sizeof t) != 0;
            for (int c = 0; c < ncomp[s]; ++c) {
                const double x = value_of(row, offset[s] + c);
                bad += memcmp(&v[k * ncomp[s] + c], &x, sizeof x) != 0;
            }
        }
        CHECK(bad == 0);
        if (bad)
            fprintf(stderr, "series %s rows %lld+%lld: %d differ\n", names[s], (long long)row0,
                    (long long)count, bad);
        /* value only, step and time only */
        CHECK(lub_h5r_series_read(r, names[s], ncomp[s], row0, count, v, NULL, NULL) == 0);
        CHECK(lub_h5r_series_read(r, names[s], ncomp[s], row0, count, NULL, st, tm) == 0);
    }
    free(v);
    free(st);
    free(tm);
}

static void check_series(const char *path)
{
    char err[256];
    lub_h5_reader *r = lub_h5r_open(path, err, sizeof err);
    CHECK(r != NULL);
    if (!r) {
        fprintf(stderr, "%s\n", err);
        return;
    }
    for (int s = 0; s < 3; ++s) {
        int64_t rows = -1;
        CHECK(lub_h5r_series_rows(r, names[s], &rows) == 0 && rows == ROWS);
        /* chunks of 700: 0-699, 700-1399 (crosses 1024), ..., 2100-2499 (the close's flush) */
        for (int64_t row0 = 0; row0 < ROWS; row0 += 700)
            check_chunk(r, s, row0, row0 + 700 <= ROWS ? 700 : ROWS - row0);
        check_chunk(r, s, 1000, 1100); /* across both boundaries, 1024 and 2048 */
        check_chunk(r, s, 2047, 2);
        check_chunk(r, s, ROWS - 1, 1);
        check_chunk(r, s, 0, ROWS);
    }
    /* alternating between series (the reader keeps the last one open) */
    check_chunk(r, 2, 1020, 10);
    check_chunk(r, 0, 1020, 10);
    check_chunk(r, 2, 1030, 10);

    double buf[9 * 4];
    int64_t st[4];
    CHECK(lub_h5r_series_read(r, names[0], 1, ROWS, 0, buf, st, NULL) == 0); /* empty, at end */
    CHECK(lub_h5r_series_read(r, names[0], 1, ROWS - 3, 4, buf, st, NULL) == -1);
    CHECK(strstr(lub_h5r_error(r), "out of range") && strstr(lub_h5r_error(r), "strain"));
    printf("out of range: %s\n", lub_h5r_error(r));
    CHECK(lub_h5r_series_read(r, names[1], 3, ROWS, 1, buf, NULL, NULL) == -1);
    CHECK(lub_h5r_series_read(r, names[1], 3, -1, 2, buf, NULL, NULL) == -1);
    CHECK(lub_h5r_series_read(r, names[1], 3, 0, -1, buf, NULL, NULL) == -1);
    CHECK(lub_h5r_series_read(r, names[1], 3, INT64_MAX, 2, buf, NULL, NULL) == -1);
    CHECK(lub_h5r_series_read(r, names[1], 3, 2, INT64_MAX, buf, NULL, NULL) == -1);
    CHECK(lub_h5r_series_read(r, names[1], 9, 0, 1, buf, NULL, NULL) == -1);
    CHECK(strstr(lub_h5r_error(r), "group/velocity_mean") && strstr(lub_h5r_error(r), "ncomp 9"));
    printf("wrong ncomp: %s\n", lub_h5r_error(r));
    CHECK(lub_h5r_series_read(r, names[2], 3, 0, 1, buf, NULL, NULL) == -1);
    CHECK(lub_h5r_series_read(r, names[0], 9, 0, 1, buf, NULL, NULL) == -1);
    CHECK(lub_h5r_series_read(r, names[0], 2, 0, 1, buf, NULL, NULL) == -1);
    int64_t rows = 7;
    CHECK(lub_h5r_series_rows(r, "no_such_series", &rows) == -1 && rows == 7);
    CHECK(strstr(lub_h5r_error(r), "no_such_series") != NULL);
    printf("missing series: %s\n", lub_h5r_error(r));
    CHECK(lub_h5r_series_read(r, "group", 1, 0, 1, buf, NULL, NULL) == -1); /* a group */
    /* after errors, reads still work */
    check_chunk(r, 1, 2040, 20);
    lub_h5r_close(r);
}

static void check_particles(const char *path, int with_omega)
{
    char err[256];
    lub_h5_reader *r = lub_h5r_open(path, err, sizeof err);
    CHECK(r != NULL);
    if (!r)
        return;
    int64_t frames = -1, n = -1;
    CHECK(lub_h5r_frames(r, &frames, &n) == 0 && frames == FRAMES && n == N);
    double pos[N * 3], vel[N * 3], omega[N * 3], edges[9], time;
    int64_t step;
    for (int k = 0; k < FRAMES; ++k) {
        memset(omega, 0, sizeof omega);
        CHECK(lub_h5r_frame_read(r, k, &step, &time, edges, pos, vel, with_omega ? omega : NULL) ==
              0);
        CHECK(step == 100 * k && time == 0.5 * k);
        const double box[9] = {10 + k, 0, 0, 0.5 * k, 11, 0, 0, 0, 12};
        const double zeros[9] = {0};
        CHECK(memcmp(edges, k == 2 ? zeros : box, sizeof edges) == 0);
        int bad = 0;
        for (int i = 0; i < N; ++i)
            for (int c = 0; c < 3; ++c) {
                bad += pos[3 * i + c] != particle_of(k, 0, i, c);
                bad += vel[3 * i + c] != particle_of(k, 1, i, c);
                bad += with_omega && omega[3 * i + c] != particle_of(k, 2, i, c);
            }
        CHECK(bad == 0);
        /* the images, where written: as written; else "none" (1), image untouched */
        int32_t image[N * 3];
        memset(image, 0x7f, sizeof image);
        const int irc = lub_h5r_frame_image(r, k, image);
        int ibad = 0;
        for (int j = 0; j < N * 3; ++j)
            ibad += image[j] != (with_omega ? 100 * k + j - 50 : 0x7f7f7f7f);
        CHECK(irc == (with_omega ? 0 : 1) && ibad == 0);
        /* only some of the outputs */
        CHECK(lub_h5r_frame_read(r, k, NULL, NULL, NULL, pos, NULL, NULL) == 0);
        CHECK(lub_h5r_frame_read(r, k, &step, NULL, NULL, NULL, NULL, NULL) == 0 &&
              step == 100 * k);
    }
    CHECK(lub_h5r_frame_read(r, FRAMES, &step, &time, edges, pos, vel, NULL) == -1);
    CHECK(strstr(lub_h5r_error(r), "out of range") != NULL);
    printf("frame out of range: %s\n", lub_h5r_error(r));
    CHECK(lub_h5r_frame_read(r, -1, &step, &time, edges, pos, vel, NULL) == -1);
    int32_t image[N * 3];
    CHECK(lub_h5r_frame_image(r, FRAMES, image) == -1);
    if (!with_omega) {
        CHECK(lub_h5r_frame_read(r, 0, &step, &time, edges, pos, vel, omega) == -1);
        CHECK(strstr(lub_h5r_error(r), "angular velocities") != NULL);
        printf("no omega: %s\n", lub_h5r_error(r));
    }
    lub_h5r_close(r);
}

int main(int argc, char **argv)
{
    if (argc != 2)
        return 2;
    char path[4096], err[256];
    snprintf(path, sizeof path, "%s/reader_full.h5", argv[1]);
    if (write_file(path, 1, 1) == 0) {
        check_series(path);
        check_particles(path, 1);
    }
    snprintf(path, sizeof path, "%s/reader_no_omega.h5", argv[1]);
    if (write_file(path, 0, 1) == 0)
        check_particles(path, 0);

    snprintf(path, sizeof path, "%s/reader_no_particles.h5", argv[1]);
    if (write_file(path, 0, 0) == 0) {
        lub_h5_reader *r = lub_h5r_open(path, err, sizeof err);
        CHECK(r != NULL);
        int64_t frames = 7;
        CHECK(r && lub_h5r_frames(r, &frames, NULL) == -1 && frames == 7);
        CHECK(r && strstr(lub_h5r_error(r), "/particles/all") != NULL);
        CHECK(r && lub_h5r_frame_read(r, 0, NULL, NULL, NULL, NULL, NULL, NULL) == -1);
        if (r)
            printf("no particles: %s\n", lub_h5r_error(r));
        if (r)
            check_chunk(r, 0, 0, ROWS);
        lub_h5r_close(r);
    }

    snprintf(path, sizeof path, "%s/reader_missing.h5", argv[1]);
    remove(path);
    CHECK(lub_h5r_open(path, err, sizeof err) == NULL && strstr(err, path) != NULL);
    printf("missing file: %s\n", err);
    snprintf(path, sizeof path, "%s/reader_text.h5", argv[1]);
    FILE *fp = fopen(path, "w");
    if (fp) {
        fputs("not hdf5\n", fp);
        fclose(fp);
    }
    CHECK(lub_h5r_open(path, err, sizeof err) == NULL && strstr(err, "not an HDF5 file"));
    printf("not HDF5: %s\n", err);
    return failures ? 1 : 0;
}
