/* engine_child.h — starting the `lubdem run` engine as a supervised child process.
 *
 * The child gets its own process group (so SIGTERM/SIGKILL reach everything it starts),
 * PR_SET_PDEATHSIG=SIGKILL (it dies with the worker), rlimits on CPU time, address space and
 * file size, stdout on a pipe (progress lines, read by the worker) and stderr appended to the
 * job log. The child never touches the database. Returns 0 with *p filled, -1 with errno. */
#ifndef LUBD_ENGINE_CHILD_H
#define LUBD_ENGINE_CHILD_H

#include <sys/types.h>

typedef struct {
    const char *engine; /* path of the lubdem binary */
    const char *spec;   /* spec.json */
    const char *out_dir;
    int log_fd;          /* stderr of the engine (append mode) */
    long cpu_s;          /* RLIMIT_CPU, 0 = unlimited */
    long mem_mb;         /* RLIMIT_AS, 0 = unlimited (sanitizer builds need 0) */
    long fsize_mb;       /* RLIMIT_FSIZE, 0 = unlimited */
    int threads;         /* --threads N, 0 = engine default */
    int resume;          /* --resume: out_dir holds the checkpoint of the job's stopped run */
    int checkpoint_s;    /* --checkpoint-every N (0: not passed) */
    int keep_checkpoint; /* --keep-checkpoint */
} lubd_engine_opts;

typedef struct {
    pid_t pid;     /* also the process group id */
    int stdout_fd; /* read end, O_CLOEXEC; caller closes */
} lubd_engine_proc;

int lubd_engine_spawn(const lubd_engine_opts *o, lubd_engine_proc *p);
/* Describes a wait status in words ("exit code 3", "killed by signal 9 (SIGKILL) ..."). */
void lubd_describe_status(int status, char *buf, size_t n);

#endif
