#include "bench/frame_gl.hpp"

#include <glm/gtc/type_ptr.hpp>

namespace aerial::bench {

BoundTexture::BoundTexture(const gl::Api& api, const scene::Texture& texture) : api_(api) {
    api_.GenTextures(1, &id_);
    api_.BindTexture(GL_TEXTURE_2D, id_);
    api_.PixelStorei(GL_UNPACK_ALIGNMENT, 1);
    const auto levels = scene::mipmap_levels(texture);
    int w = texture.width, h = texture.height;
    for (std::size_t level = 0; level < levels.size(); ++level) {
        api_.TexImage2D(GL_TEXTURE_2D, GLint(level), GL_RGB8, w, h, 0, GL_RGB, GL_UNSIGNED_BYTE,
                        levels[level].data());
        w = std::max(1, w / 2);
        h = std::max(1, h / 2);
    }
    api_.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR_MIPMAP_LINEAR);
    api_.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    api_.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_REPEAT);
    api_.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_REPEAT);
    api_.TexEnvi(GL_TEXTURE_ENV, GL_TEXTURE_ENV_MODE, GL_MODULATE);
    api_.Enable(GL_TEXTURE_2D);
}

BoundTexture::~BoundTexture() {
    api_.Disable(GL_TEXTURE_2D);
    api_.BindTexture(GL_TEXTURE_2D, 0);
    api_.DeleteTextures(1, &id_);
}

Matrices camera_matrices(const scene::Camera& camera) {
    return {scene::projection_matrix(camera), scene::view_matrix(camera)};
}

void load_matrix(const gl::Api& api, unsigned mode, const glm::dmat4& m) {
    const glm::mat4 f(m);
    api.MatrixMode(mode);
    api.LoadMatrixf(glm::value_ptr(f));
}

void draw_arrays(const gl::Api& api, const scene::MeshData& mesh) {
    if (api.ClientActiveTexture) api.ClientActiveTexture(GL_TEXTURE0);
    api.EnableClientState(GL_VERTEX_ARRAY);
    api.VertexPointer(3, GL_FLOAT, 0, mesh.positions.data());
    const bool textured = !mesh.texcoords.empty();
    if (textured) {
        api.EnableClientState(GL_TEXTURE_COORD_ARRAY);
        api.TexCoordPointer(2, GL_FLOAT, 0, mesh.texcoords.data());
    }
    api.DrawElements(GL_TRIANGLES, GLsizei(mesh.indices.size()), GL_UNSIGNED_INT,
                     mesh.indices.data());
    if (textured) api.DisableClientState(GL_TEXTURE_COORD_ARRAY);
    api.DisableClientState(GL_VERTEX_ARRAY);
}

}  // namespace aerial::bench
