/* api_files.c — streaming result files and logs from an fd, with ETag and single Range. */
#include <errno.h>
#include <fcntl.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "api.h"
#include "http_range.h"
#include "queue.h"
#include "spec_reader.h"
#include "status_json.h"

/* Serves an open fd (ownership passes to this function). etag may be NULL. */
static enum MHD_Result serve_fd(lubd_request *r, int fd, uint64_t size, const char *type,
                                const char *etag, const char *disposition)
{
    if (etag) {
        const char *inm = lubd_header(r, MHD_HTTP_HEADER_IF_NONE_MATCH);
        /* "*" matches any representation (RFC 9110 §13.1.2) */
        const int any = inm && strspn(inm, " \t*") == strlen(inm) && strchr(inm, '*');
        if (inm && (any || strstr(inm, etag))) {
            close(fd);
            struct MHD_Response *resp =
                MHD_create_response_from_buffer(0, NULL, MHD_RESPMEM_PERSISTENT);
            if (resp)
                MHD_add_response_header(resp, MHD_HTTP_HEADER_ETAG, etag);
            return lubd_queue(r, 304, resp);
        }
    }
    const char *range = lubd_header(r, MHD_HTTP_HEADER_RANGE);
    const char *if_range = lubd_header(r, MHD_HTTP_HEADER_IF_RANGE);
    if (range && if_range && (!etag || strcmp(if_range, etag) != 0))
        range = NULL; /* representation changed: send it whole */
    uint64_t first = 0, last = size ? size - 1 : 0;
    int kind = lubd_range_parse(range, size, &first, &last);
    char cr[96];
    if (kind == LUBD_RANGE_UNSATISFIABLE) {
        close(fd);
        lubd_fault f;
        char quoted[104];
        lub_text_one_line(range, quoted, sizeof quoted);
        lubd_fail(&f, 416, LUBD_PT_BASE "range-not-satisfiable", "Range not satisfiable", NULL,
                  "range %s is outside the %llu bytes of the file", quoted,
                  (unsigned long long)size);
        struct MHD_Response *resp =
            lubd_json_response(lubd_fault_json(&f, r->url), "application/problem+json");
        if (!resp)
            return MHD_NO;
        snprintf(cr, sizeof cr, "bytes */%llu", (unsigned long long)size);
        MHD_add_response_header(resp, MHD_HTTP_HEADER_CONTENT_RANGE, cr);
        return lubd_queue(r, 416, resp);
    }
    struct MHD_Response *resp;
    unsigned status = 200;
    if (size == 0) {
        close(fd);
        resp = MHD_create_response_from_buffer(0, NULL, MHD_RESPMEM_PERSISTENT);
    } else if (kind == LUBD_RANGE_OK) {
        status = 206;
        resp = MHD_create_response_from_fd_at_offset64(last - first + 1, fd, first);
        snprintf(cr, sizeof cr, "bytes %llu-%llu/%llu", (unsigned long long)first,
                 (unsigned long long)last, (unsigned long long)size);
    } else {
        resp = MHD_create_response_from_fd_at_offset64(size, fd, 0);
    }
    if (!resp) {
        if (size != 0)
            close(fd);
        return MHD_NO;
    }
    if (status == 206)
        MHD_add_response_header(resp, MHD_HTTP_HEADER_CONTENT_RANGE, cr);
    MHD_add_response_header(resp, MHD_HTTP_HEADER_CONTENT_TYPE, type);
    MHD_add_response_header(resp, MHD_HTTP_HEADER_ACCEPT_RANGES, "bytes");
    if (etag)
        MHD_add_response_header(resp, MHD_HTTP_HEADER_ETAG, etag);
    else
        MHD_add_response_header(resp, MHD_HTTP_HEADER_CACHE_CONTROL, "no-store");
    if (disposition)
        MHD_add_response_header(resp, MHD_HTTP_HEADER_CONTENT_DISPOSITION, disposition);
    return lubd_queue(r, status, resp);
}

enum MHD_Result lubd_api_result_file(lubd_request *r, const char *id, const char *name)
{
    lubd_fault f;
    lubd_job j;
    if (lubd_load_visible_job(r, id, &j, &f, 0) != 0)
        return lubd_reply_fault(r, &f);
    if (strcmp(j.state, "dismissed") == 0) { /* as /results: its files are gone for good */
        lubd_fail(&f, 410, LUBD_PT_BASE "job-dismissed", "Job dismissed", NULL,
                  "job %s was dismissed: %s", id, j.message);
        return lubd_reply_fault(r, &f);
    }
    /* A failed job's files are those its engine wrote and the worker kept (its summary, a
     * partial or failed result.h5, a checkpoint); they are moved and recorded like a
     * successful job's, so nothing half-written is served either. */
    if (strcmp(j.state, "successful") != 0 && strcmp(j.state, "failed") != 0) {
        lubd_fail(&f, 404, LUBD_OGC_EXC "result-not-ready", "Result not ready", NULL,
                  "job %s is %s: its files are served once it has finished", id, j.state);
        f.retry_after = 2;
        return lubd_reply_fault(r, &f);
    }
    lubd_result_file *files;
    int n;
    sqlite3 *db = lubd_db_acquire(&r->srv->pool);
    int rc = lubd_queue_results(db, id, &files, &n);
    lubd_db_release(&r->srv->pool, db); /* nothing of the DB is held while streaming */
    if (rc != 0) {
        lubd_fail(&f, 500, LUBD_PT_BASE "internal", "Internal error", NULL, "database error");
        return lubd_reply_fault(r, &f);
    }
    const lubd_result_file *rf = NULL;
    for (int i = 0; i < n; ++i)
        if (strcmp(files[i].name, name) == 0)
            rf = &files[i];
    if (!rf) {
        free(files);
        char quoted[68];
        lub_text_one_line(name, quoted, sizeof quoted);
        lubd_fail(&f, 404, LUBD_PT_BASE "no-such-output", "No such output", NULL,
                  "job %s has no output \"%s\" (see /jobs/%s/results)", id, quoted, id);
        return lubd_reply_fault(r, &f);
    }
    char path[1400], etag[80], disp[200];
    snprintf(path, sizeof path, "%s/%s/result/%s", r->srv->cfg->jobs_dir, id, rf->name);
    snprintf(etag, sizeof etag, "\"%s\"", rf->sha256);
    snprintf(disp, sizeof disp, "attachment; filename=\"%s-%s\"", id, rf->name);
    char type[64];
    snprintf(type, sizeof type, "%s", rf->media_type);
    long long expect = rf->size;
    free(files);
    int fd = open(path, O_RDONLY | O_CLOEXEC);
    struct stat st;
    if (fd < 0 || fstat(fd, &st) != 0 || !S_ISREG(st.st_mode) || st.st_size != expect) {
        if (fd >= 0)
            close(fd);
        lubd_fail(&f, 500, LUBD_PT_BASE "internal", "Internal error", NULL,
                  "result file of job %s is missing or does not match its recorded size", id);
        return lubd_reply_fault(r, &f);
    }
    return serve_fd(r, fd, (uint64_t)st.st_size, type, etag, disp);
}

enum MHD_Result lubd_api_log(lubd_request *r, const char *id)
{
    lubd_fault f;
    lubd_job j;
    if (lubd_load_visible_job(r, id, &j, &f, 0) != 0)
        return lubd_reply_fault(r, &f);
    /* The latest attempt's log: the highest attempt-N folder that holds one. Not simply that
     * of j.attempt: a job released at a service stop has its attempt count taken back (it
     * runs again under the same number), and until 2026-12-07 such a job was served an
     * empty log, for good once it was dismissed before it ran again. */
    char path[1400];
    int fd = -1;
    const int top = j.max_attempts > j.attempt ? j.max_attempts : j.attempt;
    for (int k = top; k > 0 && fd < 0; --k) {
        snprintf(path, sizeof path, "%s/%s/attempt-%d/log", r->srv->cfg->jobs_dir, id, k);
        fd = open(path, O_RDONLY | O_CLOEXEC);
    }
    struct stat st;
    if (fd < 0 || fstat(fd, &st) != 0) {
        if (fd >= 0)
            close(fd);
        /* Not started yet (or no log): an empty log. */
        struct MHD_Response *resp =
            MHD_create_response_from_buffer(0, NULL, MHD_RESPMEM_PERSISTENT);
        if (resp)
            MHD_add_response_header(resp, MHD_HTTP_HEADER_CONTENT_TYPE,
                                    "text/plain; charset=utf-8");
        return lubd_queue(r, 200, resp);
    }
    return serve_fd(r, fd, (uint64_t)st.st_size, "text/plain; charset=utf-8", NULL, NULL);
}
