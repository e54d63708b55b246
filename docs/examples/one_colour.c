/* One vertex colour: F_ex goes straight into the engine's interleaved ARGB32 colour field, L_in
 * into a second colour buffer, and aerial draws two passes around the engine's own draw call. */
#include <string.h>

#include <aerial/aerial.h>

#include "engine.h"

static aerial_context* air;
static aerial_gl* gl;

int one_colour_init(aerial_gl_load_function load, void* user) {
    return AERIAL_CHECK_VERSION() == AERIAL_OK &&
           aerial_context_create(NULL, AERIAL_MODEL_HEIGHT, &air) == AERIAL_OK &&
           aerial_gl_create(load, user, &gl) == AERIAL_OK;
}

/* aerial calls this twice: pass 0 with F_ex, pass 1 with L_in (blend, depth EQUAL, culling). */
static void draw_pass(void* user, aerial_pass pass) {
    const engine_coloured_mesh* mesh = (const engine_coloured_mesh*)user;
    if (pass == AERIAL_PASS_EXTINCTION) {
        engine_draw_coloured(mesh, &mesh->vertices[0].colour, sizeof(engine_vertex));
    } else {
        engine_draw_coloured(mesh, mesh->in_scattering, sizeof(unsigned int));
    }
}

int one_colour_frame(const engine_camera* camera, engine_coloured_mesh* meshes, size_t count) {
    aerial_view view;
    size_t i;
    memset(&view, 0, sizeof view);
    memcpy(view.eye, camera->position, sizeof view.eye);
    memcpy(view.sun_dir, camera->sun_dir, sizeof view.sun_dir);
    view.meters_per_unit = camera->meters_per_unit;
    if (aerial_context_set_view(air, &view) != AERIAL_OK) return 0;
    for (i = 0; i < count; ++i) {
        aerial_positions positions;
        aerial_outputs out;
        memset(&positions, 0, sizeof positions);
        memset(&out, 0, sizeof out);
        positions.x = meshes[i].vertices[0].xyz;
        positions.count = meshes[i].vertex_count;
        positions.stride_bytes = sizeof(engine_vertex);
        out.colour_format = AERIAL_COLOUR_ARGB32;
        out.extinction_rgba8 = (unsigned char*)&meshes[i].vertices[0].colour;
        out.extinction_rgba8_stride = sizeof(engine_vertex);
        out.in_scattering_rgba8 = (unsigned char*)meshes[i].in_scattering;
        if (aerial_shade(air, &positions, &out, NULL, NULL) != AERIAL_OK ||
            aerial_gl_draw_two_pass(gl, NULL, NULL, draw_pass, &meshes[i]) != AERIAL_OK) {
            return 0;
        }
    }
    return 1;
}

void one_colour_shutdown(void) {
    aerial_gl_destroy(gl);
    aerial_context_destroy(air);
}
