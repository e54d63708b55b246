// What aerial-bench and its tests need to draw a mesh of a scene file themselves, for the
// baselines the library does not ship (fog functions, the lookup textures, the per-pixel image
// of a tessellation): the scene's texture bound, the camera's matrices loaded, client arrays
// drawn. The library's own methods draw through aerial::scene::SceneRenderer instead.
#pragma once

#include <glm/mat4x4.hpp>

#include "aerial/gl_api.hpp"
#include "aerial/scene.hpp"
#include "aerial/scene_renderer.hpp"

namespace aerial::bench {

/// A scene texture (mipmapped with scene::mipmap_levels) bound on the active unit,
/// GL_LINEAR_MIPMAP_LINEAR, GL_REPEAT, GL_MODULATE, GL_TEXTURE_2D enabled; the destructor
/// disables, unbinds and deletes it.
class BoundTexture {
  public:
    BoundTexture(const gl::Api& api, const scene::Texture& texture);
    BoundTexture(const BoundTexture&) = delete;
    BoundTexture& operator=(const BoundTexture&) = delete;
    ~BoundTexture();

  private:
    const gl::Api& api_;
    unsigned id_ = 0;
};

/// Projection and view of a camera (scene::projection_matrix, scene::view_matrix).
struct Matrices {
    glm::dmat4 projection;
    glm::dmat4 view;
};
Matrices camera_matrices(const scene::Camera& camera);

/// Loads `m` (as float) into the matrix stack `mode` (GL_PROJECTION, GL_MODELVIEW).
void load_matrix(const gl::Api& api, unsigned mode, const glm::dmat4& m);

/// Draws `mesh` (positions and texture coordinates from client arrays, texture unit 0) with
/// whatever state is set; leaves those two client arrays disabled.
void draw_arrays(const gl::Api& api, const scene::MeshData& mesh);

}  // namespace aerial::bench
