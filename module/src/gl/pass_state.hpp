// Internal: the state of the two-pass path's L_in pass and the checks that an engine's draw
// callback left the state the module set (draw_with_colours, draw_two_pass).
#pragma once

#include <optional>

#include "aerial/error.hpp"
#include "aerial/gl.hpp"
#include "aerial/gl_api.hpp"
#include "aerial/gl_state_saver.hpp"

namespace aerial::gl::detail {

/// What every fixed-function path sets the same way (draw_with_colours, draw_two_pass): no
/// vertex, fragment or GLSL program, no GL lighting unless options keep it, the engine's texture
/// modulated on options.texture_unit (or texturing off there when untextured).
void common_state(const Api& api, StateSaver& s, const ApplyOptions& options);

/// Pass 2 of two: + L_in on exactly the pixels pass 1 left in front. Every texture unit,
/// lighting and alpha writes off; blend ONE, ONE; depth EQUAL without writes; back faces culled
/// with options.cull_back_faces; a black fog colour (pass 1 already added (1 - f) x the fog
/// colour, and the sum must be f (texture F_ex + L_in) + (1 - f) fog colour, as in one pass).
void in_scattering_pass_state(const Api& api, StateSaver& s, const ApplyOptions& options);

/// Error "engine.colour_array" (or "engine.secondary_colour_array") when the colour array is no
/// longer `expected` from client memory, or was disabled, after the engine's draw callback.
std::optional<Error> check_colour_array(const Api& api, const char* function, const void* expected,
                                        bool secondary);

/// Errors "engine.blend", "engine.depth_func", "engine.depth_mask" when the engine's draw
/// callback changed the L_in pass's blend or depth state.
std::optional<Error> check_in_scattering_state(const Api& api, const char* function);

}  // namespace aerial::gl::detail
