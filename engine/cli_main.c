/* cli_main.c — the `lubdem` command line (contract in README.md, "CLI contract"). */
#include <errno.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "build_info.h"
#include "contact_batch.h"
#include "run_driver.h"
#include "scene.h"

static volatile sig_atomic_t stop_flag = 0;

/* SIGTERM, SIGINT, SIGXCPU (the CPU-time limit): the run stops at its next step; the flag holds
 * the signal, so that the summary can say which */
static void on_stop_signal(int sig) { stop_flag = sig; }

static void usage(FILE *f)
{
    fprintf(f, "usage:\n"
               "  lubdem run SPEC.json --out DIR [--threads N] [--resume] [--keep-checkpoint]\n"
               "             [--checkpoint-every SECONDS] [--quiet] [--json-errors]\n"
               "  lubdem validate SPEC.json [--json-errors]\n"
               "  lubdem scenes\n"
               "  lubdem version\n"
               "SPEC may be '-' for standard input. Exit codes: 0 ok, 1 internal, 2 usage or\n"
               "invalid spec, 3 numerical failure, 4 output error, 5 stopped by a signal.\n"
               "--resume continues the run stopped in DIR from DIR/checkpoint.h5, or starts it\n"
               "when there is none; --keep-checkpoint keeps the checkpoint of a completed run,\n"
               "to extend it; --checkpoint-every also writes one every SECONDS of wall time (a\n"
               "kill -9 then loses at most that much). With --resume the spec must be the\n"
               "stopped run's, except these members (/strain not below the strain already run):\n");
    /* from the scenes' own lists, which the continuation checks */
    for (const lub_scene *const *s = lub_scene_list(); *s; ++s) {
        if (!(*s)->resumable || !(*s)->resume_may_differ)
            continue;
        fprintf(f, "  %s:", (*s)->name);
        for (const char *const *m = (*s)->resume_may_differ; *m; ++m)
            fprintf(f, "%s /%s", m == (*s)->resume_may_differ ? "" : ",", *m);
        fprintf(f, "\n");
    }
}

/* The largest spec read: specs are a few kB, and a larger input is a mistake (README, CLI
 * contract, "Spec"). */
#define SPEC_MAX_BYTES ((size_t)64 << 20)

/* Reads a whole file (or stdin for "-") into a NUL-terminated buffer of *len bytes (the file may
 * hold NUL bytes of its own: the caller checks); caller frees. NULL with the reason in why[]:
 * the system's (the file cannot be opened or read), larger than SPEC_MAX_BYTES, or no memory. */
static char *read_all(const char *path, size_t *len, char *why, size_t why_len)
{
    FILE *f = strcmp(path, "-") == 0 ? stdin : fopen(path, "rb");
    if (!f) {
        snprintf(why, why_len, "%s", strerror(errno));
        return NULL;
    }
    size_t cap = 1 << 14, n = 0;
    char *buf = malloc(cap);
    for (;;) {
        if (!buf) {
            snprintf(why, why_len, "out of memory");
            break;
        }
        /* read at most one byte beyond the limit, which is then known to be passed */
        size_t want = cap - n - 1;
        if (want > SPEC_MAX_BYTES + 1 - n)
            want = SPEC_MAX_BYTES + 1 - n;
        errno = 0;
        const size_t got = fread(buf + n, 1, want, f);
        n += got;
        if (n > SPEC_MAX_BYTES) {
            snprintf(why, why_len, "larger than %zu MiB (a spec is a few kB)",
                     SPEC_MAX_BYTES >> 20);
            free(buf);
            buf = NULL;
            break;
        }
        if (got < want) { /* the end of the file, or an error */
            if (ferror(f)) {
                snprintf(why, why_len, "%s", errno ? strerror(errno) : "read error");
                free(buf);
                buf = NULL;
            }
            break;
        }
        char *nb = realloc(buf, cap * 2);
        if (!nb)
            free(buf);
        buf = nb;
        cap *= 2;
    }
    if (buf) {
        buf[n] = '\0';
        *len = n;
    }
    if (f != stdin)
        fclose(f);
    return buf;
}

/* rc, or 4 (output error, README "Exit codes") with a line on stderr when what was printed on
 * stdout could not all be written (a full disk, a closed pipe). The caller sets errno to 0
 * before it prints, so that the reason of a failed write is still in errno. */
static int stdout_written(int rc, const char *what)
{
    if (fflush(stdout) != 0 || ferror(stdout)) {
        fprintf(stderr, "error: cannot write %s to standard output: %s\n", what,
                errno ? strerror(errno) : "write error");
        return LUB_EXIT_IO;
    }
    return rc;
}

static int cmd_scenes(void)
{
    json_t *arr = json_array();
    for (const lub_scene *const *s = lub_scene_list(); *s; ++s)
        json_array_append_new(arr, json_pack("{s:s, s:s, s:s}", "name", (*s)->name, "title",
                                             (*s)->title, "description", (*s)->description));
    char *text = json_dumps(arr, JSON_INDENT(2));
    json_decref(arr);
    if (!text) {
        fprintf(stderr, "error: out of memory\n");
        return LUB_EXIT_INTERNAL;
    }
    errno = 0;
    printf("%s\n", text);
    free(text);
    return stdout_written(0, "the scene list");
}

int main(int argc, char **argv)
{
    if (argc < 2) {
        usage(stderr);
        return 2;
    }
    const char *cmd = argv[1];
    if (strcmp(cmd, "scenes") == 0)
        return cmd_scenes();
    if (strcmp(cmd, "version") == 0) {
        errno = 0;
        printf("lubdem %s (git %s; %s; %s; contact law SIMD %s)\n", lub_build_version(),
               lub_build_git(), lub_build_compiler(), lub_build_cflags(), lub_pair_batch_isa());
        return stdout_written(0, "the version");
    }
    if (strcmp(cmd, "--help") == 0 || strcmp(cmd, "help") == 0) {
        errno = 0;
        usage(stdout);
        return stdout_written(0, "the usage");
    }
    if (strcmp(cmd, "run") != 0 && strcmp(cmd, "validate") != 0) {
        fprintf(stderr, "error: unknown command '%s'\n", cmd);
        usage(stderr);
        return 2;
    }
    const char *spec_path = NULL, *out_dir = NULL;
    int threads = 1, quiet = 0, json_errors = 0, resume = 0, keep_checkpoint = 0;
    double checkpoint_every = 0.0;
    for (int i = 2; i < argc; ++i) {
        if (strcmp(argv[i], "--out") == 0 && i + 1 < argc) {
            out_dir = argv[++i];
            if (!out_dir[0]) {
                fprintf(stderr, "error: --out needs a folder name, not an empty one\n");
                return 2;
            }
        } else if (strcmp(argv[i], "--threads") == 0 && i + 1 < argc) {
            char *end;
            long t = strtol(argv[++i], &end, 10);
            if (*end || t < 1 || t > 1024) {
                fprintf(stderr, "error: --threads must be an integer from 1 to 1024\n");
                return 2;
            }
            threads = (int)t;
        } else if (strcmp(argv[i], "--quiet") == 0) {
            quiet = 1;
        } else if (strcmp(argv[i], "--resume") == 0) {
            resume = 1;
        } else if (strcmp(argv[i], "--keep-checkpoint") == 0) {
            keep_checkpoint = 1;
        } else if (strcmp(argv[i], "--checkpoint-every") == 0 && i + 1 < argc) {
            char *end;
            const double s = strtod(argv[++i], &end);
            if (*end || !(s >= 0.1 && s <= 1e7)) {
                fprintf(stderr, "error: --checkpoint-every must be a number of seconds from 0.1 "
                                "to 1e7\n");
                return 2;
            }
            checkpoint_every = s;
        } else if (strcmp(argv[i], "--json-errors") == 0) {
            json_errors = 1;
        } else if (!spec_path && (argv[i][0] != '-' || strcmp(argv[i], "-") == 0)) {
            spec_path = argv[i];
        } else {
            fprintf(stderr, "error: unexpected argument '%s'\n", argv[i]);
            usage(stderr);
            return 2;
        }
    }
    if (!spec_path) {
        fprintf(stderr, "error: missing SPEC.json\n");
        usage(stderr);
        return 2;
    }
    size_t text_len = 0;
    char why[128];
    char *text = read_all(spec_path, &text_len, why, sizeof why);
    if (!text) { /* with --json-errors in the JSON form too, as the NUL byte below */
        if (json_errors) {
            lub_error err;
            lub_fail(&err, "", "cannot read spec %s: %s", spec_path, why);
            lub_report_spec_error(stderr, json_errors, &err);
        } else {
            fprintf(stderr, "error: cannot read spec %s: %s\n", spec_path, why);
        }
        return 2;
    }
    const char *nul = memchr(text, '\0', text_len);
    if (nul) { /* the JSON reader would stop there and ignore the rest */
        lub_error err;
        lub_fail(&err, "", "the spec holds a NUL byte at byte %zu of %zu: a spec is JSON text",
                 (size_t)(nul - text), text_len);
        lub_report_spec_error(stderr, json_errors, &err);
        free(text);
        return 2;
    }
    int rc;
    if (strcmp(cmd, "validate") == 0) {
        rc = lub_validate_spec(text, stdout, stderr, json_errors);
    } else {
        if (!out_dir) {
            fprintf(stderr, "error: run needs --out DIR\n");
            free(text);
            return 2;
        }
        struct sigaction sa;
        memset(&sa, 0, sizeof sa);
        sa.sa_handler = on_stop_signal;
        sigemptyset(&sa.sa_mask);
        sigaction(SIGTERM, &sa, NULL);
        sigaction(SIGINT, &sa, NULL);
        /* the soft CPU-time limit (ulimit -t; lubdemd --cpu-s sets the hard one 5 s later):
         * stop with the results so far and a checkpoint instead of dying without them */
        sigaction(SIGXCPU, &sa, NULL);
        /* a write beyond RLIMIT_FSIZE fails (EFBIG: exit 4 with a message) instead of killing
         * the process; the snapshot writer keeps clear of the limit (h5md_writer.h) */
        signal(SIGXFSZ, SIG_IGN);
        lub_run_request req = {.spec_text = text,
                               .out_dir = out_dir,
                               .threads = threads,
                               .progress = quiet ? NULL : stdout,
                               .diag = stderr,
                               .json_errors = json_errors,
                               .stop_requested = &stop_flag,
                               .resume = resume,
                               .keep_checkpoint = keep_checkpoint,
                               .checkpoint_every_s = checkpoint_every};
        rc = lub_run_spec(&req);
    }
    free(text);
    return rc;
}
