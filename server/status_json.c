/* status_json.c — statusInfo rendering (OGC API - Processes 1.0 statusInfo.yaml + extras). */
#include "status_json.h"

#include <ctype.h>
#include <math.h>
#include <stdio.h>
#include <string.h>
#include <time.h>

void lubd_rfc3339(double t, char *buf, size_t n)
{
    time_t secs = (time_t)floor(t);
    int ms = (int)((t - floor(t)) * 1000.0);
    if (ms > 999)
        ms = 999;
    struct tm tm;
    gmtime_r(&secs, &tm);
    char base[32];
    strftime(base, sizeof base, "%Y-%m-%dT%H:%M:%S", &tm);
    snprintf(buf, n, "%s.%03dZ", base, ms);
}

int lubd_job_finished(const lubd_job *j)
{
    return strcmp(j->state, "accepted") != 0 && strcmp(j->state, "running") != 0;
}

static void set_time(json_t *o, const char *key, double t)
{
    if (t < 0)
        return;
    char buf[40];
    lubd_rfc3339(t, buf, sizeof buf);
    json_object_set_new(o, key, json_string(buf));
}

static json_t *mklink(const char *href, const char *rel, const char *type, const char *title)
{
    return json_pack("{s:s, s:s, s:s, s:s}", "href", href, "rel", rel, "type", type, "title",
                     title);
}

json_t *lubd_status_json(const lubd_job *j, const char *base, int with_user)
{
    json_t *o = json_object();
    if (!o)
        return NULL;
    json_object_set_new(o, "jobID", json_string(j->id));
    json_object_set_new(o, "id", json_string(j->id));
    json_object_set_new(o, "type", json_string("process"));
    json_object_set_new(o, "processID", json_string(j->process_id));
    json_object_set_new(o, "status", json_string(j->state));
    json_t *m = json_string(j->message);
    json_object_set_new(o, "message", m ? m : json_string("(message not valid UTF-8)"));
    set_time(o, "created", j->created);
    set_time(o, "started", j->started);
    set_time(o, "finished", j->finished);
    set_time(o, "updated", j->updated);
    json_object_set_new(o, "progress", json_integer(j->progress));
    json_object_set_new(o, "attempt", json_integer(j->attempt));
    json_object_set_new(o, "maxAttempts", json_integer(j->max_attempts));
    json_object_set_new(o, "priority", json_integer(j->priority));
    if (j->failure_kind[0])
        json_object_set_new(o, "failure_kind", json_string(j->failure_kind));
    if (with_user)
        json_object_set_new(o, "user", json_string(j->user));
    char href[1200];
    json_t *links = json_array();
    snprintf(href, sizeof href, "%s/jobs/%s", base, j->id);
    json_array_append_new(links, mklink(href, "self", "application/json", "this job"));
    if (j->continue_from[0]) {
        json_object_set_new(o, "continue_from", json_string(j->continue_from));
        snprintf(href, sizeof href, "%s/jobs/%s", base, j->continue_from);
        json_array_append_new(links, mklink(href, "continues", "application/json",
                                            "the job whose checkpoint this one continues"));
    }
    if (strcmp(j->state, "successful") == 0) {
        snprintf(href, sizeof href, "%s/jobs/%s/results", base, j->id);
        json_array_append_new(links, mklink(href, "http://www.opengis.net/def/rel/ogc/1.0/results",
                                            "application/json", "results"));
    }
    snprintf(href, sizeof href, "%s/jobs/%s/log", base, j->id);
    json_array_append_new(links, mklink(href, "log", "text/plain", "engine log"));
    json_object_set_new(o, "links", links);
    return o;
}

/* n decimal digits at *s into *out (advancing *s); 0, or -1 */
static int digits(const char **s, int n, int *out)
{
    int v = 0;
    for (int i = 0; i < n; ++i, ++*s) {
        if (!isdigit((unsigned char)**s))
            return -1;
        v = v * 10 + (**s - '0');
    }
    *out = v;
    return 0;
}

/* days from 1970-01-01 to the proleptic Gregorian date y-m-d */
static long long days_from_civil(int y, int m, int d)
{
    y -= m <= 2;
    const long long era = (y >= 0 ? y : y - 399) / 400;
    const long long yoe = y - era * 400;
    const long long doy = (153 * (m + (m > 2 ? -3 : 9)) + 2) / 5 + d - 1;
    const long long doe = yoe * 365 + yoe / 4 - yoe / 100 + doy;
    return era * 146097 + doe - 719468;
}

int lubd_parse_rfc3339(const char *s, long long *floor_ms, long long *ceil_ms)
{
    int y, mo, d, h, mi, sec;
    if (digits(&s, 4, &y) || *s++ != '-' || digits(&s, 2, &mo) || *s++ != '-' || digits(&s, 2, &d))
        return -1;
    if (*s != 'T' && *s != 't' && *s != ' ')
        return -1;
    ++s;
    if (digits(&s, 2, &h) || *s++ != ':' || digits(&s, 2, &mi) || *s++ != ':' ||
        digits(&s, 2, &sec))
        return -1;
    static const int mdays[] = {31, 28, 31, 30, 31, 30, 31, 31, 30, 31, 30, 31};
    const int leap = (y % 4 == 0 && y % 100 != 0) || y % 400 == 0;
    if (mo < 1 || mo > 12 || d < 1 || d > mdays[mo - 1] + (mo == 2 && leap) || h > 23 || mi > 59 ||
        sec > 60)
        return -1;
    int ms = 0, rest = 0; /* the first 3 digits of the fraction; rest: a later one is not 0 */
    if (*s == '.') {
        ++s;
        if (!isdigit((unsigned char)*s))
            return -1;
        int taken = 0;
        for (; isdigit((unsigned char)*s); ++s) {
            if (taken < 3) {
                ms = ms * 10 + (*s - '0');
                ++taken;
            } else if (*s != '0') {
                rest = 1;
            }
        }
        for (; taken < 3; ++taken)
            ms *= 10;
    }
    int offset_min = 0;
    if (*s == 'Z' || *s == 'z') {
        ++s;
    } else if (*s == '+' || *s == '-' || *s == ' ') {
        const int sign = *s++ == '-' ? -1 : 1;
        int oh, om;
        if (digits(&s, 2, &oh) || *s++ != ':' || digits(&s, 2, &om) || oh > 23 || om > 59)
            return -1;
        offset_min = sign * (oh * 60 + om);
    } else {
        return -1;
    }
    if (*s)
        return -1;
    const long long secs =
        days_from_civil(y, mo, d) * 86400LL + h * 3600LL + mi * 60LL + sec - offset_min * 60LL;
    *floor_ms = secs * 1000 + ms;
    *ceil_ms = *floor_ms + rest;
    return 0;
}
