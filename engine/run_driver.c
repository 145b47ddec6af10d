/* run_driver.c — one spec to one result folder (see run_driver.h and README "CLI contract"). */
#include "run_driver.h"

#include <errno.h>
#include <fcntl.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>
#ifdef _OPENMP
#include <omp.h>
#endif

#include "build_info.h"
#include "checkpoint_file.h"
#include "file_copy.h"
#include "json_overflow.h"
#include "json_text.h"
#include "processors.h"
#include "resume_spec.h"
#include "run_context.h"
#include "scene.h"

void lub_report_spec_error(FILE *diag, int json_errors, const lub_error *err)
{
    char pointer[6 * sizeof err->pointer], message[6 * sizeof err->message];
    lub_text_one_line(err->pointer, pointer, sizeof pointer);
    lub_text_one_line(err->message, message, sizeof message);
    if (json_errors) {
        /* the texts as they are (JSON escapes control characters); the one-line forms when
         * they are not valid UTF-8, which json_pack refuses; a fixed object when even that
         * fails (no memory) */
        json_t *o = json_pack("{s:s, s:s}", "pointer", err->pointer, "message", err->message);
        if (!o)
            o = json_pack("{s:s, s:s}", "pointer", pointer, "message", message);
        char *s = o ? json_dumps(o, JSON_COMPACT) : NULL;
        fprintf(diag, "%s\n", s ? s : "{\"pointer\": \"\", \"message\": \"invalid spec\"}");
        free(s);
        json_decref(o);
    } else {
        fprintf(diag, "error: %s: %s\n", pointer[0] ? pointer : "(root)", message);
    }
}

/* s with control characters and bytes that are not UTF-8 escaped (lub_text_one_line), in a new
 * string the caller frees; NULL without memory. */
static char *one_line_dup(const char *s)
{
    const size_t size = 6 * strlen(s) + 1; /* a byte takes at most 6 ("\\u001F") */
    char *out = malloc(size);
    return out ? (char *)lub_text_one_line(s, out, size) : NULL;
}

/* A refusal the run makes (exit 2) on diag: "error: <line>" (the line names the member, or
 * begins with "--resume: "), or with --json-errors {"pointer": pointer, "message": message}
 * (pointer "" when the refusal is not about one member), as the spec errors are; one line and
 * valid JSON whatever the texts hold (lub_report_spec_error). */
static void report_refusal(FILE *diag, int json_errors, const char *pointer, const char *message,
                           const char *line)
{
    if (json_errors) {
        json_t *o = json_pack("{s:s, s:s}", "pointer", pointer, "message", message);
        if (!o) { /* not valid UTF-8 (a folder's name): its one-line form */
            char *p1 = one_line_dup(pointer), *m1 = one_line_dup(message);
            o = p1 && m1 ? json_pack("{s:s, s:s}", "pointer", p1, "message", m1) : NULL;
            free(p1);
            free(m1);
        }
        char *s = o ? json_dumps(o, JSON_COMPACT) : NULL;
        fprintf(diag, "%s\n", s ? s : "{\"pointer\": \"\", \"message\": \"refused\"}");
        free(s);
        json_decref(o);
    } else {
        char *l1 = one_line_dup(line);
        fprintf(diag, "error: %s\n", l1 ? l1 : line);
        free(l1);
    }
}

/* The member a refusal's text begins with ("/strain: 1 here, ..."), into out[len] ("" when it
 * begins otherwise); returns the text after "<pointer>: " (text itself when none). */
static const char *leading_pointer(const char *text, char *out, size_t len)
{
    out[0] = '\0';
    const char *colon = text[0] == '/' ? strstr(text, ": ") : NULL;
    if (!colon || (size_t)(colon - text) >= len || memchr(text, ' ', (size_t)(colon - text)))
        return text;
    memcpy(out, text, (size_t)(colon - text));
    out[colon - text] = '\0';
    return colon + 2;
}

/* Parse + resolve; on failure reports and returns NULL. */
static json_t *parse_and_resolve(const char *text, FILE *diag, int json_errors)
{
    json_error_t jerr;
    lub_error err;
    json_t *spec = json_loads(text, JSON_REJECT_DUPLICATES, &jerr);
    if (!spec) {
        if (lub_json_overflow_member(text, &jerr, &err) != 0 &&
            lub_json_duplicate_member(text, &jerr, &err) != 0)
            lub_fail(&err, "", "invalid JSON at line %d column %d: %s", jerr.line, jerr.column,
                     jerr.text);
        lub_report_spec_error(diag, json_errors, &err);
        return NULL;
    }
    if (lub_json_underflow_member(text, &err) == 0) { /* read as 0 without a word */
        json_decref(spec);
        lub_report_spec_error(diag, json_errors, &err);
        return NULL;
    }
    json_t *resolved = NULL;
    int rc = lub_spec_resolve(spec, &resolved, &err);
    json_decref(spec);
    if (rc) {
        lub_report_spec_error(diag, json_errors, &err);
        return NULL;
    }
    return resolved;
}

int lub_validate_spec(const char *spec_text, FILE *out, FILE *diag, int json_errors)
{
    json_t *resolved = parse_and_resolve(spec_text, diag, json_errors);
    if (!resolved)
        return LUB_EXIT_BAD_SPEC;
    char *s = lub_json_dumps(resolved, JSON_INDENT(2) | JSON_SORT_KEYS);
    json_decref(resolved);
    if (!s) {
        fprintf(diag, "error: out of memory\n");
        return LUB_EXIT_INTERNAL;
    }
    errno = 0;
    const int bad = fprintf(out, "%s\n", s) < 0 || fflush(out) != 0 || ferror(out);
    free(s);
    if (bad) { /* a full disk, a closed pipe: the caller must not take the spec as printed */
        fprintf(diag, "error: cannot write the resolved spec: %s\n",
                errno ? strerror(errno) : "write error");
        return LUB_EXIT_IO;
    }
    return LUB_EXIT_OK;
}

/* The output folder of at most MKDIR_MAX - 1 bytes. */
#define MKDIR_MAX 4096

/* Creates path and the folders above it that are missing; made[i] (MKDIR_MAX flags, zeroed by
 * the caller) is set for each prefix path[0..i) this call created, for remove_made. 0, or -1
 * with errno set: the system's reason, ENOTDIR when path is there but not a folder. */
static int mkdir_p(const char *path, unsigned char *made)
{
    char buf[MKDIR_MAX];
    size_t n = strlen(path);
    if (n == 0 || n >= sizeof buf) { /* errno says why: the caller prints it */
        errno = n ? ENAMETOOLONG : ENOENT;
        return -1;
    }
    memcpy(buf, path, n + 1);
    for (size_t i = 1; i <= n; ++i) {
        if (buf[i] == '/' || buf[i] == '\0') {
            char c = buf[i];
            buf[i] = '\0';
            if (mkdir(buf, 0775) == 0)
                made[i] = 1;
            else if (errno != EEXIST)
                return -1;
            buf[i] = c;
        }
    }
    struct stat st;
    if (stat(path, &st) != 0)
        return -1;
    if (!S_ISDIR(st.st_mode)) { /* mkdir's EEXIST: a file, not a folder, has the name */
        errno = ENOTDIR;
        return -1;
    }
    return 0;
}

/* Removes the folders mkdir_p created for path (those it marked in made), the deepest first,
 * when they are empty: a run that writes nothing leaves no folder of its own. */
static void remove_made(const char *path, const unsigned char *made)
{
    char buf[MKDIR_MAX];
    const size_t n = strlen(path);
    if (n >= sizeof buf)
        return;
    memcpy(buf, path, n + 1);
    for (size_t i = n; i >= 1; --i) {
        if (made[i]) {
            buf[i] = '\0';
            rmdir(buf);
        }
    }
}

static int write_file_atomic(const char *dir, const char *name, const char *text)
{
    char tmp[4200], dst[4200];
    snprintf(tmp, sizeof tmp, "%s/.%s.tmp", dir, name);
    snprintf(dst, sizeof dst, "%s/%s", dir, name);
    FILE *f = fopen(tmp, "w");
    if (!f)
        return -1;
    int ok = fputs(text, f) >= 0 && fputc('\n', f) != EOF;
    ok = (fflush(f) == 0) && ok;
    ok = (fsync(fileno(f)) == 0) && ok;
    ok = (fclose(f) == 0) && ok;
    if (!ok || rename(tmp, dst) != 0) {
        unlink(tmp);
        return -1;
    }
    return 0;
}

/* appends text to the summary's "warnings" array (created when absent) */
static void append_warning(lub_run_ctx *ctx, const char *text) { lub_summary_warn(ctx, text); }

/* 1 when the scene's lower bound of its memory fits in what this process may still take
 * (memory_budget.h); 0 with the diagnostic set otherwise, before anything is allocated. */
static int fits_in_memory(const lub_scene *scene, const json_t *resolved, lub_run_ctx *ctx)
{
    lub_memory_need need;
    memset(&need, 0, sizeof need);
    if (!scene->memory_need || scene->memory_need(resolved, ctx->threads, &need) != 0)
        return 1;
    return lub_memory_need_fits(ctx, &need);
}

/* result.h5 could not be written (reason: the system's, with what failed and from which step)
 * and has been removed. A run that completed or was stopped ends with exit 4 and this as its
 * diagnostic; a run that failed on its own (1, 3, or 4 from the scene) keeps its code and
 * diagnostic, with this appended. Either way the summary still carries the run's results,
 * and the advice names the spec members that set the output's size where the scene has them. */
static void report_result_h5_lost(lub_run_ctx *ctx, int *rc, const char *out_dir,
                                  const char *reason, int room, const json_t *resolved,
                                  int checkpoint_kept)
{
    char advice[160] = "";
    const int samples = json_object_get(resolved, "sample_strain") != NULL;
    const int snapshots = json_object_get(resolved, "snapshots") != NULL;
    if (samples || snapshots)
        snprintf(advice, sizeof advice, ", or write less (%s%s%s)",
                 samples ? "raise /sample_strain" : "", samples && snapshots ? ", " : "",
                 snapshots ? "lower /snapshots" : "");
    char text[sizeof ctx->diagnostic];
    if (!room) /* result.h5 was written but could not take its name (a folder of that name) */
        snprintf(text, sizeof text,
                 "cannot put result.h5 in place in %s: %s; this run's file was removed, and "
                 "summary.json holds the run's results without it%s",
                 out_dir, reason,
                 checkpoint_kept ? "; the checkpoint it continued from (or its last periodic "
                                   "one) is kept with the file holding its rows"
                                 : "");
    else if (checkpoint_kept)
        snprintf(text, sizeof text,
                 "cannot write result.h5 in %s: %s; this run's file was removed, and "
                 "summary.json holds the run's results without it; the checkpoint it continued "
                 "from (or its last periodic one) is kept with the file holding its rows, so "
                 "lubdem run --resume goes on from there once the run has room (free disk space; "
                 "the file-size limit: ulimit -f, lubdemd --fsize-mb)%s",
                 out_dir, reason[0] ? reason : "HDF5 error", advice);
    else
        snprintf(text, sizeof text,
                 "cannot write result.h5 in %s: %s; it was removed, and summary.json holds the "
                 "run's results without it; give the run room (free disk space; the file-size "
                 "limit: ulimit -f, lubdemd --fsize-mb)%s",
                 out_dir, reason[0] ? reason : "HDF5 error", advice);
    if (*rc != LUB_EXIT_OK) { /* a stopped run's diagnostic says why it stopped: kept */
        const size_t len = strlen(ctx->diagnostic);
        snprintf(ctx->diagnostic + len, sizeof ctx->diagnostic - len, "%s%s",
                 len ? "; besides, " : "", text);
        if (*rc == LUB_EXIT_INTERRUPTED)
            *rc = LUB_EXIT_IO;
        return;
    }
    snprintf(ctx->diagnostic, sizeof ctx->diagnostic, "%s", text);
    *rc = LUB_EXIT_IO;
}

/* --resume with DIR/checkpoint.h5 present: 0 when the checkpoint belongs to this spec (the same
 * resolved spec, member for member, but for may_differ) and the file holding its rows is there
 * (result.h5 of a stopped run, LUB_PERIODIC_OUTPUT of a periodic checkpoint), whose path goes to
 * result_path[result_len]; otherwise the reason in why[len]. */
static int check_resume(const char *ckpt_path, const char *out_dir, const json_t *resolved,
                        const char *const *may_differ, char *result_path, size_t result_len,
                        char *why, size_t len, char *at, size_t at_len)
{
    at[0] = '\0';
    char err[400];
    lub_ckpt *c = lub_ckpt_open(ckpt_path, err, sizeof err);
    if (!c) {
        snprintf(why, len, "%s", err);
        return -1;
    }
    char *output = lub_ckpt_get_text(c, "output_file");
    const int output_known =
        output && (strcmp(output, "result.h5") == 0 || strcmp(output, LUB_PERIODIC_OUTPUT) == 0);
    snprintf(result_path, result_len, "%s/%s", out_dir, output_known ? output : "result.h5");
    free(output);
    char *text = lub_ckpt_get_text(c, "spec_resolved");
    json_t *saved = text ? json_loads(text, 0, NULL) : NULL;
    /* resolved again by this build, so that a member added since the checkpoint was written
     * takes its default, which is defined to be the behaviour before it existed (a stopped run
     * from before /initial_gap continues); the spec as saved when it no longer resolves, so that
     * the comparison names what differs */
    json_t *saved_now = NULL;
    lub_error resolve_err;
    memset(&resolve_err, 0, sizeof resolve_err);
    if (saved && lub_spec_resolve(saved, &saved_now, &resolve_err) == 0) {
        json_decref(saved);
        saved = saved_now;
    }
    int rc = 0;
    char differ[600];
    if (!saved) {
        snprintf(why, len, "%s holds no readable spec (%s)", ckpt_path,
                 text ? "invalid JSON" : lub_ckpt_error(c));
        rc = -1;
    } else if (lub_resume_spec_mismatch(resolved, saved, may_differ, differ, sizeof differ, at,
                                        at_len) != 0) {
        char free_members[200]; /* the members a continuation may change */
        lub_resume_free_members(may_differ, free_members, sizeof free_members);
        snprintf(why, len,
                 "%s: continue with the same spec (every member, defaults included%s), or run "
                 "without --resume to start afresh",
                 differ, free_members);
        rc = -1;
    } else if (!output_known) {
        snprintf(why, len, "%s does not name the file that holds its time series", ckpt_path);
        rc = -1;
    } else if (access(result_path, R_OK) != 0) {
        snprintf(why, len,
                 "the stopped run's %s is missing (%s): the checkpoint continues its time series; "
                 "run without --resume to start afresh",
                 result_path, strerror(errno));
        rc = -1;
    }
    json_decref(saved);
    free(text);
    lub_ckpt_close(c, NULL, 0);
    return rc;
}

/* --resume of a scene that takes no checkpoints, with DIR/checkpoint.h5 present: the checkpoint
 * is another scene's, so the refusal names /scene, with the scene that wrote it when it can be
 * read, into why[len] (the text after "cannot continue from DIR/checkpoint.h5: "). */
static void other_scene_refusal(const char *ckpt_path, const lub_scene *scene, char *why,
                                size_t len)
{
    char err[400] = "", saved_scene[160] = "";
    lub_ckpt *c = lub_ckpt_open(ckpt_path, err, sizeof err);
    char *text = c ? lub_ckpt_get_text(c, "spec_resolved") : NULL;
    json_t *saved = text ? json_loads(text, 0, NULL) : NULL;
    const char *name = json_string_value(json_object_get(saved, "scene"));
    if (name)
        snprintf(saved_scene, sizeof saved_scene, "\"%s\" in the stopped run's spec", name);
    else
        snprintf(saved_scene, sizeof saved_scene, "a checkpoint whose spec cannot be read (%.100s)",
                 c ? (text ? "invalid JSON" : lub_ckpt_error(c)) : err);
    json_decref(saved);
    free(text);
    lub_ckpt_close(c, NULL, 0);
    char resumable[200] = ""; /* the scenes --resume continues */
    for (const lub_scene *const *s = lub_scene_list(); *s; ++s) {
        if (!(*s)->resumable)
            continue;
        const size_t used = strlen(resumable);
        snprintf(resumable + used, sizeof resumable - used, "%s%s", used ? ", " : "", (*s)->name);
    }
    snprintf(why, len,
             "/scene: \"%s\" here, %s: a %s run takes no checkpoint and continues none "
             "(--resume continues %s); give another --out, or run without --resume to start "
             "afresh (which removes the checkpoint)",
             scene->name, saved_scene, scene->name, resumable);
}

static const char *status_of(int rc)
{
    switch (rc) {
    case LUB_EXIT_OK: return "complete";
    case LUB_EXIT_INTERRUPTED: return "partial";
    default: return "failed";
    }
}

/* ------------------------------------------------------------------------------------------ */
/* One run, in phases over one state (lub_run_spec at the end orchestrates them). */

#define RUN_PATH_LEN 4200
/* the checkpoint notes of the parts that ran the run (BUILD_NOTES) */
enum { BUILD_NOTE_COUNT = 5 };

typedef struct {
    const lub_run_request *req;
    const lub_scene *scene;
    json_t *resolved;
    /* the files in DIR: result.h5 and checkpoint.h5 are written under a temporary name and
     * renamed; copy_*: the periodic checkpoint's copy of result.h5 */
    char h5_tmp[RUN_PATH_LEN], h5_dst[RUN_PATH_LEN], ckpt_tmp[RUN_PATH_LEN], ckpt_dst[RUN_PATH_LEN],
        copy_tmp[RUN_PATH_LEN], copy_dst[RUN_PATH_LEN];
    char resume_result[RUN_PATH_LEN]; /* the stopped run's file with the rows (check_resume) */
    int resuming;                     /* continues the checkpoint in DIR */
    lub_h5 *h5;
    lub_progress progress;
    lub_periodic_ckpt periodic;
    lub_run_ctx ctx;
    int threads_requested, processors;
    int thread_limit;        /* OpenMP's (OMP_THREAD_LIMIT) */
    int rc;                  /* the exit code so far */
    double wall;             /* the scene's wall time, s */
    const char *stop_advice; /* a stopped run's --resume advice, added if its checkpoint is kept */
    int h5_failed, h5_room;  /* result.h5 lost; the loss is one of room, not of its name */
    char h5_reason[400];
    int renamed;         /* result.h5 took its name */
    int checkpoint_kept; /* a checkpoint.h5 in DIR continues this run */
    /* the builds and thread counts that ran parts of the run (run_builds_init): the summary's
     * "builds", and the notes each checkpoint carries (BUILD_NOTES names, note_texts their
     * texts) */
    json_t *builds;
    char *earlier_builds;  /* JSON: the parts before this one */
    char build_from[24];   /* the step this part began at */
    char part_threads[16]; /* the threads of this part */
    const char *note_texts[BUILD_NOTE_COUNT];
    char build_warning[1024];      /* a continuation by another build: its warning */
    unsigned char made[MKDIR_MAX]; /* the folders of DIR this run created (mkdir_p) */
} run_state;

/* The checkpoint notes (lub_ckpt_set_notes) that say which builds, on how many threads, ran
 * the run: the build that wrote it, the step its part of the run began at, the parts before it
 * (a JSON array of {"lubdem_version", "git_commit", "threads", "from_step"}, oldest first),
 * and the threads of its part (since 2026-12-07; a checkpoint without that note is of a part
 * whose thread count is not known, and its entry has no "threads"). */
static const char *const BUILD_NOTES[BUILD_NOTE_COUNT] = {
    "lubdem_version", "git_commit", "build_from_step", "earlier_builds", "threads"};

/* One part of the run: threads <= 0 when not known (omitted). */
static json_t *build_entry(const char *version, const char *commit, int threads,
                           long long from_step)
{
    json_t *e = json_pack("{s:s, s:s}", "lubdem_version", version, "git_commit", commit);
    if (e && threads > 0)
        json_object_set_new(e, "threads", json_integer(threads));
    if (e)
        json_object_set_new(e, "from_step", json_integer((json_int_t)from_step));
    return e;
}

/* s->builds and the notes of this run's checkpoints: this build and thread count from step 0
 * for a fresh run; for a continuation, the checkpoint's parts, then this one from the
 * checkpoint's step when it is another build than the one that wrote the checkpoint (with a
 * warning: until 2026-12-07 a checkpoint did not say which build wrote it, and a continuation
 * by another build went unnoticed) or runs on another number of threads (no warning: the run
 * is then the same to round-off, not bit for bit; until 2026-12-07 only the last part's
 * threads were reported). A checkpoint written before then counts as of an "unknown" build. */
static void run_builds_init(run_state *s)
{
    const char *version = lub_build_version(), *commit = lub_build_git();
    const int threads = lub_threads_usable(s->req->threads > 0 ? s->req->threads : 1);
    json_t *earlier = json_array();
    long long from = 0;
    s->builds = json_array();
    if (s->resuming) {
        lub_ckpt *c = lub_ckpt_open(s->ckpt_dst, NULL, 0);
        char *notes[BUILD_NOTE_COUNT] = {NULL};
        int64_t step = 0;
        for (int i = 0; i < BUILD_NOTE_COUNT && c; ++i)
            notes[i] = lub_ckpt_get_note(c, BUILD_NOTES[i]);
        if (c && lub_ckpt_get_i64_or(c, "step", 0, &step) != 0)
            step = 0;
        lub_ckpt_close(c, NULL, 0);
        json_t *list = notes[3] ? json_loads(notes[3], 0, NULL) : NULL;
        if (json_is_array(list))
            json_array_extend(s->builds, list);
        json_decref(list);
        const char *v = notes[0] ? notes[0] : "unknown", *g = notes[1] ? notes[1] : "unknown";
        const long long v_from = notes[2] ? strtoll(notes[2], NULL, 10) : 0;
        const int v_threads = notes[4] ? atoi(notes[4]) : 0; /* 0: not known */
        const int same_build = strcmp(v, version) == 0 && strcmp(g, commit) == 0;
        if (same_build && v_threads == threads) { /* the same part goes on */
            json_array_extend(earlier, s->builds);
            from = v_from;
        } else {
            json_array_append_new(s->builds, build_entry(v, g, v_threads, v_from));
            json_array_extend(earlier, s->builds);
            from = (long long)step;
        }
        if (!same_build)
            snprintf(s->build_warning, sizeof s->build_warning,
                     "the checkpoint this run continued was written by another build (lubdem "
                     "%.100s, git %.100s) than this one (lubdem %.100s, git %.100s): the run's "
                     "steps before %lld and after come from different builds (summary builds), "
                     "whose results may differ by more than round-off",
                     v, g, version, commit, from);
        for (int i = 0; i < BUILD_NOTE_COUNT; ++i)
            free(notes[i]);
    }
    json_array_append_new(s->builds, build_entry(version, commit, threads, from));
    s->earlier_builds = json_dumps(earlier, JSON_COMPACT);
    json_decref(earlier);
    snprintf(s->build_from, sizeof s->build_from, "%lld", from);
    s->note_texts[0] = version;
    s->note_texts[1] = commit;
    s->note_texts[2] = s->build_from;
    s->note_texts[3] = s->earlier_builds ? s->earlier_builds : "[]";
    snprintf(s->part_threads, sizeof s->part_threads, "%d", threads);
    s->note_texts[4] = s->part_threads;
}

/* The files' paths in DIR. */
static void run_paths(run_state *s)
{
    const char *dir = s->req->out_dir;
    snprintf(s->h5_tmp, sizeof s->h5_tmp, "%s/.result.h5.tmp", dir);
    snprintf(s->h5_dst, sizeof s->h5_dst, "%s/result.h5", dir);
    snprintf(s->ckpt_tmp, sizeof s->ckpt_tmp, "%s/.checkpoint.h5.tmp", dir);
    snprintf(s->ckpt_dst, sizeof s->ckpt_dst, "%s/checkpoint.h5", dir);
    snprintf(s->copy_tmp, sizeof s->copy_tmp, "%s/.%s.tmp", dir, LUB_PERIODIC_OUTPUT);
    snprintf(s->copy_dst, sizeof s->copy_dst, "%s/%s", dir, LUB_PERIODIC_OUTPUT);
}

/* What a checkpoint already in DIR means for this run: continued (--resume, its scene), a
 * refusal (--resume: it does not fit, or is another scene's), or replaced (with a note). Runs
 * before anything is written: the old files stay as they are on refusal. LUB_EXIT_OK, or
 * LUB_EXIT_BAD_SPEC with the refusal reported. */
static int run_check_checkpoint(run_state *s)
{
    const lub_run_request *req = s->req;
    const int had_checkpoint = access(s->ckpt_dst, F_OK) == 0;
    s->resuming = req->resume && had_checkpoint && s->scene->resumable;
    if (s->resuming) {
        char why[2 * RUN_PATH_LEN + 1024]; /* two paths and the spec members that differ */
        char at[256];                      /* the first member that differs, if any */
        if (check_resume(s->ckpt_dst, req->out_dir, s->resolved, s->scene->resume_may_differ,
                         s->resume_result, sizeof s->resume_result, why, sizeof why, at,
                         sizeof at)) {
            char line[sizeof why + RUN_PATH_LEN + 64];
            snprintf(line, sizeof line, "--resume: cannot continue from %s: %s", s->ckpt_dst, why);
            report_refusal(req->diag, req->json_errors, at, line, line);
            return LUB_EXIT_BAD_SPEC;
        }
    } else if (req->resume && had_checkpoint) { /* another scene's checkpoint: left as it is */
        char why[RUN_PATH_LEN + 1024];
        other_scene_refusal(s->ckpt_dst, s->scene, why, sizeof why);
        char line[sizeof why + RUN_PATH_LEN + 64];
        snprintf(line, sizeof line, "--resume: cannot continue from %s: %s", s->ckpt_dst, why);
        report_refusal(req->diag, req->json_errors, "/scene", line, line);
        return LUB_EXIT_BAD_SPEC;
    } else if (req->resume && req->progress) {
        fprintf(req->progress,
                "resume: %s holds no checkpoint; the run starts from the beginning\n",
                req->out_dir);
    } else if (had_checkpoint) {
        fprintf(req->diag,
                "note: %s holds the checkpoint of a stopped run; this run starts afresh and "
                "replaces it (lubdem run --resume continues it)\n",
                req->out_dir);
    }
    return LUB_EXIT_OK;
}

/* The scene's context: output file, progress, stop flag, checkpoints, threads. */
static void run_context_init(run_state *s)
{
    const lub_run_request *req = s->req;
    lub_run_ctx *ctx = &s->ctx;
    lub_progress_init(&s->progress, req->progress, 0.5);
    memset(ctx, 0, sizeof *ctx);
    ctx->out = s->h5;
    ctx->progress = &s->progress;
    ctx->stop_requested = req->stop_requested;
    ctx->summary_results = json_object();
    ctx->summary_extra = json_object();
    if (s->scene->resumable) {
        ctx->checkpoint_path = s->ckpt_tmp;
        ctx->checkpoint_always = req->keep_checkpoint;
    }
    if (s->resuming) {
        ctx->resume_path = s->ckpt_dst;
        ctx->resume_result = s->resume_result;
    }
    if (s->scene->resumable && req->checkpoint_every_s > 0.0) {
        lub_periodic_init(&s->periodic, req->checkpoint_every_s, s->h5_tmp, s->copy_tmp,
                          s->copy_dst, s->ckpt_tmp, s->ckpt_dst);
        s->periodic.notes = BUILD_NOTE_COUNT;
        s->periodic.note_names = BUILD_NOTES;
        s->periodic.note_texts = s->note_texts;
        ctx->periodic = &s->periodic;
    }
    /* more threads than processors only slow a run down (every OpenMP barrier waits for a
     * thread that is not running: on 2 processors: 1.6 s with 2 threads, 51 s with 256) */
    s->threads_requested = req->threads > 0 ? req->threads : 1;
    s->processors = lub_processors_available();
    s->thread_limit = lub_omp_thread_limit();
    ctx->threads = lub_threads_usable(s->threads_requested);
#ifdef _OPENMP
    /* teams of exactly ctx->threads (OMP_DYNAMIC=true let the runtime give fewer on a loaded
     * host: a different run, the summary none the wiser); once, before any parallel region */
    omp_set_dynamic(0);
#endif
}

/* The threads the run used: the smallest team a scene's steps got, or ctx->threads when the
 * scene does not say (no step, or a scene without OpenMP teams). */
static int run_threads_used(const run_state *s)
{
    const int used = s->ctx.threads_used;
    return used > 0 && used < s->ctx.threads ? used : s->ctx.threads;
}

/* A refused continuation, or one that failed before it took up the stopped run (the memory
 * check, say), ran nothing: the stopped run's files stay as they were (its checkpoint still
 * continues it), and nothing new is kept. 1 (reported, s->rc the exit code) when the run is
 * one of those. */
static int run_not_begun(run_state *s)
{
    const lub_run_request *req = s->req;
    lub_run_ctx *ctx = &s->ctx;
    const int not_begun =
        s->resuming && !ctx->resume_begun && s->rc != LUB_EXIT_OK && s->rc != LUB_EXIT_INTERRUPTED;
    if (!(ctx->resume_rejected || not_begun))
        return 0;
    lub_h5_finish(s->h5, "failed", NULL, 0);
    unlink(s->h5_tmp);
    unlink(s->ckpt_tmp);
    if (ctx->resume_rejected) { /* "cannot continue from DIR/checkpoint.h5: [/member: ]..." */
        char line[sizeof ctx->diagnostic + 16], prefix[RUN_PATH_LEN + 32], at[256] = "";
        snprintf(line, sizeof line, "--resume: %s", ctx->diagnostic);
        snprintf(prefix, sizeof prefix, "cannot continue from %s: ", s->ckpt_dst);
        if (strncmp(ctx->diagnostic, prefix, strlen(prefix)) == 0)
            leading_pointer(ctx->diagnostic + strlen(prefix), at, sizeof at);
        report_refusal(req->diag, req->json_errors, at, line, line);
        s->rc = LUB_EXIT_BAD_SPEC;
    } else { /* a spec refusal only the run makes keeps its pointer under --json-errors */
        char line[sizeof ctx->diagnostic + 4400], at[256] = "";
        snprintf(line, sizeof line,
                 "--resume: %s; the stopped run's files in %s are left as they were "
                 "(--resume continues from them)",
                 ctx->diagnostic, req->out_dir);
        if (s->rc == LUB_EXIT_BAD_SPEC)
            leading_pointer(ctx->diagnostic, at, sizeof at);
        if (s->rc == LUB_EXIT_BAD_SPEC && req->json_errors)
            report_refusal(req->diag, 1, at, line, line);
        else
            fprintf(req->diag, "error: %s\n", line);
    }
    return 1;
}

/* Why a stopped run stopped, into the diagnostic; the --resume advice (s->stop_advice) and
 * the note on stderr follow once the checkpoint is known to be kept (run_report_stop). A stop
 * request that came after the scene's last step does not make the run partial: it completed
 * (every scene that can stop early returns LUB_EXIT_INTERRUPTED when it did). */
static void run_stop_reason(run_state *s)
{
    const lub_run_request *req = s->req;
    lub_run_ctx *ctx = &s->ctx;
    if (s->rc != LUB_EXIT_INTERRUPTED || !req->stop_requested || !*req->stop_requested)
        return;
    if (*req->stop_requested == SIGXCPU) {
        const size_t used = strlen(ctx->diagnostic);
        snprintf(ctx->diagnostic + used, sizeof ctx->diagnostic - used,
                 "%sstopped at the CPU time limit of this process (SIGXCPU: ulimit -t, lubdemd "
                 "--cpu-s): the results are those of the steps done",
                 used ? "; " : "");
        s->stop_advice = "; lubdem run --resume with a higher limit continues the run";
        return;
    }
    /* SIGTERM, SIGINT: said in the summary too (until 2026-12-06 only its status said it); a
     * scene that says why itself ("stopped while generating the packing") keeps its words,
     * which go to stderr too (they did not until 2026-12-06) */
    const int sig = (int)*req->stop_requested;
    if (!ctx->diagnostic[0])
        snprintf(ctx->diagnostic, sizeof ctx->diagnostic,
                 "stopped by a signal (%s): the results are those of the steps done",
                 sig == SIGTERM  ? "SIGTERM"
                 : sig == SIGINT ? "SIGINT"
                                 : "a stop request");
    s->stop_advice = "; lubdem run --resume continues the run";
}

/* The driver's warnings: a continuation by another build, fewer threads than asked for,
 * particle snapshots not written. */
static void run_driver_warnings(run_state *s)
{
    lub_run_ctx *ctx = &s->ctx;
    if (s->build_warning[0])
        append_warning(ctx, s->build_warning);
    if (s->req->checkpoint_every_s > 0.0 && !s->scene->resumable) {
        char text[512]; /* until 2026-12-07 it was ignored without a word */
        snprintf(text, sizeof text,
                 "--checkpoint-every was ignored: a %s run takes no checkpoints (--resume "
                 "continues simple_shear and resuspension runs)",
                 s->scene->name);
        append_warning(ctx, text);
    }
    if (ctx->threads < s->threads_requested && s->processors <= s->thread_limit) {
        char text[256];
        snprintf(text, sizeof text,
                 "--threads %d asked for more threads than the %d processor%s this process may "
                 "run on; the run used %d (more threads would only slow it down)",
                 s->threads_requested, s->processors, s->processors == 1 ? "" : "s", ctx->threads);
        append_warning(ctx, text);
    } else if (ctx->threads < s->threads_requested) {
        char text[256];
        snprintf(text, sizeof text,
                 "--threads %d asked for more threads than the OpenMP thread limit of %d "
                 "(OMP_THREAD_LIMIT); the run used %d: its results are those of a %d-thread "
                 "run",
                 s->threads_requested, s->thread_limit, ctx->threads, ctx->threads);
        append_warning(ctx, text);
    }
    const int used = run_threads_used(s);
    if (used < ctx->threads) {
        char text[256];
        snprintf(text, sizeof text,
                 "OpenMP gave teams of as few as %d of the %d threads the run asked for; the "
                 "summary's threads is %d (a %d-thread run differs by round-off)",
                 used, ctx->threads, used, ctx->threads);
        append_warning(ctx, text);
    }
    char why[256];
    int64_t first_skipped = 0;
    const int64_t skipped = lub_h5_snapshots_skipped(s->h5, &first_skipped, why, sizeof why);
    if (skipped > 0) {
        char text[512];
        snprintf(text, sizeof text,
                 "%lld particle snapshot%s from step %lld on %s not written: %s; the other "
                 "outputs are not affected; lower /snapshots (or run with more room)",
                 (long long)skipped, skipped == 1 ? "" : "s", (long long)first_skipped,
                 skipped == 1 ? "was" : "were", why);
        append_warning(ctx, text);
    }
}

/* result.h5: parameters, status, close, sync, rename; s->h5_failed (with its reason and
 * whether it was room) when any of them failed; s->h5 is freed. */
static void run_finish_result_h5(run_state *s)
{
    char *resolved_text = lub_json_dumps(s->resolved, JSON_INDENT(2) | JSON_SORT_KEYS);
    json_t *units = json_object_get(s->ctx.summary_extra, "units");
    char *units_text = units ? json_dumps(units, JSON_COMPACT | JSON_SORT_KEYS) : NULL;
    const int params_failed =
        lub_h5_write_parameters(s->h5, s->req->spec_text, resolved_text, units_text) != 0;
    char params_reason[256] = ""; /* lub_h5_finish frees h5 and its last error */
    if (params_failed)
        snprintf(params_reason, sizeof params_reason, "%s", lub_h5_last_error(s->h5));
    s->h5_failed = lub_h5_finish(s->h5, status_of(s->rc), s->h5_reason, sizeof s->h5_reason) != 0;
    s->h5 = NULL;
    if (params_failed && !s->h5_failed) {
        s->h5_failed = 1;
        snprintf(s->h5_reason, sizeof s->h5_reason, "%s", params_reason);
    }
    free(resolved_text);
    free(units_text);
    if (!s->h5_failed && lub_sync_path(s->h5_tmp) != 0) {
        s->h5_failed = 1;
        snprintf(s->h5_reason, sizeof s->h5_reason, "%s (putting it on disk)", strerror(errno));
    }
    s->h5_room = 1;
    if (!s->h5_failed && rename(s->h5_tmp, s->h5_dst) != 0) {
        s->h5_failed = 1;
        s->h5_room = lub_h5_output_failure(errno);
        snprintf(s->h5_reason, sizeof s->h5_reason, "%s", strerror(errno));
    }
    s->renamed = !s->h5_failed;
}

/* checkpoint.h5 goes with the result.h5 just renamed: a new one replaces the old (and a
 * periodic one's copy of result.h5); a run that ends otherwise removes the old one and its
 * copy (its result.h5 has been replaced), except a run stopped without a new one that was
 * continued or took periodic checkpoints (the last checkpoint and the file with its rows
 * still go together). Sets s->checkpoint_kept. */
static void run_settle_checkpoint(run_state *s)
{
    lub_run_ctx *ctx = &s->ctx;
    char notes_why[600] = "";
    if (ctx->checkpoint_written && s->renamed &&
        lub_ckpt_set_notes(s->ckpt_tmp, BUILD_NOTE_COUNT, BUILD_NOTES, s->note_texts, notes_why,
                           sizeof notes_why) == 0 &&
        lub_sync_path(s->ckpt_tmp) == 0 && rename(s->ckpt_tmp, s->ckpt_dst) == 0) {
        s->checkpoint_kept = 1;
        unlink(s->copy_dst);
        return;
    }
    const char *reason = !s->renamed    ? "result.h5 could not be written"
                         : notes_why[0] ? notes_why
                                        : strerror(errno);
    /* The checkpoint this run continued from, or the last periodic one, still goes with the
     * file holding its rows when the run was stopped, or when it lost its result.h5: --resume
     * continues from it once the run has room. */
    const int periodic_taken = ctx->periodic && ctx->periodic->written > 0;
    if ((s->rc == LUB_EXIT_INTERRUPTED || s->h5_failed) && (s->resuming || periodic_taken)) {
        s->checkpoint_kept = access(s->ckpt_dst, F_OK) == 0;
    } else {
        unlink(s->ckpt_dst);
        unlink(s->copy_dst);
    }
    char text[600] = "";
    const char *then = s->checkpoint_kept ? "--resume continues from the last one kept"
                                          : "--resume will start this run afresh";
    if (ctx->checkpoint_written)
        snprintf(text, sizeof text, "no checkpoint was kept (%.400s): %s", reason, then);
    else if (ctx->checkpoint_failure[0])
        snprintf(text, sizeof text, "no checkpoint was written (%.400s): %s",
                 ctx->checkpoint_failure, then);
    unlink(s->ckpt_tmp);
    if (text[0])
        append_warning(ctx, text);
    /* the scene advised --resume before the checkpoint was lost (until 2026-12-06 both pieces
     * of advice stood side by side) */
    if (!s->checkpoint_kept)
        lub_run_withdraw_resume_advice(ctx->summary_extra);
}

/* A stopped run's note on stderr (advising --resume only if it can), and a failed periodic
 * checkpoint's warning. */
static void run_report_stop(run_state *s)
{
    lub_run_ctx *ctx = &s->ctx;
    if (s->stop_advice) {
        if (s->checkpoint_kept) {
            const size_t used = strlen(ctx->diagnostic);
            snprintf(ctx->diagnostic + used, sizeof ctx->diagnostic - used, "%s", s->stop_advice);
        }
        fprintf(s->req->diag, "note: %s\n", ctx->diagnostic);
    }
    /* this run's copy of result.h5 not published, or one a killed run left (until 2026-12-07
     * it was removed only by a run taking periodic checkpoints too) */
    unlink(s->copy_tmp);
    if (ctx->periodic) {
        if (ctx->periodic->failure[0]) {
            char text[600];
            snprintf(text, sizeof text,
                     "a periodic checkpoint failed (%s); the run went on, with the last one "
                     "taken (%ld in all)",
                     ctx->periodic->failure, ctx->periodic->written);
            append_warning(ctx, text);
        }
    }
}

/* summary.json: fixed members, then whatever the scene added (active_terms, units, ...);
 * results at 10 significant digits, the spec exact. 0, or -1 with *failed_errno. */
static int run_write_summary(run_state *s, int *failed_errno)
{
    lub_run_ctx *ctx = &s->ctx;
    json_t *summary = json_object();
    json_object_set_new(summary, "scene", json_string(s->scene->name));
    json_object_set_new(summary, "status", json_string(status_of(s->rc)));
    json_object_set_new(summary, "exit_code", json_integer(s->rc));
    json_object_set(summary, "results", ctx->summary_results);
    json_object_update(summary, ctx->summary_extra);
    json_object_set_new(summary, "wall_time_s", json_real(s->wall));
    json_object_set_new(summary, "threads", json_integer(run_threads_used(s)));
    json_object_set_new(summary, "threads_requested", json_integer(s->threads_requested));
    if (s->resuming)
        json_object_set_new(summary, "resumed_from_step", json_integer(ctx->resumed_from_step));
    if (s->checkpoint_kept)
        json_object_set_new(summary, "checkpoint", json_string("checkpoint.h5"));
    if (ctx->periodic)
        json_object_set_new(summary, "periodic_checkpoints", json_integer(ctx->periodic->written));
    if (ctx->diagnostic[0])
        json_object_set_new(summary, "diagnostic", json_string(ctx->diagnostic));
    json_object_set_new(summary, "lubdem_version", json_string(lub_build_version()));
    json_object_set_new(summary, "git_commit", json_string(lub_build_git()));
    if (s->builds)
        json_object_set(summary, "builds", s->builds);
    /* results at 10 significant digits; the spec exact, so that a continuation built from it
     * is the same run (until 2026-12-06 it was rounded too: 1/30 came back as 0.03333333333,
     * and --resume refused the default resuspension spec taken from its own summary) */
    json_t *rounded = json_deep_copy(summary);
    if (rounded) { /* out of memory: all exact */
        json_decref(summary);
        summary = rounded;
        lub_json_round_reals(summary, 10);
    }
    json_object_set(summary, "spec", s->resolved);
    char *text = lub_json_dumps(summary, JSON_INDENT(2));
    errno = 0;
    const int failed = write_file_atomic(s->req->out_dir, "summary.json", text) != 0;
    *failed_errno = errno;
    lub_sync_path(s->req->out_dir); /* the renames into DIR, on disk too (best effort) */
    free(text);
    json_decref(summary);
    return failed ? -1 : 0;
}

/* The scene's advisory warnings (summary "warnings") on stderr, one line each, for runs that
 * did not fail: a failed run's last stderr line stays its error. */
static void run_report_warnings(run_state *s)
{
    json_t *warnings = json_object_get(s->ctx.summary_extra, "warnings");
    if (!json_is_array(warnings) || (s->rc != LUB_EXIT_OK && s->rc != LUB_EXIT_INTERRUPTED))
        return;
    size_t w;
    json_t *wtext;
    json_array_foreach (warnings, w, wtext) {
        if (json_is_string(wtext))
            fprintf(s->req->diag, "warning: %s\n", json_string_value(wtext));
    }
}

/* stderr once the summary is written: the error of a failed run, or the refusal only the run
 * could make. */
static void run_report_outcome(run_state *s)
{
    const lub_run_request *req = s->req;
    lub_run_ctx *ctx = &s->ctx;
    if (s->rc == LUB_EXIT_NUMERICAL || s->rc == LUB_EXIT_INTERNAL || s->rc == LUB_EXIT_IO)
        fprintf(req->diag, "error: %s\n",
                ctx->diagnostic[0] ? ctx->diagnostic : "the scene failed without a diagnostic");
    if (s->rc == LUB_EXIT_BAD_SPEC) { /* a refusal only the run could make */
        const char *line = ctx->diagnostic[0] ? ctx->diagnostic : "refused";
        char pointer[256];
        const char *message = leading_pointer(line, pointer, sizeof pointer);
        report_refusal(req->diag, req->json_errors, pointer, message, line);
    }
}

/* The file in DIR that holds the rows of the checkpoint at ckpt_path (its "output_file":
 * result.h5 or LUB_PERIODIC_OUTPUT) into out[len]; "" when it cannot be read. */
static void checkpoint_rows_file(const char *ckpt_path, const char *out_dir, char *out, size_t len)
{
    out[0] = '\0';
    lub_ckpt *c = lub_ckpt_open(ckpt_path, NULL, 0);
    char *name = c ? lub_ckpt_get_text(c, "output_file") : NULL;
    if (name && (strcmp(name, "result.h5") == 0 || strcmp(name, LUB_PERIODIC_OUTPUT) == 0))
        snprintf(out, len, "%s/%s", out_dir, name);
    free(name);
    lub_ckpt_close(c, NULL, 0);
}

/* A summary that could not be written: the errors the summary would have held go to stderr,
 * and no result.h5 stays without it, unless a checkpoint is kept: the checkpoint and the file
 * holding its rows then stay (until 2026-12-07 they were removed too, and with them the
 * stopped run a continuation had taken up), so that --resume goes on once the summary can be
 * written. Exit 4 whatever the run's own outcome was: no summary is left to read. scene_rc,
 * scene_diagnostic: the scene's own outcome, before the loss of result.h5 was added. */
static void run_summary_lost(run_state *s, int summary_errno, int scene_rc,
                             const char *scene_diagnostic)
{
    const lub_run_request *req = s->req;
    if (scene_rc != LUB_EXIT_OK && scene_rc != LUB_EXIT_INTERRUPTED)
        fprintf(req->diag, "error: %s\n",
                scene_diagnostic[0] ? scene_diagnostic : "the scene failed without a diagnostic");
    if (s->h5_failed)
        fprintf(req->diag, "error: cannot write result.h5 in %s: %s\n", req->out_dir,
                s->h5_reason[0] ? s->h5_reason : "HDF5 error");
    fprintf(req->diag, "error: cannot write the results in %s%s%s\n", req->out_dir,
            summary_errno ? ": " : "", summary_errno ? strerror(summary_errno) : "");
    char rows[RUN_PATH_LEN] = "";
    if (s->checkpoint_kept)
        checkpoint_rows_file(s->ckpt_dst, req->out_dir, rows, sizeof rows);
    if (rows[0]) { /* the checkpoint and its rows stay; a result.h5 it does not need goes */
        if (strcmp(rows, s->h5_dst) != 0 && s->renamed)
            unlink(s->h5_dst);
        if (strcmp(rows, s->copy_dst) != 0)
            unlink(s->copy_dst);
        fprintf(req->diag,
                "note: %s and %s, which holds its rows, are kept: lubdem run --resume continues "
                "the run once summary.json can be written\n",
                s->ckpt_dst, rows);
    } else if (s->renamed) { /* no result.h5 without its summary, no checkpoint without both */
        unlink(s->h5_dst);
        unlink(s->ckpt_dst);
        unlink(s->copy_dst);
    }
    s->rc = LUB_EXIT_IO;
}

/* Everything after the scene's run: result.h5, the checkpoint, the summary, stderr. */
static void run_conclude(run_state *s)
{
    lub_run_ctx *ctx = &s->ctx;
    run_stop_reason(s);
    run_driver_warnings(s);
    /* on failure result.h5 is removed (which frees its space for the summary) and the run's
     * results still go to summary.json */
    run_finish_result_h5(s);
    run_settle_checkpoint(s);
    run_report_stop(s);
    const int scene_rc = s->rc; /* what the scene said, before the loss of result.h5 is added */
    char scene_diagnostic[sizeof ctx->diagnostic];
    memcpy(scene_diagnostic, ctx->diagnostic, sizeof scene_diagnostic);
    if (s->h5_failed) {
        unlink(s->h5_tmp);
        /* an older result.h5 in DIR is not this run's (a stale one beside this run's summary
         * was taken for its file), unless it holds the rows of the checkpoint kept */
        const int rows_in_result =
            s->checkpoint_kept && s->resuming && strcmp(s->resume_result, s->h5_dst) == 0;
        if (!rows_in_result)
            unlink(s->h5_dst);
        report_result_h5_lost(ctx, &s->rc, s->req->out_dir, s->h5_reason, s->h5_room, s->resolved,
                              s->checkpoint_kept);
    }
    /* the last progress line: 1 only for a run that completed (a failed run's said 1) */
    lub_progress_end(&s->progress, s->rc == LUB_EXIT_OK);
    int summary_errno = 0;
    const int summary_failed = run_write_summary(s, &summary_errno) != 0;
    run_report_warnings(s);
    if (!summary_failed)
        run_report_outcome(s);
    else
        run_summary_lost(s, summary_errno, scene_rc, scene_diagnostic);
}

int lub_run_spec(const lub_run_request *req)
{
    run_state *s = calloc(1, sizeof *s);
    if (!s) {
        fprintf(req->diag, "error: out of memory\n");
        return LUB_EXIT_INTERNAL;
    }
    s->req = req;
    s->resolved = parse_and_resolve(req->spec_text, req->diag, req->json_errors);
    if (!s->resolved) {
        free(s);
        return LUB_EXIT_BAD_SPEC; /* nothing created */
    }
    s->scene = lub_scene_find(json_string_value(json_object_get(s->resolved, "scene")));
    if (mkdir_p(req->out_dir, s->made) != 0) {
        fprintf(req->diag, "error: cannot create output folder %s: %s\n", req->out_dir,
                strerror(errno));
        s->rc = LUB_EXIT_IO;
    } else {
        run_paths(s);
        s->rc = run_check_checkpoint(s);
        if (s->rc == LUB_EXIT_OK)
            run_builds_init(s);
    }
    if (s->rc == LUB_EXIT_OK) {
        char errbuf[4400];
        s->h5 = lub_h5_create(s->h5_tmp, errbuf, sizeof errbuf);
        if (!s->h5) {
            fprintf(req->diag, "error: %s\n", errbuf);
            unlink(s->h5_tmp); /* what HDF5 may have begun */
            s->rc = LUB_EXIT_IO;
        }
    }
    if (s->rc != LUB_EXIT_OK) { /* refused or not started: nothing run, nothing written */
        remove_made(req->out_dir, s->made);
        const int rc = s->rc;
        json_decref(s->resolved);
        json_decref(s->builds);
        free(s->earlier_builds);
        free(s);
        return rc;
    }
    run_context_init(s);
    const double t0 = lub_wall_seconds();
    s->rc = fits_in_memory(s->scene, s->resolved, &s->ctx) ? s->scene->run(s->resolved, &s->ctx)
                                                           : LUB_EXIT_INTERNAL;
    s->wall = lub_wall_seconds() - t0;
    if (!run_not_begun(s))
        run_conclude(s);
    const int rc = s->rc;
    json_decref(s->ctx.summary_results);
    json_decref(s->ctx.summary_extra);
    json_decref(s->resolved);
    json_decref(s->builds);
    free(s->earlier_builds);
    free(s);
    return rc;
}
