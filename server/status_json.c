/* status_json.c — statusInfo rendering (OGC API - Processes 1.0 statusInfo.yaml + extras). */
#include "status_json.h"

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
