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
#define AERIAL_VERSION_MINOR 2
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
    AERIAL_ERROR_INTERNAL = 15,     /* a bug: the message says where */
    AERIAL_ERROR_ENGINE_STATE = 16, /* the engine's draw callback changed state aerial had set
                                       (e.g. re-pointed the colour array): the colours drawn were
                                       not aerial's; the message names the state */
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
#define AERIAL_ZERO_GROUND_ALBEDO 16u
#define AERIAL_ZERO_OZONE_ABSORPTION 32u
#define AERIAL_ZERO_OZONE_CENTER_ALTITUDE 64u

/* Rayleigh and Mie coefficients per metre at sea level, falling off as exp(-altitude / scale
 * height); ozone absorbs in a tent-shaped layer (density 1 at its centre, 0 at centre +- width/2
 * and beyond). Channels are R, G, B. A field that is 0 (a vector: all three 0) takes its default,
 * the `earth` preset, unless its bit is set in zero_fields (fields whose default is 0, or that
 * cannot be 0, have no bit). The fields are aerial::Atmosphere's (aerial/atmosphere.hpp). */
typedef struct aerial_atmosphere {
    double rayleigh_scattering[3];  /* 1/m, >= 0; default 5.802e-6, 13.558e-6, 33.1e-6 */
    double mie_scattering[3];       /* 1/m, >= 0; default 3.996e-6 on each channel */
    double mie_absorption[3];       /* 1/m, >= 0; default 0 */
    double mie_g;                   /* Henyey-Greenstein g, |g| < 1, > 0 forwards; default 0.8 */
    double rayleigh_scale_height_m; /* m, > 0; default 8000 */
    double mie_scale_height_m;      /* m, > 0; default 1200 */
    /* at the ozone layer's peak, 1/m, >= 0; default 0.650e-6, 1.881e-6, 0.085e-6 */
    double ozone_absorption[3];
    double ozone_center_altitude_m; /* the layer's peak, m, in [0, 1e6]; default 25000 */
    double ozone_width_m;           /* the layer's full width, m, in [1, 1e6]; default 30000 */
    double planet_radius_m;         /* m, > 0; default 6360e3 */
    double atmosphere_radius_m;     /* m, > planet_radius_m; default 6420e3 */
    double ground_albedo[3];        /* Lambertian, each in [0, 1]; default 0.1 on each channel */
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
    AERIAL_MODEL_REFERENCE = 2,        /* numerical ground truth, every order of scattering:
                                          slowest (tables per atmosphere); no ARB program */
    AERIAL_MODEL_SINGLE_SCATTERING = 3 /* the reference without the higher orders; slow */
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
 * Separate arrays: x, y and z all set, stride_bytes between consecutive floats (0: 4).
 * Model space: with model_matrix set, the positions are in the node's own frame and the world
 * position is model_matrix x (x, y, z, 1), so a node under a transform needs no world copy. */
typedef struct aerial_positions {
    const float* x;
    const float* y;
    const float* z;
    size_t count;
    size_t stride_bytes;
    /* 16 floats, column-major (glLoadMatrixf's layout), affine (bottom row 0, 0, 0, 1), mapping
     * the positions to the world; NULL (default): the positions are world positions. */
    const float* model_matrix;
} aerial_positions;

/* How a colour output is laid out in memory (every *_rgba8 output of a call). */
typedef enum aerial_colour_format {
    AERIAL_COLOUR_RGBA8 = 0, /* bytes R, G, B, A (glColorPointer(4, GL_UNSIGNED_BYTE, ...)) */
    AERIAL_COLOUR_BGRA8 = 1, /* bytes B, G, R, A (GL_BGRA, EXT_vertex_array_bgra) */
    /* one native-endian 32-bit word A << 24 | R << 16 | G << 8 | B: Direct3D's D3DCOLOR and
       Irrlicht's video::SColor (B, G, R, A bytes on a little-endian machine) */
    AERIAL_COLOUR_ARGB32 = 2
} aerial_colour_format;

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
    /* The layout of the three *_rgba8 outputs; default AERIAL_COLOUR_RGBA8. With a stride the
     * codes go straight into the colour field of an interleaved engine vertex (point the output
     * at the first vertex's colour field, stride = sizeof(vertex)). */
    aerial_colour_format colour_format;
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
 * than its element, lit_rgba8 without lighting normals, exposure < 0 or not finite, no output,
 * a model matrix that is not finite and affine, a colour format out of range. */
aerial_status aerial_shade(const aerial_context* context, const aerial_positions* positions,
                           const aerial_outputs* outputs, const aerial_batch_settings* settings,
                           aerial_batch_stats* stats);

/* ---- Exposure ----------------------------------------------------------------------------- */

/* aerial::ExposureOptions: the exposure maps a grey card lit by the sun (through the atmosphere)
 * and the sky to `key`, so that noon, dusk and every preset read alike. */
typedef struct aerial_exposure_options {
    double albedo;   /* reflectance of the grey card, (0, 1]; default (0) 0.18 */
    double key;      /* exposed radiance of the card before the tone curve, > 0; default 0.5 */
    double min_gain; /* limits, as multiples of the exposure of a card lit by E_sun0 at the */
    double max_gain; /* zenith and no sky, 0 < min <= max; defaults 0.5 and 64 */
    /* non-zero: the card stands at card_altitude_m (m above sea level); default (0): at the
     * eye's altitude */
    int use_card_altitude;
    double card_altitude_m;
} aerial_exposure_options;

/* The exposure for the context's atmosphere and current view (aerial::auto_exposure with the
 * sun irradiance and the skylight at the card's altitude, the sun's elevation above its
 * horizon): pass it as aerial_display.exposure. Costs about 128 sky rays (well under a
 * millisecond); call it when the sun or the atmosphere moved. options NULL means defaults. */
aerial_status aerial_auto_exposure(const aerial_context* context,
                                   const aerial_exposure_options* options, float* exposure);

/* ---- Sky: the dome, the cubemap and the sun sprite ---------------------------------------- */

/* How the sky radiance along a direction is computed (aerial::SkyMethod), cheapest first. */
typedef enum aerial_sky_method {
    /* what aerial::scene's built-in sky uses for the context's model: DOME_HP for
       HOFFMAN_PREETHAM, DOME_HEIGHT for HEIGHT (and REFERENCE); the cubemap takes
       HEIGHT_CHAINED (aerial::scene's cubemap sky) */
    AERIAL_SKY_AUTOMATIC = 0,
    AERIAL_SKY_DOME_HP = 1,        /* the 2002 dome, a fitted radius per elevation */
    AERIAL_SKY_DOME_HP_SINGLE = 2, /* the same, one radius */
    AERIAL_SKY_DOME_HEIGHT = 3,    /* the height model to the top of the atmosphere */
    AERIAL_SKY_HEIGHT_CHAINED = 4, /* the height model over `segments` pieces of the ray */
    AERIAL_SKY_REFERENCE = 5       /* numerical; about a millisecond a direction */
} aerial_sky_method;

typedef struct aerial_sky_options {
    aerial_sky_method method; /* default AERIAL_SKY_AUTOMATIC */
    int segments;             /* HEIGHT_CHAINED: pieces of the ray, >= 1; default (0) 12 */
} aerial_sky_options;

/* The sky of a context's atmosphere and view. Holds the per-frame state, the fitted dome of the
 * 2002 method (kept while the atmosphere holds and the eye's altitude moves less than 25 m) and
 * the cubemap's cache. One thread at a time, as a context. */
typedef struct aerial_sky aerial_sky;

aerial_status aerial_sky_create(const aerial_sky_options* options, aerial_sky** out);
void aerial_sky_destroy(aerial_sky* sky); /* NULL is fine */
const char* aerial_sky_last_error(const aerial_sky* sky);
/* Once per frame, after aerial_context_set_view: takes the context's atmosphere, model and view.
 * AERIAL_ERROR_NO_VIEW before the context has a view. */
aerial_status aerial_sky_set_frame(aerial_sky* sky, const aerial_context* context);

/* The raw linear sky radiance towards a world direction (any length > 0). */
aerial_status aerial_sky_radiance(const aerial_sky* sky, const double direction[3], float rgb[3]);

/* Where sky colours go: RGBA8 codes after the display (alpha 255) and/or raw linear floats. */
typedef struct aerial_sky_colours {
    unsigned char* rgba8;
    size_t rgba8_stride; /* bytes between vertices; default (0) 4 */
    aerial_colour_format format;
    float* rgb;
    size_t rgb_stride; /* default (0) 12 */
} aerial_sky_colours;

/* Colours for the vertices of a dome the engine owns and draws: each vertex gets the sky seen
 * along the direction from `centre` to it (centre NULL: the view's eye; positions in engine
 * units, model_matrix applied first), so the dome's radius and tessellation do not change the
 * look. Vertices below the horizon get the horizon's colour in their azimuth (as aerial::scene's
 * dome skirt and the cubemap: terrain covers them). Draw them as the dome's vertex colours with
 * texturing, lighting and fog off, depth writes off, behind everything. display NULL: exposure
 * 1, clamp. AERIAL_ERROR_INVALID_BATCH for bad arrays; a vertex at the centre, straight below it
 * or not finite gets black. */
aerial_status aerial_sky_shade_dome(const aerial_sky* sky, const aerial_positions* vertices,
                                    const double centre[3], const aerial_display* display,
                                    const aerial_sky_colours* out);

/* The six faces of a sky cubemap, size x size texels each, in GL's order and orientation (+X,
 * -X, +Y, -Y, +Z, -Z, as glTexImage2D(GL_TEXTURE_CUBE_MAP_POSITIVE_X + i) takes them, row t = 0
 * first), 4 bytes a texel in `format` (RGBA8 or BGRA8; ARGB32 is BGRA8 on little-endian
 * machines), face i at faces + i * size * size * 4. capacity_bytes >= 6 * size * size * 4.
 * The texels are rewritten only when a texel could have moved by half an 8-bit step since they
 * were made (the sun, the eye's altitude, the exposure), or the atmosphere, tone curve, format or
 * size changed (aerial::SkyCubemapCache with its default options; a recompute may be spread over
 * a few calls); *changed (may be NULL) is 1 when the texels differ from the previous call's
 * (upload them then), else 0 (the same texels). Texels below the horizon repeat the horizon. */
aerial_status aerial_sky_cubemap(aerial_sky* sky, int size, aerial_colour_format format,
                                 const aerial_display* display, unsigned char* faces,
                                 size_t capacity_bytes, int* changed);

typedef struct aerial_sun_sprite_options {
    int size;               /* texels a side, >= 8; default (0) 64 */
    double half_width_rad;  /* angular half-width of the square, (0, 0.8); default 0.087 */
    double sun_radius_rad;  /* angular radius of the disc; default 0.00465 (0.267 deg) */
    double halo_g;          /* Henyey-Greenstein g of the halo, [0.9, 1); default 0.95 */
    int disc_supersampling; /* per axis, >= 1; default 4 */
} aerial_sun_sprite_options;

/* Where and how to draw the sprite. */
typedef struct aerial_sun_sprite_info {
    int size;               /* texels a side of the image written */
    double half_width_rad;  /* the square spans this angle either side of `direction` */
    double direction[3];    /* unit world direction towards the sun: the square's centre */
    float transmittance[3]; /* the sun's colour at the eye: E_sun(eye) / E_sun0, in [0, 1] */
} aerial_sun_sprite_info;

/* The sun sprite (disc and the narrow Mie halo no per-vertex dome carries, aerial::
 * make_sun_sprite), size x size texels of `format`, row 0 at the sprite's -v edge; draw it
 * additively (glBlendFunc(GL_ONE, GL_ONE)) as a square facing the eye, centred on
 * info->direction, spanning half_width_rad either side, depth test off, after the sky.
 * rgba may be NULL (capacity 0) to ask only for the info. */
aerial_status aerial_sky_sun_sprite(const aerial_sky* sky, const aerial_sun_sprite_options* options,
                                    const aerial_display* display, aerial_colour_format format,
                                    unsigned char* rgba, size_t capacity_bytes,
                                    aerial_sun_sprite_info* info);

/* ---- Night: the moon and the stars (aerial/night.hpp, docs/night.md) --------------------- */

/* A moment in UTC (aerial::UtcDateTime): Gregorian 1901 .. 2099. */
typedef struct aerial_utc_time {
    int year;
    int month; /* 1 .. 12 */
    int day;   /* 1 .. days in the month */
    int hour;  /* 0 .. 23 */
    int minute;
    double second;
} aerial_utc_time;

/* aerial::MoonPosition, and what an engine needs to light and draw with it. */
typedef struct aerial_moon {
    double elevation_rad;        /* topocentric, geometric (no refraction) */
    double azimuth_rad;          /* clockwise from north, [0, 2 pi) */
    double direction_enu[3];     /* unit, towards it: east, north, up */
    double distance_km;          /* earth's centre to the moon's */
    double phase_angle_rad;      /* sun - moon - earth: 0 full moon, pi new moon */
    double illuminated_fraction; /* of the disc, 0 .. 1 */
    /* its illuminance over the sun's (Krisciunas & Schaefer 1991): the moon's light through the
     * models is a context whose atmosphere's sun_irradiance is scaled by this and whose view's
     * sun_dir is the moon's direction (mapped to the engine's axes); L_in adds up */
    double light_fraction;
} aerial_moon;

/* The moon for a time and place (latitude in [-pi/2, pi/2], longitude in [-pi, pi], east
 * positive, radians; libnova). */
aerial_status aerial_moon_position(const aerial_utc_time* time, double latitude_rad,
                                   double longitude_rad, aerial_moon* moon);

/* Where the lit limb of the moon's disc faces, radians counterclockwise from the top as the
 * observer sees it (aerial::moon_bright_limb_angle_rad); the three directions in one frame. */
aerial_status aerial_moon_bright_limb_angle(const double moon_dir[3], const double sun_dir[3],
                                            const double up[3], double* angle_rad);

/* The moon's disc with its phase (aerial::make_moon_sprite): size x size RGBA8 texels, top row
 * first, into rgba (capacity >= size * size * 4 bytes); the lit side towards the bright limb
 * angle, shaded by Lommel-Seeliger's law, white at the brightest texel; modulate and draw it
 * facing the eye with its top along the sky's up. size 8 .. 1024. */
aerial_status aerial_moon_sprite(double phase_angle_rad, double bright_limb_angle_rad, int size,
                                 unsigned char* rgba, size_t capacity);

/* The exposure into the night (aerial::night_exposure): `card_irradiance` is the light on a
 * level grey card in units of the context's E_sun0 (each light's direct light times the sine of
 * its elevation, plus the skylight), `sky_irradiance` the skylight part of it (NULL: the card
 * alone). The options' key and albedo at and above 5 cd/m2 on the card (auto_exposure's rule,
 * no gain limit); below, the card shown darker as (L / 5 cd/m2)^0.25, and where the sky lights
 * the card (twilight) the sky's mean radiance held at 0.1. *exposure is 0 where the card gets
 * no light. options NULL means defaults. */
aerial_status aerial_night_exposure(const aerial_context* context, const double card_irradiance[3],
                                    const double sky_irradiance[3],
                                    const aerial_exposure_options* options, float* exposure);

/* A star catalogue (aerial::read_star_catalogue). */
typedef struct aerial_stars aerial_stars;

/* path NULL: the Yale Bright Star Catalogue of Debian's xplanet (/usr/share/xplanet/stars/BSC).
 * A bad line is AERIAL_ERROR_INVALID_ARGUMENT naming the file and line. */
aerial_status aerial_stars_load(const char* path, aerial_stars** out);
void aerial_stars_destroy(aerial_stars* stars); /* NULL is fine */
const char* aerial_stars_last_error(const aerial_stars* stars);
size_t aerial_stars_count(const aerial_stars* stars);

/* Who looks, when, where the lights are. */
typedef struct aerial_star_query {
    aerial_utc_time time;
    double latitude_rad;
    double longitude_rad;
    double altitude_m;       /* the observer above sea level, >= 0 */
    double sun_enu[3];       /* unit, towards the sun: east, north, up */
    const aerial_moon* moon; /* NULL: no moon in the sky */
    /* airglow, zodiacal light and unresolved stars, cd/m2; default (0) 1.7e-4 (a dark site) */
    double natural_background_cd_m2;
} aerial_star_query;

/* A star the naked eye sees: draw a point towards direction_enu, brighter the larger
 * limiting_magnitude - apparent_magnitude (> 0). */
typedef struct aerial_visible_star {
    float direction_enu[3];
    float apparent_magnitude; /* dimmed by the atmosphere along its direction */
    float limiting_magnitude; /* the eye's limit against the sky in its direction */
} aerial_visible_star;

/* The stars above the horizon brighter than the limit in their direction (aerial::visible_stars:
 * the context's atmosphere, the model's own sky luminance with the sun and the moon, Schaefer's
 * threshold). Writes at most `capacity` into `out` and the number visible into *count; when that
 * exceeds capacity it returns AERIAL_ERROR_BUFFER_TOO_SMALL (out may be NULL with capacity 0 to
 * ask for the count). */
aerial_status aerial_visible_stars(aerial_stars* stars, const aerial_context* context,
                                   const aerial_star_query* query, aerial_visible_star* out,
                                   size_t capacity, size_t* count);

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
    /* two-pass: non-zero culls back faces (GL_FRONT_FACE as the engine set it) in the L_in pass,
     * so that the back faces of a closed mesh drawn without culling do not add L_in a second
     * time at its silhouette; default 0: the engine's culling as it is (a mirroring transform
     * flips the winding, and a sky dome is seen from inside: only the engine knows) */
    int cull_back_faces;
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
 * every piece of GL state it changed. path_used may be NULL. The callback must point only its
 * positions and texture coordinates and draw: when it re-points the colour or secondary-colour
 * array (as an engine's own draw call does when its vertices carry a colour), the result is
 * AERIAL_ERROR_ENGINE_STATE naming the array, instead of a silently wrong image; such engines
 * use aerial_gl_draw_two_pass with colours NULL. */
aerial_status aerial_gl_draw_colours(aerial_gl* gl, const aerial_draw_options* options,
                                     const aerial_vertex_colours* colours,
                                     aerial_draw_function draw, void* user, aerial_path* path_used);

/* ---- OpenGL: engines with one vertex colour ----------------------------------------------- */

/* The pass a two-pass callback draws. */
typedef enum aerial_pass {
    AERIAL_PASS_EXTINCTION = 0,   /* the mesh with its texture x F_ex, the engine's own state */
    AERIAL_PASS_IN_SCATTERING = 1 /* L_in added: blend ONE, ONE, depth EQUAL, no texture */
} aerial_pass;

/* The engine's draw call for one pass: with aerial's colours (aerial_gl_draw_two_pass with
 * colours set) it points only positions and texture coordinates and draws; with colours NULL
 * it draws its mesh with its one vertex colour holding F_ex in pass 0 and L_in in pass 1 (two
 * colour buffers, or one rewritten between the passes). */
typedef void (*aerial_draw_pass_function)(void* user, aerial_pass pass);

/* Draws an opaque mesh in two passes around the engine's own draw call: pass 0 as the engine
 * set it up (its texture, depth test, blend and fog state, the primary colour F_ex), pass 1
 * adds L_in: blend ONE, ONE; depth function EQUAL, depth and alpha writes off; texturing,
 * lighting and alpha test off; fog colour black (fog fades L_in instead of adding its colour
 * twice); with options->cull_back_faces, back faces culled so that a silhouette's back faces
 * do not add L_in a second time (else the engine's culling). Every piece of state is restored
 * afterwards. colours: aerial points the colour array at colours->primary for pass 0 and
 * colours->secondary for pass 1 (NULL: the engine's own colour array). After each pass it checks
 * that the callback left the state it set (colour array, blend, depth function and mask):
 * AERIAL_ERROR_ENGINE_STATE names what the engine's draw changed. */
aerial_status aerial_gl_draw_two_pass(aerial_gl* gl, const aerial_draw_options* options,
                                      const aerial_vertex_colours* colours,
                                      aerial_draw_pass_function draw, void* user);

/* ---- OpenGL: the ARB vertex program ------------------------------------------------------- */

typedef enum aerial_parameter_space {
    AERIAL_PARAMETERS_LOCAL = 0, /* program.local[i] of the program object */
    AERIAL_PARAMETERS_ENV = 1    /* program.env[i], shared by the context's vertex programs */
} aerial_parameter_space;

/* ARB_vertex_program resource limits (aerial::ArbLimits); 0 in a field: the spec minimum. */
typedef struct aerial_arb_limits {
    int max_instructions; /* MAX_PROGRAM_(NATIVE_)INSTRUCTIONS_ARB; spec minimum 128 */
    int max_temporaries;  /* spec minimum 12 */
    int max_parameters;   /* spec minimum 96 */
    int max_attributes;   /* spec minimum 16 */
} aerial_arb_limits;

/* The driver's native limits (MAX_PROGRAM_NATIVE_*_ARB of GL_VERTEX_PROGRAM_ARB), for
 * aerial_arb_options.limits. Only queries: creates no program object and changes no state.
 * AERIAL_ERROR_GL_UNSUPPORTED without GL_ARB_vertex_program. */
aerial_status aerial_gl_arb_limits(aerial_gl* gl, aerial_arb_limits* out);

typedef enum aerial_height_fidelity {
    AERIAL_HEIGHT_FIDELITY_AUTOMATIC = 0, /* the highest level that fits the limits */
    AERIAL_HEIGHT_FIDELITY_SPEC_MINIMUM = 1,
    AERIAL_HEIGHT_FIDELITY_EXACT_OPTICAL_DEPTH = 2,
    AERIAL_HEIGHT_FIDELITY_FULL = 3, /* the CPU model's single scattering; 245 instructions */
    AERIAL_HEIGHT_FIDELITY_MULTIPLE_SCATTERING = 4 /* all of the CPU model; 424 instructions */
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
     * rather than `limits` (default 0). */
    int use_native_limits;
    /* The limits the program must fit and AUTOMATIC resolves against: a driver's native limits
     * from aerial_gl_arb_limits, or an engine's own; a field left 0 is the spec minimum. */
    aerial_arb_limits limits;
    /* non-zero: vertex.position is in model space and the program reads the world position as
     * M x vertex.position from three parameter vectors (aerial_arb_model_matrix, index in
     * aerial_arb_info.model_matrix_index), set per draw; default 0: world positions. */
    int model_matrix;
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

/* What the program `options` describe is and reads. */
typedef struct aerial_arb_info {
    aerial_model model;
    aerial_height_fidelity height_fidelity; /* height: the level chosen (never AUTOMATIC) */
    int instructions;                       /* as the spec counts them (section 2.14.3.7) */
    int temporaries;
    int parameter_bindings; /* distinct parameter bindings: state, local/env, constants */
    int attributes;
    int parameter_base;     /* first per-frame vector (program.local or .env) */
    int parameter_count;    /* per-frame vectors, from parameter_base (aerial_arb_parameters) */
    int model_matrix_index; /* first of the 3 model-matrix vectors; -1 without model_matrix */
} aerial_arb_info;

/* The program without GL: the chosen level, its resources and where its parameters go. Fails
 * as aerial_arb_generate does (AERIAL_ERROR_ARB_PROGRAM naming the exceeded limit). */
aerial_status aerial_arb_describe(const aerial_arb_options* options, aerial_arb_info* out);

/* One parameter vector of the layout. */
typedef struct aerial_arb_parameter {
    int index;           /* absolute program.local / program.env index */
    const char* name;    /* "eye", "sun", ... (static storage) */
    const char* meaning; /* one line: what x, y, z, w hold (static storage) */
} aerial_arb_parameter;

/* The parameter layout (per-frame vectors, then the model matrix's rows), `count` entries
 * (AERIAL_ERROR_BUFFER_TOO_SMALL when capacity is smaller; out may be NULL with capacity 0). */
aerial_status aerial_arb_parameter_layout(const aerial_arb_options* options,
                                          aerial_arb_parameter* out, size_t capacity,
                                          size_t* count);

/* The three model-matrix vectors (12 floats, the matrix's top three rows) of a column-major
 * affine matrix, for index aerial_arb_info.model_matrix_index; per draw. */
aerial_status aerial_arb_model_matrix(const aerial_arb_options* options, const float model[16],
                                      float vectors[12]);

/* The state an engine that binds the program itself (a material system, Irrlicht's
 * addShaderMaterial) must set around its draw, set and later restored by aerial: GL_COLOR_SUM
 * on (the program writes L_in to the secondary colour, which GL adds only with COLOR_SUM: without
 * it the sky renders black), GL_TEXTURE_ENV_MODE MODULATE on options->texture_unit (texturing
 * off there with options->untextured). The engine binds and enables its program. Saves what it
 * changes; aerial_gl_restore_program_state puts it back. Not nested: a second set before the
 * restore is AERIAL_ERROR_INVALID_ARGUMENT. */
aerial_status aerial_gl_set_program_state(aerial_gl* gl, const aerial_draw_options* options);
aerial_status aerial_gl_restore_program_state(aerial_gl* gl);

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
