/* engine_child.c — fork/exec of the engine with limits and death signal. */
#define _GNU_SOURCE
#include "engine_child.h"

#include <errno.h>
#include <fcntl.h>
#include <signal.h>
#include <stdio.h>
#include <string.h>
#include <sys/prctl.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

static void set_limit(int resource, long value, long scale)
{
    if (value <= 0)
        return;
    struct rlimit rl = {(rlim_t)value * (rlim_t)scale, (rlim_t)value * (rlim_t)scale};
    if (resource == RLIMIT_CPU)
        rl.rlim_max = rl.rlim_cur + 5; /* SIGXCPU first, SIGKILL 5 s later */
    setrlimit(resource, &rl);
}

int lubd_engine_spawn(const lubd_engine_opts *o, lubd_engine_proc *p)
{
    int fds[2];
    if (pipe2(fds, O_CLOEXEC) != 0)
        return -1;
    char threads[32];
    snprintf(threads, sizeof threads, "%d", o->threads);
    const char *argv[16];
    int a = 0;
    argv[a++] = o->engine;
    argv[a++] = "run";
    argv[a++] = o->spec;
    argv[a++] = "--out";
    argv[a++] = o->out_dir;
    if (o->threads > 0) {
        argv[a++] = "--threads";
        argv[a++] = threads;
    }
    if (o->resume)
        argv[a++] = "--resume";
    char every[32];
    snprintf(every, sizeof every, "%d", o->checkpoint_s);
    if (o->checkpoint_s > 0) {
        argv[a++] = "--checkpoint-every";
        argv[a++] = every;
    }
    if (o->keep_checkpoint)
        argv[a++] = "--keep-checkpoint";
    argv[a] = NULL;
    pid_t parent = getpid();
    pid_t pid = fork();
    if (pid < 0) {
        int e = errno;
        close(fds[0]);
        close(fds[1]);
        errno = e;
        return -1;
    }
    if (pid == 0) {
        /* Child: only async-signal-safe calls until exec. */
        setpgid(0, 0);
        prctl(PR_SET_PDEATHSIG, SIGKILL);
        if (getppid() != parent)
            _exit(126); /* the worker died before we armed the death signal */
        sigset_t none;
        sigemptyset(&none);
        sigprocmask(SIG_SETMASK, &none, NULL);
        signal(SIGPIPE, SIG_DFL);
        signal(SIGTERM, SIG_DFL);
        signal(SIGINT, SIG_DFL);
        int devnull = open("/dev/null", O_RDONLY);
        if (devnull >= 0)
            dup2(devnull, 0);
        dup2(fds[1], 1);
        dup2(o->log_fd, 2);
        set_limit(RLIMIT_CPU, o->cpu_s, 1);
        set_limit(RLIMIT_AS, o->mem_mb, 1024L * 1024L);
        set_limit(RLIMIT_FSIZE, o->fsize_mb, 1024L * 1024L);
        const struct rlimit no_core = {0, 0}; /* set_limit takes 0 for "no limit" */
        setrlimit(RLIMIT_CORE, &no_core);
        execv(o->engine, (char *const *)argv);
        static const char msg[] = "error: lubdemd could not execute the engine binary\n";
        ssize_t ignored = write(2, msg, sizeof msg - 1);
        (void)ignored;
        _exit(127);
    }
    setpgid(pid, pid); /* also from the parent: no race with kill(-pid) */
    close(fds[1]);
    p->pid = pid;
    p->stdout_fd = fds[0];
    return 0;
}

void lubd_describe_status(int status, char *buf, size_t n)
{
    if (WIFEXITED(status)) {
        snprintf(buf, n, "exit code %d", WEXITSTATUS(status));
    } else if (WIFSIGNALED(status)) {
        int s = WTERMSIG(status);
        const char *why = "";
        if (s == SIGXCPU)
            why = ": CPU time limit exceeded";
        else if (s == SIGXFSZ)
            why = ": output size limit exceeded";
        else if (s == SIGKILL)
            why = ": killed (CPU hard limit, memory, or an operator)";
        else if (s == SIGSEGV || s == SIGBUS || s == SIGABRT || s == SIGFPE || s == SIGILL)
            why = ": the engine crashed";
        snprintf(buf, n, "killed by signal %d (%s)%s", s, strsignal(s), why);
    } else {
        snprintf(buf, n, "wait status %d", status);
    }
}
