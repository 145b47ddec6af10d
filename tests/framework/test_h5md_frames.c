/* test_h5md_frames.c — frame sets of result.h5 (h5md_writer.h: records whose number changes
 * from frame to frame, such as the interaction network): frames of 5, 0, 9000 (across the
 * 4096-row chunks) and 3 rows of an int64, a 3-vector of doubles and an int8 column are read
 * back bit for bit (lub_h5r_rows) with their index (step, time, row_start, row_count) and
 * units; lub_h5_continue_frames copies the first three into a new file, which then appends
 * its own, and refuses more frames than the old file holds; frames that would come within
 * LUB_H5_SNAPSHOT_RESERVE_BYTES of the file-size limit are skipped (with every later one) and
 * reported; reads of another shape, out of range or of a missing dataset fail with a message;
 * a set of no columns or of too many is refused. Usage: test_h5md_frames DIR. */
#include <hdf5.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "framework_check.h"
#include "h5md_continue.h"
#include "h5md_reader.h"
#include "h5md_writer.h"

enum { FRAMES = 4, MOST = 9000 };
static const int64_t rows_of[FRAMES] = {5, 0, MOST, 3};
static const lub_h5_column cols[3] = {
    {"index", LUB_H5_I64, 1, "1"}, {"force", LUB_H5_F64, 3, "N"}, {"flag", LUB_H5_I8, 1, "1"}};

static int64_t index_of(int frame, int64_t r) { return 1000003 * frame + 7 * r - 11; }
static double force_of(int frame, int64_t r, int c)
{
    uint64_t x = (uint64_t)(frame * 131 + c) * 0x9e3779b97f4a7c15u + (uint64_t)r * 0x94d049bbu;
    x ^= x >> 29;
    return (double)(x >> 11) * 0x1.0p-30 - 1e3;
}
static int8_t flag_of(int frame, int64_t r) { return (int8_t)((frame + r) % 3 - 1); }

static int64_t idx[MOST];
static double force[3 * MOST];
static int8_t flag[MOST];

static void fill(int frame)
{
    for (int64_t r = 0; r < rows_of[frame]; ++r) {
        idx[r] = index_of(frame, r);
        for (int c = 0; c < 3; ++c)
            force[3 * r + c] = force_of(frame, r, c);
        flag[r] = flag_of(frame, r);
    }
}

static int append(lub_h5_frames *fr, int frame)
{
    fill(frame);
    const void *const data[3] = {idx, force, flag};
    return lub_h5_frames_append(fr, 10 * frame + 1, 0.25 * frame, rows_of[frame], data);
}

/* frames [0, frames) of /net in path: index and rows as written */
static void check_file(const char *path, int frames, const int *which)
{
    char err[256];
    lub_h5_reader *r = lub_h5r_open(path, err, sizeof err);
    CHECK(r != NULL);
    if (!r)
        return;
    int64_t step[FRAMES], start[FRAMES], count[FRAMES], total = -1;
    double time[FRAMES];
    CHECK(lub_h5r_rows(r, "/net/step", LUB_H5_I64, 1, 0, frames, step, &total) == 0 &&
          total == frames);
    CHECK(lub_h5r_rows(r, "/net/time", LUB_H5_F64, 1, 0, frames, time, NULL) == 0);
    CHECK(lub_h5r_rows(r, "/net/row_start", LUB_H5_I64, 1, 0, frames, start, NULL) == 0);
    CHECK(lub_h5r_rows(r, "/net/row_count", LUB_H5_I64, 1, 0, frames, count, NULL) == 0);
    int64_t rows = 0;
    for (int k = 0; k < frames; ++k) {
        const int f = which[k];
        CHECK(step[k] == 10 * f + 1 && time[k] == 0.25 * f);
        CHECK(start[k] == rows && count[k] == rows_of[f]);
        static int64_t got_i[MOST];
        static double got_f[3 * MOST];
        static int8_t got_b[MOST];
        CHECK(lub_h5r_rows(r, "/net/index", LUB_H5_I64, 1, rows, count[k], got_i, NULL) == 0);
        CHECK(lub_h5r_rows(r, "/net/force", LUB_H5_F64, 3, rows, count[k], got_f, NULL) == 0);
        CHECK(lub_h5r_rows(r, "/net/flag", LUB_H5_I8, 1, rows, count[k], got_b, NULL) == 0);
        fill(f);
        CHECK(memcmp(got_i, idx, (size_t)count[k] * sizeof *idx) == 0);
        CHECK(memcmp(got_f, force, (size_t)count[k] * 3 * sizeof *force) == 0);
        CHECK(memcmp(got_b, flag, (size_t)count[k] * sizeof *flag) == 0);
        rows += count[k];
    }
    CHECK(lub_h5r_rows(r, "/net/index", LUB_H5_I64, 1, 0, 0, idx, &total) == 0 && total == rows);
    /* another shape, out of range, missing */
    CHECK(lub_h5r_rows(r, "/net/force", LUB_H5_F64, 1, 0, 1, force, NULL) == -1);
    CHECK(strstr(lub_h5r_error(r), "/net/force") != NULL);
    printf("wrong shape: %s\n", lub_h5r_error(r));
    CHECK(lub_h5r_rows(r, "/net/index", LUB_H5_I64, 1, rows, 1, idx, NULL) == -1);
    CHECK(lub_h5r_rows(r, "/net/index", LUB_H5_I64, 1, 2, INT64_MAX, idx, NULL) == -1);
    CHECK(lub_h5r_rows(r, "/net/index", LUB_H5_I64, 1, -1, 1, idx, NULL) == -1);
    printf("out of range: %s\n", lub_h5r_error(r));
    CHECK(lub_h5r_rows(r, "/net/nothing", LUB_H5_I64, 1, 0, 1, idx, NULL) == -1);
    CHECK(strstr(lub_h5r_error(r), "absent") != NULL);
    lub_h5r_close(r);
    /* units, as attributes of the columns and of time */
    hid_t file = H5Fopen(path, H5F_ACC_RDONLY, H5P_DEFAULT);
    const char *want[2][2] = {{"/net/force", "N"}, {"/net/time", "s"}};
    for (int k = 0; k < 2 && file >= 0; ++k) {
        char *unit = NULL;
        hid_t d = H5Dopen2(file, want[k][0], H5P_DEFAULT);
        hid_t a = d >= 0 ? H5Aopen(d, "unit", H5P_DEFAULT) : -1;
        hid_t t = a >= 0 ? H5Aget_type(a) : -1;
        CHECK(t >= 0 && H5Aread(a, t, &unit) >= 0 && unit && strcmp(unit, want[k][1]) == 0);
        if (unit)
            H5free_memory(unit);
        if (t >= 0)
            H5Tclose(t);
        if (a >= 0)
            H5Aclose(a);
        if (d >= 0)
            H5Dclose(d);
    }
    CHECK(file >= 0);
    if (file >= 0)
        H5Fclose(file);
}

int main(int argc, char **argv)
{
    if (argc != 2)
        return 2;
    char path[4096], copy[4096], err[256];
    snprintf(path, sizeof path, "%s/frames.h5", argv[1]);
    snprintf(copy, sizeof copy, "%s/frames_continued.h5", argv[1]);

    lub_h5 *f = lub_h5_create(path, err, sizeof err);
    CHECK(f != NULL);
    if (!f)
        return 1;
    lub_h5_column many[25];
    for (int c = 0; c < 25; ++c)
        many[c] = cols[0];
    CHECK(lub_h5_frames_define(f, "none", 0, cols, "s") == NULL);
    CHECK(lub_h5_frames_define(f, "many", 25, many, "s") == NULL);
    lub_h5_frames *fr = lub_h5_frames_define(f, "net", 3, cols, "s");
    CHECK(fr != NULL);
    int64_t last = 0;
    CHECK(fr && lub_h5_frames_written(fr, &last) == 0 && last == -1);
    for (int k = 0; fr && k < FRAMES; ++k)
        CHECK(append(fr, k) == 0);
    CHECK(fr && lub_h5_frames_written(fr, &last) == FRAMES && last == 31);
    CHECK(fr && lub_h5_frames_skipped(fr, NULL, NULL, 0) == 0);
    CHECK(lub_h5_close(f, "complete") == 0);
    const int all[FRAMES] = {0, 1, 2, 3};
    check_file(path, FRAMES, all);

    /* a continuation: the first three frames copied, then one of its own (frame 1 again) */
    f = lub_h5_create(copy, err, sizeof err);
    fr = f ? lub_h5_frames_define(f, "net", 3, cols, "s") : NULL;
    CHECK(fr != NULL);
    char why[512] = "";
    CHECK(fr && lub_h5_continue_frames(path, fr, 0, why, sizeof why) == 0);
    CHECK(fr && lub_h5_continue_frames(path, fr, 3, why, sizeof why) == 0);
    CHECK(fr && lub_h5_frames_written(fr, &last) == 3 && last == 21);
    CHECK(fr && append(fr, 1) == 0);
    CHECK(fr && lub_h5_continue_frames(path, fr, 5, why, sizeof why) == -1);
    CHECK(strstr(why, "5 frames of /net") != NULL);
    printf("too many frames: %s\n", why);
    CHECK(lub_h5_close(f, "complete") == 0);
    const int continued[FRAMES] = {0, 1, 2, 1};
    check_file(copy, FRAMES, continued);

    /* room for the first two frames only: the big third and the fourth are skipped */
    snprintf(path, sizeof path, "%s/frames_room.h5", argv[1]);
    f = lub_h5_create(path, err, sizeof err);
    fr = f ? lub_h5_frames_define(f, "net", 3, cols, "s") : NULL;
    CHECK(fr != NULL && lub_h5_flush(f) == 0);
    struct stat st;
    const uint64_t size = stat(path, &st) == 0 ? (uint64_t)st.st_size : 0u; /* flushed */
    CHECK(size > 0);
    if (fr) {
        lub_h5_set_byte_limit(f, size + LUB_H5_SNAPSHOT_RESERVE_BYTES + 100000u);
        for (int k = 0; k < FRAMES; ++k)
            CHECK(append(fr, k) == 0);
        int64_t first = -1;
        char reason[256];
        CHECK(lub_h5_frames_skipped(fr, &first, reason, sizeof reason) == 2 && first == 21);
        CHECK(strstr(reason, "a frame of /net") != NULL && strstr(reason, "RLIMIT_FSIZE"));
        CHECK(lub_h5_frames_written(fr, &last) == 2 && last == 11);
        printf("room: %s\n", reason);
    }
    CHECK(f && lub_h5_close(f, "complete") == 0);
    return failures ? 1 : 0;
}
