// aerial/gl.hpp — F_ex and L_in applied by the fixed pipeline of the engine's GL context: the
// fixed-function paths for colours computed on the CPU (aerial/batch.hpp), and the ARB vertex
// program backend (aerial/arb_program.hpp) loaded into GL.
//
// How to use this (CPU colours):
//   1. Once per context: `auto api = aerial::gl::load_api(loader, user);` (aerial/gl_api.hpp).
//   2. Once: `auto path = aerial::gl::choose_path(api->caps, aerial::gl::Path::automatic);` —
//      secondary colour where the context has it, else the combiner path, else two passes.
//      For the combiner path also create `aerial::gl::CombinerTexture::create(*api)` once.
//   3. Per frame and mesh: shade the vertices into RGBA8 arrays with aerial::shade_into, then
//        aerial::gl::draw_with_colours(*api, {*path}, colours, [&] { engine_draw_mesh(); });
//      The engine has its texture bound and its target enabled on ApplyOptions::texture_unit
//      (unit 0 by default) as it would without the module; the callback points the engine's own
//      vertex and texcoord arrays and issues its draw call; two-pass calls it twice. The colour
//      arrays are the module's: the callback must not touch GL_COLOR_ARRAY or
//      GL_SECONDARY_COLOR_ARRAY, nor the unit after texture_unit on the combiner path.
//
// How to use this (ARB vertex program):
//   1. Once: `auto program = aerial::gl::ArbVertexProgram::create(*api, generated);` with the
//      text from aerial::generate_arb_program. A rejected program is an error that gives
//      GL_PROGRAM_ERROR_POSITION_ARB and the driver's error string.
//   2. Per frame: `program->set_parameters(aerial::arb_program_parameters(...).value())`.
//   3. Per mesh: `program->draw([&] { engine_draw_mesh(); });` The program reads world-space
//      positions from vertex.position (w = 1: glVertex3*, 3-component arrays) and transforms
//      them with state.matrix.mvp, so the modelview matrix must map world space to eye space
//      (no per-object model matrix unless the positions are pre-transformed).
//
// Every call saves the GL state it changes with glGet* just before changing it and restores it
// before returning (also when the callback throws). It never uses glPushAttrib or
// glPushClientAttrib: engines use those stacks, which are only 16 deep, and they do not cover
// the program binding. aerial/gl_state.hpp snapshots all of it for regression tests. The module
// never creates or owns a context, and does not read or clear the engine's GL error flag (a
// program the driver rejects leaves glProgramStringARB's GL_INVALID_OPERATION there, as any
// failed GL call would). Saving and restoring costs some twenty glGet calls a draw on the
// secondary-colour path, about fifty on the combiner and two-pass paths.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "aerial/arb_program.hpp"
#include "aerial/error.hpp"

namespace aerial::gl {

struct Api;        // aerial/gl_api.hpp
struct Caps;       // aerial/gl_api.hpp
class StateSaver;  // aerial/gl_state_saver.hpp

/// How the fixed pipeline combines texture, F_ex and L_in: colour = texture × F_ex + L_in.
/// Every path first switches off what would bypass the fixed pipeline (GL_VERTEX_PROGRAM_ARB,
/// GL_FRAGMENT_PROGRAM_ARB, the GLSL program) and GL lighting (unless
/// ApplyOptions::fixed_function_lighting), sets GL_MODULATE on texture_unit (or disables its
/// texture targets when untextured), and points GL_COLOR_ARRAY at F_ex with array buffer 0 bound.
/// Besides, each path touches:
enum class Path {
    automatic,  ///< the first available of secondary_color, combiner, two_pass
    /// One pass: texture MODULATE primary colour (F_ex), L_in as the secondary colour
    /// (glSecondaryColorPointer, 3 × GL_UNSIGNED_BYTE) with GL_COLOR_SUM on. GL 1.4 or
    /// EXT_secondary_color. Touches GL_SECONDARY_COLOR_ARRAY and GL_COLOR_SUM.
    secondary_color,
    /// One pass without secondary colour (GL 1.3-era engines, and engines with fixed-function
    /// lighting on, which replaces the secondary colour): unit texture_unit MODULATE (texture ×
    /// F_ex); unit texture_unit + 1 COMBINE with RGB = ADD(PREVIOUS, TEXTURE), alpha =
    /// REPLACE(PREVIOUS), its TEXTURE an identity 3D texture sampled at texcoords computed from
    /// L_in (see CombinerTexture), which its linear filter turns back into L_in per pixel.
    /// Needs GL 1.3 or ARB_multitexture + ARB_/EXT_texture_env_combine, and GL 1.2 or
    /// EXT_texture3D. Touches on unit + 1: the texture targets' enables and TEXTURE_GEN_S/T/R, the
    /// 3D binding, the texture matrix (identity while drawing), the whole combine state, the
    /// texcoord array; GL_COLOR_SUM (off) where it exists. Measured within 1 LSB of the other
    /// paths on llvmpipe and softpipe (docs/gl-paths.md).
    combiner,
    /// GL 1.1: pass 1 texture × F_ex with the engine's depth, blend and fog state; pass 2 L_in
    /// as the primary colour with texturing off on every unit, GL lighting off, blending ONE/ONE
    /// (equation FUNC_ADD), depth func EQUAL, depth writes off, alpha writes off (the colour mask
    /// otherwise as the engine had it) and, where fog is on, fog colour black: pass 1 already
    /// blended (1 - f) × the fog colour in, and pass 2 must add only f × L_in. Needs the depth
    /// test on for overlapping geometry, and assumes opaque geometry (pass 2 adds L_in in full
    /// where pass 1 blended). Equal to one pass within 1 LSB (docs/gl-paths.md).
    two_pass,
};

/// "automatic", "secondary-color", "combiner", "two-pass".
const char* path_name(Path path);
std::optional<Path> parse_path(std::string_view name);

/// The path to use for `requested` on a context with `caps`: `automatic` picks the first available;
/// a forced path the context lacks is an error naming the missing version or extension.
///
/// Secondary colour counts as available when the context is GL 1.4 or later (where it is core)
/// OR lists GL_EXT_secondary_color, and glSecondaryColorPointer resolved: hiding the extension
/// from a GL 1.4+ context (MESA_EXTENSION_OVERRIDE=-GL_EXT_secondary_color) does not remove it,
/// because the version says it is there; only a context below 1.4 without the extension lacks
/// it. The combiner path needs GL 1.3 or ARB_multitexture with 2 units,
/// ARB_/EXT_texture_env_combine and GL 1.2 or EXT_texture3D. Two passes need GL 1.1 only.
///
/// With `fixed_function_lighting` (see ApplyOptions) the secondary-colour path is not
/// available (GL lighting replaces the secondary colour), so `automatic` picks the combiner or
/// two passes, and forcing secondary_color is an error naming "fixed_function_lighting".
Result<Path> choose_path(const Caps& caps, Path requested, bool fixed_function_lighting = false);

/// Per-vertex colours in caller memory, one RGBA8 record per vertex of the engine's draw (in
/// the order the engine's arrays have them), e.g. from aerial::shade_into.
struct VertexColours {
    const std::uint8_t* primary = nullptr;    ///< F_ex, or F_ex × lit colour (lit_rgba8)
    const std::uint8_t* secondary = nullptr;  ///< L_in after exposure
    std::size_t primary_stride_bytes = 0;     ///< 0: tightly packed (4)
    std::size_t secondary_stride_bytes = 0;   ///< 0: tightly packed (4)
    std::size_t vertex_count = 0;             ///< records in each array
};

/// The combiner path's GL resources: an RGBA8 identity 3D texture of size³ texels (texel
/// (i, j, k) = (i, j, k) × 255 / (size - 1), GL_LINEAR, CLAMP_TO_EDGE, no mipmaps) and the
/// scratch buffer of float texture coordinates (0.5 + (size - 1) L_in) / size that make its
/// linear filter return L_in. Create one per context and pass it in ApplyOptions::combiner;
/// without it each combiner draw creates and deletes one.
///
/// Why 16 texels a side by default (16 KB) rather than the minimal 2: the filter computes
/// texel_a + w (texel_b - texel_a) with w quantised to 8 bits on llvmpipe (and to 8 bits or fewer
/// on the hardware of the era), which costs up to 1 LSB between two texels 255 apart, and only
/// 17/256 LSB between texels 17 apart. Measured against the secondary-colour path on llvmpipe,
/// both sizes stay within 1 LSB, but against the two-pass path size 2 reaches 2 LSB on a few
/// pixels and size 16 stays within 1 (docs/gl-paths.md, "GL layer"). Sizes are those where
/// 255 / (size - 1) is a whole number, so every texel is exact: 2, 4, 6, 16, 18.
///
/// Move-only; the destructor deletes the texture (the context and `api` must still be alive).
class CombinerTexture {
  public:
    static constexpr int kDefaultSize = 16;
    /// Errors: field "combiner" naming the missing GL 1.2 3D textures; field "size" for a size
    /// not in the list above. Leaves the engine's texture bindings, active unit and pixel-unpack
    /// state as it found them.
    static Result<CombinerTexture> create(const Api& api, int size = kDefaultSize);

    CombinerTexture(CombinerTexture&& other) noexcept;
    CombinerTexture& operator=(CombinerTexture&& other) noexcept;
    CombinerTexture(const CombinerTexture&) = delete;
    CombinerTexture& operator=(const CombinerTexture&) = delete;
    ~CombinerTexture();

    unsigned id() const { return id_; }  ///< the GL texture name
    int size() const { return size_; }   ///< texels a side
    /// The texture coordinates (3 floats a vertex, tightly packed) that make the texture return
    /// `colours.secondary` (L_in); valid until the next call.
    const float* texcoords_for(const VertexColours& colours);

  private:
    CombinerTexture(const Api* api, unsigned id, int size) : api_(api), id_(id), size_(size) {}
    const Api* api_ = nullptr;
    unsigned id_ = 0;
    int size_ = kDefaultSize;
    std::vector<float> texcoords_;
};

struct ApplyOptions {
    Path path = Path::automatic;
    /// The texture unit holding the engine's texture (the one F_ex modulates). The combiner
    /// path uses the next unit as well.
    int texture_unit = 0;
    /// False when the engine draws untextured: the colour is then F_ex + L_in (a white texel).
    /// The paths then disable texturing on texture_unit while they draw.
    bool textured = true;
    /// The combiner path's texture (see CombinerTexture); null: a temporary one per draw.
    CombinerTexture* combiner = nullptr;
    /// False (default): the paths switch GL lighting off while they draw, and the primary array
    /// is the whole surface colour factor (F_ex, or F_ex × lighting baked by shade_into's
    /// lit_rgba8). True: the engine's GL lighting stays on and the primary array feeds the
    /// material through GL_COLOR_MATERIAL (GL_FRONT_AND_BACK, GL_AMBIENT_AND_DIFFUSE), so the lit
    /// colour is F_ex × (ambient + diffuse lighting); pass F_ex × the material colour if it is
    /// not white. Emission and specular are not attenuated. GL lighting ignores the secondary
    /// colour array, so only the combiner path and two passes (L_in added unlit in pass 2) can
    /// add L_in then: `automatic` picks one of them. The material's ambient and diffuse colours,
    /// which colour tracking overwrites, are restored after the draw.
    bool fixed_function_lighting = false;
    /// True: the two-pass L_in pass culls back faces (GL_FRONT_FACE as the engine set it), so
    /// that a silhouette's back faces, which pass the depth test EQUAL where they meet the front
    /// faces, do not add L_in a second time: for engines that draw closed meshes without
    /// culling and wind them consistently. False (default): the engine's culling as it is (the
    /// module cannot know the winding: a mirroring transform flips it, a dome is seen from
    /// inside).
    bool cull_back_faces = false;
};

/// What a draw did, for the engine's statistics.
struct ApplyStats {
    Path path = Path::automatic;  ///< the path used (never automatic)
    int passes = 0;               ///< times the callback was called
};

/// Draws the engine's geometry (the callback) with F_ex and L_in applied along options.path.
/// Errors (nothing drawn, state unchanged): a null colour array, a forced path the context lacks,
/// a texture unit outside the context's range.
Result<ApplyStats> draw_with_colours(const Api& api, const ApplyOptions& options,
                                     const VertexColours& colours,
                                     const std::function<void()>& draw);

/// Which pass a draw_two_pass callback draws.
enum class Pass {
    extinction,     ///< the mesh with the engine's state: texture x F_ex (the primary colour)
    in_scattering,  ///< + L_in: blend ONE, ONE, depth EQUAL, no texture, black fog
};

/// Two passes around an engine's own draw call, for engines whose vertices carry one colour:
/// pass `extinction` as the engine set it up (its texture, depth, blend and fog state; lighting
/// off unless options.fixed_function_lighting), then pass `in_scattering` adds L_in (blend ONE,
/// ONE; depth EQUAL, depth and alpha writes off; every texture unit, lighting and alpha test off;
/// a black fog colour; back faces culled with options.cull_back_faces). With `colours` the
/// module points the colour array at colours->primary, then at colours->secondary, and the
/// callback must draw without touching it; with null colours the callback draws its own colour
/// array, holding F_ex in the first pass and L_in in the second. After each pass the state the
/// module set is checked: an error with field "engine.colour_array", "engine.blend",
/// "engine.depth_func", "engine.depth_mask" or "engine.texture" names what the engine's draw
/// changed (the image is then wrong; the state is restored either way).
Result<ApplyStats> draw_two_pass(const Api& api, const ApplyOptions& options,
                                 const VertexColours* colours,
                                 const std::function<void(Pass)>& draw);

/// The state an ARB vertex program of generate_arb_program needs when the engine binds and
/// enables the program itself (a material system): GL_COLOR_SUM on (the program writes L_in to
/// the secondary colour, which GL adds only with COLOR_SUM), GL_TEXTURE_ENV_MODE MODULATE on
/// options.texture_unit (texturing off there when !options.textured), no fragment program and
/// no GLSL program. ArbVertexProgram::draw sets the same. Saves what it changes; the destructor
/// or restore() puts it back (the context must be current then). Move-only.
class ProgramDrawState {
  public:
    /// Errors: "context" with no current context; "texture_unit" out of the context's range.
    static Result<ProgramDrawState> set(const Api& api, const ApplyOptions& options = {});
    void restore();
    ProgramDrawState(ProgramDrawState&&) noexcept;
    ProgramDrawState& operator=(ProgramDrawState&&) noexcept;
    ~ProgramDrawState();

  private:
    explicit ProgramDrawState(std::unique_ptr<StateSaver> saver);
    std::unique_ptr<StateSaver> saver_;
};

/// The driver's native ARB_vertex_program limits (GL_MAX_PROGRAM_NATIVE_INSTRUCTIONS_ARB,
/// _TEMPORARIES_, _PARAMETERS_, _ATTRIBS_ of GL_VERTEX_PROGRAM_ARB); a limit the driver answers
/// with 0, and all of them when the context lacks GL_ARB_vertex_program, are the spec's minimums
/// (ArbLimits{}). Put them in ArbProgramOptions::limits with height_fidelity = automatic and
/// generate_arb_program takes the highest height fidelity this driver runs natively (its choice
/// is in ArbProgram::options.height_fidelity).
ArbLimits native_arb_limits(const Api& api);

/// A GL program object holding a generated ARB vertex program. Move-only; the destructor deletes
/// the program object (the context and `api` must still be alive then). Keeps a pointer to `api`.
class ArbVertexProgram {
  public:
    /// Loads `program` into a new program object; the program bound before stays bound. Errors
    /// (nothing is left behind): field "GL_ARB_vertex_program" when the context lacks it (load
    /// the Api again after MESA_EXTENSION_OVERRIDE and the like); the exceeded resource
    /// ("instructions", "temporaries", "parameters", "attributes", from check_arb_limits) against
    /// the driver's GL_MAX_PROGRAM_NATIVE_*_ARB values, checked before loading; "parameter_base"
    /// when the program reads a program.local/env index beyond the driver's
    /// GL_MAX_PROGRAM_LOCAL/ENV_PARAMETERS_ARB; field "program" with GL_PROGRAM_ERROR_POSITION_ARB
    /// (also as line and column of the text) and GL_PROGRAM_ERROR_STRING_ARB when the driver
    /// rejects the text, or when it loads it but says GL_PROGRAM_UNDER_NATIVE_LIMITS_ARB false.
    static Result<ArbVertexProgram> create(const Api& api, const ArbProgram& program);

    ArbVertexProgram(ArbVertexProgram&& other) noexcept;
    ArbVertexProgram& operator=(ArbVertexProgram&& other) noexcept;
    ArbVertexProgram(const ArbVertexProgram&) = delete;
    ArbVertexProgram& operator=(const ArbVertexProgram&) = delete;
    ~ArbVertexProgram();

    /// Uploads one frame's parameters (from aerial::arb_program_parameters with the same
    /// options) to program.local (glProgramLocalParameter4fvARB with this program bound for the
    /// call, then the previous binding back) or program.env (glProgramEnvParameter4fvARB, shared
    /// by every program of the context), as the program's options say. Errors: "parameters" when
    /// the count is not what the program reads (counted from its text: kArbParameterCount for
    /// hoffman-preetham), "parameters[i]" for a value that is not finite. Const like draw():
    /// neither changes the C++ object (only GL state), so both work through Result's operator->.
    std::optional<Error> set_parameters(const std::vector<std::array<float, 4>>& parameters) const;

    /// Draws the engine's geometry with the program bound and GL_VERTEX_PROGRAM_ARB enabled,
    /// texture MODULATE on ApplyOptions::texture_unit (texture targets disabled there when
    /// untextured), GL_COLOR_SUM on (COLOR_SUM_ARB is ARB_vertex_program's own enum, so no
    /// EXT_secondary_color is needed), fragment and GLSL programs off; restores everything after.
    /// The stats report Path::secondary_color (the program's outputs are combined that way);
    /// ApplyOptions::path, combiner and fixed_function_lighting are ignored.
    Result<ApplyStats> draw(const std::function<void()>& draw,
                            const ApplyOptions& options = {}) const;

    unsigned id() const { return id_; }  ///< the GL program name
    const ArbProgram& program() const { return program_; }

  private:
    ArbVertexProgram(const Api* api, unsigned id, ArbProgram program);
    const Api* api_ = nullptr;
    unsigned id_ = 0;
    ArbProgram program_;
};

}  // namespace aerial::gl
