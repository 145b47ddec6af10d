/* spec_resolve.c — top-level validation of a spec document: root shape, "scene", dispatch. */
#include <stdio.h>

#include "scene.h"

int lub_spec_resolve(const json_t *spec, json_t **resolved, lub_error *err)
{
    *resolved = NULL;
    if (!json_is_object(spec))
        return lub_fail(err, "", "the spec must be a JSON object");
    json_t *scene = json_object_get(spec, "scene");
    if (!scene)
        return lub_fail(err, "/scene",
                        "required string is missing (one of the names listed by "
                        "`lubdem scenes`)");
    if (!json_is_string(scene))
        return lub_fail(err, "/scene", "must be a string");
    const lub_scene *s = lub_scene_find(json_string_value(scene));
    if (!s) {
        char names[512];
        size_t n = 0;
        names[0] = '\0';
        for (const lub_scene *const *it = lub_scene_list(); *it && n < sizeof names - 64; ++it)
            n += (size_t)snprintf(names + n, sizeof names - n, "%s\"%s\"",
                                  it == lub_scene_list() ? "" : ", ", (*it)->name);
        return lub_fail(err, "/scene", "unknown scene \"%.*s\" (known: %s)",
                        lub_utf8_prefix(json_string_value(scene), 80), json_string_value(scene),
                        names);
    }
    json_t *copy = json_deep_copy(spec);
    if (!copy)
        return lub_fail(err, "", "out of memory");
    if (s->resolve(copy, err) != 0) {
        json_decref(copy);
        return -1;
    }
    *resolved = copy;
    return 0;
}
