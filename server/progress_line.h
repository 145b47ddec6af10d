/* progress_line.h — parsing the engine's progress lines (README "CLI contract"):
 *   progress fraction=0.2500 step=1200 steps_per_s=3.1e+05 eta_s=12.0
 * Pure. Returns 1 and fills *p for a progress line, 0 for any other line. */
#ifndef LUBD_PROGRESS_LINE_H
#define LUBD_PROGRESS_LINE_H

typedef struct {
    double fraction;           /* clamped to [0,1] */
    long long step;            /* -1 if absent */
    double steps_per_s, eta_s; /* -1 if absent */
} lubd_progress;

int lubd_progress_parse(const char *line, lubd_progress *p);

#endif
