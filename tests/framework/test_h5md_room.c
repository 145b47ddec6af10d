/* test_h5md_room.c — particle snapshots that would come within LUB_H5_SNAPSHOT_RESERVE_BYTES of
 * the file-size limit are skipped, as is every later one, and reported (count, first step,
 * reason); the file stays valid and the time series go on. A limit below the reserve skips
 * the very first snapshot. A time series the system refuses to take (here: beyond
 * RLIMIT_FSIZE, EFBIG) gives the file up in the middle of the run: every write returns 0 from
 * then on, lub_h5_output_lost says why and from which step, and closing reports the failure.
 * Usage: test_h5md_room DIR (scratch files are written there). */
#include <errno.h>
#include <hdf5.h>
#include <signal.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>

#include "framework_check.h"
#include "h5md_writer.h"

enum { N = 1000, FRAMES = 10 };
/* position + velocity + angular velocity of N particles, step, time and the 3x3 box */
#define FRAME_BYTES ((uint64_t)N * 3u * 8u * 3u + 2u * 8u + 9u * 8u)

static double pos[N * 3], vel[N * 3], omega[N * 3], radius[N];

static hsize_t frames_in(const char *path)
{
    hid_t file = H5Fopen(path, H5F_ACC_RDONLY, H5P_DEFAULT);
    hid_t ds = file >= 0 ? H5Dopen2(file, "particles/all/position/value", H5P_DEFAULT) : -1;
    hsize_t dims[3] = {0, 0, 0};
    if (ds >= 0) {
        hid_t sp = H5Dget_space(ds);
        H5Sget_simple_extent_dims(sp, dims, NULL);
        H5Sclose(sp);
        H5Dclose(ds);
    }
    if (file >= 0)
        H5Fclose(file);
    return dims[0];
}

/* writes FRAMES snapshots (and one series row each) under a limit of room_frames frames above
 * the file's size after the particle group is defined plus the reserve; returns the skip
 * count */
static int64_t run(const char *path, double room_frames, int64_t *first_step, char *why, size_t len)
{
    char err[256];
    lub_h5 *f = lub_h5_create(path, err, sizeof err);
    CHECK(f != NULL);
    if (!f)
        return -1;
    const char *names[1] = {"strain"};
    const int ncomp[1] = {1};
    const char *units[1] = {"1"};
    lub_h5_table *t = lub_h5_table_create(f, 1, names, ncomp, units);
    const char *boundary[3] = {"periodic", "periodic", "periodic"};
    CHECK(t != NULL && lub_h5_particles_define(f, N, radius, boundary) == 0);
    CHECK(lub_h5_flush(f) == 0);
    /* the size after define (flushed): the limit is relative to it */
    FILE *fp = fopen(path, "rb");
    long base = 0;
    if (fp) {
        fseek(fp, 0, SEEK_END);
        base = ftell(fp);
        fclose(fp);
    }
    const double limit =
        (double)base + (double)LUB_H5_SNAPSHOT_RESERVE_BYTES + room_frames * (double)FRAME_BYTES;
    lub_h5_set_byte_limit(f, limit > 0.0 ? (uint64_t)limit : 0u);
    for (int k = 0; k < FRAMES; ++k) {
        const double box[9] = {10, 0, 0, 0, 10, 0, 0, 0, 10};
        const double row[1] = {0.1 * k};
        /* every snapshot returns 0, written or skipped */
        CHECK(lub_h5_particles_snapshot(f, 7 * k, 0.7 * k, box, pos, vel, omega, NULL) == 0);
        CHECK(lub_h5_table_append(t, 7 * k, 0.7 * k, row) == 0);
        /* no flush here: the room check must see the chunks HDF5 still caches (it did not
         * until 2026-12-06, and this loop flushed after every snapshot) */
    }
    int64_t skipped = lub_h5_snapshots_skipped(f, first_step, why, len);
    CHECK(lub_h5_close(f, "complete") == 0);
    return skipped;
}

/* A 1 MiB file-size limit (the last test: it stays for the process) under a time series of
 * incompressible 3x3 tensors, 72 kB per 1024 rows: HDF5's chunk cache (1 MiB per dataset)
 * takes the first rows, the later ones reach the file and the limit. */
static void lost_output(const char *dir)
{
    char path[4096], why[400], err[256];
    snprintf(path, sizeof path, "%s/room_lost.h5", dir);
    signal(SIGXFSZ, SIG_IGN); /* EFBIG instead of the signal, as lubdem does */
    struct rlimit lim = {1u << 20, 1u << 20};
    getrlimit(RLIMIT_FSIZE, &lim);
    lim.rlim_cur = 1u << 20;
    CHECK(setrlimit(RLIMIT_FSIZE, &lim) == 0);
    lub_h5 *f = lub_h5_create(path, err, sizeof err);
    CHECK(f != NULL);
    if (!f)
        return;
    const char *names[1] = {"stress"};
    const int ncomp[1] = {9};
    const char *units[1] = {"1"};
    lub_h5_table *t = lub_h5_table_create(f, 1, names, ncomp, units);
    CHECK(t != NULL);
    uint64_t state = 12345u;
    int64_t lost_at = -1;
    enum { ROWS = 200000 };
    for (int64_t step = 0; t && step < ROWS; ++step) {
        double row[9];
        for (int k = 0; k < 9; ++k) { /* xorshift: deflate cannot shrink it */
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            row[k] = (double)(state >> 11) * 0x1.0p-53;
        }
        CHECK(lub_h5_table_append(t, step, 0.001 * (double)step, row) == 0);
        if (lost_at < 0 && lub_h5_output_lost(f, NULL, 0))
            lost_at = step;
    }
    /* given up in the middle (14 MB of rows against 1 MiB), not only at the close */
    CHECK(lost_at > 0 && lost_at < ROWS / 2);
    CHECK(lub_h5_output_lost(f, why, sizeof why) == 1);
    CHECK(strstr(why, strerror(EFBIG)) != NULL && strstr(why, "time series from step") != NULL);
    printf("lost_at_step=%lld reason=%s\n", (long long)lost_at, why);
    /* every later write is skipped and returns 0 */
    const double box[9] = {10, 0, 0, 0, 10, 0, 0, 0, 10};
    const char *boundary[3] = {"periodic", "periodic", "periodic"};
    const int64_t dims[1] = {3};
    CHECK(lub_h5_particles_define(f, N, radius, boundary) == 0);
    CHECK(lub_h5_particles_snapshot(f, 1, 0.1, box, pos, vel, omega, NULL) == 0);
    CHECK(lub_h5_write_array(f, "profile", 1, dims, box, "1") == 0);
    CHECK(lub_h5_write_parameters(f, "{}", "{}", "{}") == 0);
    CHECK(lub_h5_flush(f) == 0);
    char closed[400];
    CHECK(lub_h5_finish(f, "complete", closed, sizeof closed) == -1);
    CHECK(strcmp(closed, why) == 0);
}

int main(int argc, char **argv)
{
    if (argc != 2)
        return 2;
    for (int i = 0; i < N * 3; ++i)
        pos[i] = vel[i] = omega[i] = 0.001 * i;
    for (int i = 0; i < N; ++i)
        radius[i] = 1.0;
    char path[4096], why[256];
    int64_t first = -1;

    /* room for 4.5 frames: frames 0-3 are written, 4-9 skipped (from step 28) */
    snprintf(path, sizeof path, "%s/room_limited.h5", argv[1]);
    int64_t skipped = run(path, 4.5, &first, why, sizeof why);
    CHECK(skipped == FRAMES - 4);
    CHECK(first == 28);
    CHECK(strstr(why, "RLIMIT_FSIZE") != NULL);
    CHECK(frames_in(path) == 4);
    printf("room_limited_frames=%llu skipped=%lld reason=%s\n", (unsigned long long)frames_in(path),
           (long long)skipped, why);

    /* a limit below the reserve: not even the first snapshot */
    snprintf(path, sizeof path, "%s/room_none.h5", argv[1]);
    skipped = run(path, -1e6, &first, why, sizeof why);
    CHECK(skipped == FRAMES && first == 0 && frames_in(path) == 0);

    /* no limit (beyond this process's): all written, nothing reported */
    snprintf(path, sizeof path, "%s/room_free.h5", argv[1]);
    skipped = run(path, 1e6, &first, why, sizeof why);
    CHECK(skipped == 0 && why[0] == '\0' && frames_in(path) == FRAMES);

    lost_output(argv[1]);
    return failures ? 1 : 0;
}
