/* processors.c — processors available to this process (see processors.h). */
#define _GNU_SOURCE /* sched_getaffinity, CPU_COUNT_S */
#include "processors.h"

#include <sched.h>
#include <unistd.h>
#ifdef _OPENMP
#include <omp.h>
#endif

int lub_omp_thread_limit(void)
{
#ifdef _OPENMP
    const int limit = omp_get_thread_limit();
    return limit > 0 ? limit : 1;
#else
    return 1;
#endif
}

int lub_threads_usable(int requested)
{
    const int processors = lub_processors_available();
    const int limit = lub_omp_thread_limit();
    int usable = requested > 0 ? requested : 1;
    if (usable > processors)
        usable = processors;
    if (usable > limit)
        usable = limit;
    return usable;
}

int lub_processors_available(void)
{
    /* a mask large enough for any machine this runs on; CPU_ALLOC avoids the 1024-CPU limit
     * of cpu_set_t */
    const int max_cpus = 8192;
    cpu_set_t *mask = CPU_ALLOC(max_cpus);
    if (mask) {
        const size_t size = CPU_ALLOC_SIZE(max_cpus);
        CPU_ZERO_S(size, mask);
        int count = 0;
        if (sched_getaffinity(0, size, mask) == 0)
            count = CPU_COUNT_S(size, mask);
        CPU_FREE(mask);
        if (count > 0)
            return count;
    }
    const long online = sysconf(_SC_NPROCESSORS_ONLN);
    return online > 0 ? (int)online : 1;
}
