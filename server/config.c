/* config.c — defaults and option parsing. */
#include "config.h"

#include "fsutil.h"

#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#ifndef LUBDEM_SCHEMA_DIR_DEFAULT
#define LUBDEM_SCHEMA_DIR_DEFAULT "schema"
#endif

static int exists_exec(const char *p) { return access(p, X_OK) == 0; }

void lubd_config_defaults(lubd_config *c, const char *argv0)
{
    memset(c, 0, sizeof *c);
    snprintf(c->run_dir, sizeof c->run_dir, "run");
    ssize_t n = readlink("/proc/self/exe", c->self_exe, sizeof c->self_exe - 1);
    if (n > 0)
        c->self_exe[n] = '\0';
    else
        snprintf(c->self_exe, sizeof c->self_exe, "%s", argv0);
    /* The engine: <build>/engine/lubdem next to <build>/server/lubdemd, else beside us. */
    char dir[1024];
    snprintf(dir, sizeof dir, "%s", c->self_exe);
    char *slash = strrchr(dir, '/');
    if (slash)
        *slash = '\0';
    else
        snprintf(dir, sizeof dir, ".");
    lubd_pathf(c->engine, sizeof c->engine, "%s/../engine/lubdem", dir);
    if (!exists_exec(c->engine))
        lubd_pathf(c->engine, sizeof c->engine, "%s/lubdem", dir);
    snprintf(c->schema_dir, sizeof c->schema_dir, "%s", LUBDEM_SCHEMA_DIR_DEFAULT);
    snprintf(c->listen_host, sizeof c->listen_host, "127.0.0.1");
    c->port = 8080;
    long cores = sysconf(_SC_NPROCESSORS_ONLN);
    c->workers = cores > 0 ? (int)cores : 1;
    c->http_threads = c->workers < 4 ? c->workers : 4;
    if (c->http_threads < 2)
        c->http_threads = 2;
    c->lease_s = 30;
    c->max_attempts = 3;
    c->user_cap = 100;
    c->max_body = 1L << 20;
    c->cpu_s = 24 * 3600;
    c->mem_mb = 8192;
    c->fsize_mb = 16384;
    c->grace_s = 10;
    c->wall_s = 2 * 86400;
    c->checkpoint_s = 600;
    c->keep_checkpoints = 1;
}

void lubd_config_finish(lubd_config *c)
{
    if (!c->db_path[0])
        snprintf(c->db_path, sizeof c->db_path, "%s/queue.db", c->run_dir);
    if (!c->jobs_dir[0])
        snprintf(c->jobs_dir, sizeof c->jobs_dir, "%s/jobs", c->run_dir);
}

void lubd_config_usage(void)
{
    fprintf(stderr,
            "usage:\n"
            "  lubdemd [--init-defaults] [options]       run the service (HTTP + workers)\n"
            "  lubdemd token create --user NAME [--admin] [--run-dir DIR]\n"
            "  lubdemd token revoke TOKEN|TOKEN_ID [--run-dir DIR]\n"
            "  lubdemd token list [--run-dir DIR]\n"
            "  lubdemd user cap --user NAME N [--run-dir DIR]   (N < 0: server default)\n"
            "options (defaults in brackets):\n"
            "  --run-dir DIR      state directory [./run]: queue.db, jobs/\n"
            "  --db PATH          queue database [RUN/queue.db]\n"
            "  --jobs-dir DIR     job directories [RUN/jobs]\n"
            "  --listen HOST:PORT [127.0.0.1:8080]; PORT 0 = any free port\n"
            "  --port-file FILE   write the bound port to FILE\n"
            "  --workers N        worker processes [cores]; 0 = queue only\n"
            "  --http-threads N   HTTP thread pool [min(cores,4), at least 2]\n"
            "  --engine PATH      lubdem binary [next to this build]\n"
            "  --schema-dir DIR   openapi.json and <scene>.schema.json [source schema/]\n"
            "  --lease-s N        job lease [30]; heartbeat every min(N/3, 1 s)\n"
            "  --max-attempts N   attempts for jobs whose worker dies or whose engine is\n"
            "                     killed with SIGKILL from outside (the OOM killer) [3]\n"
            "  --user-cap N       default max queued+running jobs per user [100]\n"
            "  --max-body-kb N    request body limit [1024]\n"
            "  --cpu-s N --mem-mb N --fsize-mb N   engine limits [86400, 8192, 16384]; 0=off\n"
            "  --grace-s N        SIGTERM->SIGKILL delay on cancel [10]\n"
            "  --wall-s N         wall-clock limit of each engine run: SIGTERM, then\n"
            "                     SIGKILL after --grace-s; the job fails with its\n"
            "                     checkpoint [172800]; 0=off\n"
            "  --engine-threads N threads per engine run [engine default]\n"
            "  --checkpoint-s N   engine checkpoint every N s; a job requeued after its\n"
            "                     worker died continues from it [600]; 0=off\n"
            "  --keep-checkpoints 0|1  a completed simple_shear/resuspension job keeps its\n"
            "                     checkpoint, which a \"continue_from\" job extends [1]\n"
            "  --init-defaults    create RUN and a local admin token (RUN/local-token)\n"
            "  --quiet            no start-up banner\n");
}

static int want_int(const char *opt, const char *v, long min, long max, long *out)
{
    char *end;
    long x = strtol(v ? v : "", &end, 10);
    if (!v || *end || end == v || x < min || x > max) {
        fprintf(stderr, "lubdemd: %s needs an integer in [%ld, %ld]\n", opt, min, max);
        return -1;
    }
    *out = x;
    return 0;
}

int lubd_config_parse(lubd_config *c, int argc, char **argv, int first)
{
    for (int i = first; i < argc; ++i) {
        const char *o = argv[i];
        const char *v = i + 1 < argc ? argv[i + 1] : NULL;
        long x;
#define STR_OPT(name, field)                                                                       \
    if (strcmp(o, name) == 0) {                                                                    \
        if (!v) {                                                                                  \
            fprintf(stderr, "lubdemd: %s needs a value\n", o);                                     \
            return -1;                                                                             \
        }                                                                                          \
        snprintf(field, sizeof field, "%s", v);                                                    \
        ++i;                                                                                       \
        continue;                                                                                  \
    }
#define INT_OPT(name, field, min, max)                                                             \
    if (strcmp(o, name) == 0) {                                                                    \
        if (want_int(o, v, min, max, &x) != 0)                                                     \
            return -1;                                                                             \
        field = x;                                                                                 \
        ++i;                                                                                       \
        continue;                                                                                  \
    }
        STR_OPT("--run-dir", c->run_dir)
        STR_OPT("--db", c->db_path)
        STR_OPT("--jobs-dir", c->jobs_dir)
        STR_OPT("--engine", c->engine)
        STR_OPT("--schema-dir", c->schema_dir)
        INT_OPT("--workers", c->workers, 0, 256)
        INT_OPT("--http-threads", c->http_threads, 1, 64)
        INT_OPT("--lease-s", c->lease_s, 1, 86400)
        INT_OPT("--max-attempts", c->max_attempts, 1, 100)
        INT_OPT("--user-cap", c->user_cap, 1, 1000000)
        INT_OPT("--cpu-s", c->cpu_s, 0, 100L * 86400)
        INT_OPT("--mem-mb", c->mem_mb, 0, 1L << 30)
        INT_OPT("--fsize-mb", c->fsize_mb, 0, 1L << 30)
        INT_OPT("--grace-s", c->grace_s, 0, 3600)
        INT_OPT("--wall-s", c->wall_s, 0, 100L * 86400)
        INT_OPT("--engine-threads", c->engine_threads, 0, 1024)
        INT_OPT("--checkpoint-s", c->checkpoint_s, 0, 10000000)
        INT_OPT("--keep-checkpoints", c->keep_checkpoints, 0, 1)
        if (strcmp(o, "--max-body-kb") == 0) {
            if (want_int(o, v, 1, 1L << 20, &x) != 0)
                return -1;
            c->max_body = x * 1024;
            ++i;
            continue;
        }
        if (strcmp(o, "--listen") == 0) {
            const char *colon = v ? strrchr(v, ':') : NULL;
            if (!colon || colon == v || (size_t)(colon - v) >= sizeof c->listen_host ||
                want_int(o, colon + 1, 0, 65535, &x) != 0) {
                fprintf(stderr, "lubdemd: --listen needs HOST:PORT (IPv4), e.g. 127.0.0.1:8080\n");
                return -1;
            }
            memcpy(c->listen_host, v, (size_t)(colon - v));
            c->listen_host[colon - v] = '\0';
            c->port = (int)x;
            ++i;
            continue;
        }
        if (strcmp(o, "--port-file") == 0 && v) {
            c->port_file = v;
            ++i;
            continue;
        }
        if (strcmp(o, "--init-defaults") == 0) {
            c->init_defaults = 1;
            continue;
        }
        if (strcmp(o, "--quiet") == 0) {
            c->quiet = 1;
            continue;
        }
        if (strcmp(o, "--help") == 0 || strcmp(o, "-h") == 0) {
            lubd_config_usage();
            exit(0);
        }
        fprintf(stderr, "lubdemd: unknown option %s\n", o);
        lubd_config_usage();
        return -1;
#undef STR_OPT
#undef INT_OPT
    }
    lubd_config_finish(c);
    return 0;
}
