/* scene_registry.c — the table of scenes. Add one line per scene (declared in its own file). */
#include <string.h>

#include "scene.h"

extern const lub_scene lub_scene_falling_sphere;
extern const lub_scene lub_scene_two_spheres_shear;
extern const lub_scene lub_scene_simple_shear;
extern const lub_scene lub_scene_resuspension;
extern const lub_scene lub_scene_continuum_rheometer;
extern const lub_scene lub_scene_continuum_steady_curves;
extern const lub_scene lub_scene_sbm_resuspension;
extern const lub_scene lub_scene_sbm_channel;
/* further scenes: declare here and list below */

static const lub_scene *const scene_table[] = {
    &lub_scene_falling_sphere,   &lub_scene_two_spheres_shear,   &lub_scene_simple_shear,
    &lub_scene_resuspension,     &lub_scene_continuum_rheometer, &lub_scene_continuum_steady_curves,
    &lub_scene_sbm_resuspension, &lub_scene_sbm_channel,         NULL,
};

const lub_scene *const *lub_scene_list(void) { return scene_table; }

const lub_scene *lub_scene_find(const char *name)
{
    for (const lub_scene *const *s = scene_table; *s; ++s)
        if (strcmp((*s)->name, name) == 0)
            return *s;
    return NULL;
}
