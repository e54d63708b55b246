// The OpenSceneGraph adapter (aerial/osg.hpp): per-frame F_ex and L_in for the Geometry below a
// node, through OSG's own arrays and state (no GL call here).
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include <osg/Array>
#include <osg/Geometry>
#include <osg/Matrix>
#include <osg/NodeVisitor>
#include <osg/StateSet>
#include <osg/TexEnv>
#include <osg/Transform>
#include <osg/VertexProgram>
#include <osg/io_utils>

#include "../common/error_text.hpp"
#include "../common/names.hpp"
#include "aerial/osg.hpp"
#include "aerial/sun.hpp"

#ifndef GL_COLOR_SUM
#define GL_COLOR_SUM 0x8458  // GL 1.4 / EXT_secondary_color: adds the secondary colour
#endif

namespace aerial::osg_adapter {

namespace {

/// Every Geometry below a node, with the matrix from its local frame to the node's parent frame.
class CollectGeometry : public ::osg::NodeVisitor {
  public:
    struct Entry {
        ::osg::Geometry* geometry = nullptr;
        ::osg::Matrixd to_world;
    };

    CollectGeometry(const ::osg::Matrixd& parent_to_world)
        : ::osg::NodeVisitor(TRAVERSE_ALL_CHILDREN), parent_to_world_(parent_to_world) {}

    void apply(::osg::Geometry& geometry) override {
        // The path ends with the Geometry; cameras below the node start their own frame.
        const ::osg::Matrixd local = ::osg::computeLocalToWorld(getNodePath(), true);
        entries.push_back({&geometry, local * parent_to_world_});
    }

    std::vector<Entry> entries;

  private:
    ::osg::Matrixd parent_to_world_;
};

std::string geometry_name(const ::osg::Geometry& g, std::size_t index) {
    return g.getName().empty() ? "geometry " + std::to_string(index)
                               : "geometry '" + g.getName() + "'";
}

}  // namespace

constexpr aerial::detail::NameTable<Backend, 2> kBackendNames{
    {{Backend::cpu, "cpu"}, {Backend::arb, "arb"}}};

const char* backend_name(Backend backend) {
    return aerial::detail::name_in(kBackendNames, backend);
}

Result<Backend> parse_backend(std::string_view name) {
    return aerial::detail::parse_in("osg_adapter::parse_backend", kBackendNames, "backend", name);
}

namespace {

using aerial::detail::from;
using aerial::detail::invalid;
using aerial::detail::number;
constexpr const char* kUpdateNow = "osg_adapter::ScatteringCallback::update_now";

}  // namespace

std::optional<Error> validate(const Settings& s) {
    constexpr const char* kFunction = "osg_adapter::validate";
    if (auto e = validate(s.atmosphere)) return from(kFunction, *e, "atmosphere.");
    View view;
    view.eye = glm::dvec3(0.0);
    view.sun_dir = s.sun_dir;
    view.up = s.up;
    view.meters_per_unit = s.meters_per_unit;
    if (auto e = validate(view)) return from(kFunction, *e);
    if (!(s.display.exposure > 0.0f) || !std::isfinite(s.display.exposure)) {
        return invalid(kFunction, "display.exposure", "a finite value > 0",
                       number(s.display.exposure));
    }
    if (s.texture_units < 0 || s.texture_units > kArbMaxTexcoordUnits) {
        return invalid(kFunction, "texture_units", "0 to " + number(kArbMaxTexcoordUnits),
                       number(s.texture_units));
    }
    if (s.backend == Backend::arb) {
        if (is_numerical(s.model)) {
            return invalid(kFunction, "model",
                           "hoffman-preetham or height (the models the arb backend has "
                           "programs for)",
                           std::string(model_name(s.model)));
        }
        if (s.display.tone != ToneCurve::clamp) {
            return invalid(kFunction, "display.tone",
                           "clamp with the arb backend (GL clamps the secondary colour)",
                           std::string(tone_curve_name(s.display.tone)));
        }
    }
    return std::nullopt;
}

Result<::osg::ref_ptr<ScatteringCallback>> ScatteringCallback::create(const Settings& settings,
                                                                      ::osg::Camera* camera) {
    ::osg::ref_ptr<ScatteringCallback> cb = new ScatteringCallback();
    if (auto e = cb->set_settings(settings)) {
        return from("osg_adapter::ScatteringCallback::create", *e);
    }
    cb->camera_ = camera;
    return cb;
}

std::optional<Error> ScatteringCallback::set_settings(const Settings& settings) {
    constexpr const char* kFunction = "osg_adapter::ScatteringCallback::set_settings";
    if (auto e = validate(settings)) return from(kFunction, *e);
    ArbProgram program;
    if (settings.backend == Backend::arb) {
        ArbProgramOptions options;
        options.model = settings.model;
        options.parameter_space = ParameterSpace::local;
        options.texcoord_units = settings.texture_units;
        options.limits = settings.arb_limits;
        options.model_matrix = true;  // Geometries below transforms keep model-space vertices
        auto generated = generate_arb_program(options);
        if (!generated) return from(kFunction, generated.error());
        program = std::move(generated.value());
    }
    settings_ = settings;
    program_ = std::move(program);
    vertex_program_ = nullptr;  // a new program object for the new text
    remove_transformed_programs();
    return std::nullopt;
}

void ScatteringCallback::operator()(::osg::Node* node, ::osg::NodeVisitor* nv) {
    // OSG calls this; its errors are kept for last_error().
    constexpr const char* kOperator = "osg_adapter::ScatteringCallback::operator()";
    if (node && nv && nv->getVisitorType() == ::osg::NodeVisitor::UPDATE_VISITOR) {
        ::osg::ref_ptr<::osg::Camera> camera;
        if (!camera_.lock(camera)) {
            error_ = aerial::detail::error(kOperator, "camera",
                                           "no camera to read the eye from (set_camera)");
        } else {
            const ::osg::Vec3d eye = camera->getInverseViewMatrix().getTrans();
            // The update visitor's path runs from the root to `node`: drop `node` itself, whose
            // own transform the collector applies.
            ::osg::NodePath parents = nv->getNodePath();
            if (!parents.empty() && parents.back() == node) parents.pop_back();
            error_ = update(*node, ::osg::computeLocalToWorld(parents, true),
                            glm::dvec3(eye.x(), eye.y(), eye.z()));
            if (error_) error_ = from(kOperator, *error_);
        }
        if (error_ && !warned_) {
            OSG_WARN << "aerial::osg_adapter: " << error_->message << std::endl;
            warned_ = true;
        }
    }
    traverse(node, nv);
}

std::optional<Error> ScatteringCallback::update_now(::osg::Node& node, const glm::dvec3& eye) {
    ::osg::Matrixd parent_to_world;  // identity for a root
    const ::osg::NodePathList paths = node.getParentalNodePaths();
    if (!paths.empty()) {
        ::osg::NodePath parents = paths.front();
        if (!parents.empty() && parents.back() == &node) parents.pop_back();
        parent_to_world = ::osg::computeLocalToWorld(parents, true);
    }
    error_ = update(node, parent_to_world, eye);
    return error_;
}

std::optional<Error> ScatteringCallback::update(::osg::Node& node,
                                                const ::osg::Matrixd& parent_to_world,
                                                const glm::dvec3& eye) {
    report_ = UpdateReport{};
    View view;
    view.eye = eye;
    view.sun_dir = settings_.sun_dir;
    view.up = settings_.up;
    view.meters_per_unit = settings_.meters_per_unit;
    auto frame = prepare_frame<float>(settings_.atmosphere, view, settings_.model);
    if (!frame) return from(kUpdateNow, frame.error());  // "eye" when the camera is not finite
    prepare_state(node);
    CollectGeometry collect(parent_to_world);
    node.accept(collect);
    report_.geometries = collect.entries.size();
    for (std::size_t i = 0; i < collect.entries.size(); ++i) {
        ::osg::Geometry& g = *collect.entries[i].geometry;
        const ::osg::Matrixd& to_world = collect.entries[i].to_world;
        auto* vertices = dynamic_cast<::osg::Vec3Array*>(g.getVertexArray());
        if (!vertices) {
            return invalid(kUpdateNow, "vertices",
                           "an osg::Vec3Array vertex array (3 floats a vertex)",
                           geometry_name(g, i) + " without one");
        }
        const std::size_t n = vertices->size();
        report_.vertices += n;
        if (settings_.backend == Backend::arb) {
            if (!to_world.isIdentity()) {
                Transformed& t = transformed(g);
                const ::osg::Matrixf model(to_world);
                t.rows = arb_model_matrix_parameters(model.ptr());
                t.seen = true;
            }
            continue;
        }
        if (n == 0) continue;
        // Model-space vertices with their matrix: no world copy. OSG's matrices multiply row
        // vectors, so their storage is the column-major array of the column-vector matrix.
        Positions positions = Positions::aos(&(*vertices)[0].x(), n);
        const ::osg::Matrixf model(to_world);
        if (!to_world.isIdentity()) positions.model_matrix = model.ptr();
        auto* primary = dynamic_cast<::osg::Vec4ubArray*>(g.getColorArray());
        if (!primary || primary->size() != n) {
            primary = new ::osg::Vec4ubArray(unsigned(n));
            primary->setNormalize(true);
            g.setColorArray(primary, ::osg::Array::BIND_PER_VERTEX);
        }
        auto* secondary = dynamic_cast<::osg::Vec3ubArray*>(g.getSecondaryColorArray());
        if (!secondary || secondary->size() != n) {
            secondary = new ::osg::Vec3ubArray(unsigned(n));
            secondary->setNormalize(true);
            g.setSecondaryColorArray(secondary, ::osg::Array::BIND_PER_VERTEX);
        }
        g.setDataVariance(::osg::Object::DYNAMIC);
        // Display lists would freeze the colours; buffer objects follow Array::dirty().
        if (g.getUseDisplayList()) {
            g.setUseDisplayList(false);
            g.setUseVertexBufferObjects(true);
        }
        secondary_.resize(4 * n);
        BatchOutputs out;
        out.extinction_rgba8 = &(*primary)[0].r();
        out.in_scattering_rgba8 = secondary_.data();
        BatchSettings batch;
        batch.display = settings_.display;
        batch.kernel = settings_.kernel;
        batch.threads = settings_.threads;
        auto stats = shade_into(*frame, positions, out, batch);
        if (!stats) return from(kUpdateNow, stats.error());
        report_.invalid_vertices += stats->invalid_vertices;
        for (std::size_t v = 0; v < n; ++v) {
            (*secondary)[v].set(secondary_[4 * v], secondary_[4 * v + 1], secondary_[4 * v + 2]);
        }
        primary->dirty();
        secondary->dirty();
    }
    if (settings_.backend == Backend::arb) {
        auto parameters = arb_program_parameters(*frame, settings_.display, program_.options);
        if (!parameters) return from(kUpdateNow, parameters.error());
        const GLuint base = GLuint(program_.options.parameter_base);
        const auto set = [&](::osg::VertexProgram& vp) {
            for (std::size_t i = 0; i < parameters->size(); ++i) {
                const auto& p = (*parameters)[i];
                vp.setProgramLocalParameter(base + GLuint(i), ::osg::Vec4(p[0], p[1], p[2], p[3]));
            }
        };
        set(*vertex_program_);  // the identity's model rows: world-space Geometries
        const GLuint rows = GLuint(arb_model_matrix_parameter_index(program_.options));
        for (Transformed& t : transformed_) {
            if (!t.seen) continue;
            set(*t.program);
            for (GLuint r = 0; r < 3; ++r) {
                const auto& row = t.rows[r];
                t.program->setProgramLocalParameter(rows + r,
                                                    ::osg::Vec4(row[0], row[1], row[2], row[3]));
            }
            t.seen = false;
        }
    }
    return std::nullopt;
}

ScatteringCallback::Transformed& ScatteringCallback::transformed(::osg::Geometry& geometry) {
    for (Transformed& t : transformed_) {
        if (t.geometry == &geometry) return t;
    }
    Transformed t;
    t.geometry = &geometry;
    t.program = new ::osg::VertexProgram;
    t.program->setVertexProgram(program_.text);
    // Compiling this Geometry's display list with its own vertex program crashed inside Mesa's
    // llvmpipe (EGL, OSG 3.6, test_osg_adapter); buffer objects draw the same colours.
    if (geometry.getUseDisplayList()) {
        geometry.setUseDisplayList(false);
        geometry.setUseVertexBufferObjects(true);
    }
    geometry.getOrCreateStateSet()->setAttributeAndModes(t.program.get(),
                                                         ::osg::StateAttribute::ON);
    transformed_.push_back(t);
    return transformed_.back();
}

void ScatteringCallback::remove_transformed_programs() {
    for (Transformed& t : transformed_) {
        ::osg::ref_ptr<::osg::Geometry> geometry;
        if (t.geometry.lock(geometry) && geometry->getStateSet()) {
            geometry->getStateSet()->removeAttribute(t.program.get());
        }
    }
    transformed_.clear();
}

void ScatteringCallback::prepare_state(::osg::Node& node) {
    ::osg::StateSet* state = node.getOrCreateStateSet();
    state->setDataVariance(::osg::Object::DYNAMIC);
    state->setMode(GL_COLOR_SUM, ::osg::StateAttribute::ON);
    state->setMode(GL_LIGHTING, ::osg::StateAttribute::OFF);
    for (int u = 0; u < settings_.texture_units; ++u) {
        if (!state->getTextureAttribute(unsigned(u), ::osg::StateAttribute::TEXENV)) {
            state->setTextureAttribute(unsigned(u), new ::osg::TexEnv(::osg::TexEnv::MODULATE));
        }
    }
    ::osg::StateAttribute* current = state->getAttribute(::osg::StateAttribute::VERTEXPROGRAM);
    if (settings_.backend == Backend::arb) {
        if (!vertex_program_) {
            vertex_program_ = new ::osg::VertexProgram;
            vertex_program_->setVertexProgram(program_.text);
        }
        if (current != vertex_program_.get()) {
            state->setAttributeAndModes(vertex_program_.get(), ::osg::StateAttribute::ON);
        }
    } else {
        if (current && current == installed_program_.get()) {
            state->removeAttribute(current);  // ours, from an earlier arb setting
        }
        remove_transformed_programs();
    }
    installed_program_ = settings_.backend == Backend::arb ? vertex_program_ : nullptr;
}

}  // namespace aerial::osg_adapter
