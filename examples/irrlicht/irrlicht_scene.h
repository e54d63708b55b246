/* irrlicht_scene.h -- the one source of the Irrlicht example's scene, shared by the Irrlicht
 * program (aerial-irrlicht-example, Y-up left-handed) and its reference (aerial-irrlicht-reference,
 * aerial::scene in the Z-up right-handed twin). Every quantity here is in the twin's frame:
 * x east, y north, z up, metres. The Irrlicht world is the same with y and z swapped. */
#ifndef AERIAL_EXAMPLES_IRRLICHT_SCENE_H
#define AERIAL_EXAMPLES_IRRLICHT_SCENE_H

#include <math.h>
#include <string.h>

#include "aerial/aerial.h"

/* The terrain: a square of SCENE_TERRAIN_SIZE_M metres centred on the origin, sampled on a grid
 * of SCENE_GRID_N x SCENE_GRID_N vertices (16 641 < 65 536: Irrlicht's 16-bit indices). */
#define SCENE_TERRAIN_SIZE_M 16000.0
#define SCENE_GRID_N 129

/* The camera (the twin's frame), a pinhole with a vertical field of view. */
#define SCENE_EYE_X 0.0
#define SCENE_EYE_Y (-7600.0)
#define SCENE_EYE_Z 1000.0
#define SCENE_TARGET_X 0.0
#define SCENE_TARGET_Y 4000.0
#define SCENE_TARGET_Z 200.0
#define SCENE_FOV_Y_RAD 0.9
#define SCENE_NEAR_M 10.0
#define SCENE_FAR_M 40000.0

/* The sun, 20 degrees above the horizon, behind the camera and to its right (outside the view,
 * so that neither program draws a sun disc). Azimuth from +x towards +y. */
#define SCENE_SUN_ELEVATION_DEG 20.0
#define SCENE_SUN_AZIMUTH_DEG (-60.0)

/* The terrain's texture: one albedo (all mipmap levels equal, so that the engines' filters and
 * mipmap generation cannot differ), bytes R, G, B; SCENE_TEXTURE_SIDE texels a side. */
#define SCENE_ALBEDO_R 96
#define SCENE_ALBEDO_G 112
#define SCENE_ALBEDO_B 72
#define SCENE_TEXTURE_SIDE 4
/* Metres per texture repetition (texcoords x / repeat, y / repeat). */
#define SCENE_TEXTURE_REPEAT_M 500.0

#define SCENE_PI 3.14159265358979323846

/* Height above sea level at (x, y), metres: a sum of sines, in [30, 630]. */
static double scene_height(double x, double y) {
    return 330.0 + 150.0 * sin(0.00041 * x + 0.3) * cos(0.00057 * y) +
           100.0 * sin(0.0013 * x + 0.0009 * y) + 50.0 * sin(0.003 * x - 0.0021 * y + 1.0);
}

/* Grid vertex (i, j), i along x and j along y, in the twin's frame. */
static void scene_grid_point(int i, int j, double xyz[3]) {
    const double step = SCENE_TERRAIN_SIZE_M / (SCENE_GRID_N - 1);
    xyz[0] = -0.5 * SCENE_TERRAIN_SIZE_M + step * i;
    xyz[1] = -0.5 * SCENE_TERRAIN_SIZE_M + step * j;
    xyz[2] = scene_height(xyz[0], xyz[1]);
}

/* The six vertex indices (two triangles) of grid cell (i, j), 0 <= i, j < SCENE_GRID_N - 1,
 * vertex (i, j) at index j * SCENE_GRID_N + i; clockwise seen from above. The two programs show
 * the same image, so a triangle winds the same way on both screens: clockwise is what Irrlicht
 * (glFrontFace(GL_CW)) takes as the front (aerial::scene does not cull). */
static void scene_cell_indices(int i, int j, unsigned int out[6]) {
    const unsigned int a = (unsigned int)(j * SCENE_GRID_N + i), b = a + 1, c = a + SCENE_GRID_N,
                       d = c + 1;
    out[0] = a;
    out[1] = d;
    out[2] = b;
    out[3] = a;
    out[4] = c;
    out[5] = d;
}

/* The unit vector towards the sun, the twin's frame. */
static void scene_sun_dir(double out[3]) {
    const double e = SCENE_SUN_ELEVATION_DEG * SCENE_PI / 180.0;
    const double a = SCENE_SUN_AZIMUTH_DEG * SCENE_PI / 180.0;
    out[0] = cos(e) * cos(a);
    out[1] = cos(e) * sin(a);
    out[2] = sin(e);
}

/* The twin's (x, y, z) as the Irrlicht world's (x, z, y), and back (the same swap). */
static void scene_swap_yz(const double in[3], double out[3]) {
    out[0] = in[0];
    out[1] = in[2];
    out[2] = in[1];
}

/* The dome of aerial::scene's built-in sky (make_sky_dome_mesh(kSkyDomeRings,
 * kSkyDomeSegments) for up = +z, plus its skirt ring 10 degrees below the horizon), replicated
 * direction for direction so that both programs interpolate the same vertex colours. */
#define SCENE_DOME_RINGS 12
#define SCENE_DOME_SEGMENTS 32
#define SCENE_DOME_SKIRT_DEG (-10.0)
/* rings x segments, the zenith, the skirt */
#define SCENE_DOME_VERTICES (SCENE_DOME_RINGS * SCENE_DOME_SEGMENTS + 1 + SCENE_DOME_SEGMENTS)
/* Drawn at this fraction of the far distance around the eye (as aerial::scene draws it). */
#define SCENE_DOME_RADIUS_OF_FAR 0.5

/* The frame as the Irrlicht program gives it to aerial (Y-up, its own coordinates, metres):
 * both programs take the exposure from aerial_auto_exposure with this view. */
static void scene_aerial_view(aerial_view* view) {
    const double eye[3] = {SCENE_EYE_X, SCENE_EYE_Y, SCENE_EYE_Z};
    double sun[3];
    memset(view, 0, sizeof *view);
    scene_swap_yz(eye, view->eye);
    scene_sun_dir(sun);
    scene_swap_yz(sun, view->sun_dir);
    view->up[1] = 1.0;
    view->meters_per_unit = 1.0;
}

#endif /* AERIAL_EXAMPLES_IRRLICHT_SCENE_H */
