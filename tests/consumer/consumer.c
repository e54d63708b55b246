/* A C engine module built against the installed package: checks the library it links, shades
 * a few vertices and prints them. Exits 0 on success. */
#include <stdio.h>
#include <string.h>

#include <aerial/aerial.h>

int main(void) {
    aerial_context* context = NULL;
    aerial_view view;
    aerial_positions positions;
    aerial_outputs outputs;
    float xyz[6] = {1000.0f, 0.0f, 10.0f, 20000.0f, 5000.0f, 10.0f};
    unsigned char fex[8];
    unsigned char lin[8];

    if (AERIAL_CHECK_VERSION() != AERIAL_OK) {
        fprintf(stderr, "consumer_c: %s\n", aerial_last_error_message());
        return 1;
    }
    memset(&view, 0, sizeof view);
    memset(&positions, 0, sizeof positions);
    memset(&outputs, 0, sizeof outputs);
    view.eye[2] = 50.0;
    view.sun_dir[1] = 0.6;
    view.sun_dir[2] = 0.8;
    positions.x = xyz;
    positions.count = 2;
    outputs.extinction_rgba8 = fex;
    outputs.in_scattering_rgba8 = lin;
    if (aerial_context_create(NULL, AERIAL_MODEL_HEIGHT, &context) != AERIAL_OK ||
        aerial_context_set_view(context, &view) != AERIAL_OK ||
        aerial_shade(context, &positions, &outputs, NULL, NULL) != AERIAL_OK) {
        fprintf(stderr, "consumer_c: %s\n", aerial_last_error_message());
        aerial_context_destroy(context);
        return 1;
    }
    printf("consumer_c: aerial %d, F_ex %d %d %d -> %d %d %d, L_in %d %d %d -> %d %d %d\n",
           aerial_library_version(), fex[0], fex[1], fex[2], fex[4], fex[5], fex[6], lin[0], lin[1],
           lin[2], lin[4], lin[5], lin[6]);
    aerial_context_destroy(context);
    /* Farther vertices are hazier: less F_ex, more L_in in blue. */
    return fex[6] < fex[2] && lin[6] > lin[2] ? 0 : 1;
}
