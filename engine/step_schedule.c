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
        const int64_t left = e->next > done ? e->next - done : 0;
        e->next = done + (int64_t)llround((double)left * scale);
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
