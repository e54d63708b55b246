/* A material system with ARB programs: the engine owns the program object; aerial gives the
 * text (the best height level the driver runs), the parameters and the state to set. */
#include <string.h>

#include <aerial/aerial.h>

#include "engine.h"

#define MAX_PARAMETERS 2048 /* every level: the highest reads 1758 */

static aerial_context* air;
static aerial_gl* gl;
static aerial_arb_options options;
static unsigned int program;

int material_init(aerial_gl_load_function load, void* user) {
    static char text[32768]; /* the highest level: about 21 500 bytes */
    aerial_arb_info info;
    memset(&options, 0, sizeof options);
    options.model = AERIAL_MODEL_HEIGHT; /* height fidelity AUTOMATIC: the best that fits */
    if (AERIAL_CHECK_VERSION() != AERIAL_OK ||
        aerial_context_create(NULL, AERIAL_MODEL_HEIGHT, &air) != AERIAL_OK ||
        aerial_gl_create(load, user, &gl) != AERIAL_OK ||
        aerial_gl_arb_limits(gl, &options.limits) != AERIAL_OK || /* only queries */
        aerial_arb_describe(&options, &info) != AERIAL_OK ||
        info.parameter_count > MAX_PARAMETERS ||
        aerial_arb_generate(&options, text, sizeof text, NULL, NULL) != AERIAL_OK) {
        return 0;
    }
    program = engine_program_create(text); /* the engine's glProgramStringARB */
    return program != 0;
}

int material_frame(const engine_camera* camera, engine_mesh* meshes, size_t mesh_count) {
    aerial_view view;
    static float vectors[4 * MAX_PARAMETERS];
    size_t count = 0, i;
    memset(&view, 0, sizeof view);
    memcpy(view.eye, camera->position, sizeof view.eye);
    memcpy(view.sun_dir, camera->sun_dir, sizeof view.sun_dir);
    view.meters_per_unit = camera->meters_per_unit;
    if (aerial_context_set_view(air, &view) != AERIAL_OK ||
        aerial_arb_parameters(air, &options, NULL, vectors, MAX_PARAMETERS, &count) != AERIAL_OK) {
        return 0;
    }
    for (i = 0; i < count; ++i) { /* program.local[parameter_base + i], once per frame */
        engine_program_local(program, options.parameter_base + (int)i, vectors + 4 * i);
    }
    /* GL_COLOR_SUM (the program writes L_in to the secondary colour) and MODULATE. */
    if (aerial_gl_set_program_state(gl, NULL) != AERIAL_OK) return 0;
    for (i = 0; i < mesh_count; ++i) engine_program_draw(program, &meshes[i]);
    return aerial_gl_restore_program_state(gl) == AERIAL_OK;
}

void material_shutdown(void) {
    aerial_gl_destroy(gl);
    aerial_context_destroy(air);
}
