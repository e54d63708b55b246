// Internal: the release and move steps the module's move-only owners of a GL texture share
// (SkyCubemapTexture, SunSpriteTexture, CombinerTexture).
#pragma once

#include <utility>

#include "aerial/gl_api.hpp"

namespace aerial::gl::detail {

/// Deletes the texture an owner holds (0: none).
inline void release_texture(const Api* api, unsigned id) {
    if (id != 0) api->DeleteTextures(1, &id);
}

/// An owner's move assignment of its context and texture: releases its own texture, takes the
/// other's and leaves the other without one.
inline void take_texture(const Api*& api, unsigned& id, const Api* other_api, unsigned& other_id) {
    release_texture(api, id);
    api = other_api;
    id = std::exchange(other_id, 0u);
}

}  // namespace aerial::gl::detail
