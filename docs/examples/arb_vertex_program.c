/* ARB_vertex_program era: the GPU computes F_ex and L_in per vertex; nothing per vertex on the
 * CPU, a few parameter vectors per frame. */
#include <string.h>

#include <aerial/aerial.h>

#include "engine.h"

static aerial_context* air;
static aerial_gl* gl;
static aerial_arb_program* program;

int arb_init(aerial_gl_load_function load, void* user) {
    aerial_arb_options options;
    memset(&options, 0, sizeof options); /* the 2002 model, program.local[0..5], 1 texcoord set */
    return AERIAL_CHECK_VERSION() == AERIAL_OK &&
           aerial_context_create(NULL, AERIAL_MODEL_HOFFMAN_PREETHAM, &air) == AERIAL_OK &&
           aerial_gl_create(load, user, &gl) == AERIAL_OK &&
           aerial_arb_program_create(gl, &options, &program) == AERIAL_OK;
}

int arb_frame(const engine_camera* camera, engine_mesh* meshes, size_t mesh_count) {
    aerial_view view;
    size_t i;
    memset(&view, 0, sizeof view);
    memcpy(view.eye, camera->position, sizeof view.eye);
    memcpy(view.sun_dir, camera->sun_dir, sizeof view.sun_dir);
    view.meters_per_unit = camera->meters_per_unit;
    if (aerial_context_set_view(air, &view) != AERIAL_OK ||
        aerial_arb_program_set_frame(program, air, NULL) != AERIAL_OK) {
        return 0;
    }
    for (i = 0; i < mesh_count; ++i) {
        /* The modelview matrix must map world to eye space: positions are world positions. */
        if (aerial_arb_program_draw(program, NULL, engine_draw_mesh, &meshes[i]) != AERIAL_OK) {
            return 0;
        }
    }
    return 1;
}

void arb_shutdown(void) {
    aerial_arb_program_destroy(program);
    aerial_gl_destroy(gl);
    aerial_context_destroy(air);
}
