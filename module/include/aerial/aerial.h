/* aerial/aerial.h -- the plain C interface of the module (C89, also valid C++).
 *
 * How to use this:
 *   1. Once, in a module compiled separately from the engine: check that the library you link
 *      is the one this header describes: `if (AERIAL_CHECK_VERSION() != AERIAL_OK) ...`.
 *   2. Once: describe the air and make a context (a zero-initialised aerial_atmosphere is the
 *      `earth` preset; or fill one with aerial_atmosphere_preset("hazy", &atmosphere)):
 *        aerial_context* ctx; aerial_context_create(&atmosphere, AERIAL_MODEL_HEIGHT, &ctx);
 *   3. Per frame: `aerial_context_set_view(ctx, &view);` (eye, sun direction, up, units).
 *   4. Per mesh: shade the vertices into your own arrays, F_ex for glColorPointer and L_in for
 *      glSecondaryColorPointer: `aerial_shade(ctx, &positions, &outputs, &settings, &stats);`
 *      Or per vertex: `aerial_scatter(ctx, xyz, &result);`
 *   5. GPU path instead of 4: `aerial_gl_create(loader, user, &gl);` and
 *      `aerial_arb_program_create(gl, &options, &program);` once per GL context, then per frame
 *      `aerial_arb_program_set_frame(program, ctx, &display);` and per mesh
 *      `aerial_arb_program_draw(program, &draw_options, engine_draw_mesh, engine_data);`.
 *
 * Conventions (as the C++ API, aerial/aerial.hpp): metres and radians; any up axis (a
 * parameter, default +Z) and either handedness (a Y-up left-handed engine passes up = 0,1,0 and
 * its own coordinates: the models use only distances, angles and altitudes); sea level is the plane
 * through the origin perpendicular to up; positions are in engine units, scaled by meters_per_unit.
 * F_ex multiplies the surface colour, L_in is added: colour = texel * F_ex + L_in.
 *
 * Errors: every function that can fail returns an aerial_status (AERIAL_OK is 0). The message of
 * the last call on this thread is aerial_last_error_message() (empty after a success), and the
 * offending field (for example "mie_g", "sun_dir", "positions.stride_bytes") is
 * aerial_last_error_field(). Objects keep the message of the last call made on them as well
 * (aerial_context_last_error, ...). No C++ exception ever leaves a function of this header.
 *
 * Zero means default: every struct below may be zero-initialised (`aerial_view view = {0};`,
 * or memset); each field's default is listed next to it, and equals the C++ default. Where 0 is
 * a meaningful value of a field, the struct says how to ask for it.
 */
#ifndef AERIAL_AERIAL_H
#define AERIAL_AERIAL_H

#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

/* ---- Version ------------------------------------------------------------------------------ */

#define AERIAL_VERSION_MAJOR 0
#define AERIAL_VERSION_MINOR 1
#define AERIAL_VERSION_PATCH 0
/* major * 10000 + minor * 100 + patch */
#define AERIAL_VERSION \
    (AERIAL_VERSION_MAJOR * 10000 + AERIAL_VERSION_MINOR * 100 + AERIAL_VERSION_PATCH)

/* ---- Status ------------------------------------------------------------------------------- */

typedef enum aerial_status {
    AERIAL_OK = 0,
    AERIAL_ERROR_NULL_ARGUMENT = 1,      /* a required pointer is NULL */
    AERIAL_ERROR_INVALID_ARGUMENT = 2,   /* an enum value, index or option out of its range */
    AERIAL_ERROR_INVALID_ATMOSPHERE = 3, /* an atmosphere field out of range (names the field) */
    AERIAL_ERROR_INVALID_VIEW = 4,       /* a view field out of range (names the field) */
    AERIAL_ERROR_INVALID_VERTEX = 5,     /* aerial_evaluate: the vertex is not a position */
    AERIAL_ERROR_INVALID_BATCH = 6,      /* aerial_shade: array, stride, output or display */
    AERIAL_ERROR_UNKNOWN_PRESET = 7,     /* the message lists the known names */
    AERIAL_ERROR_NO_VIEW = 8,            /* the context has no view yet: set one first */
    AERIAL_ERROR_VERSION_MISMATCH = 9,   /* header and library disagree (aerial_check_version) */
    AERIAL_ERROR_BUFFER_TOO_SMALL = 10,  /* the caller's buffer cannot hold the result */
    AERIAL_ERROR_GL_UNAVAILABLE = 11,    /* no current context, or a GL 1.1 function missing */
    AERIAL_ERROR_GL_UNSUPPORTED = 12,    /* the context lacks the version or extension needed */
    AERIAL_ERROR_ARB_PROGRAM = 13,       /* no program for the model, a limit exceeded, or the
                                            driver rejected the text (with its error position) */
    AERIAL_ERROR_OUT_OF_MEMORY = 14,
    AERIAL_ERROR_INTERNAL = 15, /* a bug: the message says where */
    /* Not a status: makes every int a valid aerial_status, so that a value from a newer library
       (or any int) passed to aerial_status_string() is defined behaviour in C++ too. */
    AERIAL_STATUS_MAX_ENUM = 0x7FFFFFFF
} aerial_status;

/* A fixed text for each status ("invalid atmosphere", ...); "unknown status" for other values. */
const char* aerial_status_string(aerial_status status);

/* The message of the last call on this thread: "" after a success, else one line
 * "FUNCTION(): FIELD: expected ..., got ..." (the library's one style, with the C function's
 * name: "aerial_validate_atmosphere(): mie_g: expected |g| < 1 (g > 0 scatters forwards), got
 * 1.5"). Valid until the next call on this thread. */
const char* aerial_last_error_message(void);
/* The offending field of the last call on this thread ("" when none). */
const char* aerial_last_error_field(void);

/* ---- Atmosphere --------------------------------------------------------------------------- */

/* Bits of aerial_atmosphere.zero_fields: the field is exactly 0 rather than its default. */
#define AERIAL_ZERO_RAYLEIGH_SCATTERING 1u
#define AERIAL_ZERO_MIE_SCATTERING 2u
#define AERIAL_ZERO_MIE_G 4u
#define AERIAL_ZERO_SUN_IRRADIANCE 8u

/* Sea-level coefficients per metre, falling off as exp(-altitude / scale height). Channels are R,
 * G, B. A field that is 0 (a vector: all three 0) takes its default, the `earth` preset, unless
 * its bit is set in zero_fields. */
typedef struct aerial_atmosphere {
    double rayleigh_scattering[3];  /* 1/m, >= 0; default 5.802e-6, 13.558e-6, 33.1e-6 */
    double mie_scattering[3];       /* 1/m, >= 0; default 3.996e-6 on each channel */
    double mie_absorption[3];       /* 1/m, >= 0; default 0 */
    double mie_g;                   /* Henyey-Greenstein g, |g| < 1, > 0 forwards; default 0.8 */
    double rayleigh_scale_height_m; /* m, > 0; default 8000 */
    double mie_scale_height_m;      /* m, > 0; default 1200 */
    double planet_radius_m;         /* m, > 0; default 6360e3 */
    double atmosphere_radius_m;     /* m, > planet_radius_m; default 6420e3 */
    double sun_irradiance[3];       /* E_sun0 at the top of the atmosphere, >= 0; default 1,1,1 */
    unsigned int zero_fields;       /* AERIAL_ZERO_* bits; default none */
} aerial_atmosphere;

/* Fills `out` with a named preset ("earth", "hp2002", "hazy", "foggy", "mars"), every field
 * explicit (zero_fields set where a preset's field is 0). AERIAL_ERROR_UNKNOWN_PRESET lists the
 * names. */
aerial_status aerial_atmosphere_preset(const char* name, aerial_atmosphere* out);
/* The number of presets, and the name of preset i (NULL when i is out of range). */
size_t aerial_atmosphere_preset_count(void);
const char* aerial_atmosphere_preset_name(size_t i);
/* Parses the atmosphere JSON of the tools (aerial-eval --atmosphere); errors name the field. */
aerial_status aerial_atmosphere_from_json(const char* json_text, aerial_atmosphere* out);
/* AERIAL_ERROR_INVALID_ATMOSPHERE naming the first bad field (after defaults are applied). */
aerial_status aerial_validate_atmosphere(const aerial_atmosphere* atmosphere);

/* ---- Models and views --------------------------------------------------------------------- */

typedef enum aerial_model {
    AERIAL_MODEL_HOFFMAN_PREETHAM = 0, /* the 2002 model: constant density, cheapest */
    AERIAL_MODEL_HEIGHT = 1,           /* exponential profiles, same cost class, per vertex */
    AERIAL_MODEL_REFERENCE = 2         /* numerical ground truth, slow; no ARB program */
} aerial_model;

/* What changes per frame. */
typedef struct aerial_view {
    double eye[3];          /* eye position, engine units; taken as given (0 is the origin) */
    double sun_dir[3];      /* unit vector towards the sun; default (all 0) 0, 0, 1 */
    double up[3];           /* unit world up axis; default (all 0) 0, 0, 1 */
    double meters_per_unit; /* engine units to metres, > 0; default (0) 1 */
} aerial_view;

/* AERIAL_ERROR_INVALID_VIEW naming the first bad field: not finite, sun_dir or up not of unit
 * length (within 1e-3), meters_per_unit < 0. */
aerial_status aerial_validate_view(const aerial_view* view);

/* One vertex's result, raw linear values (before exposure). */
typedef struct aerial_scattering {
    float extinction[3];     /* F_ex in [0, 1] */
    float in_scattering[3];  /* L_in >= 0 */
    float sun_irradiance[3]; /* the sun irradiance the model used at this vertex */
} aerial_scattering;

typedef struct aerial_scattering_d {
    double extinction[3];
    double in_scattering[3];
    double sun_irradiance[3];
} aerial_scattering_d;

/* One-off evaluation in double precision, no context (the C++ aerial::evaluate): validates
 * atmosphere (NULL: defaults), view and vertex; AERIAL_ERROR_INVALID_VERTEX for a vertex with a
 * NaN or infinite coordinate or farther than 1e12 m from the eye. */
aerial_status aerial_evaluate(const aerial_atmosphere* atmosphere, const aerial_view* view,
                              aerial_model model, const double vertex[3], aerial_scattering_d* out);

/* ---- Context: atmosphere + model + the current frame -------------------------------------- */

/* A context, an aerial_gl and an aerial_arb_program are each used by one thread at a time (each
 * call records its message in the object); use one context per thread to shade in parallel. */
typedef struct aerial_context aerial_context;

/* atmosphere NULL means defaults. The context has no frame until aerial_context_set_view. */
aerial_status aerial_context_create(const aerial_atmosphere* atmosphere, aerial_model model,
                                    aerial_context** out);
void aerial_context_destroy(aerial_context* context); /* NULL is fine */
/* Replaces the atmosphere or the model; the frame is recomputed when a view is set. On an
 * error the context is unchanged. */
aerial_status aerial_context_set_atmosphere(aerial_context* context,
                                            const aerial_atmosphere* atmosphere);
aerial_status aerial_context_set_model(aerial_context* context, aerial_model model);
/* Once per frame: validates the view and does the per-frame work (E_sun at the eye, ...). */
aerial_status aerial_context_set_view(aerial_context* context, const aerial_view* view);
/* The message of the last call made on this context ("" after a success). */
const char* aerial_context_last_error(const aerial_context* context);

/* F_ex, L_in and E_sun at one vertex (engine units) with the current frame, in float: the same
 * bits as aerial::scatter<float>. A vertex that is not a position gives F_ex = 1, L_in = 0. */
aerial_status aerial_scatter(const aerial_context* context, const float vertex[3],
                             aerial_scattering* out);

/* ---- Batch shading into caller memory ----------------------------------------------------- */

/* Vertex positions (engine units). Interleaved: `x` points at the first record's x, y and z
 * follow it, `y` and `z` are NULL, records are stride_bytes apart (0: 12, tightly packed).
 * Separate arrays: x, y and z all set, stride_bytes between consecutive floats (0: 4). */
typedef struct aerial_positions {
    const float* x;
    const float* y;
    const float* z;
    size_t count;
    size_t stride_bytes;
} aerial_positions;

/* Where results go; NULL arrays are skipped, at least one must be set. Strides are in bytes, 0
 * means tightly packed (4 for RGBA8, 12 for float RGB). RGBA8 codes are
 * floor(clamp(v, 0, 1) * 255 + 0.5) with alpha 255; L_in and lit colours go through the display
 * (exposure, tone curve) first, F_ex does not. */
typedef struct aerial_outputs {
    unsigned char* extinction_rgba8; /* F_ex, for glColorPointer (texture MODULATE) */
    size_t extinction_rgba8_stride;
    unsigned char* lit_rgba8; /* F_ex x (E_sun max(N.L, 0) + ambient) x albedo: needs lighting */
    size_t lit_rgba8_stride;
    unsigned char* in_scattering_rgba8; /* L_in, for glSecondaryColorPointer + COLOR_SUM */
    size_t in_scattering_rgba8_stride;
    float* extinction_rgb; /* raw linear floats, 3 per vertex */
    size_t extinction_rgb_stride;
    float* in_scattering_rgb;
    size_t in_scattering_rgb_stride;
    float* sun_irradiance_rgb;
    size_t sun_irradiance_rgb_stride;
} aerial_outputs;

typedef enum aerial_tone {
    AERIAL_TONE_CLAMP = 0,      /* min(exposure x, 1) */
    AERIAL_TONE_EXPONENTIAL = 1 /* 1 - exp(-exposure x); not on the ARB path */
} aerial_tone;

typedef struct aerial_display {
    float exposure;   /* multiplies L_in and lit colours, > 0; default (0) 1 */
    aerial_tone tone; /* default AERIAL_TONE_CLAMP */
} aerial_display;

typedef enum aerial_kernel {
    AERIAL_KERNEL_SIMD = 0,      /* SIMD, within 0.5 LSB of the scalar model */
    AERIAL_KERNEL_SIMD_FAST = 1, /* SIMD with cheaper polynomials, within 1 LSB */
    AERIAL_KERNEL_SCALAR = 2     /* plain loop (the reference model always uses it) */
} aerial_kernel;

/* For lit_rgba8: bake the lighting into the primary colour (fixed-function lighting ignores the
 * secondary colour). */
typedef struct aerial_lighting {
    const float* normals;       /* unit normals, x, y, z at the start of each record; required */
    size_t normal_stride_bytes; /* default (0) 12 */
    float ambient[3];           /* sky irradiance added to the sun term; default 0 */
    float albedo[3];            /* multiplies the lit colour; default (all 0) 1, 1, 1 */
} aerial_lighting;

typedef struct aerial_batch_settings {
    aerial_display display;
    aerial_kernel kernel;            /* default AERIAL_KERNEL_SIMD */
    unsigned int threads;            /* worker threads including the caller; default (0) all */
    size_t min_vertices_per_thread;  /* smaller batches are not split; default (0) 32768 */
    const aerial_lighting* lighting; /* required by lit_rgba8; default NULL */
} aerial_batch_settings;

typedef struct aerial_batch_stats {
    size_t vertices;         /* shaded */
    size_t invalid_vertices; /* not positions: written as F_ex = 1, L_in = 0 */
    unsigned int threads_used;
} aerial_batch_stats;

/* Shades every position into the outputs with the context's current frame (the same bits as
 * aerial::shade_into). settings NULL means defaults; stats may be NULL. Errors
 * (AERIAL_ERROR_INVALID_BATCH, nothing written): a NULL array with count > 0, a stride smaller
 * than its element, lit_rgba8 without lighting normals, exposure < 0 or not finite, no output. */
aerial_status aerial_shade(const aerial_context* context, const aerial_positions* positions,
                           const aerial_outputs* outputs, const aerial_batch_settings* settings,
                           aerial_batch_stats* stats);

/* ---- OpenGL: the engine's context --------------------------------------------------------- */

/* Resolves a GL entry point by name (glXGetProcAddressARB, eglGetProcAddress, SDL_GL_...). */
typedef void* (*aerial_gl_load_function)(void* user, const char* name);
/* The engine's draw call for one mesh: points its vertex and texcoord arrays and draws. */
typedef void (*aerial_draw_function)(void* user);

typedef struct aerial_gl aerial_gl;

/* With the engine's context current: resolves the entry points the module calls through `load`
 * (the module never links libGL) and reads what the context offers. Keep it as long as the
 * context lives; destroy it with the context current (it may own a 3D texture). */
aerial_status aerial_gl_create(aerial_gl_load_function load, void* user, aerial_gl** out);
void aerial_gl_destroy(aerial_gl* gl); /* NULL is fine */
const char* aerial_gl_last_error(const aerial_gl* gl);
/* GL_RENDERER and GL_VERSION of the context. */
const char* aerial_gl_renderer(const aerial_gl* gl);
const char* aerial_gl_version(const aerial_gl* gl);

/* How the fixed pipeline adds L_in (aerial/gl.hpp, aerial::gl::Path). */
typedef enum aerial_path {
    AERIAL_PATH_AUTOMATIC = 0,       /* the first available of the three below */
    AERIAL_PATH_SECONDARY_COLOR = 1, /* GL 1.4 or EXT_secondary_color: one pass, COLOR_SUM */
    AERIAL_PATH_COMBINER = 2,        /* GL 1.3: texture_env_combine adds L_in from a 3D texture */
    AERIAL_PATH_TWO_PASS = 3         /* GL 1.1: F_ex pass, then L_in added ONE/ONE, depth EQUAL */
} aerial_path;

typedef struct aerial_draw_options {
    aerial_path path;            /* default AERIAL_PATH_AUTOMATIC */
    int texture_unit;            /* the unit with the engine's texture; default 0 */
    int untextured;              /* non-zero: colour = F_ex + L_in; default 0 (textured) */
    int fixed_function_lighting; /* non-zero: keep GL lighting on, F_ex feeds the material */
} aerial_draw_options;

/* One RGBA8 record per vertex of the engine's draw, e.g. from aerial_shade. */
typedef struct aerial_vertex_colours {
    const unsigned char* primary;   /* F_ex (or lit_rgba8) */
    const unsigned char* secondary; /* L_in after exposure */
    size_t primary_stride_bytes;    /* default (0) 4 */
    size_t secondary_stride_bytes;  /* default (0) 4 */
    size_t vertex_count;
} aerial_vertex_colours;

/* The path `requested` resolves to on this context (AERIAL_ERROR_GL_UNSUPPORTED names what a
 * forced path lacks). */
aerial_status aerial_gl_choose_path(aerial_gl* gl, aerial_path requested,
                                    int fixed_function_lighting, aerial_path* chosen);

/* Calls draw(user) once (twice on the two-pass path) with the colours applied, then restores
 * every piece of GL state it changed. path_used may be NULL. */
aerial_status aerial_gl_draw_colours(aerial_gl* gl, const aerial_draw_options* options,
                                     const aerial_vertex_colours* colours,
                                     aerial_draw_function draw, void* user, aerial_path* path_used);

/* ---- OpenGL: the ARB vertex program ------------------------------------------------------- */

typedef enum aerial_parameter_space {
    AERIAL_PARAMETERS_LOCAL = 0, /* program.local[i] of the program object */
    AERIAL_PARAMETERS_ENV = 1    /* program.env[i], shared by the context's vertex programs */
} aerial_parameter_space;

typedef enum aerial_height_fidelity {
    AERIAL_HEIGHT_FIDELITY_AUTOMATIC = 0, /* the highest level that fits the limits */
    AERIAL_HEIGHT_FIDELITY_SPEC_MINIMUM = 1,
    AERIAL_HEIGHT_FIDELITY_EXACT_OPTICAL_DEPTH = 2,
    AERIAL_HEIGHT_FIDELITY_FULL = 3 /* within 1 LSB of the CPU model; 249 instructions */
} aerial_height_fidelity;

/* Pass -1 as texcoord_units for a program that passes no texture coordinates through. */
#define AERIAL_NO_TEXCOORDS (-1)

typedef struct aerial_arb_options {
    aerial_model model;                     /* HOFFMAN_PREETHAM (default) or HEIGHT */
    aerial_parameter_space parameter_space; /* default AERIAL_PARAMETERS_LOCAL */
    int parameter_base;                     /* first parameter index, >= 0; default 0 */
    int texcoord_units;                     /* units 0..n-1 passed through, 1..8; default (0) 1 */
    int position_invariant;                 /* OPTION ARB_position_invariant; default 0 */
    int guard_coarse_ex2;                   /* for ~11-bit EX2 hardware; default 0 */
    aerial_height_fidelity height_fidelity; /* default AUTOMATIC */
    /* aerial_arb_program_create only: resolve AUTOMATIC against the driver's native limits
     * rather than the spec minimums (default 0: spec minimums, 127 instructions). */
    int use_native_limits;
} aerial_arb_options;

/* The program text for `options` (NULL: defaults), without GL: exactly what goes to
 * glProgramStringARB. `text` receives it with a terminating 0 when `capacity` allows
 * (AERIAL_ERROR_BUFFER_TOO_SMALL otherwise; text may be NULL with capacity 0 to ask the size).
 * `length` (without the 0) and `parameter_count` (vectors the program reads) may be NULL. */
aerial_status aerial_arb_generate(const aerial_arb_options* options, char* text, size_t capacity,
                                  size_t* length, int* parameter_count);

/* The per-frame parameter vectors (4 floats each) of the program `options` describe, from the
 * context's frame, for engines that upload them themselves: vector i goes to index
 * parameter_base + i. The context's model must be options->model; the display's tone curve
 * must be AERIAL_TONE_CLAMP. `count` receives the number of vectors. */
aerial_status aerial_arb_parameters(const aerial_context* context,
                                    const aerial_arb_options* options,
                                    const aerial_display* display, float* vectors,
                                    size_t capacity_vectors, size_t* count);

typedef struct aerial_arb_program aerial_arb_program;

/* Generates the program and loads it into a new program object of gl's context (the program
 * bound before stays bound). AERIAL_ERROR_GL_UNSUPPORTED without GL_ARB_vertex_program;
 * AERIAL_ERROR_ARB_PROGRAM with the driver's error position and string when it rejects it. */
aerial_status aerial_arb_program_create(aerial_gl* gl, const aerial_arb_options* options,
                                        aerial_arb_program** out);
/* Deletes the program object (gl's context current; gl still alive). NULL is fine. */
void aerial_arb_program_destroy(aerial_arb_program* program);
const char* aerial_arb_program_last_error(const aerial_arb_program* program);
const char* aerial_arb_program_text(const aerial_arb_program* program);
unsigned int aerial_arb_program_id(const aerial_arb_program* program); /* the GL name */
/* Once per frame: computes the parameters from the context's frame and uploads them. */
aerial_status aerial_arb_program_set_frame(aerial_arb_program* program,
                                           const aerial_context* context,
                                           const aerial_display* display);
/* Calls draw(user) with the program bound and enabled, texture MODULATE and COLOR_SUM on, then
 * unbinds it and restores every piece of GL state it changed. Only options->texture_unit and
 * options->untextured are read (NULL: defaults). */
aerial_status aerial_arb_program_draw(aerial_arb_program* program,
                                      const aerial_draw_options* options, aerial_draw_function draw,
                                      void* user);

/* ---- Version check ------------------------------------------------------------------------ */

/* AERIAL_ERROR_VERSION_MISMATCH when the library was built from a different major version (or,
 * before 1.0, a different minor version) than the header the caller was compiled with, or when
 * one of the struct sizes differs (a different compiler, packing or header). */
aerial_status aerial_check_version(int header_version, size_t sizeof_atmosphere, size_t sizeof_view,
                                   size_t sizeof_outputs, size_t sizeof_batch_settings,
                                   size_t sizeof_arb_options);

#define AERIAL_CHECK_VERSION()                                                           \
    aerial_check_version(AERIAL_VERSION, sizeof(aerial_atmosphere), sizeof(aerial_view), \
                         sizeof(aerial_outputs), sizeof(aerial_batch_settings),          \
                         sizeof(aerial_arb_options))

/* The library's AERIAL_VERSION. */
int aerial_library_version(void);

#ifdef __cplusplus
}
#endif

#endif /* AERIAL_AERIAL_H */
