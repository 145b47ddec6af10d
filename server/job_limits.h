/* job_limits.h — refusing at submission a job that cannot fit in what its engine may use.
 *
 * The scene's lower bound of its memory (scene.h memory_need, memory_budget.h) is compared
 * with the tightest of --mem-mb (the address space each engine gets) and the memory this
 * service's machine and control group have (its workers inherit them). A job refused here would
 * otherwise fail in its worker, for a large simple_shear only after minutes of packing. Reads a
 * few /proc and /sys files; no allocation beyond the scene's. */
#ifndef LUBD_JOB_LIMITS_H
#define LUBD_JOB_LIMITS_H

#include "config.h"
#include "exec_request.h"
#include "problem.h"

/* 0 when the job may fit; -1 with *f = 400 job-too-large, pointer /inputs/<member>, and the
 * engine's message (what needs how much, the ceiling) otherwise. */
int lubd_job_fits(const lubd_exec_request *req, const lubd_config *cfg, lubd_fault *f);

#endif
