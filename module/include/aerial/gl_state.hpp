// aerial/gl_state.hpp — a snapshot of the GL state the module may touch, for regression suites:
// capture before and after the module draws, and the differences name each piece that changed.
//
// How to use this:
//   1. `auto before = aerial::gl::capture_state(api);` (a current context, aerial/gl_api.hpp)
//   2. Draw with aerial::gl::draw_with_colours or ArbVertexProgram::draw.
//   3. `auto changed = aerial::gl::state_differences(before, aerial::gl::capture_state(api));`
//      is empty when everything was restored; otherwise one line a piece of state,
//      "unit 1 GL_TEXTURE_ENV_MODE: GL_MODULATE -> GL_COMBINE".
//
// What it captures (where the context has it): the enables GL_COLOR_SUM, GL_BLEND, GL_FOG,
// GL_LIGHTING, GL_COLOR_MATERIAL, GL_DEPTH_TEST, GL_ALPHA_TEST, GL_CULL_FACE,
// GL_VERTEX_PROGRAM_ARB, GL_FRAGMENT_PROGRAM_ARB; the blend functions and equations, depth function
// and write mask, colour write mask, fog colour and coordinate source, the colour-material face and
// parameter and the front and back ambient and diffuse material colours (which colour tracking
// overwrites), shade model, GL_NORMALIZE, the scissor, stencil and polygon-offset-fill enables,
// polygon offset, polygon mode, viewport, cull face mode, front face, alpha test function and
// reference, fog mode, density, start and end, the current normal, the framebuffer binding,
// matrix mode, the modelview and projection matrices and their stack depths, the unpack
// pixel-store state and the pixel unpack buffer binding; the bound ARB vertex program, the first
// 96 vertex program env parameters and local parameters of the bound program, and the GLSL
// program; the active and client active texture units; the current colour, secondary colour and
// texture coordinates; the array buffer binding; the colour, secondary colour, vertex, normal and
// fog coordinate arrays (enabled, size, type, stride, pointer, buffer); and on each of the first
// min(GL_MAX_TEXTURE_UNITS, 8) units: the enabled texture targets and texture-coordinate
// generation, the bound 1D/2D/3D/cube textures, the texture environment (mode, colour, and the
// whole combine state), the texture matrix and its stack depth, and the texture-coordinate array.
// Reading it costs a few hundred glGet calls: for tests, not frames.
#pragma once

#include <string>
#include <string_view>
#include <vector>

namespace aerial::gl {

struct Api;  // aerial/gl_api.hpp

/// One piece of state, by GL name, with its value as text (enums by name, floats exactly).
struct StateEntry {
    std::string name;   ///< "GL_BLEND", "unit 1 GL_TEXTURE_BINDING_3D", "GL_COLOR_ARRAY_POINTER"
    std::string value;  ///< "GL_TRUE", "GL_ONE GL_ZERO", "0.5 0.25 0 1", "0x7f00deadbeef"
};

struct StateSnapshot {
    std::vector<StateEntry> entries;  ///< in a fixed order for a given context
    /// The value of `name`, or null when the snapshot does not have it.
    const std::string* find(std::string_view name) const;
};

/// Reads the state listed above. Changes nothing (the active texture units it selects to read
/// per-unit state are put back). Needs a current context.
StateSnapshot capture_state(const Api& api);

/// "name: before -> after" for each entry whose value differs, and "name: missing" for an entry
/// only one snapshot has. Empty when the two are the same.
std::vector<std::string> state_differences(const StateSnapshot& before, const StateSnapshot& after);

}  // namespace aerial::gl
