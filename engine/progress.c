/* progress.c — rate-limited progress lines on stdout (format in progress.h). */
#include "progress.h"

#include <time.h>

double lub_wall_seconds(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

void lub_progress_init(lub_progress *p, FILE *stream, double interval_s)
{
    p->stream = stream;
    p->interval_s = interval_s;
    p->t_start = lub_wall_seconds();
    p->t_last = p->t_start;
    p->fraction = 0.0;
    p->have_base = 0;
    p->t_base = p->t_start;
    p->fraction_base = 0.0;
    p->step_base = 0;
    p->step = 0;
}

static void emit(lub_progress *p, double fraction, int64_t step, double now)
{
    /* this process's steps over this process's time, from the first update (none: a final
     * line before any step, rate 0) */
    const double elapsed = now - p->t_base;
    const double done = fraction - p->fraction_base;
    const double rate = p->have_base && elapsed > 0 ? (double)(step - p->step_base) / elapsed : 0.0;
    const double eta = (done > 0 && fraction < 1) ? elapsed * (1.0 - fraction) / done : 0.0;
    fprintf(p->stream, "progress fraction=%.4f step=%lld steps_per_s=%.3g eta_s=%.1f\n", fraction,
            (long long)step, rate, eta);
    fflush(p->stream);
    p->t_last = now;
}

void lub_progress_update(lub_progress *p, double fraction, int64_t step)
{
    if (!p || !p->stream)
        return;
    p->fraction = fraction;
    p->step = step;
    /* reading the clock every call costs ~20 ns; callers may call every step */
    double now = lub_wall_seconds();
    if (!p->have_base) { /* no line yet: it would have no rate and no ETA */
        p->have_base = 1;
        p->t_base = now;
        p->fraction_base = fraction < 0 ? 0 : fraction > 1 ? 1 : fraction;
        p->step_base = step;
        p->t_last = now;
        return;
    }
    if (now - p->t_last < p->interval_s)
        return;
    if (fraction < 0)
        fraction = 0;
    if (fraction > 1)
        fraction = 1;
    emit(p, fraction, step, now);
}

void lub_progress_last_step(lub_progress *p, int64_t step)
{
    if (p)
        p->step = step;
}

void lub_progress_end(lub_progress *p, int completed)
{
    if (!p || !p->stream)
        return;
    const double f = completed ? 1.0 : p->fraction < 0 ? 0 : p->fraction > 1 ? 1 : p->fraction;
    emit(p, f, p->step, lub_wall_seconds());
}
