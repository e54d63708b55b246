// An OpenSceneGraph application built against the installed osg component: makes the adapter's
// callback for a cpu-backend setting and shades a Geometry below a transform. Exits 0 on success.
#include <cstdio>

#include <aerial/osg.hpp>
#include <osg/Geometry>
#include <osg/MatrixTransform>

int main() {
    aerial::osg_adapter::Settings settings;
    auto callback = aerial::osg_adapter::ScatteringCallback::create(settings, nullptr);
    if (!callback) {
        std::fprintf(stderr, "consumer_osg: %s\n", callback.error().message.c_str());
        return 1;
    }
    osg::ref_ptr<osg::Geometry> geometry = new osg::Geometry;
    osg::ref_ptr<osg::Vec3Array> vertices = new osg::Vec3Array;
    vertices->push_back({1000.0f, 0.0f, 10.0f});
    vertices->push_back({20000.0f, 5000.0f, 10.0f});
    geometry->setVertexArray(vertices.get());
    osg::ref_ptr<osg::MatrixTransform> node = new osg::MatrixTransform;
    node->setMatrix(osg::Matrixd::translate(0.0, 100.0, 0.0));
    node->addChild(geometry.get());
    if (auto error = callback.value()->update_now(*node, glm::dvec3(0.0, 0.0, 50.0))) {
        std::fprintf(stderr, "consumer_osg: %s\n", error->message.c_str());
        return 1;
    }
    std::printf("consumer_osg: %zu vertices shaded\n", callback.value()->last_report().vertices);
    return callback.value()->last_report().vertices == 2 ? 0 : 1;
}
