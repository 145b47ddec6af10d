/* job_limits.c — see job_limits.h. */
#include "job_limits.h"

#include <stdio.h>
#include <string.h>

#include "memory_budget.h"
#include "processors.h"
#include "scene.h"

int lubd_job_fits(const lubd_exec_request *req, const lubd_config *cfg, lubd_fault *f)
{
    const lub_scene *scene =
        lub_scene_find(json_string_value(json_object_get(req->resolved, "scene")));
    lub_memory_need need;
    memset(&need, 0, sizeof need);
    const int threads = lub_threads_usable(cfg->engine_threads); /* what the engine will run */
    if (!scene || !scene->memory_need || scene->memory_need(req->resolved, threads, &need) != 0)
        return 0;
    lub_memory_room room;
    lub_memory_room_now(&room);
    if (cfg->mem_mb > 0)
        lub_memory_room_limit(&room, (double)cfg->mem_mb * 1024.0 * 1024.0,
                              "address space (lubdemd --mem-mb)");
    char ptr[300];
    snprintf(ptr, sizeof ptr, "/inputs%.250s", need.member ? need.member : "");
    if (need.member)
        need.member = ptr; /* the message names the member as the request body has it */
    char msg[600];
    if (!lub_memory_need_check(&need, &room, "a job on this service", msg, sizeof msg))
        return 0;
    return lubd_fail(f, 400, LUBD_PT_BASE "job-too-large", "Job too large for this service",
                     need.member, "%s", msg);
}
