/* processors.h — how many processors this process may run on.
 *
 * The count of the CPU affinity mask (sched_getaffinity: a Slurm or cgroup cpuset, taskset),
 * falling back to the online processors when the mask cannot be read. Always >= 1; no
 * allocation that outlives the call, no error return. */
#ifndef LUBDEM_PROCESSORS_H
#define LUBDEM_PROCESSORS_H

int lub_processors_available(void);

#endif
