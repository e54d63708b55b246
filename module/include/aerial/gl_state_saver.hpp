// aerial/gl_state_saver.hpp — records each piece of GL state just before it is changed and puts it
// back in reverse order when destroyed (also when an engine's callback throws). The module's
// draws all go through it; an engine can use it for its own state changes around them.
//
// How to use this:
//   1. With a current context and its entry points (aerial/gl_api.hpp):
//      `if (auto e = aerial::gl::no_current_context(api)) return *e;`
//   2. `aerial::gl::StateSaver saver(api);` then change state through it
//      (`saver.enable(GL_COLOR_SUM, true); saver.bind_texture(0, GL_TEXTURE_2D, id); ...`).
//   3. The destructor (or `saver.restore()`) puts back everything it changed, most recent first.
//
// Only what is changed is read with glGet* and restored; glPushAttrib is never used (engines use
// the attribute stacks, which are only 16 deep and do not cover program bindings).
//
// A driver may report a value GL itself would reject when given back (zink reports
// GL_MATRIX_MODE 0 on a fresh compatibility context). Enum-valued state (matrix mode, depth
// function, blend factors and equations, colour-material face and parameter, array types) is
// checked when read: a value outside what GL accepts is restored as GL's initial value instead,
// so the engine's state stays valid and no GL error is raised, and `rejected()` names it.
#pragma once

#include <functional>
#include <initializer_list>
#include <optional>
#include <string>
#include <vector>

#include "aerial/error.hpp"
#include "aerial/gl_api.hpp"

namespace aerial::gl {

/// Error "context" when no GL context is current on this thread (glGetString(GL_VERSION) gives
/// NULL): every entry point that talks to GL checks this first, so a call made at the wrong
/// time is a clear error rather than GL calls that silently do nothing (or crash a driver).
std::optional<Error> no_current_context(const Api& api);

class StateSaver {
  public:
    explicit StateSaver(const Api& api) : api_(api) {}
    StateSaver(const StateSaver&) = delete;
    StateSaver& operator=(const StateSaver&) = delete;
    ~StateSaver() { restore(); }

    /// Puts everything back, most recent change first; the active texture unit, the client
    /// active unit and the array buffer binding last. Safe to call twice.
    void restore();

    // Server state.
    void enable(GLenum cap, bool on);
    void unit_enable(int unit, GLenum cap, bool on);
    /// Disables every texture target on `unit`.
    void unit_disable_all_targets(int unit);
    void blend_func(GLenum source, GLenum destination);
    void depth_func(GLenum function);
    void depth_mask(bool write);
    void cull_face(GLenum face);  ///< glCullFace (GL_FRONT, GL_BACK, GL_FRONT_AND_BACK)
    /// glColorMask with the engine's red/green/blue mask kept, alpha as given AND the engine's.
    void mask_alpha();
    void fog_color(const GLfloat colour[4]);
    void tex_env(int unit, GLenum pname, GLint value);
    void bind_texture(int unit, GLenum target, GLuint texture);
    void bind_program(GLuint program);  ///< GL_VERTEX_PROGRAM_ARB binding
    void use_no_glsl_program();         ///< glUseProgram(0) where GL 2.0 has it
    void texture_matrix_identity(int unit);
    /// GL_COLOR_MATERIAL on, tracking GL_AMBIENT_AND_DIFFUSE of both faces; saves the colour
    /// material mode and the ambient and diffuse colours of both faces, which tracking changes.
    void color_material();
    void select_unit(int unit);  ///< glActiveTexture
    /// glLoadMatrixf on the GL_MODELVIEW or GL_PROJECTION stack (the matrix mode is saved too).
    void load_matrix(GLenum mode, const GLfloat matrix[16]);
    /// glPixelStorei (GL_UNPACK_ALIGNMENT, GL_UNPACK_ROW_LENGTH, ...).
    void pixel_store(GLenum pname, GLint value);
    /// Binds GL_PIXEL_UNPACK_BUFFER 0 where the context has pixel buffer objects, so that
    /// glTexImage reads client memory.
    void unbind_pixel_unpack_buffer();
    /// The current texture coordinates of `unit` are about to change (immediate mode).
    void save_current_texcoord(int unit);
    /// The current colour is about to change (glColor in immediate mode).
    void save_current_color();

    // Client state. Pointers are given with array buffer 0 bound (client memory).
    void color_array(GLint size, GLenum type, GLsizei stride, const void* pointer);
    void secondary_color_array(GLint size, GLenum type, GLsizei stride, const void* pointer);
    void texcoord_array(int unit, GLint size, GLenum type, GLsizei stride, const void* pointer);

    /// One line per value the driver reported that GL would not accept back ("GL_MATRIX_MODE: the
    /// driver reported 0x0000, ..."), each restored as GL's initial value instead. Kept after
    /// restore(), for a caller to log.
    const std::vector<std::string>& rejected() const { return rejected_; }

    /// An enum-valued piece of state: its query, its name, GL's initial value and the values
    /// GL accepts back.
    struct EnumState {
        GLenum query;
        const char* name;
        GLenum initial;
        std::initializer_list<GLenum> accepted;
    };

    /// Restores the engine's GL_ARRAY_BUFFER binding now (the callback's arrays may be in its
    /// buffers); our pointers keep the buffer 0 they were given with.
    void rebind_engine_array_buffer();

  private:
    void select_client_unit(int unit);
    void unbind_array_buffer();
    void save_current_secondary_color();
    GLint read_enum(const EnumState& state);
    GLint read_enum(const EnumState& state, GLenum query);
    GLint accepted_or_initial(const EnumState& state, GLint value);

    const Api& api_;
    std::vector<std::function<void()>> undo_;
    std::vector<std::string> rejected_;
    bool saved_active_ = false, saved_client_active_ = false, saved_array_buffer_ = false;
    GLint active_ = GL_TEXTURE0, client_active_ = GL_TEXTURE0, array_buffer_ = 0;
};

}  // namespace aerial::gl
