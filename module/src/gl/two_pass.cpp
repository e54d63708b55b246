// The two-pass L_in pass's state, the checks of what an engine's draw callback left, and
// draw_two_pass: two passes around an engine's own draw call.
#include <cstdint>
#include <cstdio>
#include <string>

#include "../common/error_text.hpp"
#include "aerial/gl.hpp"
#include "pass_state.hpp"
#include "state_saver.hpp"

namespace aerial::gl {
namespace detail {

void in_scattering_pass_state(const Api& api, StateSaver& s, const ApplyOptions& options) {
    for (int u = 0; u < saved_texture_units(api.caps); ++u) s.unit_disable_all_targets(u);
    s.enable(GL_LIGHTING, false);  // L_in is light already: added as it is
    s.enable(GL_BLEND, true);
    s.blend_func(GL_ONE, GL_ONE);
    s.depth_func(GL_EQUAL);
    s.depth_mask(false);
    s.mask_alpha();
    if (options.cull_back_faces) {
        s.enable(GL_CULL_FACE, true);
        s.cull_face(GL_BACK);
    }
    if (api.IsEnabled(GL_FOG)) {
        static constexpr GLfloat kBlack[4] = {0.0f, 0.0f, 0.0f, 0.0f};
        s.fog_color(kBlack);
    }
}

namespace {

std::string pointer_text(const void* p) {
    char text[32];
    std::snprintf(text, sizeof text, "%p", p);
    return text;
}

}  // namespace

std::optional<Error> check_colour_array(const Api& api, const char* function, const void* expected,
                                        bool secondary) {
    const char* field = secondary ? "engine.secondary_colour_array" : "engine.colour_array";
    const GLenum array = secondary ? GL_SECONDARY_COLOR_ARRAY : GL_COLOR_ARRAY;
    GLvoid* pointer = nullptr;
    api.GetPointerv(secondary ? GL_SECONDARY_COLOR_ARRAY_POINTER : GL_COLOR_ARRAY_POINTER,
                    &pointer);
    GLint buffer = 0;
    if (api.caps.vertex_buffer_object) {
        api.GetIntegerv(
            secondary ? GL_SECONDARY_COLOR_ARRAY_BUFFER_BINDING : GL_COLOR_ARRAY_BUFFER_BINDING,
            &buffer);
    }
    const bool enabled = api.IsEnabled(array) == GL_TRUE;
    if (enabled && buffer == 0 && pointer == expected) return std::nullopt;
    const std::string got = !enabled ? "the array disabled"
                            : buffer != 0
                                ? "an array in buffer object " + aerial::detail::number(buffer) +
                                      " at offset " + pointer_text(pointer)
                                : "an array at " + pointer_text(pointer);
    return aerial::detail::invalid(
        function, field,
        std::string("the draw callback to leave aerial's ") + (secondary ? "L_in" : "F_ex") +
            " array at " + pointer_text(expected) +
            " (point only positions and texture coordinates in it; an engine whose draw call sets "
            "its own vertex colours draws with draw_two_pass and no colours)",
        got + " (re-pointed by the draw callback), so the colours drawn were the engine's");
}

std::optional<Error> check_in_scattering_state(const Api& api, const char* function) {
    GLint source = 0, destination = 0, depth = 0;
    GLboolean mask = GL_FALSE;
    api.GetIntegerv(GL_BLEND_SRC, &source);
    api.GetIntegerv(GL_BLEND_DST, &destination);
    api.GetIntegerv(GL_DEPTH_FUNC, &depth);
    api.GetBooleanv(GL_DEPTH_WRITEMASK, &mask);
    const char* changed = nullptr;
    if (api.IsEnabled(GL_BLEND) != GL_TRUE || source != GL_ONE || destination != GL_ONE) {
        changed = "engine.blend";
    } else if (depth != GL_EQUAL) {
        changed = "engine.depth_func";
    } else if (mask != GL_FALSE) {
        changed = "engine.depth_mask";
    }
    if (!changed) return std::nullopt;
    return aerial::detail::invalid(
        function, changed,
        "the L_in pass's state left as set (blend ONE, ONE; depth function EQUAL; depth writes "
        "off): "
        "the engine's draw must not apply its material in the callback",
        "the engine's draw changed it, so L_in was not added as it should be");
}

}  // namespace detail

namespace {

constexpr const char* kTwoPass = "gl::draw_two_pass";

}  // namespace

Result<ApplyStats> draw_two_pass(const Api& api, const ApplyOptions& options,
                                 const VertexColours* colours,
                                 const std::function<void(Pass)>& draw) {
    if (auto e = no_current_context(api)) return aerial::detail::from(kTwoPass, *e);
    if (!draw) return aerial::detail::error(kTwoPass, "draw", "the draw callback is empty");
    if (colours && (!colours->primary || !colours->secondary)) {
        return aerial::detail::error(kTwoPass,
                                     colours->primary ? "colours.secondary" : "colours.primary",
                                     "the array is null (pass no colours to draw the engine's)");
    }
    if (options.texture_unit < 0 || options.texture_unit >= api.caps.max_texture_units) {
        return aerial::detail::invalid(
            kTwoPass, "texture_unit",
            "0 .. " + aerial::detail::number(api.caps.max_texture_units - 1),
            aerial::detail::number(options.texture_unit));
    }
    if (options.fixed_function_lighting && colours == nullptr) {
        return aerial::detail::error(kTwoPass, "fixed_function_lighting",
                                     "needs aerial's colours (GL_COLOR_MATERIAL tracks them)");
    }
    const auto stride = [](std::size_t s) { return static_cast<GLsizei>(s ? s : 4); };
    StateSaver s(api);
    detail::common_state(api, s, options);
    if (api.caps.secondary_color) s.enable(GL_COLOR_SUM, false);
    std::optional<Error> error;
    if (colours) {
        s.color_array(4, GL_UNSIGNED_BYTE, stride(colours->primary_stride_bytes), colours->primary);
        if (options.fixed_function_lighting) s.color_material();
        s.rebind_engine_array_buffer();
    }
    draw(Pass::extinction);
    if (colours) error = detail::check_colour_array(api, kTwoPass, colours->primary, false);
    if (!error) {
        detail::in_scattering_pass_state(api, s, options);
        if (colours) {
            s.color_array(4, GL_UNSIGNED_BYTE, stride(colours->secondary_stride_bytes),
                          colours->secondary);
            s.rebind_engine_array_buffer();
        }
        draw(Pass::in_scattering);
        error = detail::check_in_scattering_state(api, kTwoPass);
        if (!error && colours) {
            error = detail::check_colour_array(api, kTwoPass, colours->secondary, false);
        }
    }
    s.restore();
    if (error) return *error;
    ApplyStats stats;
    stats.path = Path::two_pass;
    stats.passes = 2;
    return stats;
}

}  // namespace aerial::gl
