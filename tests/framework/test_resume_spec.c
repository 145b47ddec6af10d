/* Unit tests of resume_spec.c: which specs may continue a checkpoint, and what a refusal says. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "framework_check.h"
#include "resume_spec.h"

static json_t *spec(const char *text)
{
    json_t *v = json_loads(text, 0, NULL);
    if (!v) {
        fprintf(stderr, "bad test JSON: %s\n", text);
        ++failures;
    }
    return v;
}

/* lub_resume_spec_mismatch of two texts; why and at as it left them. */
static int mismatch(const char *here, const char *saved, const char *const *may, char *why,
                    char *at)
{
    json_t *a = spec(here), *b = spec(saved);
    char *before = json_dumps(a, JSON_SORT_KEYS);
    why[0] = at[0] = '\0';
    const int d = lub_resume_spec_mismatch(a, b, may, why, 600, at, 200);
    char *after = json_dumps(a, JSON_SORT_KEYS);
    CHECK(before && after && strcmp(before, after) == 0); /* pure: nothing removed */
    free(before);
    free(after);
    json_decref(a);
    json_decref(b);
    return d;
}

int main(void)
{
    static const char *const may[] = {"strain", "target_rel_error", NULL};
    char why[600], at[200];
    const char *base = "{\"scene\":\"simple_shear\",\"phi\":0.5,\"strain\":20,"
                       "\"law\":{\"eps\":0.01,\"mu\":0.5}}";

    CHECK(mismatch(base, base, may, why, at) == 0 && why[0] == '\0');
    /* a member the scene lets change */
    CHECK(mismatch("{\"scene\":\"simple_shear\",\"phi\":0.5,\"strain\":60,"
                   "\"law\":{\"eps\":0.01,\"mu\":0.5}}",
                   base, may, why, at) == 0);
    /* ... but not without the list */
    CHECK(mismatch("{\"scene\":\"simple_shear\",\"phi\":0.5,\"strain\":60,"
                   "\"law\":{\"eps\":0.01,\"mu\":0.5}}",
                   base, NULL, why, at) == 1);
    CHECK(strcmp(at, "/strain") == 0);
    CHECK(strcmp(why, "/strain: 60 here, 20 in the stopped run's spec") == 0);
    /* a top-level value */
    CHECK(mismatch("{\"scene\":\"simple_shear\",\"phi\":0.49,\"strain\":20,"
                   "\"law\":{\"eps\":0.01,\"mu\":0.5}}",
                   base, may, why, at) == 1);
    CHECK(strcmp(at, "/phi") == 0);
    CHECK(strcmp(why, "/phi: 0.49 here, 0.5 in the stopped run's spec") == 0);
    /* nested, and a member the list names only at the top level */
    CHECK(mismatch("{\"scene\":\"simple_shear\",\"phi\":0.5,\"strain\":20,"
                   "\"law\":{\"eps\":0.02,\"mu\":0.5}}",
                   base, may, why, at) == 1);
    CHECK(strcmp(at, "/law/eps") == 0);
    CHECK(mismatch("{\"scene\":\"simple_shear\",\"phi\":0.5,\"strain\":20,"
                   "\"law\":{\"eps\":0.01,\"mu\":0.5,\"strain\":1}}",
                   base, may, why, at) == 1);
    CHECK(strcmp(at, "/law/strain") == 0);
    /* a member present on one side only, either side */
    CHECK(mismatch("{\"scene\":\"simple_shear\",\"phi\":0.5,\"strain\":20,\"seed\":3,"
                   "\"law\":{\"eps\":0.01,\"mu\":0.5}}",
                   base, may, why, at) == 1);
    CHECK(strcmp(why, "/seed: 3 here, absent in the stopped run's spec") == 0);
    CHECK(mismatch(base,
                   "{\"scene\":\"simple_shear\",\"phi\":0.5,\"strain\":20,\"seed\":3,"
                   "\"law\":{\"eps\":0.01,\"mu\":0.5}}",
                   may, why, at) == 1);
    CHECK(strcmp(why, "/seed: absent here, 3 in the stopped run's spec") == 0);
    /* another type at the root */
    CHECK(mismatch("[1]", "{}", NULL, why, at) == 1 && strcmp(at, "(root)") == 0);

    char members[200];
    lub_resume_free_members(may, members, sizeof members);
    CHECK(strcmp(members, "; only /strain, /target_rel_error may change") == 0);
    lub_resume_free_members(NULL, members, sizeof members);
    CHECK(members[0] == '\0');

    if (failures)
        fprintf(stderr, "%d check(s) failed\n", failures);
    else
        printf("resume_spec: all checks passed\n");
    return failures ? 1 : 0;
}
