/* file_copy.c — a whole-file copy, synced (file_copy.h). */
#define _GNU_SOURCE /* copy_file_range */
#include "file_copy.h"

#include <errno.h>
#include <fcntl.h>
#include <limits.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

/* Copies the rest of in to out inside the kernel (copy_file_range: a reflink where the file
 * system shares blocks, XFS or Btrfs; a server-side copy on NFS 4.2; no copy through user
 * space elsewhere). 0 when done, 1 when nothing was copied and the call is not available
 * for these files (the caller copies through a buffer), -1 with errno set on an error. */
static int copy_in_kernel(int in, int out)
{
    int copied = 0;
    for (;;) {
        const ssize_t n = copy_file_range(in, NULL, out, NULL, (size_t)1 << 30, 0);
        if (n > 0) {
            copied = 1;
            continue;
        }
        if (n == 0) {
            /* 0 at the start of a non-empty file: a file system that copies nothing this
             * way (some kernels return 0 rather than an error), so copy through the buffer */
            struct stat st;
            return !copied && fstat(in, &st) == 0 && st.st_size > 0 ? 1 : 0;
        }
        if (errno == EINTR)
            continue;
        if (!copied && (errno == ENOSYS || errno == EXDEV || errno == EINVAL ||
                        errno == EOPNOTSUPP || errno == EBADF))
            return 1;
        return -1;
    }
}

/* Copies the rest of in to out through a buffer; 0 or -1 with errno set. */
static int copy_through_buffer(int in, int out)
{
    char buf[1 << 16];
    for (;;) {
        const ssize_t got = read(in, buf, sizeof buf);
        if (got < 0 && errno == EINTR)
            continue;
        if (got <= 0)
            return got < 0 ? -1 : 0;
        for (ssize_t done = 0; done < got;) {
            const ssize_t put = write(out, buf + done, (size_t)(got - done));
            if (put >= 0)
                done += put;
            else if (errno != EINTR)
                return -1;
        }
    }
}

int lub_file_copy(const char *src, const char *dst, lub_copy_how how_wanted, lub_copy_how *used)
{
    const int in = open(src, O_RDONLY | O_CLOEXEC);
    if (in < 0)
        return -1;
    const int out = open(dst, O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
    int err = out < 0 ? errno : 0;
    if (!err) {
        const int how = how_wanted == LUB_COPY_IN_KERNEL ? copy_in_kernel(in, out) : 1;
        if (how == 1 && (lseek(in, 0, SEEK_SET) != 0 || lseek(out, 0, SEEK_SET) != 0 ||
                         copy_through_buffer(in, out) != 0))
            err = errno;
        else if (how < 0)
            err = errno;
        if (used)
            *used = how == 1 ? LUB_COPY_BUFFERED : LUB_COPY_IN_KERNEL;
    }
    if (out >= 0 && !err && fsync(out) != 0)
        err = errno;
    if (out >= 0 && close(out) != 0 && !err)
        err = errno;
    close(in);
    errno = err;
    return err ? -1 : 0;
}

int lub_sync_path(const char *path)
{
    const int fd = open(path, O_RDONLY | O_CLOEXEC);
    if (fd < 0)
        return -1;
    int err = fsync(fd) != 0 ? errno : 0;
    if (close(fd) != 0 && !err)
        err = errno;
    errno = err;
    return err ? -1 : 0;
}

int lub_sync_folder_of(const char *path)
{
    char dir[PATH_MAX];
    const char *slash = strrchr(path, '/');
    if (!slash)
        return lub_sync_path(".");
    const size_t n = slash == path ? 1 : (size_t)(slash - path); /* "/x": the root */
    if (n >= sizeof dir) {
        errno = ENAMETOOLONG;
        return -1;
    }
    memcpy(dir, path, n);
    dir[n] = '\0';
    return lub_sync_path(dir);
}
