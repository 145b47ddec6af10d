/* sync_log_shim.c — an LD_PRELOAD library for test_resume_safety.py: logs every fsync and
 * fdatasync (with the path of the file or folder synced, read from /proc/self/fd) and every
 * rename made through the C library, one line each, to the file named by LUBDEM_SYNC_LOG:
 *   fsync <path>
 *   rename <old> <new>
 * then calls the real function. Paths as the process gave them (rename) or as the kernel names
 * the open file (fsync: absolute). Errors: a line that cannot be written is dropped; the calls
 * themselves are not affected. Not for production builds: tests only. */
#define _GNU_SOURCE
#include <dlfcn.h>
#include <fcntl.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

/* one line to the log (opened for each line: O_APPEND keeps lines whole across processes) */
static void log_line(const char *line)
{
    const char *path = getenv("LUBDEM_SYNC_LOG");
    if (!path)
        return;
    const int fd = open(path, O_WRONLY | O_CREAT | O_APPEND | O_CLOEXEC, 0644);
    if (fd < 0)
        return;
    const size_t n = strlen(line);
    if (write(fd, line, n) != (ssize_t)n) { /* dropped: nothing else to do */
    }
    close(fd);
}

static void log_sync(int fd)
{
    char link[64], target[4096], line[4200];
    snprintf(link, sizeof link, "/proc/self/fd/%d", fd);
    const ssize_t n = readlink(link, target, sizeof target - 1);
    target[n > 0 ? (size_t)n : 0] = '\0';
    snprintf(line, sizeof line, "fsync %s\n", n > 0 ? target : "?");
    log_line(line);
}

int fsync(int fd)
{
    int (*real)(int) = (int (*)(int))dlsym(RTLD_NEXT, "fsync");
    log_sync(fd);
    return real(fd);
}

int fdatasync(int fd)
{
    int (*real)(int) = (int (*)(int))dlsym(RTLD_NEXT, "fdatasync");
    log_sync(fd);
    return real(fd);
}

int rename(const char *from, const char *to)
{
    int (*real)(const char *, const char *) =
        (int (*)(const char *, const char *))dlsym(RTLD_NEXT, "rename");
    const int rc = real(from, to);
    if (rc == 0) {
        char line[8300];
        snprintf(line, sizeof line, "rename %s %s\n", from, to);
        log_line(line);
    }
    return rc;
}
