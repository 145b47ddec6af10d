/* test_step_schedule.c — step count and periodic events under a changing step
 * (engine/step_schedule.h).
 *
 *  1. constant step: the events are due exactly where the modulo forms (step + 1) % every == 0
 *     and step % every == 0 put them, and nsteps = ceil(t_end/dt - 1e-9);
 *  2. the step falls by 5.3 and then rises by 2 during a run: the run still ends at t_end
 *     (within one step), and successive occurrences of each event stay spacing apart in time
 *     (within one step of the step in force) across both changes;
 *  3. a run's end moved (lub_schedule_set_end, a continuation asked for a longer /strain) gives
 *     the step count of a schedule built for the new end from the start, with and without a
 *     change of the step before it, for ends where floating sums of the step would miss by one;
 *  4. lub_schedule_most_occurrences bounds the occurrences of an event whatever steps up to
 *     dt_max the run takes: a step that changes at random (0.05-1 dt_max, at a fifth of the
 *     steps) never makes an interval shorter than max(2/3 spacing, spacing - dt_max/2), and
 *     the count from the start and from mid-run stays within the bound (with the rounding to
 *     the nearest step that lub_schedule_set_dt used until 2026-12-07 intervals shrank to
 *     0.52 of that shortest one, and a count could overrun a bound fixed in advance);
 *  5. a change of the step leaves an occurrence that is due at a step already taken due.
 */
#include "step_schedule.h"

#include <math.h>
#include <stdint.h>

#include "shear_test.h"

static void check_constant(void)
{
    lub_schedule s;
    const double dt = 0.013, t_end = 7.0;
    lub_schedule_init(&s, dt, t_end);
    ST_CHECK(s.nsteps == (int64_t)ceil(t_end / dt - 1e-9), "nsteps %lld", (long long)s.nsteps);
    const int a = lub_schedule_add(&s, 17, 16, 17 * dt);
    const int b = lub_schedule_add(&s, 5, 0, 5 * dt);
    int bad = 0;
    for (int64_t k = 0; k < s.nsteps; ++k) {
        bad += lub_schedule_due(&s, a, k) != ((k + 1) % 17 == 0);
        bad += lub_schedule_due(&s, b, k) != (k % 5 == 0);
    }
    ST_CHECK(bad == 0, "%d steps disagree with the modulo forms", bad);
    ST_CHECK(lub_schedule_period(0.02, 0.003) == 7 && lub_schedule_period(1e-9, 1.0) == 1,
             "period");
}

static void check_changes(void)
{
    lub_schedule s;
    const double t_end = 10.0, spacing = 0.25;
    double dt = 1e-3, t = 0.0;
    lub_schedule_init(&s, dt, t_end);
    const int ev = lub_schedule_add(&s, lub_schedule_period(spacing, dt),
                                    lub_schedule_period(spacing, dt) - 1, spacing);
    double last = -1.0, worst = 0.0;
    int64_t k;
    int n = 0;
    for (k = 0; k < s.nsteps; ++k) {
        if (lub_schedule_due(&s, ev, k)) { /* at the start of step k, time t */
            if (last >= 0.0)
                worst = fmax(worst, fabs(t - last - spacing) / dt);
            last = t;
            n++;
        }
        t += dt;
        if (k == 3000) { /* t = 3.001: mid-period */
            dt /= 5.3;
            lub_schedule_set_dt(&s, k + 1, t, dt);
        } else if (k == 3000 + 20000) {
            dt *= 2.0;
            lub_schedule_set_dt(&s, k + 1, t, dt);
        }
    }
    ST_CHECK(fabs(t - t_end) <= dt, "the run ends at t = %.9g, not %g", t, t_end);
    ST_CHECK(worst <= 1.0 + 1e-9, "spacing off by %.3g steps", worst);
    ST_CHECK(n >= 39 && n <= 40, "%d occurrences in %g at spacing %g", n, t_end, spacing);
}

/* the schedule of a run to t_short then extended to t_long, against one made for t_long */
static void check_end(double dt0, double t_short, double t_long, int change)
{
    lub_schedule a, b;
    lub_schedule_init(&a, dt0, t_short);
    lub_schedule_init(&b, dt0, t_long);
    if (change) { /* the same step change in both, after 1234 steps */
        double t = 0.0;
        for (int k = 0; k < 1234; ++k)
            t += dt0;
        lub_schedule_set_dt(&a, 1234, t, dt0 / 3.7);
        lub_schedule_set_dt(&b, 1234, t, dt0 / 3.7);
    }
    const int64_t short_steps = a.nsteps;
    lub_schedule_set_end(&a, t_long);
    ST_CHECK(a.nsteps == b.nsteps && a.t_end == b.t_end,
             "extended %g -> %g (change %d): %lld steps, a run made for %g takes %lld", t_short,
             t_long, change, (long long)a.nsteps, t_long, (long long)b.nsteps);
    lub_schedule_set_end(&a, t_short);
    ST_CHECK(a.nsteps == short_steps, "back to %g: %lld steps, not %lld", t_short,
             (long long)a.nsteps, (long long)short_steps);
}

static uint64_t lcg(uint64_t *state)
{
    *state = *state * 6364136223846793005ULL + 1442695040888963407ULL;
    return *state >> 11;
}

static void check_bound(double spacing_steps, uint64_t seed)
{
    const double dt_max = 1.0, spacing = spacing_steps * dt_max, t_end = 400.0 * spacing;
    lub_schedule s;
    double dt = dt_max, t = 0.0;
    lub_schedule_init(&s, dt, t_end);
    const int64_t every = lub_schedule_period(spacing, dt);
    const int ev = lub_schedule_add(&s, every, every - 1, spacing);
    const int64_t bound = lub_schedule_most_occurrences(&s, ev, 0.0, dt_max);
    const double shortest = fmax(2.0 * spacing / 3.0, spacing - 0.5 * dt_max);
    int64_t n = 0, n_late = 0, bound_late = -1;
    double last = -1.0, min_gap = INFINITY;
    for (int64_t k = 0; k < s.nsteps; ++k) {
        if (bound_late < 0 && t >= 0.5 * t_end) /* the bound from mid-run (a continuation's) */
            bound_late = lub_schedule_most_occurrences(&s, ev, t, dt_max);
        if (lub_schedule_due(&s, ev, k)) {
            if (last >= 0.0)
                min_gap = fmin(min_gap, t - last);
            last = t;
            ++n;
            n_late += bound_late >= 0;
        }
        t += dt;
        if (lcg(&seed) % 5 == 0) {
            dt = dt_max * (0.05 + 0.95 * (double)(lcg(&seed) % 1000) / 999.0);
            lub_schedule_set_dt(&s, k + 1, t, dt);
        }
    }
    ST_CHECK(min_gap >= shortest * (1.0 - 1e-9),
             "spacing %g steps: an interval of %.6g, below the bound's %.6g", spacing_steps,
             min_gap, shortest);
    ST_CHECK(n <= bound && n_late <= bound_late,
             "spacing %g steps: %lld occurrences (bound %lld), %lld from mid-run (bound %lld)",
             spacing_steps, (long long)n, (long long)bound, (long long)n_late,
             (long long)bound_late);
}

static void check_overdue(void)
{
    lub_schedule s;
    lub_schedule_init(&s, 1.0, 100.0);
    const int ev = lub_schedule_add(&s, 10, 9, 10.0);
    /* the step changes after step 9 is taken, before the event is asked for at step 9 */
    lub_schedule_set_dt(&s, 10, 10.0, 0.5);
    ST_CHECK(lub_schedule_due(&s, ev, 9) == 1 && s.ev[ev].next == 29,
             "an occurrence due at step 9 stays due there (next %lld)", (long long)s.ev[ev].next);
}

int main(void)
{
    const double spacings[] = {0.6, 0.7, 1.0, 1.2, 1.4, 1.6, 2.5, 3.3, 25.5};
    for (size_t i = 0; i < sizeof spacings / sizeof *spacings; ++i)
        for (uint64_t seed = 1; seed <= 4; ++seed)
            check_bound(spacings[i], seed * 7919);
    check_overdue();
    check_constant();
    check_changes();
    for (int change = 0; change < 2; ++change) {
        check_end(0.013, 7.0, 21.0, change);
        check_end(0.1, 0.3, 0.7, change); /* 0.7/0.1 = 6.999999999999999 */
        check_end(6.1e-5, 3.0, 30.0, change);
    }
    ST_DONE();
}
