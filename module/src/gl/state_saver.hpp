// Internal: the texture-unit helpers the state saver and the state snapshot share.
#pragma once

#include <vector>

#include "aerial/gl_api.hpp"
#include "aerial/gl_state_saver.hpp"

namespace aerial::gl::detail {

/// The texture targets a unit may have enabled (TEXTURE_CUBE_MAP only where the context has it).
std::vector<GLenum> texture_targets(const Caps& caps);
/// The texture binding query of a target (GL_TEXTURE_BINDING_2D for GL_TEXTURE_2D, ...).
GLenum texture_binding_query(GLenum target);
/// The units whose state the module saves and captures: min(max_texture_units, 8).
int saved_texture_units(const Caps& caps);

}  // namespace aerial::gl::detail
