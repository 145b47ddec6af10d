/* step_schedule.c — step count and periodic events under a changing step (step_schedule.h). */
#include "step_schedule.h"

#include <math.h>

static int64_t steps_for(double duration, double dt)
{
    const double k = ceil(duration / dt - 1e-9);
    if (!(k > 0.0))
        return 0;
    return k < 4.0e18 ? (int64_t)k : (int64_t)4e18;
}

void lub_schedule_init(lub_schedule *s, double dt, double t_end)
{
    s->dt = dt;
    s->t_end = t_end;
    s->nsteps = steps_for(t_end, dt);
    s->n_events = 0;
    s->anchor_step = 0;
    s->anchor_time = 0.0;
}

int lub_schedule_add(lub_schedule *s, int64_t every, int64_t first, double spacing)
{
    if (s->n_events >= LUB_SCHEDULE_MAX_EVENTS)
        return -1;
    lub_schedule_event *e = &s->ev[s->n_events];
    e->every = every < 1 ? 1 : every;
    e->next = first;
    e->spacing = spacing;
    return s->n_events++;
}

int64_t lub_schedule_period(double spacing, double dt)
{
    const double k = floor(spacing / dt + 0.5);
    if (!(k >= 1.0))
        return 1;
    return k < 4.6e18 ? (int64_t)k : (int64_t)4.6e18;
}

void lub_schedule_set_dt(lub_schedule *s, int64_t done, double time, double dt_new)
{
    const double scale = s->dt / dt_new;
    for (int k = 0; k < s->n_events; ++k) {
        lub_schedule_event *e = &s->ev[k];
        if (e->next < done) { /* due at a step already taken and not yet asked for: it stays
                               * due (until 2026-12-07 it moved to `done`, one step late) */
            e->every = lub_schedule_period(e->spacing, dt_new);
            continue;
        }
        const int64_t left = e->next - done;
        /* rounded up: a change never brings an occurrence earlier, so no interval becomes
         * shorter than the shortest period any step gives (lub_schedule_most_occurrences) */
        e->next = done + (int64_t)ceil((double)left * scale - 1e-9);
        e->every = lub_schedule_period(e->spacing, dt_new);
    }
    s->nsteps = done + steps_for(s->t_end - time, dt_new);
    s->dt = dt_new;
    s->anchor_step = done;
    s->anchor_time = time;
}

void lub_schedule_set_end(lub_schedule *s, double t_end)
{
    s->t_end = t_end;
    s->nsteps = s->anchor_step + steps_for(t_end - s->anchor_time, s->dt);
}

int64_t lub_schedule_most_occurrences(const lub_schedule *s, int id, double from_time,
                                      double dt_max)
{
    const lub_schedule_event *e = &s->ev[id];
    const double T = e->spacing;
    /* every step dt' <= dt_max: a period of max(1, round(T/dt')) steps lasts dt' >= 2T/3 when
     * it is one step (T/dt' < 3/2), else at least T - dt'/2 >= 2T/3; and at least T - dt_max/2 */
    double shortest = fmax(2.0 * T / 3.0, T - 0.5 * dt_max);
    shortest = fmin(shortest, (double)e->every * s->dt); /* a step above dt_max in force now */
    const double span = s->t_end - from_time;
    if (!(span > 0.0))
        return 2;
    if (!(shortest > 0.0))
        return (int64_t)4e18;
    const double k = floor(span / shortest + 1e-9) + 2.0;
    return k < 4.0e18 ? (int64_t)k : (int64_t)4e18;
}
