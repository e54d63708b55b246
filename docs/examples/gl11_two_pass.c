/* GL 1.1, no extensions: F_ex and L_in per vertex on the CPU, added by two passes. */
#include <string.h>

#include <aerial/aerial.h>

#include "engine.h"

static aerial_context* air;
static aerial_gl* gl;

int gl11_init(aerial_gl_load_function load, void* user) { /* once, the context current */
    return AERIAL_CHECK_VERSION() == AERIAL_OK &&
           aerial_context_create(NULL, AERIAL_MODEL_HOFFMAN_PREETHAM, &air) == AERIAL_OK &&
           aerial_gl_create(load, user, &gl) == AERIAL_OK;
}

int gl11_frame(const engine_camera* camera, engine_mesh* meshes, size_t mesh_count) {
    aerial_view view;
    aerial_draw_options draw;
    size_t i;
    memset(&view, 0, sizeof view);
    memset(&draw, 0, sizeof draw);
    memcpy(view.eye, camera->position, sizeof view.eye);
    memcpy(view.sun_dir, camera->sun_dir, sizeof view.sun_dir);
    view.meters_per_unit = camera->meters_per_unit;
    if (aerial_context_set_view(air, &view) != AERIAL_OK) return 0; /* once per frame */
    draw.path = AERIAL_PATH_TWO_PASS; /* AUTOMATIC picks it where nothing better exists */
    for (i = 0; i < mesh_count; ++i) {
        aerial_positions positions;
        aerial_outputs out;
        aerial_vertex_colours colours;
        memset(&positions, 0, sizeof positions);
        memset(&out, 0, sizeof out);
        memset(&colours, 0, sizeof colours);
        positions.x = meshes[i].xyz;
        positions.count = meshes[i].vertex_count;
        out.extinction_rgba8 = meshes[i].primary;
        out.in_scattering_rgba8 = meshes[i].secondary;
        if (aerial_shade(air, &positions, &out, NULL, NULL) != AERIAL_OK) return 0;
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

void gl11_shutdown(void) { /* the context current */
    aerial_gl_destroy(gl);
    aerial_context_destroy(air);
}
