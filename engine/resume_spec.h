/* resume_spec.h — may a run continue another run's checkpoint? The spec comparison shared by
 * `lubdem run --resume` (run_driver.c) and the service's continuation jobs (lubdemd
 * POST .../execution with "continue_from"), so that both accept and refuse the same specs. */
#ifndef LUB_RESUME_SPEC_H
#define LUB_RESUME_SPEC_H

#include <jansson.h>
#include <stddef.h>

/* Compares two resolved specs (lub_spec_resolve) member for member, defaults included, leaving
 * out the top-level members named in may_differ (a scene's resume_may_differ; NULL = none);
 * numbers compare by value (12 and 12.0 agree).
 * Returns 0 when they agree; 1 when they differ, with "POINTER: VALUE here, VALUE in the
 * stopped run's spec" (compact JSON, truncated to fit; another scene is named at /scene
 * whatever member differs before it) in why[len] and, when at is not NULL,
 * the JSON pointer alone in at[at_len]; -1 out of memory (why says so). Pure: neither spec is
 * changed. */
int lub_resume_spec_mismatch(const json_t *here, const json_t *saved, const char *const *may_differ,
                             char *why, size_t len, char *at, size_t at_len);

/* "; only /a, /b may change" for the members of may_differ (empty for none), into out[len]:
 * the tail of a refusal's advice. */
void lub_resume_free_members(const char *const *may_differ, char *out, size_t len);

#endif
