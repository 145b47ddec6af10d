/* progress.h — progress lines on stdout, the format the server parses (README, CLI contract):
 *   progress fraction=0.2500 step=1200 steps_per_s=3.1e+05 eta_s=12.0
 * At most one line per `interval_s` of wall time, plus a final line (fraction=1 when the run
 * completed, the fraction reached when it was stopped by a signal). */
#ifndef LUBDEM_PROGRESS_H
#define LUBDEM_PROGRESS_H

#include <signal.h>
#include <stdint.h>
#include <stdio.h>

typedef struct lub_progress {
    FILE *stream;                          /* NULL: silent */
    double interval_s;                     /* minimum wall time between lines */
    double t_start;                        /* wall clock at start */
    double t_last;                         /* wall clock of the last line */
    double fraction;                       /* last fraction passed to lub_progress_update */
    volatile sig_atomic_t *stop_requested; /* optional (NULL): when set at the end, the final
                                              line reports `fraction` instead of 1 */
} lub_progress;

double lub_wall_seconds(void); /* monotonic clock */
void lub_progress_init(lub_progress *p, FILE *stream, double interval_s);
/* Cheap to call every step: only formats a line when the interval has passed. */
void lub_progress_update(lub_progress *p, double fraction, int64_t step);
/* Last line: fraction=1 for a completed run; for a run stopped by a signal, the fraction
 * reached. */
void lub_progress_final(lub_progress *p, int64_t step);

#endif
