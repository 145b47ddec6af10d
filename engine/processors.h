/* processors.h — how many processors this process may run on.
 *
 * The count of the CPU affinity mask (sched_getaffinity: a Slurm or cgroup cpuset, taskset),
 * falling back to the online processors when the mask cannot be read. Always >= 1; no
 * allocation that outlives the call, no error return. */
#ifndef LUBDEM_PROCESSORS_H
#define LUBDEM_PROCESSORS_H

int lub_processors_available(void);

/* The most threads an OpenMP team of this process may have: omp_get_thread_limit() (the
 * OMP_THREAD_LIMIT environment variable; INT_MAX when it is not set), 1 in a build without
 * OpenMP. Always >= 1. */
int lub_omp_thread_limit(void);

/* The threads a run asked for `requested` (< 1: 1) really uses: at most the processors it may
 * run on (more would only wait at every barrier; run_driver.c) and at most
 * lub_omp_thread_limit() (OpenMP would give no larger team). Reads the affinity mask and the
 * OpenMP thread limit, nothing else; no side effect. It does not foresee a team that
 * OMP_DYNAMIC shrinks: the run driver turns dynamic teams off (omp_set_dynamic(0)) and reports
 * the teams the run actually got. The service sizes a job's memory with it. */
int lub_threads_usable(int requested);

#endif
