/* fuzz_request.c — libFuzzer target for the request-side parsers: the execution body
 * (JSON -> shape -> engine spec validation via lub_spec_resolve) for every process, the Range
 * header and progress lines. Built with clang -fsanitize=fuzzer,address,undefined. */
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "exec_request.h"
#include "http_range.h"
#include "progress_line.h"
#include "scene.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    if (size > 1 << 16)
        return 0;
    char *s = malloc(size + 1);
    if (!s)
        return 0;
    memcpy(s, data, size);
    s[size] = '\0';
    /* First byte selects the process, so every scene's resolve() gets exercised. */
    const lub_scene *const *scenes = lub_scene_list();
    int n = 0;
    while (scenes[n])
        ++n;
    const char *pid = size > 0 && n > 0 ? scenes[data[0] % n]->name : "none";
    lubd_exec_request r;
    lubd_fault f;
    if (lubd_exec_parse(s, size, pid, &r, &f) == 0)
        lubd_exec_free(&r);
    uint64_t first, last;
    lubd_range_parse(s, size * 7u, &first, &last);
    lubd_progress p;
    lubd_progress_parse(s, &p);
    free(s);
    return 0;
}
