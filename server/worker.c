/* worker.c — the worker loop and the life of one job attempt. */
#define _GNU_SOURCE
#include "worker.h"

#include <dirent.h>
#include <errno.h>
#include <fcntl.h>
#include <jansson.h>
#include <poll.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/prctl.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include "checkpoint_file.h"
#include "continuation.h"
#include "periodic_checkpoint.h"
#include "state_checkpoint.h"
#include "db.h"
#include "deletion.h"
#include "engine_child.h"
#include "fsutil.h"
#include "lease.h"
#include "progress_line.h"
#include "queue.h"
#include "scene.h"
#include "status_json.h"

typedef struct {
    const lubd_config *cfg;
    sqlite3 *db;
    char name[64];
    volatile sig_atomic_t *stop;
} worker_ctx;

static volatile sig_atomic_t worker_stop_flag = 0; /* written by the signal handler only */

static void on_term(int sig)
{
    (void)sig;
    worker_stop_flag = 1;
}

static double now_s(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static void sleep_ms(int ms)
{
    struct timespec ts = {ms / 1000, (long)(ms % 1000) * 1000000L};
    nanosleep(&ts, NULL);
}

static const char *media_type_of(const char *name)
{
    size_t n = strlen(name);
    if (n > 3 && strcmp(name + n - 3, ".h5") == 0)
        return "application/x-hdf5";
    if (n > 5 && strcmp(name + n - 5, ".json") == 0)
        return "application/json";
    return "application/octet-stream";
}

/* The engine's last line in the log that is not a progress line (the last "error" line if
 * there is one), as the failure diagnostic; the worker's own "lubdemd: " lines are left out.
 * Only what follows byte `from` is read: the lines of the engine that ran last (an attempt
 * that runs again under its number appends to its first run's log, and until 2026-12-06 an
 * engine that died without a word was given the first run's last error). */
static void log_diagnostic(const char *log_path, off_t from, char *out, size_t n)
{
    out[0] = '\0';
    int fd = open(log_path, O_RDONLY | O_CLOEXEC);
    if (fd < 0)
        return;
    char buf[8192];
    off_t end = lseek(fd, 0, SEEK_END);
    off_t start = end > (off_t)sizeof buf - 1 ? end - (off_t)sizeof buf + 1 : 0;
    if (start < from)
        start = from;
    ssize_t got = pread(fd, buf, sizeof buf - 1, start);
    close(fd);
    if (got <= 0)
        return;
    buf[got] = '\0';
    char *save = NULL, *best = NULL, *best_error = NULL;
    for (char *line = strtok_r(buf, "\n", &save); line; line = strtok_r(NULL, "\n", &save)) {
        if (strncmp(line, "progress ", 9) == 0 || strncmp(line, "lubdemd: ", 9) == 0 ||
            line[0] == '\0')
            continue;
        best = line;
        if (strncmp(line, "error", 5) == 0)
            best_error = line;
    }
    if (best_error)
        best = best_error;
    if (best)
        snprintf(out, n, "%s", best);
}

/* summary.json "diagnostic" member if present. */
static void summary_diagnostic(const char *out_dir, char *out, size_t n)
{
    char path[1400];
    lubd_pathf(path, sizeof path, "%s/summary.json", out_dir);
    json_t *s = json_load_file(path, 0, NULL);
    json_t *d = json_object_get(s, "diagnostic");
    if (json_is_string(d))
        snprintf(out, n, "%s", json_string_value(d));
    else if (json_is_object(d)) {
        char *txt = json_dumps(d, JSON_COMPACT);
        if (txt)
            snprintf(out, n, "%s", txt);
        free(txt);
    }
    json_decref(s);
}

/* Keeps the lease of a job alive while its outputs are checksummed: a large result.h5 takes
 * longer than a lease (85-170 MB/s on the 2-core host), and a lease let go there had the
 * reaper requeue a run that had completed. */
typedef struct {
    worker_ctx *w;
    const lubd_claim *c;
    double next_beat;
    int lost; /* the lease was lost or the job dismissed meanwhile */
} finishing_beat;

/* seconds a worker goes on asking a database that refuses to record a completed run */
#define RECORD_TRIES 30

static int beat_while_finishing(void *ctx)
{
    finishing_beat *b = ctx;
    const double t = now_s();
    if (t < b->next_beat)
        return 0;
    double every = b->w->cfg->lease_s / 3.0;
    b->next_beat = t + (every > 1.0 ? 1.0 : every);
    /* a database error is not a lost lease: the next beat tries again */
    if (lubd_lease_heartbeat(b->w->db, b->c, b->w->cfg->lease_s, -1, NULL, 0) == 0)
        b->lost = 1;
    return b->lost;
}

/* the most output files a job lists (the engine writes 4 at most) */
#define MAX_OUTPUTS 16

/* Enumerates the output files and checksums them, heartbeating through *beat. The engine's
 * temporary files (".name" or "name.tmp": half-written, e.g. the .result.h5.tmp of an engine
 * killed mid-run) are removed, so that they do not go into result/ unlisted with the rest.
 * Called once the engine has exited. Returns the count, or -1: beat->lost, or why (also on
 * stderr) says what cannot be listed: the folder cannot be read, a file cannot be read (its
 * name and errno), a name too long or more than `max` files. Such a file is never skipped:
 * it would go into result/ unlisted (until 2026-12-07 an unreadable result.h5 failed a
 * completed run as missing, an unreadable checkpoint.h5 left a job that could not be
 * continued, and files beyond the 16th were dropped without a word). */
static int collect_outputs(const char *out_dir, lubd_output_file *files, char names[][64], int max,
                           finishing_beat *beat, char *why, size_t why_len)
{
    why[0] = '\0';
    DIR *d = opendir(out_dir);
    if (!d) {
        lubd_pathf(why, why_len, "cannot read the engine's output folder: %s", strerror(errno));
        fprintf(stderr, "lubdemd worker: %s: %s\n", out_dir, why);
        return -1;
    }
    int n = 0;
    struct dirent *e;
    while (!why[0] && (e = readdir(d))) {
        if (strcmp(e->d_name, ".") == 0 || strcmp(e->d_name, "..") == 0)
            continue;
        const size_t len = strlen(e->d_name);
        char path[1400];
        if (lubd_pathf(path, sizeof path, "%s/%s", out_dir, e->d_name) != 0)
            continue;
        if (e->d_name[0] == '.' || (len > 4 && strcmp(e->d_name + len - 4, ".tmp") == 0)) {
            struct stat tmp_st;
            if (lstat(path, &tmp_st) == 0 && S_ISREG(tmp_st.st_mode) && unlink(path) != 0)
                fprintf(stderr, "lubdemd worker: cannot remove the temporary file %s: %s\n", path,
                        strerror(errno));
            continue;
        }
        struct stat st;
        if (lstat(path, &st) != 0 || !S_ISREG(st.st_mode))
            continue;
        if (len >= 64) {
            lubd_pathf(why, why_len, "the engine's output %.64s... has a name too long to list",
                       e->d_name);
            break;
        }
        if (n == max) {
            lubd_pathf(why, why_len, "the engine left more than %d files", max);
            break;
        }
        uint64_t size;
        lubd_pathf(names[n], 64, "%s", e->d_name);
        if (beat_while_finishing(beat) != 0 ||
            lubd_file_sha256(path, files[n].sha256, &size, beat_while_finishing, beat) != 0) {
            if (!beat->lost)
                lubd_pathf(why, why_len, "cannot read the engine's output %s: %s", e->d_name,
                           strerror(errno));
            break;
        }
        files[n].name = names[n];
        files[n].media_type = media_type_of(names[n]);
        files[n].size = (long long)size;
        ++n;
    }
    closedir(d);
    if (beat->lost)
        return -1;
    if (why[0]) {
        fprintf(stderr, "lubdemd worker: %s: %s\n", out_dir, why);
        return -1;
    }
    return n;
}

/* The wall clock that stamps files (Linux: the coarse real-time clock, one tick behind the
 * precise one at most): a file written after this instant never has an earlier mtime. */
static double wall_now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_REALTIME_COARSE, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* A file's modification time (s since the epoch, sub-second), -1 when it cannot be read. */
static double mtime_of(const char *path)
{
    struct stat st;
    if (stat(path, &st) != 0)
        return -1.0;
    return (double)st.st_mtim.tv_sec + 1e-9 * (double)st.st_mtim.tv_nsec;
}

/* 1 when the checkpoint at path is a periodic one: it names checkpoint-result.h5 as the file
 * holding its rows (periodic_checkpoint.h), not result.h5; 0 otherwise or unreadable. */
static int names_periodic_rows(const char *path)
{
    char err[300];
    lub_ckpt *ck = lub_ckpt_open(path, err, sizeof err);
    char *rows = ck ? lub_ckpt_get_text(ck, "output_file") : NULL;
    const int periodic = rows && strcmp(rows, LUB_PERIODIC_OUTPUT) == 0;
    free(rows);
    lub_ckpt_close(ck, NULL, 0);
    return periodic;
}

/* Removes the first `count` of summary.json and result.h5 from out_dir where they are older
 * than `started` (an earlier run's). */
static void drop_older(const char *out_dir, double started, int count)
{
    static const char *const old[2] = {"summary.json", "result.h5"};
    for (int k = 0; k < count; ++k) {
        char path[1400];
        lubd_pathf(path, sizeof path, "%s/%s", out_dir, old[k]);
        const double t = mtime_of(path);
        if (t >= 0.0 && t < started && unlink(path) != 0)
            fprintf(stderr, "lubdemd worker: cannot remove %s: %s\n", path, strerror(errno));
    }
}

/* After an engine killed mid-run that had written a periodic checkpoint of its own (a
 * checkpoint.h5 newer than `started` that names checkpoint-result.h5 as the file holding its
 * rows, periodic_checkpoint.h): the summary.json and result.h5 in out_dir older than the engine
 * are those of the stopped run it continued from, which that checkpoint supersedes; they go, so
 * that the job is not served the summary and rows of an earlier point of its run as its own.
 * A checkpoint that names result.h5 (the stopped run's own) keeps them. */
static void drop_superseded(const char *out_dir, double started)
{
    char path[1400];
    lubd_pathf(path, sizeof path, "%s/checkpoint.h5", out_dir);
    if (mtime_of(path) >= started && names_periodic_rows(path))
        drop_older(out_dir, started, 2);
}

/* After an engine run with --resume that died by a signal (a crash, the hard CPU time limit,
 * a SIGKILL from outside): it wrote no summary.json, so one older than its start is the
 * earlier run's (a stop's "interrupted", which says --resume continues it) and goes, so that
 * it is served neither as this attempt's summary nor as its diagnostic. A result.h5 older
 * than the engine goes too unless the checkpoint kept with it may need it as its rows' file
 * (one that does not name checkpoint-result.h5): the checkpoint stays, and with it what a
 * continuation needs. */
static void drop_stale(const char *out_dir, double started)
{
    char path[1400];
    lubd_pathf(path, sizeof path, "%s/checkpoint.h5", out_dir);
    const int rows_needed = access(path, F_OK) == 0 && !names_periodic_rows(path);
    drop_older(out_dir, started, rows_needed ? 1 : 2);
}

/* what the job log adds when a continuation starts from files handed over to it */
#define HANDED_NOTE " (kept for this job when that job was deleted)"

/* Puts the files a continuation starts from into out_dir: the earlier job's kept files, or,
 * once that job has been deleted, the links it handed over to this job
 * (jobs/<id>/continued-from/, lubd_continuation_hand_over). The handed-over folder is complete
 * whenever it exists, and exists before the earlier job's folder is removed; a deletion that
 * lands while the files are being linked is met by taking them again from it. Returns 0 (the
 * earlier job's folder), 1 (the handed-over files) or -1 with msg set. */
static int take_source_files(const lubd_config *cfg, const lubd_claim *c, const char *out_dir,
                             char *msg, size_t len)
{
    char handed[1300], source[1300], ckpt[1400], why[600] = "";
    lubd_pathf(handed, sizeof handed, "%s/%s/" LUBD_CONTINUED_FROM, cfg->jobs_dir, c->id);
    lubd_pathf(source, sizeof source, "%s/%s/result", cfg->jobs_dir, c->continue_from);
    lubd_pathf(ckpt, sizeof ckpt, "%s/checkpoint.h5", handed);
    const int was_handed = access(ckpt, F_OK) == 0;
    const char *from[2] = {was_handed ? handed : source, was_handed ? NULL : handed};
    for (int k = 0; k < 2 && from[k]; ++k) {
        if (lubd_rm_rf(out_dir) != 0) {
            lubd_pathf(msg, len, "system error: cannot clear %s: %s", out_dir, strerror(errno));
            return -1;
        }
        if (lubd_continuation_link_files(from[k], out_dir, why, sizeof why) == 0)
            return from[k] == handed;
        if (errno != ENOENT)
            break;
    }
    lubd_pathf(msg, len, "cannot continue job %s: %s%s", c->continue_from, why,
               errno == ENOENT ? " (the job was deleted, and its files were not kept for this one)"
                               : "");
    return -1;
}

/* END_WALL_LIMIT: this service stopped the engine at its wall-clock limit (lubdemd --wall-s) */
typedef enum { END_EXITED, END_LOST, END_SHUTDOWN, END_WALL_LIMIT } end_reason;

/* Watches a started engine to its end: copies its output into the log, turns its progress
 * lines into heartbeats, and stops it (SIGTERM, then SIGKILL after the grace time) when the
 * service stops, the lease is lost or the engine has run for the service's wall-clock limit. Leaves
 * the engine's wait status in *status_out and the CPU time it used (user + system, s) in
 * *cpu_s_out. */
static end_reason supervise_engine(worker_ctx *w, const lubd_claim *c,
                                   const lubd_engine_proc *ep_in, int log_fd, int *status_out,
                                   double *cpu_s_out)
{
    struct rusage ru;
    memset(&ru, 0, sizeof ru);
    const lubd_config *cfg = w->cfg;
    lubd_engine_proc ep = *ep_in;
    double hb_every = cfg->lease_s / 3.0;
    if (hb_every > 1.0)
        hb_every = 1.0;
    double next_hb = 0, kill_at = -1;
    const double wall_end = cfg->wall_s > 0 ? now_s() + (double)cfg->wall_s : -1.0;
    int progress = 0, progress_dirty = 1, pipe_open = 1, exited = 0, status = 0;
    char message[200] = "running";
    end_reason why = END_EXITED;
    char line[4096];
    size_t line_len = 0;
    while (!exited || pipe_open) {
        if (pipe_open) {
            struct pollfd pfd = {ep.stdout_fd, POLLIN, 0};
            int pr = poll(&pfd, 1, 200);
            if (pr > 0) {
                char buf[4096];
                ssize_t got = read(ep.stdout_fd, buf, sizeof buf);
                if (got <= 0 && !(got < 0 && errno == EINTR)) {
                    pipe_open = 0;
                } else if (got > 0) {
                    ssize_t wr = write(log_fd, buf, (size_t)got);
                    (void)wr;
                    for (ssize_t i = 0; i < got; ++i) {
                        if (buf[i] != '\n') {
                            if (line_len < sizeof line - 1)
                                line[line_len++] = buf[i];
                            continue;
                        }
                        line[line_len] = '\0';
                        line_len = 0;
                        lubd_progress p;
                        if (lubd_progress_parse(line, &p)) {
                            progress = (int)(p.fraction * 100.0);
                            if (p.eta_s >= 0)
                                snprintf(message, sizeof message,
                                         "running: %.1f%% (step %lld, eta %.0f s)",
                                         p.fraction * 100.0, p.step, p.eta_s);
                            else
                                snprintf(message, sizeof message, "running: %.1f%%",
                                         p.fraction * 100.0);
                            progress_dirty = 1;
                        }
                    }
                }
            }
        } else {
            sleep_ms(50);
        }
        if (!exited) { /* ended, but left unreaped (WNOWAIT) until its group is killed */
            siginfo_t si;
            memset(&si, 0, sizeof si);
            if (waitid(P_PID, (id_t)ep.pid, &si, WEXITED | WNOHANG | WNOWAIT) == 0 &&
                si.si_pid == ep.pid)
                exited = 1;
        }
        if (exited && pipe_open) {
            /* Drain what is left without blocking forever on a grandchild holding it. */
            struct pollfd pfd = {ep.stdout_fd, POLLIN, 0};
            if (poll(&pfd, 1, 0) <= 0)
                pipe_open = 0;
        }
        double t = now_s();
        if (*w->stop && kill_at < 0 && !exited) { /* an engine that has ended is finished */
            why = END_SHUTDOWN;
            kill(-ep.pid, SIGTERM);
            kill_at = t + cfg->grace_s;
        }
        if (wall_end >= 0 && t >= wall_end && kill_at < 0 && !exited) {
            why = END_WALL_LIMIT;
            kill(-ep.pid, SIGTERM);
            kill_at = t + cfg->grace_s;
        }
        if (!exited && t >= next_hb) {
            int hb = lubd_lease_heartbeat(w->db, c, cfg->lease_s, progress_dirty ? progress : -1,
                                          progress_dirty ? message : NULL, (long)ep.pid);
            progress_dirty = 0;
            next_hb = t + hb_every;
            if (hb == 0 && kill_at < 0) { /* lease lost or job dismissed: stop now */
                why = END_LOST;
                kill(-ep.pid, SIGTERM);
                kill_at = t + cfg->grace_s;
            }
        }
        if (kill_at >= 0 && !exited && t >= kill_at) {
            kill(-ep.pid, SIGKILL);
            kill_at = t + 3600;
        }
    }
    close(ep.stdout_fd);
    /* anything the engine left behind in its group; the engine is reaped only then, so that
     * its process-group id cannot have been reused by an unrelated group when the signal goes
     * (until 2026-12-06 it was reaped first) */
    kill(-ep.pid, SIGKILL);
    pid_t reaped;
    do
        reaped = wait4(ep.pid, &status, 0, &ru);
    while (reaped < 0 && errno == EINTR);
    *status_out = status;
    *cpu_s_out = (double)ru.ru_utime.tv_sec + 1e-6 * (double)ru.ru_utime.tv_usec +
                 (double)ru.ru_stime.tv_sec + 1e-6 * (double)ru.ru_stime.tv_usec;
    return why;
}

/* What the phases of one job attempt (run_job) share. */
typedef struct {
    worker_ctx *w;
    const lubd_claim *c;
    char job_dir[1200], attempt_dir[1300], out_dir[1400], spec_path[1400], log_path[1400],
        result_dir[1300];
    int resume;      /* out_dir holds the checkpoint the engine continues from (--resume) */
    int resume_from; /* the kept out folder: -1 none, 0 this attempt's own, 1 the previous one's */
    int from_other;  /* out_dir holds the files of the job this one continues ("continue_from") */
    int log_fd;
    lubd_engine_opts eo;
    end_reason why;           /* how the engine's supervision ended */
    int status;               /* the engine's wait status */
    char st_text[200];        /* the status in words, as the log states it */
    double cpu_used;          /* CPU time the engine used (user + system, s) */
    double started_at;        /* wall clock when the engine started (wall_now) */
    off_t log_from;           /* the log's size when the engine started: what it wrote follows */
    int killed_outside;       /* SIGKILL from outside this service (assess_kill_from_outside) */
    int killed_at_wall_limit; /* SIGKILL at this service's wall-clock limit (the same) */
    int have_ckpt;            /* ... that left out/checkpoint.h5 */
    int crashed_resumed; /* an engine run with --resume died by a signal, its checkpoint kept */
    /* why a checkpoint of an earlier run could not be kept, or "" */
    char keep_failure[3200];
    char ckpt_note[300]; /* the checkpoint a next attempt or a continuation starts from */
    char msg[900];
} job_attempt;

static void attempt_paths(job_attempt *a)
{
    const lubd_config *cfg = a->w->cfg;
    snprintf(a->job_dir, sizeof a->job_dir, "%s/%s", cfg->jobs_dir, a->c->id);
    snprintf(a->attempt_dir, sizeof a->attempt_dir, "%s/attempt-%d", a->job_dir, a->c->attempt);
    snprintf(a->out_dir, sizeof a->out_dir, "%s/out", a->attempt_dir);
    snprintf(a->spec_path, sizeof a->spec_path, "%s/spec.json", a->attempt_dir);
    snprintf(a->log_path, sizeof a->log_path, "%s/log", a->attempt_dir);
    snprintf(a->result_dir, sizeof a->result_dir, "%s/result", a->job_dir);
}

/* A job that ran before continues from its engine's checkpoint (lubdem run --resume)
 * instead of from the beginning: an attempt released when the service stopped runs again
 * under the same number, and its engine left out/checkpoint.h5 when it stopped; a job
 * requeued after its worker died runs as the next attempt, and the previous attempt's
 * engine left the last of its periodic checkpoints (--checkpoint-s). That out folder is
 * kept (moved aside, then into this attempt's folder); the rest of the attempt folder (the
 * leftovers of a crash) is cleared as before. */
static void keep_checkpointed_out(job_attempt *a, const char *keep_dir)
{
    char ckpt_path[1500], prev_out[1400];
    snprintf(prev_out, sizeof prev_out, "%s/attempt-%d/out", a->job_dir, a->c->attempt - 1);
    /* 0: this attempt's own out folder, 1: the previous one's */
    const char *sources[2] = {a->out_dir, a->c->attempt > 1 ? prev_out : NULL};
    const int cleared = lubd_rm_rf(keep_dir) == 0;
    const int clear_errno = errno;
    for (int k = 0; k < 2 && !a->resume && sources[k]; ++k) {
        snprintf(ckpt_path, sizeof ckpt_path, "%s/checkpoint.h5", sources[k]);
        if (access(ckpt_path, F_OK) != 0)
            continue;
        a->resume = cleared && rename(sources[k], keep_dir) == 0;
        if (a->resume)
            a->resume_from = k;
        else if (!a->keep_failure[0]) /* until 2026-12-06 this went without a word */
            lubd_pathf(a->keep_failure, sizeof a->keep_failure,
                       "the checkpoint %s could not be kept (cannot %s %s: %s)", ckpt_path,
                       cleared ? "move its folder to" : "clear", keep_dir,
                       strerror(cleared ? errno : clear_errno));
    }
    if (a->keep_failure[0])
        fprintf(stderr, "lubdemd worker: job %s: %s\n", a->c->id, a->keep_failure);
}

/* The log of an attempt that runs again under its number (released when the service
 * stopped) is kept and appended to: what its first run printed (its progress, the stop,
 * the engine's warnings) stays in attempt-<n>/log. Returns 1 when it was moved to keep_log. */
static int keep_attempt_log(const job_attempt *a, const char *keep_log)
{
    int kept_log = 0;
    if (unlink(keep_log) == 0 || errno == ENOENT) {
        char old_log[1400];
        snprintf(old_log, sizeof old_log, "%s/log", a->attempt_dir);
        kept_log = rename(old_log, keep_log) == 0;
    }
    return kept_log;
}

/* Clears the attempt folder, putting back the kept out folder and log, and writes the spec
 * into it. Returns 0, or -1 when the job has been failed. */
static int prepare_attempt_folder(job_attempt *a)
{
    char keep_dir[1400], keep_log[1400];
    snprintf(keep_dir, sizeof keep_dir, "%s/resume-out", a->job_dir);
    snprintf(keep_log, sizeof keep_log, "%s/resume-log", a->job_dir);
    keep_checkpointed_out(a, keep_dir);
    const int kept_log = keep_attempt_log(a, keep_log);
    if (lubd_rm_rf(a->attempt_dir) != 0 || lubd_mkdir_p(a->attempt_dir, 0750) != 0 ||
        (a->resume && rename(keep_dir, a->out_dir) != 0) ||
        (kept_log && rename(keep_log, a->log_path) != 0) ||
        lubd_write_file_atomic(a->spec_path, a->c->spec_json, strlen(a->c->spec_json)) != 0) {
        lubd_pathf(a->msg, sizeof a->msg, "system error: cannot prepare %s: %s", a->attempt_dir,
                   strerror(errno));
        lubd_lease_fail(a->w->db, a->c, "system", a->msg);
        return -1;
    }
    return 0;
}

/* Opens the attempt's log for appending (a kept log goes on). Returns 0, or -1 when the job
 * has been failed. */
static int open_log(job_attempt *a)
{
    a->log_fd = open(a->log_path, O_WRONLY | O_CREAT | O_APPEND | O_CLOEXEC, 0640);
    if (a->log_fd < 0) {
        snprintf(a->msg, sizeof a->msg, "system error: cannot open the log: %s", strerror(errno));
        lubd_lease_fail(a->w->db, a->c, "system", a->msg);
        return -1;
    }
    return 0;
}

/* The attempt's first line in the log: which job, attempt and worker, and which checkpoint
 * it continues from. */
static void write_log_header(const job_attempt *a)
{
    const lubd_claim *c = a->c;
    if (a->resume_from == 1) {
        char ckpt_now[1500], step_note[64] = "";
        lubd_pathf(ckpt_now, sizeof ckpt_now, "%s/checkpoint.h5", a->out_dir);
        const long long step = lub_run_checkpoint_step(ckpt_now);
        if (step >= 0)
            snprintf(step_note, sizeof step_note, "step %lld, ", step);
        dprintf(a->log_fd,
                "lubdemd: job %s attempt %d on worker %s, continuing from the checkpoint of "
                "attempt %d (%sthe last one its engine left)\n",
                c->id, c->attempt, a->w->name, c->attempt - 1, step_note);
    } else
        dprintf(a->log_fd, "lubdemd: job %s attempt %d on worker %s%s\n", c->id, c->attempt,
                a->w->name, a->resume ? ", continuing from the checkpoint of its stopped run" : "");
    if (a->keep_failure[0])
        dprintf(a->log_fd, "lubdemd: %s; %s\n", a->keep_failure,
                a->resume                ? "continuing from the previous attempt's instead"
                : a->c->continue_from[0] ? "this attempt starts again from the files of the job "
                                           "it continues"
                                         : "this attempt starts from the beginning");
}

/* A job submitted with "continue_from" that has no checkpoint of its own yet starts from
 * the earlier job's kept files. Returns 0, or -1 when the job has been failed (the log
 * closed). */
static int take_continued_files(job_attempt *a)
{
    a->from_other = !a->resume && a->c->continue_from[0];
    if (!a->from_other)
        return 0;
    const int taken = take_source_files(a->w->cfg, a->c, a->out_dir, a->msg, sizeof a->msg);
    if (taken < 0) {
        dprintf(a->log_fd, "lubdemd: %s\n", a->msg);
        close(a->log_fd);
        lubd_lease_fail(a->w->db, a->c, "executor", a->msg);
        return -1;
    }
    dprintf(a->log_fd, "lubdemd: continuing the run of job %s from its checkpoint%s\n",
            a->c->continue_from, taken ? HANDED_NOTE : "");
    a->resume = 1;
    return 0;
}

static void set_engine_options(job_attempt *a)
{
    const lubd_config *cfg = a->w->cfg;
    const lub_scene *scene = lub_scene_find(a->c->process_id);
    a->eo = (lubd_engine_opts){.engine = cfg->engine,
                               .spec = a->spec_path,
                               .out_dir = a->out_dir,
                               .log_fd = a->log_fd,
                               .cpu_s = cfg->cpu_s,
                               .mem_mb = cfg->mem_mb,
                               .fsize_mb = cfg->fsize_mb,
                               .threads = cfg->engine_threads,
                               .resume = a->resume,
                               /* only a scene that takes checkpoints is given the option
                                * (the engine warns that it ignores it otherwise) */
                               .checkpoint_s = scene && scene->resumable ? cfg->checkpoint_s : 0,
                               .keep_checkpoint = cfg->keep_checkpoints && scene &&
                                                  scene->resume_may_differ != NULL};
}

/* The engine used up the hard CPU time limit of this service (lubdemd --cpu-s). */
static int reached_cpu_limit(const job_attempt *a)
{
    return a->w->cfg->cpu_s > 0 && a->cpu_used >= (double)a->w->cfg->cpu_s;
}

/* Puts the engine's end in words into st_text and the log. */
static void log_engine_end(job_attempt *a)
{
    lubd_describe_status(a->status, a->st_text, sizeof a->st_text);
    if (a->why == END_EXITED && WIFSIGNALED(a->status) && WTERMSIG(a->status) == SIGKILL &&
        reached_cpu_limit(a))
        snprintf(a->st_text, sizeof a->st_text,
                 "killed by signal 9 (SIGKILL) at the hard CPU time limit of this service "
                 "(%.0f s of CPU; lubdemd --cpu-s %ld, then 5 s to stop after SIGXCPU)",
                 a->cpu_used, a->w->cfg->cpu_s);
    if (a->why == END_WALL_LIMIT && WIFSIGNALED(a->status) && WTERMSIG(a->status) == SIGKILL)
        snprintf(a->st_text, sizeof a->st_text,
                 "killed by signal 9 (SIGKILL) by this service at its wall-clock limit (%ld s; "
                 "lubdemd --wall-s): it did not stop within %d s of SIGTERM (lubdemd --grace-s)",
                 a->w->cfg->wall_s, a->w->cfg->grace_s);
    else if (a->why == END_WALL_LIMIT) {
        const size_t used = strlen(a->st_text);
        snprintf(a->st_text + used, sizeof a->st_text - used,
                 ", stopped by this service at its wall-clock limit (%ld s; lubdemd --wall-s)",
                 a->w->cfg->wall_s);
    }
    dprintf(a->log_fd, "lubdemd: engine finished: %s\n", a->st_text);
}

/* After the engine refused to continue from the checkpoint (exit 2): clears out_dir and
 * puts there the files of the job this one continues, if any. Returns 0, or -1 when the job
 * has been failed (the log closed). */
static int start_again(job_attempt *a)
{
    const lubd_claim *c = a->c;
    if (lubd_rm_rf(a->out_dir) != 0) {
        lubd_pathf(a->msg, sizeof a->msg, "system error: cannot clear %s: %s", a->out_dir,
                   strerror(errno));
        dprintf(a->log_fd, "lubdemd: %s\n", a->msg);
        close(a->log_fd);
        lubd_lease_fail(a->w->db, c, "system", a->msg);
        return -1;
    }
    a->from_other = c->continue_from[0] != '\0';
    const int taken =
        a->from_other ? take_source_files(a->w->cfg, c, a->out_dir, a->msg, sizeof a->msg) : 0;
    if (taken < 0) {
        dprintf(a->log_fd, "lubdemd: %s\n", a->msg);
        close(a->log_fd);
        lubd_lease_fail(a->w->db, c, "executor", a->msg);
        return -1;
    }
    dprintf(a->log_fd,
            "lubdemd: the engine cannot continue from the checkpoint (its reason above); "
            "starting the job again from %s%s%s\n",
            a->from_other ? "the checkpoint of job " : "the beginning",
            a->from_other ? c->continue_from : "", taken ? HANDED_NOTE : "");
    a->eo.resume = a->from_other;
    return 0;
}

/* Starts the engine and supervises it to its end, leaving why, status, st_text, cpu_used
 * and started_at. Returns 0, or -1 when the job has been failed (the log closed). */
static int run_engine(job_attempt *a)
{
    for (;;) {
        lubd_engine_proc ep;
        a->log_from = lseek(a->log_fd, 0, SEEK_END);
        if (a->log_from < 0)
            a->log_from = 0;
        if (lubd_engine_spawn(&a->eo, &ep) != 0) {
            snprintf(a->msg, sizeof a->msg, "system error: cannot start the engine: %s",
                     strerror(errno));
            close(a->log_fd);
            lubd_lease_fail(a->w->db, a->c, "system", a->msg);
            return -1;
        }
        a->started_at = wall_now();
        a->why = supervise_engine(a->w, a->c, &ep, a->log_fd, &a->status, &a->cpu_used);
        log_engine_end(a);
        /* Exit 2 of a continuation is the engine refusing the checkpoint (damaged, cut short,
         * its rows' file gone, or written for another spec by an older service): the job's
         * spec itself passed validation at submission. Rather than fail a job for the state
         * its own earlier run left, start it again, once: from the beginning, or, for a job
         * that continues another one, from that job's checkpoint. A refused checkpoint of
         * another job fails the job with the engine's reason. */
        if (a->why != END_EXITED || !a->eo.resume || a->from_other || !WIFEXITED(a->status) ||
            WEXITSTATUS(a->status) != 2)
            return 0;
        if (start_again(a) != 0)
            return -1;
    }
}

/* The service stops: the attempt goes back to the queue under its number. */
static void end_at_shutdown(const job_attempt *a)
{
    dprintf(a->log_fd,
            "lubdemd: the service is stopping: the job goes back to the queue, and attempt %d "
            "runs again when the service starts again\n",
            a->c->attempt);
    close(a->log_fd);
    lubd_lease_release(a->w->db, a->c);
}

/* The lease was lost (the job requeued, ended or dismissed meanwhile): the engine was
 * stopped and nothing is recorded. */
static void end_with_lost_lease(const job_attempt *a)
{
    lubd_job now;
    if (lubd_queue_get(a->w->db, a->c->id, &now) == 1 && strcmp(now.state, "dismissed") == 0)
        dprintf(a->log_fd,
                "lubdemd: the job was dismissed (DELETE) while it ran: the service stopped "
                "its engine and removes the files it wrote, so nothing of this run can be "
                "continued (whatever the engine said above)\n");
    else
        dprintf(a->log_fd, "lubdemd: this attempt lost its lease (its job was requeued or "
                           "ended meanwhile): the engine was stopped\n");
    close(a->log_fd);
    lubd_lease_drop(a->w->db, a->c);
}

/* An engine killed with SIGKILL by something other than this service (the kernel's OOM
 * killer, an operator; not the hard CPU time limit, which the message above names, nor a
 * DELETE or the service's stop, which end as END_LOST / END_SHUTDOWN) is what a worker's
 * death is to the job: it runs again as its next attempt, from the checkpoint the engine
 * left (its last periodic one), up to max_attempts. Sets killed_outside, have_ckpt and
 * ckpt_note, and drops the files such a checkpoint supersedes. */
static void assess_kill_from_outside(job_attempt *a)
{
    /* an engine killed at the wall-clock limit (it did not stop within the grace time after
     * SIGTERM) is not retried, but its files are treated as those of one killed from outside */
    const int killed =
        WIFSIGNALED(a->status) && WTERMSIG(a->status) == SIGKILL && !reached_cpu_limit(a);
    a->killed_outside = killed && a->why != END_WALL_LIMIT;
    a->killed_at_wall_limit = killed && a->why == END_WALL_LIMIT;
    char ckpt_file[1500];
    lubd_pathf(ckpt_file, sizeof ckpt_file, "%s/checkpoint.h5", a->out_dir);
    const double ckpt_time = killed ? mtime_of(ckpt_file) : -1.0;
    a->have_ckpt = ckpt_time >= 0.0;
    const long long ckpt_step = a->have_ckpt ? lub_run_checkpoint_step(ckpt_file) : -1;
    char step_text[64] = "";
    if (ckpt_step >= 0)
        snprintf(step_text, sizeof step_text, " of step %lld", ckpt_step);
    if (a->have_ckpt && ckpt_time >= a->started_at)
        snprintf(a->ckpt_note, sizeof a->ckpt_note,
                 "the checkpoint%s (the last periodic one its engine wrote, %.0f s before the "
                 "kill)",
                 step_text, wall_now() - ckpt_time);
    else if (a->have_ckpt)
        snprintf(a->ckpt_note, sizeof a->ckpt_note,
                 "the checkpoint%s its engine started from (it wrote no periodic one)", step_text);
    if (killed)
        drop_superseded(a->out_dir, a->started_at);
}

/* An engine killed from outside with attempts left: the job runs again as its next attempt. */
static void requeue_killed(job_attempt *a)
{
    const lubd_claim *c = a->c;
    snprintf(a->msg, sizeof a->msg,
             "requeued: the engine was killed by signal 9 (SIGKILL) on attempt %d of %d, not "
             "by this service (the kernel's OOM killer, or an operator); attempt %d %s%s",
             c->attempt, c->max_attempts, c->attempt + 1,
             a->have_ckpt ? "continues from "
                          : "starts again from the beginning (the engine had left no "
                            "checkpoint; simple_shear and resuspension write periodic ones "
                            "under lubdemd --checkpoint-s)",
             a->ckpt_note);
    dprintf(a->log_fd, "lubdemd: %s\n", a->msg);
    close(a->log_fd);
    const int rq = lubd_lease_requeue(a->w->db, c, a->msg);
    if (rq == 0)
        lubd_lease_drop(a->w->db, c);
    else if (rq < 0) /* the lease lapses and the reaper requeues it */
        fprintf(stderr, "lubdemd worker %s: could not requeue %s\n", a->w->name, c->id);
}

/* One try at recording the attempt's end: a success (kind NULL) with its n files, or a
 * failure of `kind` with its files while they are in out_dir (a failure is recorded without
 * them once they are not: a rename back after a refusal that failed). Returns as
 * lubd_lease_succeed, -1 for a success whose files are gone. */
static int record_end_once(const job_attempt *a, const char *kind, const char *message,
                           const lubd_output_file *files, int n)
{
    sqlite3 *db = a->w->db;
    const int files_there = n > 0 && access(a->out_dir, F_OK) == 0;
    if (!kind)
        return files_there
                   ? lubd_lease_succeed(db, a->c, a->out_dir, a->result_dir, files, n, message)
                   : -1;
    return files_there ? lubd_lease_fail_with_outputs(db, a->c, kind, message, a->out_dir,
                                                      a->result_dir, files, n)
                       : lubd_lease_fail(db, a->c, kind, message);
}

/* Records the attempt's end (record_end_once). A database that refuses the record (a full
 * disk, a lock held too long) is asked again every second for RECORD_TRIES s, under the
 * lease: the files are back in out_dir after each refusal (finish_with_outputs), and neither
 * a completed run nor a failure's diagnostic is thrown away for a moment's trouble (until
 * 2026-12-07 a refused failure was not asked again: the lease lapsed, the failing run was
 * done again and the job ended as "the worker died"). A failure's last try records it without
 * its files. After that the lease lapses and the job runs again. Returns as lubd_lease_succeed. */
static int record_end_retrying(const job_attempt *a, finishing_beat *beat, const char *kind,
                               const char *message, const lubd_output_file *files, int n)
{
    worker_ctx *w = a->w;
    int done = record_end_once(a, kind, message, files, n);
    for (int tries = 1; done < 0 && tries <= RECORD_TRIES && !*w->stop &&
                        (kind || access(a->out_dir, F_OK) == 0); /* a success's files are back */
         ++tries) {
        if (tries == 1)
            fprintf(stderr,
                    "lubdemd worker %s: cannot record the %s of %s; trying again for %d s\n",
                    w->name, kind ? "failure" : "success", a->c->id, RECORD_TRIES);
        sleep_ms(1000);
        beat->next_beat = 0.0;
        if (beat_while_finishing(beat)) {
            done = 0;
            break;
        }
        /* a failure's last try goes without its files, should they be what is refused */
        done = record_end_once(a, kind, message, files, kind && tries == RECORD_TRIES ? 0 : n);
    }
    return done;
}

/* Records the attempt's end (record_end_retrying) and says on stderr when it could not be;
 * a job dismissed (or a lease lost) meanwhile keeps nothing. */
static void record_end(const job_attempt *a, finishing_beat *beat, const char *kind,
                       const char *message, const lubd_output_file *files, int n)
{
    const int done = record_end_retrying(a, beat, kind, message, files, n);
    if (done < 0)
        fprintf(stderr, "lubdemd worker %s: could not record the %s of %s\n", a->w->name,
                kind ? "failure" : "success", a->c->id);
    else if (done == 0)
        lubd_lease_drop(a->w->db, a->c);
}

/* The engine exited with code 0: its outputs become the job's result. */
static void record_success(const job_attempt *a)
{
    finishing_beat beat = {a->w, a->c, 0.0, 0};
    lubd_output_file files[MAX_OUTPUTS];
    char names[MAX_OUTPUTS][64], why[400];
    int n = collect_outputs(a->out_dir, files, names, MAX_OUTPUTS, &beat, why, sizeof why);
    if (beat.lost) { /* requeued or dismissed meanwhile: the files are not ours to keep */
        lubd_lease_drop(a->w->db, a->c);
        return;
    }
    if (n < 0) { /* the service cannot keep what the engine wrote: its failure, not the run's */
        char msg[600];
        lubd_pathf(msg, sizeof msg,
                   "the engine exited with code 0 but its outputs cannot be kept: %s", why);
        record_end(a, &beat, "system", msg, files, 0);
        return;
    }
    int have_summary = 0, have_h5 = 0;
    for (int i = 0; i < n; ++i) {
        have_summary |= strcmp(files[i].name, "summary.json") == 0;
        have_h5 |= strcmp(files[i].name, "result.h5") == 0;
    }
    if (!have_summary || !have_h5) {
        record_end(a, &beat, "executor",
                   "the engine exited with code 0 but summary.json or result.h5 is missing", files,
                   0);
        return;
    }
    record_end(a, &beat, NULL, "completed", files, n);
}

/* The failure message of the job into msg: the engine's end and diagnostic, or the kill from
 * outside and the checkpoint it left, or the wall-clock limit and the checkpoint it left. */
static void failure_message(job_attempt *a, const char *diag)
{
    const lubd_claim *c = a->c;
    char ckpt[1500];
    lubd_pathf(ckpt, sizeof ckpt, "%s/checkpoint.h5", a->out_dir);
    if (a->why == END_WALL_LIMIT && access(ckpt, F_OK) == 0)
        snprintf(a->msg, sizeof a->msg,
                 "engine failed (%s)%s%s; the run's checkpoint is kept with the job's files "
                 "(checkpoint.h5): a job submitted with \"continue_from\": \"%s\" continues "
                 "the run (lubdem_client.py extend %s '{}')",
                 a->st_text, diag[0] ? ": " : "", diag, c->id, c->id);
    else if (a->why == END_WALL_LIMIT)
        snprintf(a->msg, sizeof a->msg,
                 "engine failed (%s)%s%s; no checkpoint was kept (the engine had left none)",
                 a->st_text, diag[0] ? ": " : "", diag);
    else if (a->killed_outside && a->have_ckpt)
        snprintf(a->msg, sizeof a->msg,
                 "engine failed (killed by signal 9 (SIGKILL) on attempt %d, the last of %d, not "
                 "by this service: the kernel's OOM killer or an operator); %s is kept with the "
                 "job's files (checkpoint.h5): a job submitted with \"continue_from\": \"%s\" "
                 "continues the run (lubdem_client.py extend %s '{}')",
                 c->attempt, c->max_attempts, a->ckpt_note, c->id, c->id);
    else if (a->killed_outside)
        snprintf(a->msg, sizeof a->msg,
                 "engine failed (killed by signal 9 (SIGKILL) on attempt %d, the last of %d, not "
                 "by this service: the kernel's OOM killer or an operator); no checkpoint was "
                 "kept (the engine had left none; simple_shear and resuspension write periodic "
                 "ones under lubdemd --checkpoint-s)",
                 c->attempt, c->max_attempts);
    else if (a->crashed_resumed)
        snprintf(a->msg, sizeof a->msg,
                 "engine failed (%s)%s%s; the run's checkpoint is kept with the job's files "
                 "(checkpoint.h5): a job submitted with \"continue_from\": \"%s\" continues "
                 "the run",
                 a->st_text, diag[0] ? ": " : "", diag, c->id);
    else
        snprintf(a->msg, sizeof a->msg, "engine failed (%s)%s%s", a->st_text, diag[0] ? ": " : "",
                 diag);
}

/* The engine failed: the job ends failed, with what the engine wrote. */
static void record_failure(job_attempt *a)
{
    finishing_beat beat = {a->w, a->c, 0.0, 0};
    char diag[600] = "";
    summary_diagnostic(a->out_dir, diag, sizeof diag);
    if (!diag[0] && !a->killed_outside && !a->killed_at_wall_limit)
        /* a killed engine's last line says nothing of the kill */
        log_diagnostic(a->log_path, a->log_from, diag, sizeof diag);
    /* 4 = cannot write output; 126/127 = the engine could not be executed: infrastructure. */
    int code = WIFEXITED(a->status) ? WEXITSTATUS(a->status) : -1;
    const char *kind = (code == 4 || code == 126 || code == 127) ? "system" : "executor";
    failure_message(a, diag);
    /* What the engine wrote is kept and served with the failure: the summary, the partial
     * result.h5 of a run stopped at its CPU time limit (with the checkpoint it continues
     * from), the result.h5 of a run that failed numerically (status failed, its series up to
     * the failure). A half-written file is never there: the engine writes under temporary
     * names, which collect_outputs skips. */
    lubd_output_file files[MAX_OUTPUTS];
    char names[MAX_OUTPUTS][64], why[400];
    /* exit 2: the engine wrote nothing (a refused continuation leaves the files it was
     * given, which are another job's) */
    int n = code == 2
                ? 0
                : collect_outputs(a->out_dir, files, names, MAX_OUTPUTS, &beat, why, sizeof why);
    if (beat.lost) {
        lubd_lease_drop(a->w->db, a->c);
        return;
    }
    if (n < 0) { /* the engine's failure stands; the message says why its files are not kept */
        const size_t used = strlen(a->msg);
        lubd_pathf(a->msg + used, sizeof a->msg - used, "; its files are not kept: %s", why);
        n = 0;
    }
    record_end(a, &beat, kind, a->msg, files, n);
}

/* Runs one claimed job to its end. */
static void run_job(worker_ctx *w, lubd_claim *c)
{
    job_attempt a = {.w = w, .c = c, .resume_from = -1, .log_fd = -1};
    attempt_paths(&a);
    if (prepare_attempt_folder(&a) != 0 || open_log(&a) != 0)
        return;
    write_log_header(&a);
    if (take_continued_files(&a) != 0)
        return;
    set_engine_options(&a);
    if (run_engine(&a) != 0)
        return;
    if (a.why == END_SHUTDOWN) {
        end_at_shutdown(&a);
        return;
    }
    if (a.why == END_LOST) {
        end_with_lost_lease(&a);
        return;
    }
    assess_kill_from_outside(&a);
    if (a.eo.resume && WIFSIGNALED(a.status)) {
        drop_stale(a.out_dir, a.started_at);
        char ckpt[1500];
        lubd_pathf(ckpt, sizeof ckpt, "%s/checkpoint.h5", a.out_dir);
        a.crashed_resumed = !a.killed_outside && access(ckpt, F_OK) == 0;
    }
    if (a.killed_outside && c->attempt < c->max_attempts) {
        requeue_killed(&a);
        return;
    }
    close(a.log_fd);
    if (WIFEXITED(a.status) && WEXITSTATUS(a.status) == 0)
        record_success(&a);
    else
        record_failure(&a);
}

/* A job that has ended (a requeued or released one has not) no longer needs what its engines
 * wrote outside result/ (lubd_deletion_tidy_ended: a dismissed run's files, earlier attempts'
 * partial files); a continuation no longer needs the files an earlier job handed over to it
 * when that job was deleted, nor that job's folder if it was kept for it. */
static void job_ended(worker_ctx *w, const lubd_claim *c)
{
    lubd_job j;
    if (lubd_queue_get(w->db, c->id, &j) != 1 || !lubd_job_finished(&j))
        return;
    char why[1400];
    if (j.purged) {
        /* deleted (a second DELETE) while its engine was being stopped: the deletion removed
         * the folder then, and what the engine wrote after that goes now */
        if (lubd_deletion_free(w->db, w->cfg->jobs_dir, c->id, why, sizeof why) != 0)
            fprintf(stderr, "lubdemd worker %s: %s\n", w->name, why);
    } else if (lubd_deletion_tidy_ended(w->cfg->jobs_dir, &j, why, sizeof why) < 0)
        fprintf(stderr, "lubdemd worker %s: %s\n", w->name, why);
    if (c->continue_from[0] &&
        lubd_deletion_continuation_ended(w->db, w->cfg->jobs_dir, c->id, c->continue_from, why,
                                         sizeof why) != 0)
        fprintf(stderr, "lubdemd worker %s: %s\n", w->name, why);
}

/* One job left running on its last attempt by a service that died, or by a worker that died
 * (its lease_token still set, as the reaper finds it; `cause` says which, as the message's
 * subject): when its engine left a checkpoint, what a continuation needs is kept and the job
 * fails with it, as after an engine killed from outside on its last attempt. The files older
 * than the attempt's claim are an earlier run's, treated as after an engine run with --resume
 * that died by a signal (drop_stale). Returns 1 when the job was failed with its checkpoint,
 * 0 when it is left to the reaper, -1 on an error. */
static int keep_orphan_checkpoint(worker_ctx *w, lubd_claim *c, double claimed_at,
                                  const char *cause)
{
    job_attempt a = {.w = w, .c = c, .resume_from = -1, .log_fd = -1};
    attempt_paths(&a);
    char ckpt[1500];
    lubd_pathf(ckpt, sizeof ckpt, "%s/checkpoint.h5", a.out_dir);
    if (access(ckpt, F_OK) != 0)
        return 0;
    drop_stale(a.out_dir, claimed_at); /* what drop_superseded would remove, and more */
    const double ckpt_time = mtime_of(ckpt);
    const long long step = lub_run_checkpoint_step(ckpt);
    char step_text[64] = "";
    if (step >= 0)
        snprintf(step_text, sizeof step_text, " of step %lld", step);
    snprintf(a.msg, sizeof a.msg,
             "failed: %s during attempt %d, the last of %d; the checkpoint%s (%s) is kept with "
             "the job's files (checkpoint.h5): a job submitted with \"continue_from\": \"%s\" "
             "continues the run (lubdem_client.py extend %s '{}')",
             cause, c->attempt, c->max_attempts, step_text,
             ckpt_time >= claimed_at ? "the last periodic one its engine wrote"
                                     : "the one its engine started from",
             c->id, c->id);
    finishing_beat beat = {w, c, 0.0, 0};
    lubd_output_file files[MAX_OUTPUTS];
    char names[MAX_OUTPUTS][64], why[400];
    const int n = collect_outputs(a.out_dir, files, names, MAX_OUTPUTS, &beat, why, sizeof why);
    if (n <= 0)
        return n < 0 ? -1 : 0;
    const int done =
        lubd_lease_fail_with_outputs(w->db, c, "system", a.msg, a.out_dir, a.result_dir, files, n);
    if (done == 1) {
        int fd = open(a.log_path, O_WRONLY | O_APPEND | O_CLOEXEC);
        if (fd >= 0) {
            dprintf(fd, "lubdemd: %s\n", a.msg);
            close(fd);
        }
    }
    return done;
}

/* the jobs keep_checkpoints_of reads at a time (it reads the next ones after handling these) */
#define ORPHAN_BATCH 256

/* The next at most ORPHAN_BATCH jobs on their last attempt leased to `worker` (NULL: to any
 * worker), in the order of their ids, after the id `after` ("" from the first), into claims and
 * claimed_at. Returns how many, or -1 on a database error. */
static int orphan_batch(sqlite3 *db, const char *worker, const char *after, lubd_claim *claims,
                        double *claimed_at)
{
    sqlite3_stmt *st;
    if (lubd_db_prepare(db,
                        "SELECT j.id, j.lease_token, coalesce(j.worker, ''), j.attempt, "
                        "j.max_attempts, (SELECT max(e.at) FROM job_events e WHERE e.job_id = "
                        "j.id AND e.token = j.lease_token AND e.event = 'claimed') FROM jobs j "
                        "WHERE j.state = 'running' AND j.attempt >= j.max_attempts AND "
                        "j.lease_token IS NOT NULL AND (?1 IS NULL OR j.worker = ?1) AND "
                        "j.id > ?2 ORDER BY j.id LIMIT ?3",
                        &st) != 0)
        return -1;
    if (worker)
        sqlite3_bind_text(st, 1, worker, -1, SQLITE_TRANSIENT);
    sqlite3_bind_text(st, 2, after, -1, SQLITE_TRANSIENT);
    sqlite3_bind_int(st, 3, ORPHAN_BATCH);
    int n = 0, rc;
    while ((rc = sqlite3_step(st)) == SQLITE_ROW) {
        lubd_claim *c = &claims[n];
        memset(c, 0, sizeof *c);
        snprintf(c->id, sizeof c->id, "%s", (const char *)sqlite3_column_text(st, 0));
        snprintf(c->token, sizeof c->token, "%s", (const char *)sqlite3_column_text(st, 1));
        snprintf(c->worker, sizeof c->worker, "%s", (const char *)sqlite3_column_text(st, 2));
        c->attempt = sqlite3_column_int(st, 3);
        c->max_attempts = sqlite3_column_int(st, 4);
        claimed_at[n++] = sqlite3_column_type(st, 5) == SQLITE_NULL
                              ? 0.0 /* no claim recorded: nothing counts as earlier */
                              : sqlite3_column_double(st, 5);
    }
    if (rc != SQLITE_DONE) {
        fprintf(stderr, "lubdemd: sqlite: %s\n", sqlite3_errmsg(db));
        n = -1;
    }
    sqlite3_finalize(st);
    return n;
}

/* The jobs on their last attempt leased to `worker` (NULL: to any worker) whose engines left
 * checkpoints fail with them (keep_orphan_checkpoint, `cause` in their messages): every one of
 * them, read in batches of ORPHAN_BATCH (until 2026-12-07 the first 256 only; those beyond
 * were failed by the reaper without their checkpoints). */
static int keep_checkpoints_of(const lubd_config *cfg, sqlite3 *db, const char *worker,
                               const char *cause)
{
    lubd_claim *claims = calloc(ORPHAN_BATCH, sizeof *claims);
    double *claimed_at = calloc(ORPHAN_BATCH, sizeof *claimed_at);
    int kept = 0, n = 0;
    char after[33] = ""; /* the ids are read in order: the next batch follows the last one */
    worker_ctx w = {cfg, db, "lubdemd", &worker_stop_flag};
    while (claims && claimed_at && (n = orphan_batch(db, worker, after, claims, claimed_at)) > 0) {
        for (int i = 0; i < n; ++i) {
            const int done = keep_orphan_checkpoint(&w, &claims[i], claimed_at[i], cause);
            if (done < 0)
                fprintf(stderr, "lubdemd: job %s: cannot keep the checkpoint its engine left\n",
                        claims[i].id);
            kept += done > 0;
        }
        snprintf(after, sizeof after, "%s", claims[n - 1].id);
    }
    const int failed = !claims || !claimed_at || n < 0;
    free(claims);
    free(claimed_at);
    return failed ? -1 : kept;
}

int lubd_worker_keep_orphan_checkpoints(const lubd_config *cfg, sqlite3 *db)
{
    return keep_checkpoints_of(cfg, db, NULL,
                               "the service stopped without releasing it (crash or kill -9)");
}

int lubd_worker_keep_dead_worker_checkpoints(const lubd_config *cfg, sqlite3 *db,
                                             const char *worker, const char *how)
{
    char cause[200];
    snprintf(cause, sizeof cause, "its worker process died (%s)", how);
    return keep_checkpoints_of(cfg, db, worker, cause);
}

int lubd_worker_keep_main(const lubd_config *cfg, const char *worker, const char *how)
{
    prctl(PR_SET_PDEATHSIG, SIGKILL); /* the service died: its next start takes the jobs up */
    if (getppid() == 1)
        return 1;
    signal(SIGPIPE, SIG_IGN);
    sqlite3 *db = lubd_db_open(cfg->db_path, 0);
    if (!db)
        return 1;
    const int kept = lubd_worker_keep_dead_worker_checkpoints(cfg, db, worker, how);
    lubd_db_close(db);
    if (kept < 0)
        fprintf(stderr, "lubdemd: cannot keep the checkpoints of the jobs of worker %s\n", worker);
    else if (kept > 0 && !cfg->quiet)
        fprintf(stderr,
                "lubdemd: %d job(s) of worker %s on their last attempt failed with the "
                "checkpoint their engine left\n",
                kept, worker);
    return kept < 0;
}

int lubd_worker_main(const lubd_config *cfg, const char *name)
{
    prctl(PR_SET_PDEATHSIG, SIGKILL); /* the service died: so do we (and our engine) */
    if (getppid() == 1)
        return 1;
    struct sigaction sa;
    memset(&sa, 0, sizeof sa);
    sa.sa_handler = on_term;
    sigaction(SIGTERM, &sa, NULL);
    sigaction(SIGINT, &sa, NULL);
    signal(SIGPIPE, SIG_IGN);
    sigset_t none;
    sigemptyset(&none);
    sigprocmask(SIG_SETMASK, &none, NULL);

    worker_ctx w = {cfg, NULL, "", &worker_stop_flag};
    snprintf(w.name, sizeof w.name, "%s-pid%ld", name, (long)getpid());
    w.db = lubd_db_open(cfg->db_path, 0);
    if (!w.db)
        return 1;
    sqlite3_stmt *peek;
    if (lubd_db_prepare(w.db, "SELECT 1 FROM jobs WHERE state = 'accepted' LIMIT 1", &peek) != 0)
        return 1;
    while (!worker_stop_flag) {
        /* Cheap read first: only take the write lock when there is something to claim. */
        int rc = sqlite3_step(peek);
        sqlite3_reset(peek);
        if (rc != SQLITE_ROW) {
            sleep_ms(100);
            continue;
        }
        lubd_claim c;
        int got = lubd_lease_claim(w.db, w.name, cfg->lease_s, &c);
        if (got <= 0) {
            sleep_ms(got < 0 ? 500 : 20);
            continue;
        }
        run_job(&w, &c);
        job_ended(&w, &c);
        lubd_lease_clear(&c);
    }
    sqlite3_finalize(peek);
    lubd_db_close(w.db);
    return 0;
}
