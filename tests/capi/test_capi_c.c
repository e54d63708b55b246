/* The C interface compiled as C89 (-std=c89 -pedantic -Werror): the header is valid C, and the
 * basic calls work from C. Exits 0 when every check passes, else prints what failed. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include <aerial/aerial.h>

static int failures = 0;

static void check(int condition, const char* what) {
    if (!condition) {
        fprintf(stderr, "FAILED: %s (last error: %s)\n", what, aerial_last_error_message());
        ++failures;
    }
}

int main(void) {
    aerial_atmosphere zero_atmosphere;
    aerial_atmosphere earth;
    aerial_view view;
    aerial_context* context = NULL;
    aerial_scattering point;
    aerial_positions positions;
    aerial_outputs outputs;
    aerial_batch_stats stats;
    unsigned char fex[4 * 3];
    unsigned char lin[4 * 3];
    float xyz[9];
    size_t i;

    memset(&zero_atmosphere, 0, sizeof zero_atmosphere);
    memset(&view, 0, sizeof view);
    memset(&positions, 0, sizeof positions);
    memset(&outputs, 0, sizeof outputs);
    memset(xyz, 0, sizeof xyz);

    check(AERIAL_CHECK_VERSION() == AERIAL_OK, "AERIAL_CHECK_VERSION() accepts this header");
    check(aerial_library_version() == AERIAL_VERSION, "the library version is the header's");
    check(
        aerial_check_version(AERIAL_VERSION + 10000, sizeof(aerial_atmosphere), sizeof(aerial_view),
                             sizeof(aerial_outputs), sizeof(aerial_batch_settings),
                             sizeof(aerial_arb_options)) == AERIAL_ERROR_VERSION_MISMATCH,
        "another major version is a mismatch");
    check(strcmp(aerial_last_error_field(), "header_version") == 0,
          "the mismatch names header_version");

    /* A zero atmosphere is the earth preset. */
    check(aerial_atmosphere_preset("earth", &earth) == AERIAL_OK, "the earth preset exists");
    check(aerial_context_create(&zero_atmosphere, AERIAL_MODEL_HEIGHT, &context) == AERIAL_OK,
          "a context from a zero atmosphere");
    check(aerial_validate_atmosphere(&zero_atmosphere) == AERIAL_OK, "zero atmosphere is valid");
    check(earth.ground_albedo[1] == 0.1 && earth.ozone_absorption[1] == 1.881e-6 &&
              earth.ozone_center_altitude_m == 25000.0 && earth.ozone_width_m == 30000.0,
          "earth's ground albedo and ozone layer");
    zero_atmosphere.zero_fields = AERIAL_ZERO_GROUND_ALBEDO | AERIAL_ZERO_OZONE_ABSORPTION |
                                  AERIAL_ZERO_OZONE_CENTER_ALTITUDE;
    check(aerial_validate_atmosphere(&zero_atmosphere) == AERIAL_OK,
          "no ozone and a black ground are valid");

    view.eye[2] = 100.0;
    view.sun_dir[1] = 0.6;
    view.sun_dir[2] = 0.8;
    check(aerial_scatter(context, xyz, &point) == AERIAL_ERROR_NO_VIEW,
          "scatter before a view is AERIAL_ERROR_NO_VIEW");
    check(aerial_context_set_view(context, &view) == AERIAL_OK, "set a view");

    for (i = 0; i < 3; ++i) {
        xyz[3 * i + 0] = 1000.0f * (float)(i + 1);
        xyz[3 * i + 1] = 500.0f;
        xyz[3 * i + 2] = 10.0f;
    }
    check(aerial_scatter(context, xyz, &point) == AERIAL_OK, "scatter one vertex");
    check(point.extinction[0] > 0.0f && point.extinction[0] < 1.0f, "0 < F_ex < 1 at 1 km");
    check(point.in_scattering[2] > point.in_scattering[0], "L_in is bluer than it is red");

    positions.x = xyz;
    positions.count = 3;
    outputs.extinction_rgba8 = fex;
    outputs.in_scattering_rgba8 = lin;
    check(aerial_shade(context, &positions, &outputs, NULL, &stats) == AERIAL_OK, "shade 3");
    check(stats.vertices == 3 && stats.invalid_vertices == 0, "3 vertices shaded, none invalid");
    check(fex[0] == (unsigned char)floor(point.extinction[0] * 255.0f + 0.5f),
          "the first F_ex code is the 8-bit rule applied to aerial_scatter's value");
    check(fex[3] == 255 && lin[3] == 255, "alpha is 255");

    /* Errors name the field. */
    view.sun_dir[0] = 1.0;
    check(aerial_context_set_view(context, &view) == AERIAL_ERROR_INVALID_VIEW,
          "a sun_dir of length 1.28 is an invalid view");
    check(strcmp(aerial_last_error_field(), "sun_dir") == 0, "the error names sun_dir");
    check(strstr(aerial_context_last_error(context), "aerial_context_set_view") != NULL,
          "the context's message names the function");
    check(aerial_atmosphere_preset("venus", &earth) == AERIAL_ERROR_UNKNOWN_PRESET,
          "venus is not a preset");
    check(strcmp(aerial_status_string(AERIAL_ERROR_UNKNOWN_PRESET), "unknown preset") == 0,
          "status string");
    check(strcmp(aerial_status_string((aerial_status)99), "unknown status") == 0,
          "a value outside the enum is an unknown status");

    aerial_context_destroy(context);
    if (failures == 0) printf("all C checks passed\n");
    return failures == 0 ? 0 : 1;
}
