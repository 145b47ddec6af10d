/* step_schedule.h — the step count and the periodic events (samples, snapshots, ...) of a run
 * whose time step may change while it runs.
 *
 * A run of duration t_end at step dt has nsteps = ceil(t_end/dt - 1e-9) steps. An event with
 * period `every` steps and first step `first` is due at steps first, first + every, ... (the
 * form `(step + 1) % every == 0` is first = every - 1; `step % every == 0` is first = 0). When
 * An occurrence at step k stands for the start of that step (time t_k). When
 * the step changes to dt' after `done` steps at time t:
 *   - nsteps becomes done + ceil((t_end - t)/dt' - 1e-9): the run still ends at t_end;
 *   - each event keeps its spacing in time: every = max(1, floor(spacing/dt' + 1/2)), and its
 *     next occurrence stays at the same time or moves up to one step later: the steps left
 *     before it, next - done, are scaled by dt/dt' and rounded up (until 2026-12-07 to the
 *     nearest, which could shorten an interval and so add occurrences beyond any bound fixed
 *     in advance).
 * With a constant step the schedule is exactly the modulo form above.
 *
 * The scenes keep t_end/dt within 1..LUB_MAX_STEPS (step_count.h) before they start and when
 * the step changes; the counts here are clamped to 4e18 only so that they stay in int64.
 *
 * Units: any time unit. Pure bookkeeping: no allocation, no global state.
 */
#ifndef LUBDEM_STEP_SCHEDULE_H
#define LUBDEM_STEP_SCHEDULE_H

#include <stdint.h>

enum { LUB_SCHEDULE_MAX_EVENTS = 8 };

typedef struct {
    int64_t every;  /* period in steps (>= 1) */
    int64_t next;   /* step index of the next occurrence */
    double spacing; /* period in time, kept across step changes */
} lub_schedule_event;

typedef struct {
    double dt;      /* current step (> 0) */
    double t_end;   /* duration of the run */
    int64_t nsteps; /* the run ends before step index nsteps */
    int n_events;
    lub_schedule_event ev[LUB_SCHEDULE_MAX_EVENTS];
    int64_t anchor_step; /* steps done and time at the last change of the step (0, 0 at init): */
    double anchor_time;  /* nsteps = anchor_step + ceil((t_end - anchor_time)/dt - 1e-9) */
} lub_schedule;

/* A run of duration t_end >= 0 at step dt > 0. */
void lub_schedule_init(lub_schedule *s, double dt, double t_end);

/* Adds an event with period `every` >= 1 steps (its spacing in time is `spacing`) first due
 * at step `first`; returns its id, or -1 when LUB_SCHEDULE_MAX_EVENTS are in use. */
int lub_schedule_add(lub_schedule *s, int64_t every, int64_t first, double spacing);

/* The period in steps of a spacing in time at step dt: max(1, floor(spacing/dt + 1/2)),
 * at most 2^62. */
int64_t lub_schedule_period(double spacing, double dt);

/* 1 if event `id` is due at step `step` (then its next occurrence is scheduled), else 0.
 * Call once per step, with increasing steps. */
static inline int lub_schedule_due(lub_schedule *s, int id, int64_t step)
{
    lub_schedule_event *e = &s->ev[id];
    if (step < e->next)
        return 0;
    e->next += e->every;
    return 1;
}

/* The step becomes dt_new > 0 after `done` steps, at time `time`: nsteps and every event are
 * rescheduled as described above. */
void lub_schedule_set_dt(lub_schedule *s, int64_t done, double time, double dt_new);
/* The most occurrences event `id` can have from time from_time to the end of the run, whatever
 * steps up to dt_max the run takes meanwhile (and the step in force now): no interval is shorter
 * than max(2/3 spacing, spacing - dt_max/2), so it is floor((t_end - from_time)/that) + 2. The
 * scenes reserve their sample buffers with it before the time loop, so a change of the step
 * never grows them. The bound assumes that the event is asked for (lub_schedule_due) at a step
 * before any lub_schedule_set_dt after that step, so that it is never overdue at a change: an
 * overdue event stays due at its old step and its next interval is the new period, which a step
 * that rises can make shorter (the scenes' sample events are asked for first; only
 * simple_shear's snapshots, which fill no buffer, can be overdue). */
int64_t lub_schedule_most_occurrences(const lub_schedule *s, int id, double from_time,
                                      double dt_max);
/* The run's duration becomes t_end (a run extended, or shortened before it got there): nsteps
 * is what it would have been had the run been started with t_end (from the same anchor), so
 * an extended run takes the steps of one that was asked for t_end from the start. */
void lub_schedule_set_end(lub_schedule *s, double t_end);

#endif
