/* test_memory_budget.c — the memory ceilings of memory_budget.h: cgroup v1/v2 limits read from
 * fake /sys/fs/cgroup trees (nested groups, hybrid mounts, namespaced paths, swap), the
 * address-space ceiling under a set RLIMIT_AS, and the check's verdict and message.
 * Usage: test_memory_budget <scratch dir>. */
#define _GNU_SOURCE
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <unistd.h>

#include "memory_budget.h"

static int failures = 0;
#define CHECK(cond, ...)                                                                           \
    do {                                                                                           \
        if (!(cond)) {                                                                             \
            fprintf(stderr, "FAIL %s:%d: %s: ", __FILE__, __LINE__, #cond);                        \
            fprintf(stderr, __VA_ARGS__);                                                          \
            fprintf(stderr, "\n");                                                                 \
            failures++;                                                                            \
        }                                                                                          \
    } while (0)

static char root[900];

/* mkdir -p root/dir */
static void make_dir(const char *dir)
{
    char path[1200];
    snprintf(path, sizeof path, "%s/%s", root, dir);
    for (char *p = path + strlen(root) + 1; *p; ++p)
        if (*p == '/') {
            *p = '\0';
            mkdir(path, 0755);
            *p = '/';
        }
    mkdir(path, 0755);
}

/* root/dir/file containing text (dir created) */
static void put(const char *dir, const char *file, const char *text)
{
    make_dir(dir);
    char path[1400];
    snprintf(path, sizeof path, "%s/%s/%s", root, dir, file);
    FILE *f = fopen(path, "w");
    if (!f) {
        fprintf(stderr, "cannot write %s: %s\n", path, strerror(errno));
        exit(2);
    }
    fputs(text, f);
    fclose(f);
}

/* a fresh fake tree for one case */
static void new_tree(const char *base, const char *name)
{
    snprintf(root, sizeof root, "%s/cg_%s", base, name);
    mkdir(root, 0755);
}

int main(int argc, char **argv)
{
    const char *base = argc > 1 ? argv[1] : ".";
    const double swap = 500.0, inf = INFINITY;

    /* v2: the group's memory.max, ancestors without a limit ("max"), swap bounded */
    new_tree(base, "v2");
    put("a/b", "memory.max", "1000\n");
    put("a/b", "memory.swap.max", "0\n");
    put("a", "memory.max", "max\n");
    CHECK(lub_cgroup_memory_limit("0::/a/b\n", root, swap) == 1000.0, "v2 group limit");
    /* swap the group does not bound counts as the machine's */
    put("a/b", "memory.swap.max", "max\n");
    CHECK(lub_cgroup_memory_limit("0::/a/b\n", root, swap) == 1500.0, "v2 unbounded swap");
    put("a/b", "memory.swap.max", "200\n");
    CHECK(lub_cgroup_memory_limit("0::/a/b\n", root, swap) == 1200.0, "v2 swap limit");
    /* a tighter ancestor wins */
    put("a", "memory.max", "800\n");
    put("a", "memory.swap.max", "0\n");
    CHECK(lub_cgroup_memory_limit("0::/a/b\n", root, swap) == 800.0, "v2 ancestor");
    /* hybrid: the unified hierarchy mounted at <root>/unified */
    new_tree(base, "hybrid");
    put("unified/z", "memory.max", "4096\n");
    put("unified/z", "memory.swap.max", "0\n");
    CHECK(lub_cgroup_memory_limit("1:name=systemd:/z\n0::/z\n", root, swap) == 4096.0, "v2 hybrid");

    /* v1: memory.limit_in_bytes plus the machine's swap when memsw is unlimited */
    new_tree(base, "v1");
    put("memory/x", "memory.limit_in_bytes", "2000\n");
    put("memory/x", "memory.memsw.limit_in_bytes", "9223372036854771712\n");
    put("memory", "memory.limit_in_bytes", "9223372036854771712\n");
    const char *v1 = "9:name=systemd:/\n4:memory:/x\n3:cpuset:/\n0::/\n";
    CHECK(lub_cgroup_memory_limit(v1, root, swap) == 2500.0, "v1 limit + swap");
    put("memory/x", "memory.memsw.limit_in_bytes", "2200\n");
    CHECK(lub_cgroup_memory_limit(v1, root, swap) == 2200.0, "v1 memsw");
    /* controllers mounted together ("cpu,memory") */
    new_tree(base, "v1co");
    put("cpu,memory/y", "memory.limit_in_bytes", "3000\n");
    CHECK(lub_cgroup_memory_limit("5:cpu,memory:/y\n", root, 0.0) == 3000.0, "v1 co-mounted");
    /* a path from another namespace: its folder is missing, the mount root's limit holds */
    new_tree(base, "v1ns");
    put("memory", "memory.limit_in_bytes", "7000\n");
    CHECK(lub_cgroup_memory_limit("4:memory:/process_api/0123abcd\n", root, 0.0) == 7000.0,
          "v1 namespaced path");
    /* nothing limits memory (cpu controller only, unlimited files, no tree) */
    new_tree(base, "none");
    put("memory", "memory.limit_in_bytes", "9223372036854771712\n");
    put("cpu/q", "cpu.shares", "1024\n");
    CHECK(lub_cgroup_memory_limit("2:cpu:/q\n4:memory:/\n", root, swap) == inf, "no limit");
    CHECK(lub_cgroup_memory_limit("", root, swap) == inf, "empty /proc/self/cgroup");
    CHECK(lub_cgroup_memory_limit("garbage without colons\n::\n", root, swap) == inf, "garbage");

    /* the check: verdict and message */
    lub_memory_need need = {
        .bytes = 3.0 * 1024 * 1024 * 1024, .per_item = 2300.0, .member = "/n_particles"};
    snprintf(need.what, sizeof need.what, "1000 particles");
    lub_memory_room room = {.limit = inf, .free = inf, .name = "no limit"};
    char msg[600];
    CHECK(lub_memory_need_check(&need, &room, "this process", msg, sizeof msg) == 0,
          "no ceiling: fits");
    lub_memory_room_limit(&room, 2.0 * 1024 * 1024 * 1024, "address space (lubdemd --mem-mb)");
    CHECK(room.limit == 2.0 * 1024 * 1024 * 1024 && room.free == room.limit, "narrowed");
    CHECK(lub_memory_need_check(&need, &room, "a job", msg, sizeof msg) == 1, "too large");
    CHECK(strcmp(msg, "not enough memory: 1000 particles need at least 3 GiB (2.3 kB per "
                      "particle), but a job may use 2 GiB of address space (lubdemd --mem-mb); "
                      "lower /n_particles") == 0,
          "message: %s", msg);
    lub_memory_room_limit(&room, 8.0 * 1024 * 1024 * 1024,
                          "wider"); /* a wider one changes nothing */
    CHECK(room.limit == 2.0 * 1024 * 1024 * 1024, "wider ceiling ignored");
    need.bytes = 1.5 * 1024 * 1024 * 1024;
    CHECK(lub_memory_need_check(&need, &room, "a job", msg, sizeof msg) == 0, "fits");
    need.bytes = 2.5 * 1024.0 * 1024 * 1024 * 1024;
    need.per_item = 0.0;
    CHECK(lub_memory_need_check(&need, &room, "a job", msg, sizeof msg) == 1 &&
              strstr(msg, "need at least 2.5 TiB, but"),
          "TiB: %s", msg);
    need.bytes = 300.0 * 1024 * 1024;
    room.limit = room.free = 200.0 * 1024 * 1024;
    CHECK(lub_memory_need_check(&need, &room, "a job", msg, sizeof msg) == 1 &&
              strstr(msg, "need at least 300 MiB, but a job may use 200 MiB of"),
          "MiB: %s", msg);
    char tiny[40];
    need.bytes = 1e12;
    CHECK(lub_memory_need_check(&need, &room, "a job", tiny, sizeof tiny) == 1 &&
              strlen(tiny) == sizeof tiny - 1,
          "truncated message: %s", tiny);

    /* this process under RLIMIT_AS: the ceiling is the limit, free what is not mapped */
    struct rlimit old;
    getrlimit(RLIMIT_AS, &old);
    lub_memory_room now;
    lub_memory_room_now(&now);
    CHECK(now.free > 0.0 && now.free <= now.limit, "room now: %g of %g", now.free, now.limit);
    FILE *f = fopen("/proc/self/statm", "r");
    unsigned long pages = 0;
    if (f && fscanf(f, "%lu", &pages) == 1) {
        const double mapped = (double)pages * (double)sysconf(_SC_PAGESIZE);
        const double give = 1024.0 * 1024 * 1024;
        struct rlimit lim = {(rlim_t)(mapped + give), old.rlim_max};
        if (old.rlim_max == RLIM_INFINITY || lim.rlim_cur <= old.rlim_max) {
            CHECK(setrlimit(RLIMIT_AS, &lim) == 0, "setrlimit: %s", strerror(errno));
            lub_memory_room_now(&now);
            CHECK(strstr(now.name, "RLIMIT_AS") && now.limit == (double)lim.rlim_cur &&
                      now.free > 0.9 * give && now.free <= give,
                  "address space: %s, %g of %g", now.name, now.free, now.limit);
            setrlimit(RLIMIT_AS, &old);
        }
    }
    if (f)
        fclose(f);
    if (failures)
        fprintf(stderr, "%d check(s) failed\n", failures);
    else
        printf("memory budget: all checks passed\n");
    return failures ? 1 : 0;
}
