/* test_file_copy.c — lub_file_copy (engine/file_copy.h): both ways of copying give the source
 * byte for byte (a file larger than one copy_file_range call's buffer is not needed: sizes
 * that are not multiples of the 64 KiB buffer, a hole, an empty file, a longer file
 * replaced), each failure comes back as -1 with the errno of its cause, and each copy says
 * which way it went: the buffer when asked for, the kernel otherwise unless the kernel itself
 * refuses these two files (probed here with one copy_file_range call). Argument: a scratch
 * folder. */
#define _GNU_SOURCE /* copy_file_range */
#include <errno.h>
#include <fcntl.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "file_copy.h"
#include "framework_check.h"

/* writes n pseudo-random bytes (seeded), with a hole of `hole` bytes after the first half */
static int write_sample(const char *path, size_t n, unsigned seed, long hole)
{
    FILE *f = fopen(path, "wb");
    if (!f)
        return -1;
    unsigned x = seed;
    for (size_t i = 0; i < n; i++) {
        if (i == n / 2 && hole > 0 && fseek(f, hole, SEEK_CUR) != 0)
            break;
        x = x * 1103515245u + 12345u;
        fputc((int)(x >> 16) & 0xff, f);
    }
    return fclose(f) == 0 ? 0 : -1;
}

/* 1 when the two files have the same bytes */
static int same_bytes(const char *a, const char *b)
{
    FILE *fa = fopen(a, "rb"), *fb = fopen(b, "rb");
    int same = fa && fb;
    while (same) {
        const int ca = fgetc(fa), cb = fgetc(fb);
        same = ca == cb;
        if (ca == EOF || cb == EOF)
            break;
    }
    if (fa)
        fclose(fa);
    if (fb)
        fclose(fb);
    return same;
}

/* 1 when the kernel copies one byte of the non-empty src into dst with copy_file_range, 0 when
 * it refuses (the errors lub_file_copy falls back on, or 0 bytes), -1 on another error */
static int kernel_copies(const char *src, const char *dst)
{
    const int in = open(src, O_RDONLY | O_CLOEXEC);
    const int out = open(dst, O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
    int ok = -1;
    if (in >= 0 && out >= 0) {
        const ssize_t n = copy_file_range(in, NULL, out, NULL, 1, 0);
        if (n == 1)
            ok = 1;
        else if (n == 0 || errno == ENOSYS || errno == EXDEV || errno == EINVAL ||
                 errno == EOPNOTSUPP || errno == EBADF)
            ok = 0;
    }
    if (in >= 0)
        close(in);
    if (out >= 0)
        close(out);
    return ok;
}

static long file_size(const char *path)
{
    struct stat st;
    return stat(path, &st) == 0 ? (long)st.st_size : -1;
}

int main(int argc, char **argv)
{
    if (argc != 2) {
        fprintf(stderr, "usage: %s SCRATCH_DIR\n", argv[0]);
        return 2;
    }
    char src[4096], dst[4096], big[4096], missing[4096];
    snprintf(src, sizeof src, "%s/copy_src.bin", argv[1]);
    snprintf(dst, sizeof dst, "%s/copy_dst.bin", argv[1]);
    snprintf(big, sizeof big, "%s/copy_big.bin", argv[1]);
    snprintf(missing, sizeof missing, "%s/no_such_folder/copy.bin", argv[1]);
    const lub_copy_how hows[2] = {LUB_COPY_IN_KERNEL, LUB_COPY_BUFFERED};
    const size_t sizes[4] = {0, 1, 65536 * 3 + 17, 5 * 1048576 + 4099};
    for (int h = 0; h < 2; h++) {
        for (int k = 0; k < 4; k++) {
            CHECK(write_sample(src, sizes[k], 7u + (unsigned)k, k == 3 ? 3 * 1048576 : 0) == 0);
            /* dst starts as a longer file: the copy must replace it, not overwrite a prefix */
            CHECK(write_sample(dst, 9 * 1048576, 99u, 0) == 0);
            lub_copy_how used = (lub_copy_how)-1;
            CHECK(lub_file_copy(src, dst, hows[h], &used) == 0);
            CHECK(file_size(dst) == file_size(src));
            CHECK(same_bytes(src, dst));
            if (hows[h] == LUB_COPY_BUFFERED)
                CHECK(used == LUB_COPY_BUFFERED);
            else if (sizes[k] > 0) { /* the fall-back only where the kernel refuses */
                const int kernel = kernel_copies(src, big);
                CHECK(kernel >= 0);
                CHECK(used == (kernel == 1 ? LUB_COPY_IN_KERNEL : LUB_COPY_BUFFERED));
                printf("copy of %zu bytes: %s\n", sizes[k],
                       used == LUB_COPY_IN_KERNEL ? "in the kernel" : "through the buffer");
            }
        }
        /* failures: the errno of the cause */
        errno = 0;
        CHECK(lub_file_copy(missing, dst, hows[h], NULL) == -1 && errno == ENOENT);
        errno = 0;
        CHECK(lub_file_copy(src, missing, hows[h], NULL) == -1 && errno == ENOENT);
        errno = 0;
        CHECK(lub_file_copy(src, argv[1], hows[h], NULL) == -1 && errno == EISDIR);
        /* a device that takes no data: copy_file_range does not apply (not a regular file),
         * the buffered copy then fails to write */
        errno = 0;
        CHECK(lub_file_copy(src, "/dev/full", hows[h], NULL) == -1 && errno == ENOSPC);
    }
    /* a copy of a copy stays the source (the in-kernel copy of a file it made) */
    CHECK(write_sample(src, 2 * 1048576 + 5, 3u, 0) == 0);
    CHECK(lub_file_copy(src, dst, LUB_COPY_IN_KERNEL, NULL) == 0);
    CHECK(lub_file_copy(dst, big, LUB_COPY_IN_KERNEL, NULL) == 0);
    CHECK(same_bytes(src, big));
    remove(src);
    remove(dst);
    remove(big);
    if (failures)
        fprintf(stderr, "%d check(s) failed\n", failures);
    else
        printf("file_copy: all checks passed\n");
    return failures ? 1 : 0;
}
