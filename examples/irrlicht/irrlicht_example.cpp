// aerial-irrlicht-example: one frame of a 16 km heightfield under an aerial sky, drawn by
// Irrlicht 1.8 (video::EDT_OPENGL, GLX) in its own Y-up left-handed world, with aerial used only
// through its C header. Two ways an engine of that kind adopts it:
//   --path arb  the material system: aerial's ARB vertex program as an Irrlicht shader material
//               (addShaderMaterial), its parameters set from IShaderConstantSetCallBack,
//               GL_COLOR_SUM and MODULATE set around the draw by aerial_gl_set_program_state;
//   --path cpu  one vertex colour: aerial_shade writes F_ex straight into S3DVertex::Color
//               (ARGB32), L_in into the Color of a second mesh buffer with the same positions, and
//               aerial_gl_draw_two_pass draws the two around Irrlicht's drawMeshBuffer.
// The sky is Irrlicht's own dome mesh coloured by aerial_sky_shade_dome. The frame is read back
// before the swap and written with Irrlicht's PNG writer. The scene is irrlicht_scene.h.
#include <GL/gl.h>
#include <GL/glx.h>
#include <irrlicht.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include "irrlicht_scene.h"

using namespace irr;

namespace {

constexpr const char* kTool = "aerial-irrlicht-example";
constexpr const char* kUsage =
    "usage: aerial-irrlicht-example --out FILE.png [--path arb|cpu]\n"
    "         [--fidelity spec-minimum|exact-optical-depth|full|multiple-scattering]\n"
    "         [--width N] [--height N]\n"
    "         [--buffers client|vbo] [--l-in-material engine|none]\n"
    "--buffers vbo: the terrain in Irrlicht's hardware buffers (EHM_STATIC), re-uploaded once\n"
    "after aerial_shade; client (default): Irrlicht's client arrays (EHM_NEVER).\n"
    "--l-in-material engine (cpu): the L_in pass applies an additive Irrlicht material of its\n"
    "own, as an engine that does not leave the pass's state to aerial would: the frame fails\n"
    "with aerial's AERIAL_ERROR_ENGINE_STATE naming the blend state.\n";

struct Options {
    std::string out;
    bool arb = true;
    aerial_height_fidelity fidelity = AERIAL_HEIGHT_FIDELITY_MULTIPLE_SCATTERING;
    int width = 320, height = 240;
    bool vbo = false;
    bool engine_l_in_material = false;  ///< the misuse --l-in-material engine demonstrates
};

/// One line on stderr, `aerial-irrlicht-example: MESSAGE`; returns `code`.
int fail(const std::string& message, int code = 1) {
    std::fprintf(stderr, "%s: %s\n", kTool, message.c_str());
    return code;
}

/// The message of a failed aerial call, in the library's one style.
std::string aerial_error() { return aerial_last_error_message(); }

/// Parses one flag's value; false with `error` set on a bad value.
bool parse_flag(const std::string& flag, const std::string& value, Options& o, std::string& error) {
    if (flag == "--out") {
        o.out = value;
    } else if (flag == "--path") {
        if (value != "arb" && value != "cpu") {
            error = "main(): --path: expected one of arb, cpu, got '" + value + "'";
            return false;
        }
        o.arb = value == "arb";
    } else if (flag == "--fidelity") {
        const char* names[] = {"spec-minimum", "exact-optical-depth", "full",
                               "multiple-scattering"};
        const aerial_height_fidelity levels[] = {
            AERIAL_HEIGHT_FIDELITY_SPEC_MINIMUM, AERIAL_HEIGHT_FIDELITY_EXACT_OPTICAL_DEPTH,
            AERIAL_HEIGHT_FIDELITY_FULL, AERIAL_HEIGHT_FIDELITY_MULTIPLE_SCATTERING};
        for (int i = 0; i < 4; ++i) {
            if (value == names[i]) {
                o.fidelity = levels[i];
                return true;
            }
        }
        error =
            "main(): --fidelity: expected one of spec-minimum, exact-optical-depth, full, "
            "multiple-scattering, got '" +
            value + "'";
        return false;
    } else if (flag == "--buffers") {
        if (value != "client" && value != "vbo") {
            error = "main(): --buffers: expected one of client, vbo, got '" + value + "'";
            return false;
        }
        o.vbo = value == "vbo";
    } else if (flag == "--l-in-material") {
        if (value != "engine" && value != "none") {
            error = "main(): --l-in-material: expected one of engine, none, got '" + value + "'";
            return false;
        }
        o.engine_l_in_material = value == "engine";
    } else if (flag == "--width" || flag == "--height") {
        char* end = nullptr;
        const long n = std::strtol(value.c_str(), &end, 10);
        if (value.empty() || *end != '\0' || n < 16 || n > 4096) {
            error = "main(): " + flag + ": expected an integer in 16..4096, got '" + value + "'";
            return false;
        }
        (flag == "--width" ? o.width : o.height) = int(n);
    } else {
        error = "main(): " + flag +
                ": expected one of --out, --path, --fidelity, --width, --height, --buffers, "
                "--l-in-material, got an unknown option";
        return false;
    }
    return true;
}

bool parse_options(int argc, char** argv, Options& o, std::string& error) {
    for (int i = 1; i < argc; ++i) {
        const std::string flag = argv[i];
        if (i + 1 >= argc) {
            error = "main(): " + flag + ": expected a value after it, got none";
            return false;
        }
        if (!parse_flag(flag, argv[++i], o, error)) return false;
    }
    if (o.out.empty()) error = "main(): --out: expected a PNG path, got none";
    return error.empty();
}

core::vector3df irr_point(const double twin[3]) {
    double w[3];
    scene_swap_yz(twin, w);
    return core::vector3df(f32(w[0]), f32(w[1]), f32(w[2]));
}

/// The terrain in Irrlicht's world (x, height, y of the twin); Color white until shaded.
scene::SMeshBuffer* make_terrain(bool vbo) {
    auto* mb = new scene::SMeshBuffer;
    mb->Vertices.reallocate(SCENE_GRID_N * SCENE_GRID_N);
    for (int j = 0; j < SCENE_GRID_N; ++j) {
        for (int i = 0; i < SCENE_GRID_N; ++i) {
            double p[3];
            scene_grid_point(i, j, p);
            const f32 s = f32(p[0] / SCENE_TEXTURE_REPEAT_M),
                      t = f32(p[1] / SCENE_TEXTURE_REPEAT_M);
            mb->Vertices.push_back(video::S3DVertex(irr_point(p), core::vector3df(0, 1, 0),
                                                    video::SColor(255, 255, 255, 255),
                                                    core::vector2df(s, t)));
        }
    }
    for (int j = 0; j + 1 < SCENE_GRID_N; ++j) {
        for (int i = 0; i + 1 < SCENE_GRID_N; ++i) {
            unsigned int cell[6];
            scene_cell_indices(i, j, cell);
            for (unsigned int k : cell) mb->Indices.push_back(u16(k));
        }
    }
    mb->recalculateBoundingBox();
    // vbo: uploaded at the first draw after setDirty (shade_terrain); else client arrays.
    mb->setHardwareMappingHint(vbo ? scene::EHM_STATIC : scene::EHM_NEVER);
    return mb;
}

/// aerial::scene's sky dome directions (the twin's frame, see irrlicht_scene.h), mirrored into
/// Irrlicht's world, at the dome radius around the eye; triangles as make_sky_dome_mesh's.
struct Dome {
    std::vector<video::S3DVertex> vertices;
    std::vector<u16> indices;
};

void dome_directions(std::vector<core::vector3df>& out) {
    const double skirt = SCENE_DOME_SKIRT_DEG * SCENE_PI / 180.0;
    for (int r = 0; r < SCENE_DOME_RINGS; ++r) {
        const double e = (SCENE_PI / 2) * r / SCENE_DOME_RINGS;
        for (int s = 0; s < SCENE_DOME_SEGMENTS; ++s) {
            const double a = 2 * SCENE_PI * s / SCENE_DOME_SEGMENTS;
            const double d[3] = {std::cos(e) * std::cos(a), std::cos(e) * std::sin(a), std::sin(e)};
            out.push_back(irr_point(d));
        }
    }
    const double zenith[3] = {0.0, 0.0, 1.0};
    out.push_back(irr_point(zenith));
    for (int s = 0; s < SCENE_DOME_SEGMENTS; ++s) {
        const double a = 2 * SCENE_PI * s / SCENE_DOME_SEGMENTS;
        const double d[3] = {std::cos(skirt) * std::cos(a), std::cos(skirt) * std::sin(a),
                             std::sin(skirt)};
        out.push_back(irr_point(d));
    }
}

void dome_triangles(std::vector<u16>& idx) {
    const int n = SCENE_DOME_SEGMENTS;
    const auto at = [n](int r, int s) { return u16(r * n + s % n); };
    for (int r = 0; r + 1 < SCENE_DOME_RINGS; ++r) {
        for (int s = 0; s < n; ++s) {
            idx.insert(idx.end(), {at(r, s), at(r + 1, s + 1), at(r, s + 1)});
            idx.insert(idx.end(), {at(r, s), at(r + 1, s), at(r + 1, s + 1)});
        }
    }
    const u16 zenith = u16(SCENE_DOME_RINGS * n), skirt = u16(zenith + 1);
    for (int s = 0; s < n; ++s) {
        idx.insert(idx.end(),
                   {at(SCENE_DOME_RINGS - 1, s), zenith, at(SCENE_DOME_RINGS - 1, s + 1)});
    }
    for (int s = 0; s < n; ++s) {
        const u16 below = u16(skirt + s), below1 = u16(skirt + (s + 1) % n);
        idx.insert(idx.end(), {below, at(0, s + 1), below1});
        idx.insert(idx.end(), {below, at(0, s), at(0, s + 1)});
    }
}

Dome make_dome(const core::vector3df& eye) {
    std::vector<core::vector3df> directions;
    dome_directions(directions);
    Dome d;
    const f32 radius = f32(SCENE_DOME_RADIUS_OF_FAR * SCENE_FAR_M);
    for (const auto& dir : directions) {
        d.vertices.push_back(video::S3DVertex(eye + dir * radius, -dir, video::SColor(255, 0, 0, 0),
                                              core::vector2df(0, 0)));
    }
    dome_triangles(d.indices);
    return d;
}

/// aerial's state for the frame: the context (earth, height model) with the view, the sky,
/// the exposure, and the GL object of Irrlicht's context.
struct Air {
    aerial_context* ctx = nullptr;
    aerial_sky* sky = nullptr;
    aerial_gl* gl = nullptr;
    aerial_display display{};
    /// With the context still current (aerial_gl may own GL objects).
    void release() {
        aerial_gl_destroy(gl);
        aerial_sky_destroy(sky);
        aerial_context_destroy(ctx);
        gl = nullptr;
        sky = nullptr;
        ctx = nullptr;
    }
};

void* load_gl(void*, const char* name) {
    return reinterpret_cast<void*>(glXGetProcAddressARB(reinterpret_cast<const GLubyte*>(name)));
}

/// Once, with Irrlicht's context current: the context (earth preset, height model), the sky
/// (the height model's dome method) and the GL object.
bool make_air(Air& air, std::string& error) {
    if (AERIAL_CHECK_VERSION() != AERIAL_OK ||
        aerial_context_create(nullptr, AERIAL_MODEL_HEIGHT, &air.ctx) != AERIAL_OK ||
        aerial_sky_create(nullptr, &air.sky) != AERIAL_OK ||
        aerial_gl_create(load_gl, nullptr, &air.gl) != AERIAL_OK) {
        error = aerial_error();
        return false;
    }
    return true;
}

/// Per frame: the view, the exposure (the sun or the air may have moved) and the sky's frame.
bool set_view(Air& air, std::string& error) {
    aerial_view view;
    scene_aerial_view(&view);
    if (aerial_context_set_view(air.ctx, &view) != AERIAL_OK ||
        aerial_auto_exposure(air.ctx, nullptr, &air.display.exposure) != AERIAL_OK ||
        aerial_sky_set_frame(air.sky, air.ctx) != AERIAL_OK) {
        error = aerial_error();
        return false;
    }
    return true;
}

bool shade_dome(const Air& air, Dome& dome, std::string& error) {
    aerial_positions positions{};
    positions.x = &dome.vertices[0].Pos.X;
    positions.count = dome.vertices.size();
    positions.stride_bytes = sizeof(video::S3DVertex);
    aerial_sky_colours out{};
    out.rgba8 = reinterpret_cast<unsigned char*>(&dome.vertices[0].Color);
    out.rgba8_stride = sizeof(video::S3DVertex);
    out.format = AERIAL_COLOUR_ARGB32;
    if (aerial_sky_shade_dome(air.sky, &positions, nullptr, &air.display, &out) != AERIAL_OK) {
        error = aerial_error();
        return false;
    }
    return true;
}

/// The ARB program's parameters, uploaded by Irrlicht when it binds the shader material.
/// COpenGLDriver::setVertexShaderConstant(data, start, count) calls
/// glProgramLocalParameter4fvARB(GL_VERTEX_PROGRAM_ARB, start + i, ...): program.local, so the
/// program is generated with AERIAL_PARAMETERS_LOCAL.
class ArbConstants : public video::IShaderConstantSetCallBack {
  public:
    aerial_arb_options options{};  ///< the program's, for aerial_arb_parameters
    std::vector<float> vectors;
    int base = 0;
    void OnSetConstants(video::IMaterialRendererServices* services, s32) override {
        services->setVertexShaderConstant(vectors.data(), base, s32(vectors.size() / 4));
    }
};

/// Prints the program's level, resources and parameter layout.
void describe(const aerial_arb_info& info, const aerial_arb_options& options) {
    const char* levels[] = {"automatic", "spec-minimum", "exact-optical-depth", "full",
                            "multiple-scattering"};
    std::printf(
        "%s: ARB program: height model, fidelity %s, %d instructions, %d temporaries, "
        "%d parameter vectors from program.local[%d]\n",
        kTool, levels[info.height_fidelity], info.instructions, info.temporaries,
        info.parameter_count, info.parameter_base);
    size_t n = 0;
    (void)aerial_arb_parameter_layout(&options, nullptr, 0, &n);  // the count
    std::vector<aerial_arb_parameter> layout(n);
    if (aerial_arb_parameter_layout(&options, layout.data(), n, &n) != AERIAL_OK) return;
    for (size_t i = 0; i < n; ++i) {
        std::printf("  program.local[%d] %s: %s\n", layout[i].index, layout[i].name,
                    layout[i].meaning);
    }
}

/// Generates the program for the driver's native limits and the fidelity asked for and hands
/// it to Irrlicht as a shader material; the material type (-1 with `error` set).
s32 make_arb_material(video::IVideoDriver* driver, const Air& air, aerial_height_fidelity level,
                      ArbConstants& constants, std::string& error) {
    aerial_arb_options& options = constants.options;
    options.model = AERIAL_MODEL_HEIGHT;
    options.parameter_space = AERIAL_PARAMETERS_LOCAL;  // Irrlicht's setVertexShaderConstant
    options.height_fidelity = level;
    aerial_arb_info info{};
    size_t length = 0;
    if (aerial_gl_arb_limits(air.gl, &options.limits) != AERIAL_OK ||
        aerial_arb_describe(&options, &info) != AERIAL_OK) {
        error = aerial_error();
        return -1;
    }
    const aerial_status size = aerial_arb_generate(&options, nullptr, 0, &length, nullptr);
    if (size != AERIAL_OK && size != AERIAL_ERROR_BUFFER_TOO_SMALL) {
        error = aerial_error();
        return -1;
    }
    std::vector<char> text(length + 1);
    constants.vectors.resize(4 * std::size_t(info.parameter_count));
    constants.base = info.parameter_base;
    if (aerial_arb_generate(&options, text.data(), text.size(), nullptr, nullptr) != AERIAL_OK) {
        error = aerial_error();
        return -1;
    }
    describe(info, options);
    const s32 type = driver->getGPUProgrammingServices()->addShaderMaterial(
        text.data(), nullptr, &constants, video::EMT_SOLID, 0);
    if (type < 0) {
        error =
            "make_arb_material(): addShaderMaterial: expected a material type, got -1 (Irrlicht "
            "rejected the ARB program; its log says why)";
    }
    return type;
}

}  // namespace

namespace {

/// What a frame draws with.
struct Frame {
    IrrlichtDevice* device = nullptr;
    video::IVideoDriver* driver = nullptr;
    Air air;
    Dome dome;
    scene::SMeshBuffer* fex = nullptr;  ///< the terrain; its Color: F_ex (cpu), unused (arb)
    scene::SMeshBuffer* lin = nullptr;  ///< cpu: the same positions, Color: L_in
    video::SMaterial terrain, sky;
    ArbConstants constants;
    bool engine_l_in_material = false;
};

video::ITexture* make_texture(video::IVideoDriver* driver) {
    video::IImage* image = driver->createImage(
        video::ECF_A8R8G8B8, core::dimension2d<u32>(SCENE_TEXTURE_SIDE, SCENE_TEXTURE_SIDE));
    image->fill(video::SColor(255, SCENE_ALBEDO_R, SCENE_ALBEDO_G, SCENE_ALBEDO_B));
    video::ITexture* texture = driver->addTexture("albedo", image);
    image->drop();
    return texture;
}

/// The materials: the sky unlit, untextured, no depth test or writes, both sides (seen from
/// inside); the terrain unlit with the albedo texture, Irrlicht's own back-face culling.
void make_materials(Frame& f) {
    f.sky.Lighting = false;
    f.sky.ZWriteEnable = false;
    f.sky.ZBuffer = video::ECFN_NEVER;  // Irrlicht 1.8: "never" disables the depth test
    f.sky.BackfaceCulling = false;
    f.sky.FogEnable = false;
    f.terrain.Lighting = false;
    f.terrain.FogEnable = false;
    f.terrain.ZBuffer = video::ECFN_LESSEQUAL;
    f.terrain.setTexture(0, make_texture(f.driver));
}

void set_camera(video::IVideoDriver* driver, int width, int height) {
    const double eye[3] = {SCENE_EYE_X, SCENE_EYE_Y, SCENE_EYE_Z};
    const double target[3] = {SCENE_TARGET_X, SCENE_TARGET_Y, SCENE_TARGET_Z};
    core::matrix4 view, projection;
    view.buildCameraLookAtMatrixLH(irr_point(eye), irr_point(target), core::vector3df(0, 1, 0));
    projection.buildProjectionMatrixPerspectiveFovLH(f32(SCENE_FOV_Y_RAD), f32(width) / f32(height),
                                                     f32(SCENE_NEAR_M), f32(SCENE_FAR_M));
    driver->setTransform(video::ETS_PROJECTION, projection);
    driver->setTransform(video::ETS_VIEW, view);
    driver->setTransform(video::ETS_WORLD, core::IdentityMatrix);
}

void draw_sky(Frame& f) {
    f.driver->setMaterial(f.sky);
    f.driver->drawVertexPrimitiveList(f.dome.vertices.data(), u32(f.dome.vertices.size()),
                                      f.dome.indices.data(), u32(f.dome.indices.size() / 3),
                                      video::EVT_STANDARD, scene::EPT_TRIANGLES, video::EIT_16BIT);
}

/// The material system: Irrlicht binds the program and calls OnSetConstants; aerial sets
/// GL_COLOR_SUM and MODULATE around the draw and restores them.
bool draw_terrain_arb(Frame& f, std::string& error) {
    f.driver->setMaterial(f.terrain);
    if (aerial_gl_set_program_state(f.air.gl, nullptr) != AERIAL_OK) {
        error = aerial_error();
        return false;
    }
    f.driver->drawMeshBuffer(f.fex);
    if (aerial_gl_restore_program_state(f.air.gl) != AERIAL_OK) {
        error = aerial_error();
        return false;
    }
    return true;
}

/// F_ex into the terrain's own Color fields, L_in into the twin buffer's: no copy, no swizzle.
bool shade_terrain(Frame& f, std::string& error) {
    aerial_positions positions{};
    positions.x = &f.fex->Vertices[0].Pos.X;
    positions.count = f.fex->Vertices.size();
    positions.stride_bytes = sizeof(video::S3DVertex);
    aerial_outputs out{};
    out.colour_format = AERIAL_COLOUR_ARGB32;
    out.extinction_rgba8 = reinterpret_cast<unsigned char*>(&f.fex->Vertices[0].Color);
    out.extinction_rgba8_stride = sizeof(video::S3DVertex);
    out.in_scattering_rgba8 = reinterpret_cast<unsigned char*>(&f.lin->Vertices[0].Color);
    out.in_scattering_rgba8_stride = sizeof(video::S3DVertex);
    aerial_batch_settings settings{};
    settings.display = f.air.display;
    if (aerial_shade(f.air.ctx, &positions, &out, &settings, nullptr) != AERIAL_OK) {
        error = aerial_error();
        return false;
    }
    f.fex->setDirty(scene::EBT_VERTEX);
    f.lin->setDirty(scene::EBT_VERTEX);
    return true;
}

/// Pass 0 draws the F_ex buffer, pass 1 the L_in buffer: the engine's own draw call each time.
void draw_pass(void* user, aerial_pass pass) {
    Frame& f = *static_cast<Frame*>(user);
    if (pass == AERIAL_PASS_IN_SCATTERING && f.engine_l_in_material) {
        video::SMaterial additive = f.terrain;  // what aerial's pass state already does, badly
        additive.MaterialType = video::EMT_TRANSPARENT_ADD_COLOR;
        f.driver->setMaterial(additive);
    }
    f.driver->drawMeshBuffer(pass == AERIAL_PASS_EXTINCTION ? f.fex : f.lin);
}

bool draw_terrain_cpu(Frame& f, std::string& error) {
    f.driver->setMaterial(f.terrain);
    aerial_draw_options options{};
    options.cull_back_faces = 1;  // the L_in pass culls as Irrlicht's material does
    if (aerial_gl_draw_two_pass(f.air.gl, &options, nullptr, draw_pass, &f) != AERIAL_OK) {
        error = aerial_error();
        return false;
    }
    return true;
}

/// The back buffer, bottom row last, as an Irrlicht image written by its PNG writer.
bool write_frame(Frame& f, const Options& o, std::string& error) {
    std::vector<unsigned char> rgb(std::size_t(o.width) * std::size_t(o.height) * 3);
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glReadBuffer(GL_BACK);
    glReadPixels(0, 0, o.width, o.height, GL_RGB, GL_UNSIGNED_BYTE, rgb.data());
    video::IImage* image = f.driver->createImage(
        video::ECF_R8G8B8, core::dimension2d<u32>(u32(o.width), u32(o.height)));
    auto* dst = static_cast<unsigned char*>(image->lock());
    const std::size_t row = std::size_t(o.width) * 3;
    for (int y = 0; y < o.height; ++y) {
        std::memcpy(dst + row * std::size_t(o.height - 1 - y), rgb.data() + row * std::size_t(y),
                    row);
    }
    image->unlock();
    const bool written = f.driver->writeImageToFile(image, o.out.c_str());
    image->drop();
    if (!written) error = "write_frame(): --out: expected a writable PNG path, got '" + o.out + "'";
    return written;
}

IrrlichtDevice* make_device(const Options& o) {
    SIrrlichtCreationParameters p;
    p.DriverType = video::EDT_OPENGL;
    p.WindowSize = core::dimension2d<u32>(u32(o.width), u32(o.height));
    p.Bits = 24;
    p.ZBufferBits = 24;
    p.Doublebuffer = true;
    p.Vsync = false;
    p.LoggingLevel = ELL_ERROR;
    return createDeviceEx(p);
}

/// Once: aerial's objects, the meshes, the materials (arb: the shader material).
bool setup(Frame& f, const Options& o, std::string& error) {
    if (!make_air(f.air, error)) return false;
    const double eye_twin[3] = {SCENE_EYE_X, SCENE_EYE_Y, SCENE_EYE_Z};
    f.dome = make_dome(irr_point(eye_twin));
    make_materials(f);
    f.fex = make_terrain(o.vbo);
    if (o.arb) {
        const s32 type = make_arb_material(f.driver, f.air, o.fidelity, f.constants, error);
        f.terrain.MaterialType = video::E_MATERIAL_TYPE(type);
        return type >= 0;
    }
    f.lin = make_terrain(o.vbo);
    f.engine_l_in_material = o.engine_l_in_material;
    return true;
}

/// Per frame, before drawing: the view, exposure and sky, the dome's colours, and the
/// terrain's (cpu: aerial_shade into the vertices; arb: the parameters OnSetConstants uploads).
bool update_frame(Frame& f, const Options& o, std::string& error) {
    if (!set_view(f.air, error) || !shade_dome(f.air, f.dome, error)) return false;
    if (!o.arb) return shade_terrain(f, error);
    ArbConstants& c = f.constants;
    size_t count = 0;
    if (aerial_arb_parameters(f.air.ctx, &c.options, &f.air.display, c.vectors.data(),
                              c.vectors.size() / 4, &count) != AERIAL_OK) {
        error = aerial_error();
        return false;
    }
    return true;
}

bool render(Frame& f, const Options& o, std::string& error) {
    if (!update_frame(f, o, error)) return false;
    f.driver->beginScene(true, true, video::SColor(255, 0, 0, 0));
    set_camera(f.driver, o.width, o.height);
    draw_sky(f);
    const bool drawn = o.arb ? draw_terrain_arb(f, error) : draw_terrain_cpu(f, error);
    const bool written = drawn && write_frame(f, o, error);
    f.driver->endScene();
    return written;
}

}  // namespace

int main(int argc, char** argv) {
    Options o;
    std::string error;
    if (argc == 2 && std::strcmp(argv[1], "--help") == 0) {
        std::fputs(kUsage, stdout);
        return 0;
    }
    if (!parse_options(argc, argv, o, error)) return fail(error, 2);
    Frame f;
    f.device = make_device(o);
    if (!f.device) {
        return fail("main(): createDeviceEx: expected an OpenGL device (an X display), got none");
    }
    f.driver = f.device->getVideoDriver();
    const bool ok = setup(f, o, error) && render(f, o, error);
    if (ok) {
        std::printf("%s: path=%s %dx%d exposure=%.9g GL_RENDERER=%s -> %s\n", kTool,
                    o.arb ? "arb" : "cpu", o.width, o.height, double(f.air.display.exposure),
                    reinterpret_cast<const char*>(glGetString(GL_RENDERER)), o.out.c_str());
    }
    if (f.fex) f.fex->drop();
    if (f.lin) f.lin->drop();
    f.air.release();
    f.device->drop();
    return ok ? 0 : fail(error);
}
