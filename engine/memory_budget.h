/* memory_budget.h — the memory a run may take, checked before it allocates anything.
 *
 * A simple_shear packing of 1e6+ spheres takes minutes; a run too large for the memory it may
 * use used to fail only after it (or be killed by the kernel's OOM killer, with no
 * diagnostic). Scenes state a lower bound of what they will hold (lub_memory_need, filled by
 * their memory_need hook, scene.h); the run driver and the service compare it with the
 * tightest of these ceilings:
 *  - address space: RLIMIT_AS (ulimit -v; lubdemd --mem-mb sets it for its workers), of which
 *    the address space the process already maps (/proc/self/statm) is not free;
 *  - the memory control group: cgroup v2 memory.max (+ memory.swap.max) or v1
 *    memory.limit_in_bytes (+ swap, within memory.memsw.limit_in_bytes), the smallest along
 *    the path from the process's group to the root (Slurm's --mem, a container's limit); the
 *    process's resident memory is not free;
 *  - the machine: physical memory + swap (sysinfo), resident memory not free.
 * Other processes' use is not counted: a need that passes may still not fit, one that fails
 * cannot fit. Linux reads /proc and /sys; elsewhere only RLIMIT_AS applies.
 * Units: bytes, as doubles (no overflow). No allocation; reads a few small files.
 */
#ifndef LUBDEM_MEMORY_BUDGET_H
#define LUBDEM_MEMORY_BUDGET_H

#include <stddef.h>

/* What a run will hold, at least (scene.h: memory_need). */
typedef struct {
    double bytes;       /* lower bound of the heap the run will hold, bytes */
    double per_item;    /* bytes per particle (for the message), 0 = not stated */
    const char *member; /* JSON pointer of the spec member that sets the size */
    char what[200];     /* what needs it, e.g. "1000000 particles at phi 0.5, cut-off 2 a, ..." */
} lub_memory_need;

/* The tightest ceiling. */
typedef struct {
    double limit;     /* the ceiling, bytes (INFINITY when none was found) */
    double free;      /* the part of it this process does not hold yet, bytes */
    const char *name; /* the ceiling, for messages: "address space (RLIMIT_AS: ...)" etc. */
} lub_memory_room;

/* The address-space ceiling's name in messages, and its value for this process (the soft
 * RLIMIT_AS in bytes; INFINITY without one). */
#define LUB_ADDRESS_SPACE_NAME "address space (RLIMIT_AS: ulimit -v, lubdemd --mem-mb)"
double lub_address_space_limit(void);

/* The ceilings of this process now. Never fails: a ceiling it cannot read is absent. */
void lub_memory_room_now(lub_memory_room *room);

/* The memory-control-group limit (memory + swap where the group bounds swap too), in bytes,
 * for the process whose /proc/<pid>/cgroup text is `proc_cgroup`, with the cgroup file systems
 * mounted under `sysfs_root` (normally "/sys/fs/cgroup"); v2 swap without a limit is bounded
 * by `system_swap`. INFINITY when no group limits memory. Reads only files under sysfs_root
 * (the tests point it at a fake tree). */
double lub_cgroup_memory_limit(const char *proc_cgroup, const char *sysfs_root, double system_swap);

/* 0 when `need` fits in `room`'s free part; otherwise 1, with a message in msg (one line:
 * what needs how much, what `subject` ("this process", "a job") may use, the member to
 * lower). */
int lub_memory_need_check(const lub_memory_need *need, const lub_memory_room *room,
                          const char *subject, char *msg, size_t len);

/* Narrows *room to a ceiling of `limit` bytes named `name` (nothing of it held yet) when that
 * leaves less free; for a process that is not started yet (the service's --mem-mb). */
void lub_memory_room_limit(lub_memory_room *room, double limit, const char *name);

#endif
