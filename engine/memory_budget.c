/* memory_budget.c — see memory_budget.h. */
#define _GNU_SOURCE
#include "memory_budget.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <unistd.h>
#if defined(__linux__)
#include <sys/sysinfo.h>
#endif

#define GIB (1024.0 * 1024.0 * 1024.0)
/* limits at or above this are "no limit" (cgroup v1 writes PAGE_COUNTER_MAX * page size) */
#define UNLIMITED_BYTES 1e18

/* The number in a one-line file: 1 and *v, or 0 (missing, "max", unreadable). */
static int read_bytes_file(const char *path, double *v)
{
    FILE *f = fopen(path, "r");
    if (!f)
        return 0;
    char line[64] = "";
    const int ok = fgets(line, sizeof line, f) != NULL;
    fclose(f);
    if (!ok)
        return 0;
    char *end = NULL;
    const double x = strtod(line, &end);
    if (end == line || !(x >= 0.0) || x >= UNLIMITED_BYTES)
        return 0;
    *v = x;
    return 1;
}

/* The smallest limit along group `path` and its ancestors under `mount`: v2 memory.max plus
 * memory.swap.max, v1 memory.limit_in_bytes plus swap within memory.memsw.limit_in_bytes; swap
 * the group does not bound counts as the machine's. */
static double limit_along(const char *mount, const char *path, int v2, double system_swap)
{
    char dir[1024], file[1200];
    if (snprintf(dir, sizeof dir, "%s%s", mount, path) >= (int)sizeof dir)
        return INFINITY;
    const size_t root_len = strlen(mount);
    double best = INFINITY;
    for (;;) {
        double v = 0.0, s = 0.0;
        if (v2) {
            snprintf(file, sizeof file, "%s/memory.max", dir);
            if (read_bytes_file(file, &v)) {
                snprintf(file, sizeof file, "%s/memory.swap.max", dir);
                v += read_bytes_file(file, &s) && s < system_swap ? s : system_swap;
                best = fmin(best, v);
            }
        } else { /* memory (+ the machine's swap) within the memory + swap limit */
            snprintf(file, sizeof file, "%s/memory.limit_in_bytes", dir);
            if (read_bytes_file(file, &v))
                best = fmin(best, v + system_swap);
            snprintf(file, sizeof file, "%s/memory.memsw.limit_in_bytes", dir);
            if (read_bytes_file(file, &s))
                best = fmin(best, s);
        }
        char *slash = strrchr(dir + root_len, '/');
        if (!slash)
            break;
        *slash = '\0'; /* the parent; "" after the last slash is the mount itself */
    }
    return best;
}

double lub_cgroup_memory_limit(const char *proc_cgroup, const char *sysfs_root, double system_swap)
{
    double best = INFINITY;
    const char *line = proc_cgroup;
    while (line && *line) {
        const char *eol = strchr(line, '\n');
        const size_t len = eol ? (size_t)(eol - line) : strlen(line);
        char buf[1024];
        if (len < sizeof buf) {
            memcpy(buf, line, len);
            buf[len] = '\0';
            char *c1 = strchr(buf, ':'), *c2 = c1 ? strchr(c1 + 1, ':') : NULL;
            if (c2) {
                *c1 = *c2 = '\0'; /* buf: hierarchy id */
                const char *controllers = c1 + 1, *path = c2 + 1;
                char mount[1100];
                if (*controllers == '\0' && strcmp(buf, "0") == 0) { /* v2 (unified) */
                    snprintf(mount, sizeof mount, "%s", sysfs_root);
                    best = fmin(best, limit_along(mount, path, 1, system_swap));
                    snprintf(mount, sizeof mount, "%s/unified", sysfs_root); /* hybrid */
                    best = fmin(best, limit_along(mount, path, 1, system_swap));
                } else { /* v1: a hierarchy whose controllers include "memory" */
                    char list[256];
                    snprintf(list, sizeof list, ",%s,", controllers);
                    if (strstr(list, ",memory,")) {
                        snprintf(mount, sizeof mount, "%s/%s", sysfs_root, controllers);
                        best = fmin(best, limit_along(mount, path, 0, system_swap));
                    }
                }
            }
        }
        line = eol ? eol + 1 : NULL;
    }
    return best;
}

/* Address space and resident memory of this process, bytes (0 when unknown). */
static void process_usage(double *mapped, double *resident)
{
    *mapped = *resident = 0.0;
#if defined(__linux__)
    FILE *f = fopen("/proc/self/statm", "r");
    if (!f)
        return;
    unsigned long size = 0, rss = 0;
    if (fscanf(f, "%lu %lu", &size, &rss) == 2) {
        const double page = (double)sysconf(_SC_PAGESIZE);
        *mapped = (double)size * page;
        *resident = (double)rss * page;
    }
    fclose(f);
#endif
}

static void consider(lub_memory_room *room, double limit, double held, const char *name)
{
    const double free_part = limit > held ? limit - held : 0.0;
    if (free_part < room->free) {
        room->limit = limit;
        room->free = free_part;
        room->name = name;
    }
}

void lub_memory_room_limit(lub_memory_room *room, double limit, const char *name)
{
    consider(room, limit, 0.0, name);
}

double lub_address_space_limit(void)
{
    struct rlimit as;
    if (getrlimit(RLIMIT_AS, &as) == 0 && as.rlim_cur != RLIM_INFINITY)
        return (double)as.rlim_cur;
    return INFINITY;
}

void lub_memory_room_now(lub_memory_room *room)
{
    room->limit = room->free = INFINITY;
    room->name = "no limit";
    double mapped, resident;
    process_usage(&mapped, &resident);
    const double address_space = lub_address_space_limit();
    if (isfinite(address_space))
        consider(room, address_space, mapped, LUB_ADDRESS_SPACE_NAME);
#if defined(__linux__)
    struct sysinfo si;
    double swap = 0.0;
    if (sysinfo(&si) == 0) {
        const double unit = si.mem_unit ? (double)si.mem_unit : 1.0;
        swap = (double)si.totalswap * unit;
        consider(room, (double)si.totalram * unit + swap, resident,
                 "memory and swap on this machine");
    }
    FILE *f = fopen("/proc/self/cgroup", "r");
    if (f) {
        char text[4096];
        const size_t got = fread(text, 1, sizeof text - 1, f);
        fclose(f);
        text[got] = '\0';
        consider(room, lub_cgroup_memory_limit(text, "/sys/fs/cgroup", swap), resident,
                 "memory in its control group (cgroup limit: Slurm --mem, a container's "
                 "memory limit)");
    }
#endif
}

/* "1.2 TiB" from 1 TiB up, "1.23 GiB" from 1 GiB up, "456 MiB" below. */
static const char *size_text(double bytes, char *buf, size_t len)
{
    if (bytes >= 1024.0 * GIB)
        snprintf(buf, len, "%.3g TiB", bytes / (1024.0 * GIB));
    else if (bytes >= GIB)
        snprintf(buf, len, "%.3g GiB", bytes / GIB);
    else
        snprintf(buf, len, "%.3g MiB", bytes / (1024.0 * 1024.0));
    return buf;
}

int lub_memory_need_check(const lub_memory_need *need, const lub_memory_room *room,
                          const char *subject, char *msg, size_t len)
{
    if (!(need->bytes > room->free))
        return 0;
    char a[32], b[32], c[32];
    int w = snprintf(msg, len, "not enough memory: %s need at least %s", need->what,
                     size_text(need->bytes, a, sizeof a));
    if (need->per_item > 0.0 && w >= 0 && (size_t)w < len)
        w += snprintf(msg + w, len - (size_t)w, " (%.3g kB per particle)", need->per_item / 1e3);
    if (w >= 0 && (size_t)w < len)
        w += snprintf(msg + w, len - (size_t)w, ", but %s may use %s of %s", subject,
                      size_text(room->limit, b, sizeof b), room->name);
    if (room->free < room->limit && w >= 0 && (size_t)w < len)
        w += snprintf(msg + w, len - (size_t)w, ", %s of it free",
                      size_text(room->free, c, sizeof c));
    if (need->member && w >= 0 && (size_t)w < len)
        snprintf(msg + w, len - (size_t)w, "; lower %s", need->member);
    return 1;
}
