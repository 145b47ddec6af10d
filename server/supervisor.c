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

/* argv for `lubdemd worker`, built before fork (the child only calls execv). */
typedef struct {
    char num[10][24];
    char name[32];
    const char *argv[40];
} worker_argv;

static void build_argv(const lubd_config *c, int index, worker_argv *w)
{
    int a = 0, k = 0;
    w->argv[a++] = c->self_exe;
    w->argv[a++] = "worker";
    snprintf(w->name, sizeof w->name, "w%d", index);
    w->argv[a++] = "--name";
    w->argv[a++] = w->name;
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

/* After worker `index` (process pid) ended with `status`: lubd_worker_keep_dead_worker_checkpoints
 * for the jobs it held. */
static void keep_dead_worker_checkpoints(const lubd_config *cfg, sqlite3 *db, int index, pid_t pid,
                                         int status)
{
    char name[64], how[64];
    snprintf(name, sizeof name, "w%d-pid%ld", index, (long)pid);
    if (WIFSIGNALED(status))
        snprintf(how, sizeof how, "signal %d", WTERMSIG(status));
    else
        snprintf(how, sizeof how, "exit code %d", WEXITSTATUS(status));
    const int kept = lubd_worker_keep_dead_worker_checkpoints(cfg, db, name, how);
    if (kept < 0)
        fprintf(stderr, "lubdemd: cannot keep the checkpoints of the jobs of worker %s\n", name);
    else if (kept > 0 && !cfg->quiet)
        fprintf(stderr,
                "lubdemd: %d job(s) of worker %s on their last attempt failed with the "
                "checkpoint their engine left\n",
                kept, name);
}

static pid_t spawn_worker(const lubd_config *cfg, int index)
{
    worker_argv w;
    build_argv(cfg, index, &w);
    pid_t parent = getpid();
    pid_t pid = fork();
    if (pid == 0) {
        prctl(PR_SET_PDEATHSIG, SIGKILL);
        if (getppid() != parent)
            _exit(1);
        sigset_t none;
        sigemptyset(&none);
        sigprocmask(SIG_SETMASK, &none, NULL);
        execv(cfg->self_exe, (char *const *)w.argv);
        _exit(127);
    }
    return pid;
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
                keep_dead_worker_checkpoints(cfg, db, i, pid, status);
            }
        }
    }
    /* Stop: workers give their jobs back, then exit. */
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
        if (!left)
            break;
        if (mono() > deadline) {
            for (int i = 0; i < n; ++i)
                if (slots[i].pid > 0) {
                    kill(slots[i].pid, SIGKILL);
                    waitpid(slots[i].pid, NULL, 0);
                    slots[i].pid = 0;
                }
            break;
        }
        struct timespec ts = {0, 50 * 1000000L};
        nanosleep(&ts, NULL);
    }
    atomic_store(&srv->workers_alive, 0);
    free(slots);
    lubd_db_close(db);
    return 0;
}
