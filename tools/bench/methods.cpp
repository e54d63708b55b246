#include "bench/methods.hpp"

#include <algorithm>
#include <cmath>
#include <utility>

#include <glm/geometric.hpp>

#include "aerial/gl_api.hpp"
#include "aerial/validation/scene_render.hpp"

namespace aerial::bench {
namespace {

constexpr double kPi = 3.14159265358979323846;

/// The array buffer binding, set to 0 while client arrays are pointed at, then put back.
class ClientArrays {
  public:
    explicit ClientArrays(const gl::Api& api) : api_(api) {
        if (api_.caps.vertex_buffer_object) {
            api_.GetIntegerv(GL_ARRAY_BUFFER_BINDING, &buffer_);
            api_.BindBuffer(GL_ARRAY_BUFFER, 0);
        }
    }
    ~ClientArrays() {
        if (api_.caps.vertex_buffer_object) api_.BindBuffer(GL_ARRAY_BUFFER, GLuint(buffer_));
    }
    ClientArrays(const ClientArrays&) = delete;
    ClientArrays& operator=(const ClientArrays&) = delete;

  private:
    const gl::Api& api_;
    GLint buffer_ = 0;
};

/// Everything LutTexture::draw changes on one texture unit, read on construction and written
/// back on destruction (the unit is made active for both, the caller restores the active unit).
class UnitState {
  public:
    UnitState(const gl::Api& api, GLenum unit) : api_(api), unit_(unit) {
        api_.ActiveTexture(unit_);
        api_.ClientActiveTexture(unit_);
        enabled_1d_ = api_.IsEnabled(GL_TEXTURE_1D);
        enabled_2d_ = api_.IsEnabled(GL_TEXTURE_2D);
        api_.GetIntegerv(GL_TEXTURE_BINDING_1D, &binding_1d_);
        api_.GetIntegerv(GL_TEXTURE_BINDING_2D, &binding_2d_);
        array_enabled_ = api_.IsEnabled(GL_TEXTURE_COORD_ARRAY);
        api_.GetIntegerv(GL_TEXTURE_COORD_ARRAY_SIZE, &array_size_);
        api_.GetIntegerv(GL_TEXTURE_COORD_ARRAY_TYPE, &array_type_);
        api_.GetIntegerv(GL_TEXTURE_COORD_ARRAY_STRIDE, &array_stride_);
        api_.GetPointerv(GL_TEXTURE_COORD_ARRAY_POINTER, &array_pointer_);
        for (std::size_t i = 0; i < kEnv.size(); ++i)
            api_.GetTexEnviv(GL_TEXTURE_ENV, kEnv[i], &env_[i]);
    }
    ~UnitState() {
        api_.ActiveTexture(unit_);
        api_.ClientActiveTexture(unit_);
        for (std::size_t i = 0; i < kEnv.size(); ++i)
            api_.TexEnvi(GL_TEXTURE_ENV, kEnv[i], env_[i]);
        api_.TexCoordPointer(array_size_, GLenum(array_type_), array_stride_, array_pointer_);
        (array_enabled_ ? api_.EnableClientState : api_.DisableClientState)(GL_TEXTURE_COORD_ARRAY);
        api_.BindTexture(GL_TEXTURE_1D, GLuint(binding_1d_));
        api_.BindTexture(GL_TEXTURE_2D, GLuint(binding_2d_));
        (enabled_1d_ ? api_.Enable : api_.Disable)(GL_TEXTURE_1D);
        (enabled_2d_ ? api_.Enable : api_.Disable)(GL_TEXTURE_2D);
    }
    UnitState(const UnitState&) = delete;
    UnitState& operator=(const UnitState&) = delete;

  private:
    static constexpr std::array<GLenum, 11> kEnv = {
        GL_TEXTURE_ENV_MODE, GL_COMBINE_RGB,  GL_COMBINE_ALPHA, GL_SOURCE0_RGB,
        GL_SOURCE1_RGB,      GL_OPERAND0_RGB, GL_OPERAND1_RGB,  GL_SOURCE0_ALPHA,
        GL_OPERAND0_ALPHA,   GL_RGB_SCALE,    GL_ALPHA_SCALE};
    const gl::Api& api_;
    GLenum unit_;
    GLboolean enabled_1d_ = GL_FALSE, enabled_2d_ = GL_FALSE, array_enabled_ = GL_FALSE;
    GLint binding_1d_ = 0, binding_2d_ = 0;
    GLint array_size_ = 4, array_type_ = GL_FLOAT, array_stride_ = 0;
    void* array_pointer_ = nullptr;
    std::array<GLint, kEnv.size()> env_{};
};

/// Distance (m) and phase-angle cosine of a vertex seen from the frame's eye.
std::pair<double, double> distance_and_cosine(const Frame<float>& frame, const float* p) {
    const glm::dvec3 d =
        (glm::dvec3(p[0], p[1], p[2]) - glm::dvec3(frame.view.eye)) * double(frame.meters_per_unit);
    const double s = glm::length(d);
    const double cos_theta = s > 0.0 ? glm::dot(d, glm::dvec3(frame.sun_dir)) / s : 1.0;
    return {s, std::clamp(cos_theta, -1.0, 1.0)};
}

}  // namespace

FlightGearFog flightgear_fog(const Frame<float>& frame, const Display& display) {
    const validation::FogParameters gl_fog = validation::fog_parameters(frame, display);
    FlightGearFog fog;
    // GL fog's density is the green extinction per engine unit; its inverse in metres is one
    // attenuation length.
    fog.visibility_m =
        gl_fog.density > 0.0f ? double(frame.meters_per_unit) / double(gl_fog.density) : 0.0;
    std::copy(std::begin(gl_fog.colour), std::end(gl_fog.colour), std::begin(fog.colour));
    return fog;
}

double flightgear_fog_factor(double distance_m, double visibility_m) {
    if (!(visibility_m > 0.0)) return 1.0;
    const double x = distance_m / visibility_m;
    const double x2 = x * x;
    return std::exp(-x - x2 * x2);
}

void flightgear_fog_coordinates(const FlightGearFog& fog, const Frame<float>& frame,
                                const float* positions, std::size_t count,
                                std::vector<float>& coords) {
    coords.resize(count);
    for (std::size_t i = 0; i < count; ++i) {
        const double s = distance_and_cosine(frame, positions + 3 * i).first;
        coords[i] = float(1.0 - flightgear_fog_factor(s, fog.visibility_m));
    }
}

std::optional<Error> draw_with_flightgear_fog(const gl::Api& api, const FlightGearFog& fog,
                                              const float* coords,
                                              const std::function<void()>& draw) {
    if (!api.caps.fog_coord || !api.FogCoordPointer) {
        return Error{"GL_EXT_fog_coord",
                     "GL_EXT_fog_coord: fg-fog needs fog coordinates (GL 1.4 or EXT_fog_coord)"};
    }
    const ClientArrays arrays(api);
    const GLboolean fog_enabled = api.IsEnabled(GL_FOG);
    const GLboolean array_enabled = api.IsEnabled(GL_FOG_COORD_ARRAY);
    GLint mode = GL_EXP, source = GL_FRAGMENT_DEPTH, array_type = GL_FLOAT, array_stride = 0;
    GLfloat start = 0.0f, end = 1.0f, colour[4] = {0, 0, 0, 0};
    void* array_pointer = nullptr;
    api.GetIntegerv(GL_FOG_MODE, &mode);
    api.GetIntegerv(GL_FOG_COORD_SRC, &source);
    api.GetFloatv(GL_FOG_START, &start);
    api.GetFloatv(GL_FOG_END, &end);
    api.GetFloatv(GL_FOG_COLOR, colour);
    api.GetIntegerv(GL_FOG_COORD_ARRAY_TYPE, &array_type);
    api.GetIntegerv(GL_FOG_COORD_ARRAY_STRIDE, &array_stride);
    api.GetPointerv(GL_FOG_COORD_ARRAY_POINTER, &array_pointer);

    api.Fogi(GL_FOG_MODE, GL_LINEAR);
    api.Fogf(GL_FOG_START, 0.0f);
    api.Fogf(GL_FOG_END, 1.0f);
    api.Fogfv(GL_FOG_COLOR, fog.colour);
    api.Fogi(GL_FOG_COORD_SRC, GL_FOG_COORD);
    api.FogCoordPointer(GL_FLOAT, 0, coords);
    api.EnableClientState(GL_FOG_COORD_ARRAY);
    api.Enable(GL_FOG);
    draw();

    (fog_enabled ? api.Enable : api.Disable)(GL_FOG);
    (array_enabled ? api.EnableClientState : api.DisableClientState)(GL_FOG_COORD_ARRAY);
    api.FogCoordPointer(GLenum(array_type), array_stride, array_pointer);
    api.Fogi(GL_FOG_COORD_SRC, source);
    api.Fogi(GL_FOG_MODE, mode);
    api.Fogf(GL_FOG_START, start);
    api.Fogf(GL_FOG_END, end);
    api.Fogfv(GL_FOG_COLOR, colour);
    return std::nullopt;
}

Result<LutTexture> LutTexture::create(const gl::Api& api, const Frame<float>& frame,
                                      const Display& display, double max_distance_m) {
    if (frame.model != Model::hoffman_preetham) {
        return Error{"model",
                     "model: the lookup tables hold the hoffman-preetham model only, got " +
                         std::string(model_name(frame.model))};
    }
    if (!(max_distance_m > 0.0) || !std::isfinite(max_distance_m)) {
        return Error{"max_distance_m", "max_distance_m: expected a positive finite distance, got " +
                                           std::to_string(max_distance_m)};
    }
    GLint units = 1;
    api.GetIntegerv(GL_MAX_TEXTURE_UNITS, &units);
    if (!api.caps.texture_env_combine || !api.caps.multitexture || units < 3) {
        return Error{"GL_ARB_texture_env_combine",
                     "GL_ARB_texture_env_combine: lut-texture needs texture combiners and 3 "
                     "texture units, the context has " +
                         std::to_string(units)};
    }
    const int n = kDistanceTexels, m = kAngleTexels;
    std::vector<std::uint8_t> extinction(3 * std::size_t(n));
    std::vector<std::uint8_t> in_scattering(3 * std::size_t(n) * std::size_t(m));
    for (int j = 0; j < m; ++j) {
        const float cos_theta = float(std::cos(kPi * j / (m - 1)));
        for (int i = 0; i < n; ++i) {
            const float s = float(max_distance_m * i / (n - 1));
            const Scattering<float> v =
                hoffman_preetham_closed_form(frame, s, cos_theta, frame.sun_irradiance_eye);
            for (int c = 0; c < 3; ++c) {
                if (j == 0)
                    extinction[3 * std::size_t(i) + std::size_t(c)] = to_unorm8(v.extinction[c]);
                in_scattering[3 * (std::size_t(j) * std::size_t(n) + std::size_t(i)) +
                              std::size_t(c)] =
                    to_unorm8(display_value(display, v.in_scattering[c]));
            }
        }
    }
    GLint active = GL_TEXTURE0, binding_1d = 0, binding_2d = 0, alignment = 4, unpack_buffer = 0;
    api.GetIntegerv(GL_ACTIVE_TEXTURE, &active);
    api.GetIntegerv(GL_TEXTURE_BINDING_1D, &binding_1d);
    api.GetIntegerv(GL_TEXTURE_BINDING_2D, &binding_2d);
    api.GetIntegerv(GL_UNPACK_ALIGNMENT, &alignment);
    if (api.caps.pixel_buffer_object) {
        api.GetIntegerv(GL_PIXEL_UNPACK_BUFFER_BINDING, &unpack_buffer);
        api.BindBuffer(GL_PIXEL_UNPACK_BUFFER, 0);
    }
    api.PixelStorei(GL_UNPACK_ALIGNMENT, 1);
    GLuint ids[2] = {0, 0};
    api.GenTextures(2, ids);
    api.BindTexture(GL_TEXTURE_1D, ids[0]);
    api.TexImage1D(GL_TEXTURE_1D, 0, GL_RGB8, n, 0, GL_RGB, GL_UNSIGNED_BYTE, extinction.data());
    api.BindTexture(GL_TEXTURE_2D, ids[1]);
    api.TexImage2D(GL_TEXTURE_2D, 0, GL_RGB8, n, m, 0, GL_RGB, GL_UNSIGNED_BYTE,
                   in_scattering.data());
    for (GLenum target : {GLenum(GL_TEXTURE_1D), GLenum(GL_TEXTURE_2D)}) {
        api.BindTexture(target, target == GL_TEXTURE_1D ? ids[0] : ids[1]);
        api.TexParameteri(target, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
        api.TexParameteri(target, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
        api.TexParameteri(target, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
        api.TexParameteri(target, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    }
    api.BindTexture(GL_TEXTURE_1D, GLuint(binding_1d));
    api.BindTexture(GL_TEXTURE_2D, GLuint(binding_2d));
    api.PixelStorei(GL_UNPACK_ALIGNMENT, alignment);
    if (api.caps.pixel_buffer_object) api.BindBuffer(GL_PIXEL_UNPACK_BUFFER, GLuint(unpack_buffer));
    api.ActiveTexture(GLenum(active));
    return LutTexture(&api, ids[0], ids[1], max_distance_m);
}

LutTexture::LutTexture(LutTexture&& other) noexcept
    : api_(other.api_),
      extinction_id_(std::exchange(other.extinction_id_, 0u)),
      in_scattering_id_(std::exchange(other.in_scattering_id_, 0u)),
      max_distance_m_(other.max_distance_m_) {}

LutTexture& LutTexture::operator=(LutTexture&& other) noexcept {
    if (this != &other) {
        this->~LutTexture();
        new (this) LutTexture(std::move(other));
    }
    return *this;
}

LutTexture::~LutTexture() {
    if (api_ && (extinction_id_ || in_scattering_id_)) {
        const GLuint ids[2] = {extinction_id_, in_scattering_id_};
        api_->DeleteTextures(2, ids);
    }
}

void LutTexture::texcoords(const Frame<float>& frame, const float* positions, std::size_t count,
                           std::vector<float>& coords) const {
    coords.resize(2 * count);
    const double n = kDistanceTexels, m = kAngleTexels;
    for (std::size_t i = 0; i < count; ++i) {
        const auto [s, cos_theta] = distance_and_cosine(frame, positions + 3 * i);
        const double u = std::min(s / max_distance_m_, 1.0);
        const double v = std::acos(cos_theta) / kPi;
        coords[2 * i] = float((0.5 + u * (n - 1.0)) / n);
        coords[2 * i + 1] = float((0.5 + v * (m - 1.0)) / m);
    }
}

void LutTexture::draw(const float* coords, const std::function<void()>& draw) const {
    const gl::Api& api = *api_;
    const ClientArrays arrays(api);
    GLint active = GL_TEXTURE0, client_active = GL_TEXTURE0;
    api.GetIntegerv(GL_ACTIVE_TEXTURE, &active);
    api.GetIntegerv(GL_CLIENT_ACTIVE_TEXTURE, &client_active);
    {
        // One combiner stage on the active unit: previous (op) this unit's table, looked up at
        // coords; alpha passes through.
        const auto combine = [&](GLenum other_target, GLenum target, GLuint id, GLint op) {
            api.Disable(other_target);
            api.BindTexture(target, id);
            api.Enable(target);
            api.TexEnvi(GL_TEXTURE_ENV, GL_TEXTURE_ENV_MODE, GL_COMBINE);
            api.TexEnvi(GL_TEXTURE_ENV, GL_COMBINE_RGB, op);
            api.TexEnvi(GL_TEXTURE_ENV, GL_SOURCE0_RGB, GL_PREVIOUS);
            api.TexEnvi(GL_TEXTURE_ENV, GL_OPERAND0_RGB, GL_SRC_COLOR);
            api.TexEnvi(GL_TEXTURE_ENV, GL_SOURCE1_RGB, GL_TEXTURE);
            api.TexEnvi(GL_TEXTURE_ENV, GL_OPERAND1_RGB, GL_SRC_COLOR);
            api.TexEnvi(GL_TEXTURE_ENV, GL_COMBINE_ALPHA, GL_REPLACE);
            api.TexEnvi(GL_TEXTURE_ENV, GL_SOURCE0_ALPHA, GL_PREVIOUS);
            api.TexEnvi(GL_TEXTURE_ENV, GL_OPERAND0_ALPHA, GL_SRC_ALPHA);
            api.TexEnvi(GL_TEXTURE_ENV, GL_RGB_SCALE, 1);
            api.TexEnvi(GL_TEXTURE_ENV, GL_ALPHA_SCALE, 1);
            api.TexCoordPointer(2, GL_FLOAT, 0, coords);
            api.EnableClientState(GL_TEXTURE_COORD_ARRAY);
        };
        const UnitState unit1(api, GL_TEXTURE1);
        combine(GL_TEXTURE_2D, GL_TEXTURE_1D, extinction_id_, GL_MODULATE);  // x F_ex
        const UnitState unit2(api, GL_TEXTURE2);
        combine(GL_TEXTURE_1D, GL_TEXTURE_2D, in_scattering_id_, GL_ADD);  // + L_in
        api.ActiveTexture(GL_TEXTURE0);
        api.ClientActiveTexture(GL_TEXTURE0);
        draw();
    }  // unit 2, then unit 1 put back
    api.ActiveTexture(GLenum(active));
    api.ClientActiveTexture(GLenum(client_active));
}

}  // namespace aerial::bench
