/* processors.h — how many processors this process may run on.
 *
 * The count of the CPU affinity mask (sched_getaffinity: a Slurm or cgroup cpuset, taskset),
 * falling back to the online processors when the mask cannot be read. Always >= 1; no
 * allocation that outlives the call, no error return. */
#ifndef LUBDEM_PROCESSORS_H
#define LUBDEM_PROCESSORS_H

int lub_processors_available(void);

/* The threads a run asked for `requested` (< 1: 1) really uses: at most the processors it may
 * run on (more would only wait at every barrier; run_driver.c). The service sizes a job's
 * memory with it. */
int lub_threads_usable(int requested);

#endif
