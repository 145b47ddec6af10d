/* scene_probe.c — runs one spec (file or "-") in-process and prints every summary result as
 * name=value lines plus wall_s and rc (used by the benchmark script and by hand). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "scene_harness.h"

int main(int argc, char **argv)
{
    if (argc < 2) {
        fprintf(stderr, "usage: scene_probe SPEC.json|- [KEEP.h5]\n");
        return 2;
    }
    FILE *f = strcmp(argv[1], "-") == 0 ? stdin : fopen(argv[1], "r");
    if (!f) {
        perror(argv[1]);
        return 2;
    }
    static char buf[1 << 16];
    size_t n = fread(buf, 1, sizeof buf - 1, f);
    buf[n] = '\0';
    if (f != stdin)
        fclose(f);
    scene_outcome o;
    scene_run_text(buf, argc > 2 ? argv[2] : NULL, &o);
    printf("rc=%d\nwall_s=%.6g\n", o.rc, o.wall_s);
    if (o.message[0])
        printf("message=%s\n", o.message);
    const char *key;
    json_t *e;
    if (o.results)
        json_object_foreach (o.results, key, e) {
            json_t *v = json_object_get(e, "value");
            if (json_is_number(v))
                printf("%s=%.12g\n", key, json_number_value(v));
            else
                printf("%s=nan\n", key);
        }
    json_t *reg = o.extra ? json_object_get(o.extra, "regime") : NULL;
    if (reg)
        printf("regime=%s\n", json_string_value(reg));
    json_t *st = o.extra ? json_object_get(o.extra, "steps") : NULL;
    if (st)
        printf("steps=%lld\n", (long long)json_integer_value(st));
    int rc = o.rc;
    scene_outcome_free(&o);
    return rc;
}
