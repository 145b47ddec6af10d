/* api.h — HTTP handlers (one file per resource family). Each returns the MHD result of
 * queueing exactly one response. They use connections from r->srv->pool for the duration of
 * the call only, and never hold a statement open while a file is being streamed. */
#ifndef LUBD_API_H
#define LUBD_API_H

#include "http_server.h"

/* api_meta.c */
enum MHD_Result lubd_api_landing(lubd_request *r);
enum MHD_Result lubd_api_conformance(lubd_request *r);
enum MHD_Result lubd_api_openapi(lubd_request *r);
enum MHD_Result lubd_api_health(lubd_request *r);
/* api_processes.c */
enum MHD_Result lubd_api_processes(lubd_request *r);
enum MHD_Result lubd_api_process(lubd_request *r, const char *id);
enum MHD_Result lubd_api_execute(lubd_request *r, const char *id);
/* api_jobs.c */
enum MHD_Result lubd_api_jobs(lubd_request *r);
enum MHD_Result lubd_api_job(lubd_request *r, const char *id);
enum MHD_Result lubd_api_dismiss(lubd_request *r, const char *id);
enum MHD_Result lubd_api_results(lubd_request *r, const char *id);
/* Authenticates, loads job `id` and checks that the caller may see it (owner or admin;
 * others get 404, as for an unknown id). Purged jobs give 410 unless allow_purged.
 * Returns 0, or -1 with *f set. Defined in api_jobs.c. */
int lubd_load_visible_job(lubd_request *r, const char *id, void *job /* lubd_job */, lubd_fault *f,
                          int allow_purged);
/* api_files.c */
enum MHD_Result lubd_api_result_file(lubd_request *r, const char *id, const char *name);
enum MHD_Result lubd_api_log(lubd_request *r, const char *id);

#endif
