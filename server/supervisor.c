/* supervisor.c — worker processes and periodic reaping. */
#define _GNU_SOURCE
#include "supervisor.h"

#include <errno.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include "lease.h"
#include "queue.h"
#include "worker.h"

typedef struct {
    pid_t pid;         /* 0 = not running */
    double restart_at; /* monotonic time of the next start attempt */
    int failures;      /* consecutive quick deaths, for the back-off */
    double started;
} worker_slot;

static double mono(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

int lubd_reap_once(sqlite3 *db, int quiet)
{
    int requeued = 0, failed = 0;
    if (lubd_queue_reap(db, &requeued, &failed) != 0)
        return -1;
    if (!quiet && (requeued || failed))
        fprintf(stderr, "lubdemd: reaper: %d job(s) requeued, %d failed after max attempts\n",
                requeued, failed);
    return 0;
}

/* argv for `lubdemd worker` or `lubdemd keep-checkpoints`, built before fork (the child only
 * calls execv). */
typedef struct {
    char num[10][24];
    char name[64], how[64];
    const char *argv[44];
} worker_argv;

/* self_exe, then the NULL-terminated `lead` (the subcommand and its own options), then the
 * service's options a worker runs with. */
static void build_argv(const lubd_config *c, const char *const *lead, worker_argv *w)
{
    int a = 0, k = 0;
    w->argv[a++] = c->self_exe;
    while (*lead)
        w->argv[a++] = *lead++;
    w->argv[a++] = "--db";
    w->argv[a++] = c->db_path;
    w->argv[a++] = "--jobs-dir";
    w->argv[a++] = c->jobs_dir;
    w->argv[a++] = "--engine";
    w->argv[a++] = c->engine;
#define NUM(opt, v)                                                                                \
    snprintf(w->num[k], sizeof w->num[k], "%ld", (long)(v));                                       \
    w->argv[a++] = opt;                                                                            \
    w->argv[a++] = w->num[k++];
    NUM("--lease-s", c->lease_s)
    NUM("--cpu-s", c->cpu_s)
    NUM("--mem-mb", c->mem_mb)
    NUM("--fsize-mb", c->fsize_mb)
    NUM("--grace-s", c->grace_s)
    NUM("--wall-s", c->wall_s)
    NUM("--engine-threads", c->engine_threads)
    NUM("--checkpoint-s", c->checkpoint_s)
    NUM("--keep-checkpoints", c->keep_checkpoints)
#undef NUM
    w->argv[a] = NULL;
}

/* fork + exec of argv, the child dying with the service (PR_SET_PDEATHSIG). The pid, or -1. */
static pid_t spawn(const lubd_config *cfg, const worker_argv *w)
{
    pid_t parent = getpid();
    pid_t pid = fork();
    if (pid == 0) {
        prctl(PR_SET_PDEATHSIG, SIGKILL);
        if (getppid() != parent)
            _exit(1);
        sigset_t none;
        sigemptyset(&none);
        sigprocmask(SIG_SETMASK, &none, NULL);
        execv(cfg->self_exe, (char *const *)w->argv);
        _exit(127);
    }
    return pid;
}

static pid_t spawn_worker(const lubd_config *cfg, int index)
{
    worker_argv w;
    snprintf(w.name, sizeof w.name, "w%d", index);
    const char *lead[] = {"worker", "--name", w.name, NULL};
    build_argv(cfg, lead, &w);
    return spawn(cfg, &w);
}

/* The processes that keep a dead worker's checkpoints (keep_dead_worker_checkpoints), so that
 * they are waited for at the stop. */
typedef struct {
    pid_t *pids;
    int n, cap;
} helper_set;

/* After worker `index` (process pid) ended with `status`: its jobs on their last attempt keep
 * the checkpoints their engines left (lubd_worker_keep_dead_worker_checkpoints), in a process
 * of their own (`lubdemd keep-checkpoints`): checksumming the kept files takes as long as
 * reading them (seconds for a large checkpoint-result.h5), and until 2026-12-07 it was done
 * here, in the supervisor's loop, which meanwhile neither reaped leases nor restarted workers.
 * The leases of those jobs are extended first, so that the reaper does not fail them without
 * their checkpoints before that process heartbeats them. */
static void keep_dead_worker_checkpoints(const lubd_config *cfg, sqlite3 *db, int index, pid_t pid,
                                         int status, helper_set *helpers)
{
    worker_argv w;
    snprintf(w.name, sizeof w.name, "w%d-pid%ld", index, (long)pid);
    if (WIFSIGNALED(status))
        snprintf(w.how, sizeof w.how, "signal %d", WTERMSIG(status));
    else
        snprintf(w.how, sizeof w.how, "exit code %d", WEXITSTATUS(status));
    const int held = lubd_lease_extend_last_attempts(db, w.name, cfg->lease_s);
    if (held == 0)
        return; /* none of its jobs is on its last attempt */
    const char *lead[] = {"keep-checkpoints",
                          "--worker",
                          w.name,
                          "--how",
                          w.how,
                          cfg->quiet ? "--quiet" : NULL,
                          NULL};
    build_argv(cfg, lead, &w);
    if (helpers->n == helpers->cap) {
        const int cap = helpers->cap ? 2 * helpers->cap : 4;
        pid_t *grown = realloc(helpers->pids, (size_t)cap * sizeof *grown);
        if (grown) {
            helpers->pids = grown;
            helpers->cap = cap;
        }
    }
    const pid_t child = helpers->n < helpers->cap ? spawn(cfg, &w) : -1;
    if (child < 0) {
        fprintf(stderr,
                "lubdemd: cannot start the process that keeps the checkpoints of the jobs of "
                "worker %s: %s\n",
                w.name, strerror(errno));
        return;
    }
    helpers->pids[helpers->n++] = child;
}

/* Forgets helper `pid` once it has been waited for: 1 when it was one, 0 when not. */
static int helper_ended(helper_set *helpers, pid_t pid)
{
    for (int i = 0; i < helpers->n; ++i)
        if (helpers->pids[i] == pid) {
            helpers->pids[i] = helpers->pids[--helpers->n];
            return 1;
        }
    return 0;
}

int lubd_supervise(const lubd_config *cfg, lubd_server *srv)
{
    sqlite3 *db = lubd_db_open(cfg->db_path, 0);
    if (!db)
        return -1;
    int n = cfg->workers;
    worker_slot *slots = calloc((size_t)(n > 0 ? n : 1), sizeof *slots);
    if (!slots) {
        lubd_db_close(db);
        return -1;
    }
    sigset_t set;
    sigemptyset(&set);
    sigaddset(&set, SIGTERM);
    sigaddset(&set, SIGINT);
    sigaddset(&set, SIGCHLD);
    double reap_every = cfg->lease_s / 2.0;
    if (reap_every > 5)
        reap_every = 5;
    if (reap_every < 0.5)
        reap_every = 0.5;
    double next_reap = 0;
    int stopping = 0;
    helper_set helpers = {NULL, 0, 0};
    while (!stopping) {
        double t = mono();
        int alive = 0;
        for (int i = 0; i < n; ++i) {
            if (slots[i].pid == 0 && t >= slots[i].restart_at) {
                slots[i].pid = spawn_worker(cfg, i);
                if (slots[i].pid < 0) {
                    slots[i].pid = 0;
                    slots[i].restart_at = t + 1;
                } else {
                    slots[i].started = t;
                }
            }
            alive += slots[i].pid > 0;
        }
        atomic_store(&srv->workers_alive, alive);
        if (t >= next_reap) {
            lubd_reap_once(db, cfg->quiet);
            next_reap = t + reap_every;
        }
        struct timespec timeout = {0, 250 * 1000000L};
        int sig = sigtimedwait(&set, NULL, &timeout);
        if (sig == SIGTERM || sig == SIGINT)
            stopping = 1;
        int status;
        pid_t pid;
        while ((pid = waitpid(-1, &status, WNOHANG)) > 0) {
            if (helper_ended(&helpers, pid)) {
                if (!WIFEXITED(status) || WEXITSTATUS(status) != 0)
                    fprintf(stderr,
                            "lubdemd: the process that keeps a dead worker's checkpoints "
                            "(pid %ld) ended with %s %d\n",
                            (long)pid, WIFSIGNALED(status) ? "signal" : "exit code",
                            WIFSIGNALED(status) ? WTERMSIG(status) : WEXITSTATUS(status));
                continue;
            }
            for (int i = 0; i < n; ++i) {
                if (slots[i].pid != pid)
                    continue;
                slots[i].pid = 0;
                double now = mono();
                slots[i].failures = (now - slots[i].started < 5) ? slots[i].failures + 1 : 0;
                double delay = slots[i].failures > 5 ? 5.0 : 0.2 * slots[i].failures;
                slots[i].restart_at = now + delay;
                if (!stopping)
                    fprintf(stderr, "lubdemd: worker w%d (pid %ld) died (%s %d); restarting\n", i,
                            (long)pid, WIFSIGNALED(status) ? "signal" : "exit",
                            WIFSIGNALED(status) ? WTERMSIG(status) : WEXITSTATUS(status));
                /* its engine died with it (PR_SET_PDEATHSIG): a job it held on its last
                 * attempt keeps the checkpoint that engine left (until 2026-12-07 the reaper
                 * failed it without, a lease later) */
                keep_dead_worker_checkpoints(cfg, db, i, pid, status, &helpers);
            }
        }
    }
    /* Stop: workers give their jobs back, then exit; the processes keeping a dead worker's
     * checkpoints are given the same time to finish (one killed leaves its jobs running, to be
     * taken up at the next start as those of a service that died). */
    for (int i = 0; i < n; ++i)
        if (slots[i].pid > 0)
            kill(slots[i].pid, SIGTERM);
    double deadline = mono() + cfg->grace_s + 5;
    for (;;) {
        int left = 0;
        for (int i = 0; i < n; ++i) {
            if (slots[i].pid <= 0)
                continue;
            int status;
            if (waitpid(slots[i].pid, &status, WNOHANG) == slots[i].pid)
                slots[i].pid = 0;
            else
                ++left;
        }
        for (int i = helpers.n - 1; i >= 0; --i) {
            if (waitpid(helpers.pids[i], NULL, WNOHANG) == helpers.pids[i])
                helper_ended(&helpers, helpers.pids[i]);
            else
                ++left;
        }
        if (!left)
            break;
        if (mono() > deadline) {
            for (int i = 0; i < n; ++i)
                if (slots[i].pid > 0) {
                    kill(slots[i].pid, SIGKILL);
                    waitpid(slots[i].pid, NULL, 0);
                    slots[i].pid = 0;
                }
            while (helpers.n > 0) {
                kill(helpers.pids[0], SIGKILL);
                waitpid(helpers.pids[0], NULL, 0);
                helper_ended(&helpers, helpers.pids[0]);
            }
            break;
        }
        struct timespec ts = {0, 50 * 1000000L};
        nanosleep(&ts, NULL);
    }
    atomic_store(&srv->workers_alive, 0);
    free(helpers.pids);
    free(slots);
    lubd_db_close(db);
    return 0;
}
