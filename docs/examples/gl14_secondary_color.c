/* GL 1.4 (or EXT_secondary_color): F_ex with the sun's lighting baked into the primary colour,
 * L_in as the secondary colour, GL_COLOR_SUM adds it in one pass. */
#include <string.h>

#include <aerial/aerial.h>

#include "engine.h"

static aerial_context* air;
static aerial_gl* gl;

int gl14_init(aerial_gl_load_function load, void* user) {
    aerial_atmosphere hazy;
    return AERIAL_CHECK_VERSION() == AERIAL_OK &&
           aerial_atmosphere_preset("hazy", &hazy) == AERIAL_OK &&
           aerial_context_create(&hazy, AERIAL_MODEL_HEIGHT, &air) == AERIAL_OK &&
           aerial_gl_create(load, user, &gl) == AERIAL_OK;
}

int gl14_frame(const engine_camera* camera, engine_mesh* meshes, size_t mesh_count) {
    aerial_view view;
    aerial_lighting light;
    aerial_batch_settings settings;
    aerial_draw_options draw;
    size_t i;
    memset(&view, 0, sizeof view);
    memset(&light, 0, sizeof light);
    memset(&settings, 0, sizeof settings);
    memset(&draw, 0, sizeof draw);
    memcpy(view.eye, camera->position, sizeof view.eye);
    memcpy(view.sun_dir, camera->sun_dir, sizeof view.sun_dir);
    view.meters_per_unit = camera->meters_per_unit;
    if (aerial_context_set_view(air, &view) != AERIAL_OK) return 0;
    light.ambient[0] = light.ambient[1] = light.ambient[2] = 0.2f; /* the sky's share */
    settings.display.exposure = 2.0f;
    settings.lighting = &light;
    draw.path = AERIAL_PATH_SECONDARY_COLOR;
    for (i = 0; i < mesh_count; ++i) {
        aerial_positions positions;
        aerial_outputs out;
        aerial_vertex_colours colours;
        memset(&positions, 0, sizeof positions);
        memset(&out, 0, sizeof out);
        memset(&colours, 0, sizeof colours);
        positions.x = meshes[i].xyz;
        positions.count = meshes[i].vertex_count;
        light.normals = meshes[i].normals;
        out.lit_rgba8 = meshes[i].primary; /* GL lighting stays off: it is baked in here */
        out.in_scattering_rgba8 = meshes[i].secondary;
        if (aerial_shade(air, &positions, &out, &settings, NULL) != AERIAL_OK) return 0;
        colours.primary = meshes[i].primary;
        colours.secondary = meshes[i].secondary;
        colours.vertex_count = meshes[i].vertex_count;
        if (aerial_gl_draw_colours(gl, &draw, &colours, engine_draw_mesh, &meshes[i], NULL) !=
            AERIAL_OK) {
            return 0;
        }
    }
    return 1;
}

void gl14_shutdown(void) {
    aerial_gl_destroy(gl);
    aerial_context_destroy(air);
}
