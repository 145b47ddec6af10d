/* Unit tests of progress.c: the rate and the ETA of the progress lines count from the first
 * update of the process, so a resumed run (which starts at a step and a fraction of its
 * checkpoint) reports its own speed, not all its steps over this process's time. */
#include <math.h>
#include <stdio.h>
#include <string.h>
#include <time.h>

#include "framework_check.h"
#include "progress.h"

static void sleep_s(double s)
{
    struct timespec ts = {(time_t)s, (long)((s - (double)(time_t)s) * 1e9)};
    nanosleep(&ts, NULL);
}

/* The last progress line written to f: fraction, step, rate and ETA; 1 when one was read. */
static int last_line(FILE *f, double *fraction, long long *step, double *rate, double *eta)
{
    char line[200];
    int got = 0;
    rewind(f);
    while (fgets(line, sizeof line, f))
        got = sscanf(line, "progress fraction=%lf step=%lld steps_per_s=%lf eta_s=%lf", fraction,
                     step, rate, eta) == 4;
    return got;
}

/* A run whose first update is at (f0, s0), then (f1, s1) after `pause` seconds: the line
 * reports (s1 - s0) steps over the time since the first update, and an ETA of that time
 * times (1 - f1) / (f1 - f0). */
static void check_run(double f0, long long s0, double f1, long long s1, double pause)
{
    FILE *f = tmpfile();
    CHECK(f != NULL);
    if (!f)
        return;
    lub_progress p;
    lub_progress_init(&p, f, 0.05);
    sleep_s(0.1); /* set-up before the first step: not counted */
    const double t0 = lub_wall_seconds();
    lub_progress_update(&p, f0, s0);
    CHECK(ftell(f) == 0); /* no line at the first update: it would have no rate, no ETA */
    sleep_s(pause);
    lub_progress_update(&p, f1, s1);
    const double took = lub_wall_seconds() - t0;
    double fr = -1, rate = -1, eta = -1;
    long long step = -1;
    CHECK(last_line(f, &fr, &step, &rate, &eta));
    CHECK(step == s1 && fr > f1 - 1e-4 && fr < f1 + 1e-4);
    /* the line's time since the first update lies between pause and took */
    CHECK(rate <= (double)(s1 - s0) / pause * 1.01 && rate >= (double)(s1 - s0) / took * 0.99);
    /* eta_s is printed to 0.1 s, so up to 0.05 s of rounding on top of the bounds: about 1 s
     * here, where 3 % is 0.03 s (until 2026-12-07 the bounds left the rounding out, and a
     * sleep that overran by 17 ms on a loaded host printed 1.0 for 0.95 and failed) */
    const double ratio = (1.0 - f1) / (f1 - f0), eta_print = 0.05;
    CHECK(eta >= pause * ratio * 0.97 - eta_print && eta <= took * ratio * 1.03 + eta_print);
    /* the two agree on the time: eta = (s1 - s0) / rate * ratio (rate to 3 digits) */
    const double eta_of_rate = (double)(s1 - s0) / rate * ratio;
    CHECK(fabs(eta - eta_of_rate) <= eta_print + 0.01 * eta_of_rate);
    /* the final line of a run that failed or stopped: the fraction reached, not 1 (a failed
     * run's said 1 until 2026-12-06) */
    lub_progress_last_step(&p, s1 + 10);
    lub_progress_end(&p, 0);
    CHECK(last_line(f, &fr, &step, &rate, &eta) && fr > f1 - 1e-4 && fr < f1 + 1e-4 &&
          step == s1 + 10);
    /* the final line of a completed run: fraction 1, ETA 0 */
    lub_progress_end(&p, 1);
    CHECK(last_line(f, &fr, &step, &rate, &eta) && fr == 1.0 && eta == 0.0 && step == s1 + 10);
    fclose(f);
}

int main(void)
{
    check_run(0.0, 0, 0.25, 1000, 0.3);        /* a fresh run */
    check_run(0.5, 21366, 0.55, 23366, 0.3);   /* resumed half way */
    check_run(0.9, 100000, 0.92, 100500, 0.3); /* resumed near its end */
    /* no update at all (a run that stopped at once): the line is still written */
    FILE *f = tmpfile();
    if (f) {
        lub_progress p;
        lub_progress_init(&p, f, 0.05);
        lub_progress_end(&p, 1);
        double fr, rate, eta;
        long long step;
        CHECK(last_line(f, &fr, &step, &rate, &eta) && fr == 1.0 && step == 0 && rate == 0.0);
        lub_progress_end(&p, 0); /* failed before its first step */
        CHECK(last_line(f, &fr, &step, &rate, &eta) && fr == 0.0 && step == 0);
        fclose(f);
    }
    if (failures)
        fprintf(stderr, "%d failure(s)\n", failures);
    return failures ? 1 : 0;
}
