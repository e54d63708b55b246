/* What the integration examples assume of the engine: a camera, meshes with RGBA8 colour arrays
 * of their own, and the engine's draw call. tests/capi/test_docs_examples.cpp implements it and
 * runs the examples on a headless context. */
#ifndef ENGINE_H
#define ENGINE_H

#include <stddef.h>

typedef struct engine_camera {
    double position[3];     /* eye, engine units */
    double sun_dir[3];      /* unit vector towards the sun */
    double meters_per_unit; /* the engine's unit in metres */
} engine_camera;

typedef struct engine_mesh {
    const float* xyz;     /* world positions, engine units, x y z tightly packed */
    const float* normals; /* unit normals, tightly packed (for the lit example) */
    size_t vertex_count;
    unsigned char* primary;   /* RGBA8 per vertex: F_ex (or F_ex with the lighting baked in) */
    unsigned char* secondary; /* RGBA8 per vertex: L_in */
} engine_mesh;

/* The engine's own draw of one mesh (glVertexPointer, glTexCoordPointer, glDrawElements):
 * `mesh` is the engine_mesh. It must not touch the colour or secondary-colour arrays. */
void engine_draw_mesh(void* mesh);

#endif
