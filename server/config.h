/* config.h — lubdemd settings: embedded defaults and command-line options.
 *
 * One lubd_config value is filled by lubd_config_defaults() + lubd_config_parse() in main()
 * and passed by pointer to every component (no globals). Strings point into argv or into the
 * struct's own buffers. lubd_config_parse returns 0, or -1 after printing the problem. */
#ifndef LUBD_CONFIG_H
#define LUBD_CONFIG_H

typedef struct {
    char run_dir[1024];           /* ./run */
    char db_path[1100];           /* <run_dir>/queue.db */
    char jobs_dir[1100];          /* <run_dir>/jobs */
    char engine[1024];            /* lubdem binary */
    char schema_dir[1024];        /* schema/ (openapi.json, <scene>.schema.json) */
    char self_exe[1024];          /* this binary, to start workers */
    char listen_host[64];         /* 127.0.0.1 */
    int port;                     /* 8080; 0 = any free port */
    const char *port_file;        /* write the bound port here (tests) */
    int workers;                  /* worker processes; default = online cores */
    int http_threads;             /* MHD thread pool */
    int lease_s;                  /* lease duration; heartbeat every lease/3 (at most 1 s) */
    int max_attempts;             /* attempts before a job whose worker keeps dying fails */
    int user_cap;                 /* default max accepted+running jobs per user */
    long max_body;                /* request body cap in bytes */
    long cpu_s, mem_mb, fsize_mb; /* engine rlimits (0 = unlimited) */
    int grace_s;                  /* SIGTERM -> SIGKILL delay when cancelling */
    long wall_s;                  /* wall-clock limit of one engine run (s, 0 = none): SIGTERM,
                                     then SIGKILL grace_s later; the job fails, its checkpoint
                                     kept (a hung engine does not hold its worker for ever) */
    int engine_threads;           /* --threads for the engine (0 = engine default) */
    int checkpoint_s;             /* --checkpoint-every for the engine: a checkpoint every so many
                                     seconds of a simple_shear or resuspension run, from which a
                                     job requeued after its worker died continues (0 = off) */
    int keep_checkpoints;         /* 1: a completed simple_shear or resuspension job keeps its
                                     engine's checkpoint among its files (--keep-checkpoint), so
                                     a job with "continue_from" can extend it; 0: it does not */
    int init_defaults;            /* create ./run and a local admin token if none exists */
    int quiet;
} lubd_config;

void lubd_config_defaults(lubd_config *c, const char *argv0);
/* Parses options from argv[first..argc); unknown options are errors. */
int lubd_config_parse(lubd_config *c, int argc, char **argv, int first);
/* Recomputes db_path/jobs_dir when run_dir changed and they were not set explicitly. */
void lubd_config_finish(lubd_config *c);
void lubd_config_usage(void);

#endif
