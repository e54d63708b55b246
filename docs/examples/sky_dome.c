/* The sky on a dome the engine owns: each vertex gets the sky along its direction from the eye,
 * so the dome's radius does not matter; the exposure follows the light of the scene. */
#include <string.h>

#include <aerial/aerial.h>

#include "engine.h"

static aerial_context* air;
static aerial_sky* sky;

int sky_init(void) {
    return AERIAL_CHECK_VERSION() == AERIAL_OK &&
           aerial_context_create(NULL, AERIAL_MODEL_HEIGHT, &air) == AERIAL_OK &&
           aerial_sky_create(NULL, &sky) == AERIAL_OK; /* the height model's dome sky */
}

int sky_frame(const engine_camera* camera, engine_dome* dome) {
    aerial_view view;
    aerial_display display;
    aerial_positions vertices;
    aerial_sky_colours out;
    memset(&view, 0, sizeof view);
    memset(&display, 0, sizeof display);
    memset(&vertices, 0, sizeof vertices);
    memset(&out, 0, sizeof out);
    memcpy(view.eye, camera->position, sizeof view.eye);
    memcpy(view.sun_dir, camera->sun_dir, sizeof view.sun_dir);
    view.meters_per_unit = camera->meters_per_unit;
    if (aerial_context_set_view(air, &view) != AERIAL_OK ||
        aerial_auto_exposure(air, NULL, &display.exposure) != AERIAL_OK ||
        aerial_sky_set_frame(sky, air) != AERIAL_OK) {
        return 0;
    }
    vertices.x = dome->xyz;
    vertices.count = dome->vertex_count;
    out.rgba8 = dome->rgba; /* AERIAL_COLOUR_BGRA8 / _ARGB32 for other vertex layouts */
    if (aerial_sky_shade_dome(sky, &vertices, NULL, &display, &out) != AERIAL_OK) return 0;
    engine_draw_dome(dome);
    return 1;
}

void sky_shutdown(void) {
    aerial_sky_destroy(sky);
    aerial_context_destroy(air);
}
