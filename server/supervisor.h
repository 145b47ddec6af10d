/* supervisor.h — the service's main loop: worker processes, reaper, signals.
 *
 * Starts cfg->workers worker processes (`lubdemd worker ...`, fork + exec with
 * PR_SET_PDEATHSIG so they die with the service), restarts any that dies (with a back-off),
 * runs the lease reaper at start and every min(lease/2, 5) s, and returns on SIGTERM/SIGINT
 * after asking the workers to stop (SIGTERM; SIGKILL after grace_s + 5 s). The jobs a dead
 * worker held on their last attempt keep their engines' checkpoints through a short-lived
 * process of their own (`lubdemd keep-checkpoints`, worker.h), which checksums the files while
 * this loop goes on; it is waited for at the stop like a worker. The caller must
 * have blocked SIGTERM, SIGINT and SIGCHLD in every thread before calling. Keeps
 * srv->workers_alive up to date. Returns 0 on a clean stop, -1 on a fatal error. */
#ifndef LUBD_SUPERVISOR_H
#define LUBD_SUPERVISOR_H

#include "config.h"
#include "http_server.h"

int lubd_supervise(const lubd_config *cfg, lubd_server *srv);
/* One reaper pass with a caller-owned connection; prints what it did unless quiet. */
int lubd_reap_once(sqlite3 *db, int quiet);

#endif
