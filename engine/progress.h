/* progress.h — progress lines on stdout, the format the server parses (README, CLI contract):
 *   progress fraction=0.2500 step=1200 steps_per_s=3.1e+05 eta_s=12.0
 * At most one line per `interval_s` of wall time, plus a final line (lub_progress_end:
 * fraction=1 when the run completed, the fraction reached when it stopped or failed; until
 * 2026-12-06 a failed run's final line said 1, which the service showed as progress 100). `step`
 * and `fraction` are the run's own (a resumed run goes on from the checkpoint's); `steps_per_s` and
 * `eta_s` count from the first lub_progress_update of this process, so the steps and the fraction a
 * resumed run started from, and the set-up before its first step, are not read as this process's;
 * the first line comes `interval_s` after the first update (one at it would have neither) (until
 * 2026-12-06 a resumed run reported all its steps over this process's time: ten times the rate, and
 * an ETA far too short). */
#ifndef LUBDEM_PROGRESS_H
#define LUBDEM_PROGRESS_H

#include <stdint.h>
#include <stdio.h>

typedef struct lub_progress {
    FILE *stream;                 /* NULL: silent */
    double interval_s;            /* minimum wall time between lines */
    double t_start;               /* wall clock at start */
    double t_last;                /* wall clock of the last line */
    double fraction;              /* last fraction passed to lub_progress_update */
    int have_base;                /* the first update has been seen */
    double t_base, fraction_base; /* wall clock and fraction at the first update */
    int64_t step_base;            /* step at the first update */
    int64_t step;                 /* last step passed to an update or last_step */
} lub_progress;

double lub_wall_seconds(void); /* monotonic clock */
void lub_progress_init(lub_progress *p, FILE *stream, double interval_s);
/* Cheap to call every step: only formats a line when the interval has passed. */
void lub_progress_update(lub_progress *p, double fraction, int64_t step);
/* The scene's last step, for the final line (the scenes call it when their loop ends). */
void lub_progress_last_step(lub_progress *p, int64_t step);
/* The final line, written by the run driver once the run's outcome is known: fraction 1 when
 * `completed`, otherwise the last fraction reached (0 before any update); step: the last one
 * passed to lub_progress_last_step or an update. */
void lub_progress_end(lub_progress *p, int completed);

#endif
