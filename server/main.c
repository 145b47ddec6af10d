/* main.c — `lubdemd`: the service, its admin commands and the internal worker entries (`worker`,
 * `keep-checkpoints`). */
#include <errno.h>
#include <fcntl.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include "config.h"
#include "db.h"
#include "deletion.h"
#include "fsutil.h"
#include "http_server.h"
#include "queue.h"
#include "supervisor.h"
#include "tokens.h"
#include "worker.h"

/* Removes "--user NAME" and "--admin" from argv (in place); returns the new argc. */
static int take_user_opts(int argc, char **argv, const char **user, int *admin)
{
    int out = 0;
    for (int i = 0; i < argc; ++i) {
        if (strcmp(argv[i], "--user") == 0 && i + 1 < argc) {
            *user = argv[++i];
            continue;
        }
        if (strcmp(argv[i], "--admin") == 0) {
            *admin = 1;
            continue;
        }
        argv[out++] = argv[i];
    }
    return out;
}

/* The one service that uses a queue holds an exclusive lock on "<queue>.lock" for its whole
 * life (the descriptor is closed on exec, so workers and engines do not hold it). Holding it,
 * the start may take every running lease for the orphan of a service that died. Returns the
 * descriptor, or -1 after saying why. */
static int lock_queue(const lubd_config *cfg)
{
    char path[1200];
    if (lubd_pathf(path, sizeof path, "%s.lock", cfg->db_path) != 0) {
        fprintf(stderr, "lubdemd: path too long: %s.lock\n", cfg->db_path);
        return -1;
    }
    int fd = open(path, O_RDWR | O_CREAT | O_CLOEXEC, 0640);
    if (fd < 0) {
        fprintf(stderr, "lubdemd: cannot open %s: %s\n", path, strerror(errno));
        return -1;
    }
    if (flock(fd, LOCK_EX | LOCK_NB) != 0) {
        char pid[32] = "";
        ssize_t got = pread(fd, pid, sizeof pid - 1, 0);
        pid[got > 0 ? got : 0] = '\0';
        pid[strcspn(pid, "\n")] = '\0';
        fprintf(stderr,
                "lubdemd: another lubdemd%s%s%s is serving the queue %s (lock %s); stop it first, "
                "or give this one another --run-dir\n",
                pid[0] ? " (pid " : "", pid, pid[0] ? ")" : "", cfg->db_path, path);
        close(fd);
        return -1;
    }
    char mine[32];
    const int len = snprintf(mine, sizeof mine, "%ld\n", (long)getpid());
    if (ftruncate(fd, 0) != 0 || pwrite(fd, mine, (size_t)len, 0) != len)
        fprintf(stderr, "lubdemd: cannot write the pid into %s (the lock holds)\n", path);
    return fd;
}

/* Creates the run directory and opens the queue; the service (lock_fd not NULL) takes the
 * queue's lock first, the admin commands do not. */
static sqlite3 *open_state(lubd_config *cfg, int *lock_fd)
{
    if (lubd_mkdir_p(cfg->run_dir, 0750) != 0 || lubd_mkdir_p(cfg->jobs_dir, 0750) != 0) {
        fprintf(stderr, "lubdemd: cannot create %s: %s\n", cfg->run_dir, strerror(errno));
        return NULL;
    }
    if (lock_fd && (*lock_fd = lock_queue(cfg)) < 0)
        return NULL;
    return lubd_db_open(cfg->db_path, 1);
}

static int cmd_token(lubd_config *cfg, int argc, char **argv)
{
    if (argc < 3) {
        lubd_config_usage();
        return 2;
    }
    const char *user = NULL;
    int admin = 0;
    const char *sub = argv[2];
    const char *target = NULL;
    int first = 3;
    if (strcmp(sub, "revoke") == 0 && argc > 3 && argv[3][0] != '-') {
        target = argv[3];
        first = 4;
    }
    long long cap = 0;
    if (strcmp(sub, "cap") == 0) { /* `lubdemd user cap --user U N` */
        argc = take_user_opts(argc, argv, &user, &admin);
        if (argc < 4 || !user) {
            lubd_config_usage();
            return 2;
        }
        cap = strtoll(argv[3], NULL, 10);
        first = 4;
    }
    argc = take_user_opts(argc, argv, &user, &admin);
    if (lubd_config_parse(cfg, argc, argv, first) != 0)
        return 2;
    sqlite3 *db = open_state(cfg, NULL);
    if (!db)
        return 1;
    int rc = 0;
    if (strcmp(sub, "create") == 0) {
        char token[LUBD_TOKEN_MAX];
        if (!user) {
            fprintf(stderr, "lubdemd: token create needs --user NAME\n");
            rc = 2;
        } else if (lubd_token_create(db, user, admin, token) != 0) {
            rc = 1;
        } else {
            printf("%s\n", token);
            fprintf(stderr,
                    "lubdemd: token for user %s%s created; it is shown only once "
                    "(only its SHA-256 is stored in %s)\n",
                    user, admin ? " (admin)" : "", cfg->db_path);
        }
    } else if (strcmp(sub, "revoke") == 0 && target) {
        int r = lubd_token_revoke(db, target);
        rc = r == 1 ? 0 : 1;
        fprintf(stderr, "lubdemd: %s\n", r == 1 ? "token revoked" : "no such active token");
    } else if (strcmp(sub, "list") == 0) {
        rc = lubd_token_list(db, stdout) == 0 ? 0 : 1;
    } else if (strcmp(sub, "cap") == 0) {
        rc = lubd_user_set_cap(db, user, cap) == 0 ? 0 : 1;
        if (rc)
            fprintf(stderr, "lubdemd: no such user %s\n", user);
    } else {
        lubd_config_usage();
        rc = 2;
    }
    lubd_db_close(db);
    return rc;
}

/* --init-defaults: a local admin token in RUN/local-token (0600) if no token exists yet. */
static int init_default_token(lubd_config *cfg, sqlite3 *db, char *token_file, size_t n)
{
    snprintf(token_file, n, "%s/local-token", cfg->run_dir);
    if (access(token_file, R_OK) == 0 || lubd_token_count(db) > 0)
        return 0;
    char token[LUBD_TOKEN_MAX];
    const char *who = getenv("USER");
    if (!who || !who[0])
        who = "local";
    if (lubd_token_create(db, who, 1, token) != 0)
        return -1;
    size_t len = strlen(token);
    token[len] = '\n';
    int rc = lubd_write_file_atomic(token_file, token, len + 1);
    return rc;
}

static void banner(const lubd_config *cfg, int port, const char *token_file, int have_file)
{
    fprintf(stderr, "lubdemd: listening on http://%s:%d  (workers %d, engine %s, state %s/)\n",
            cfg->listen_host, port, cfg->workers, cfg->engine, cfg->run_dir);
    if (cfg->quiet)
        return;
    fprintf(stderr, "\nSubmit a first job:\n");
    if (have_file)
        fprintf(stderr, "  TOKEN=$(cat %s)\n", token_file);
    else
        fprintf(stderr, "  TOKEN=$(%s token create --user $USER --run-dir %s)\n", cfg->self_exe,
                cfg->run_dir);
    fprintf(stderr,
            "  curl -s -H \"Authorization: Bearer $TOKEN\" -H 'Content-Type: application/json' "
            "\\\n       -d '{\"inputs\": {}}' http://%s:%d/processes/falling_sphere/execution\n"
            "  curl -s -H \"Authorization: Bearer $TOKEN\" http://%s:%d/jobs/<jobID>\n"
            "  client_examples/walkthrough.sh does the whole round trip (LUBDEM_URL, "
            "LUBDEM_TOKEN).\n\n",
            cfg->listen_host, port, cfg->listen_host, port);
}

static int cmd_serve(lubd_config *cfg)
{
    if (cfg->workers > 0 && access(cfg->engine, X_OK) != 0) {
        fprintf(stderr, "lubdemd: engine binary %s not found or not executable (use --engine)\n",
                cfg->engine);
        return 1;
    }
    int lock_fd = -1;
    sqlite3 *db = open_state(cfg, &lock_fd);
    if (!db)
        return 1;
    char token_file[1200] = "";
    int have_file = 0;
    if (cfg->init_defaults && init_default_token(cfg, db, token_file, sizeof token_file) != 0) {
        lubd_db_close(db);
        return 1;
    }
    have_file = cfg->init_defaults && access(token_file, R_OK) == 0;
    int requeued = 0, failed = 0;
    /* jobs on their last attempt that kept a checkpoint fail with it, the reaper takes the rest */
    const int kept = lubd_worker_keep_orphan_checkpoints(cfg, db);
    if (kept > 0 && !cfg->quiet)
        fprintf(stderr,
                "lubdemd: %d job(s) left running on their last attempt by a service that died "
                "failed with the checkpoint their engine left\n",
                kept);
    if (lubd_queue_reap_orphans(db, &requeued, &failed) != 0)
        fprintf(stderr, "lubdemd: cannot requeue the jobs the last service left running\n");
    else if (!cfg->quiet && (requeued || failed))
        fprintf(stderr,
                "lubdemd: %d job(s) left running by a service that died requeued, %d failed after "
                "their last attempt\n",
                requeued, failed);
    /* what deletions left on disk when the service stopped between their steps */
    lubd_deletion_sweep(db, cfg->jobs_dir, cfg->quiet);
    lubd_db_close(db);

    /* Signals are taken synchronously by the supervisor; block them before any thread. */
    sigset_t set;
    sigemptyset(&set);
    sigaddset(&set, SIGTERM);
    sigaddset(&set, SIGINT);
    sigaddset(&set, SIGCHLD);
    sigprocmask(SIG_BLOCK, &set, NULL);
    signal(SIGPIPE, SIG_IGN);

    lubd_server srv;
    memset(&srv, 0, sizeof srv);
    atomic_init(&srv.workers_alive, 0);
    if (lubd_http_start(&srv, cfg) != 0)
        return 1;
    if (cfg->port_file) {
        char p[16];
        int len = snprintf(p, sizeof p, "%d\n", srv.port);
        if (lubd_write_file_atomic(cfg->port_file, p, (size_t)len) != 0)
            fprintf(stderr, "lubdemd: cannot write %s\n", cfg->port_file);
    }
    banner(cfg, srv.port, token_file, have_file);
    int rc = lubd_supervise(cfg, &srv);
    lubd_http_stop(&srv);
    fprintf(stderr, "lubdemd: stopped\n");
    close(lock_fd); /* after the workers: none of them still runs a job */
    return rc == 0 ? 0 : 1;
}

int main(int argc, char **argv)
{
    umask(027); /* state files (queue.db with token hashes, job folders) not world-readable */
    lubd_config cfg;
    lubd_config_defaults(&cfg, argv[0]);
    if (argc > 1 && strcmp(argv[1], "worker") == 0) {
        const char *name = "w";
        int first = 2;
        if (argc > 3 && strcmp(argv[2], "--name") == 0) {
            name = argv[3];
            first = 4;
        }
        if (lubd_config_parse(&cfg, argc, argv, first) != 0)
            return 2;
        return lubd_worker_main(&cfg, name);
    }
    /* internal: keeps the checkpoints of a dead worker's jobs (supervisor.c) */
    if (argc > 5 && strcmp(argv[1], "keep-checkpoints") == 0 && strcmp(argv[2], "--worker") == 0 &&
        strcmp(argv[4], "--how") == 0) {
        if (lubd_config_parse(&cfg, argc, argv, 6) != 0)
            return 2;
        return lubd_worker_keep_main(&cfg, argv[3], argv[5]);
    }
    if (argc > 1 && (strcmp(argv[1], "token") == 0 || strcmp(argv[1], "user") == 0))
        return cmd_token(&cfg, argc, argv);
    int first = 1;
    if (argc > 1 && strcmp(argv[1], "serve") == 0)
        first = 2;
    if (lubd_config_parse(&cfg, argc, argv, first) != 0)
        return 2;
    return cmd_serve(&cfg);
}
