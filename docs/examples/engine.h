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

/* An engine with a material system: it owns its program objects. engine_program_create loads
 * ARB vertex program text (0 on failure), engine_program_local sets program.local[index], and
 * engine_program_draw binds and enables the program, draws the mesh, and disables it. */
unsigned int engine_program_create(const char* text);
void engine_program_local(unsigned int program, int index, const float vector[4]);
void engine_program_draw(unsigned int program, engine_mesh* mesh);

/* An engine whose vertices carry one colour: a packed ARGB32 word (D3DCOLOR) in each
 * interleaved record. engine_draw_coloured draws the mesh with its one colour array pointing
 * at `colours` (ARGB32, `stride` bytes apart) instead of its vertices' own field. */
typedef struct engine_vertex {
    float xyz[3];
    unsigned int colour; /* A << 24 | R << 16 | G << 8 | B */
    float uv[2];
} engine_vertex;

typedef struct engine_coloured_mesh {
    engine_vertex* vertices;
    size_t vertex_count;
    unsigned int* in_scattering; /* ARGB32 per vertex: the colours of the L_in pass */
} engine_coloured_mesh;

void engine_draw_coloured(const engine_coloured_mesh* mesh, const unsigned int* colours,
                          size_t stride);

/* The engine's sky dome: vertices around the eye (any radius), one RGBA8 colour each, drawn
 * first with texturing, lighting and depth writes off. */
typedef struct engine_dome {
    const float* xyz; /* world positions, engine units, tightly packed */
    size_t vertex_count;
    unsigned char* rgba; /* RGBA8 per vertex */
} engine_dome;

void engine_draw_dome(const engine_dome* dome);

#endif
