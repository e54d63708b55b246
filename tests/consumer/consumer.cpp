// A C++ engine built against the installed package: one call into each exported library.
#include <cstdio>

#include <aerial/aerial.hpp>
#include <aerial/arb_program.hpp>
#include <aerial/mesh.hpp>
#include <aerial/scene.hpp>

int main() {
    auto atmosphere = aerial::atmosphere_preset("hazy");
    aerial::View view;
    view.eye = {0, 0, 50};
    view.sun_dir = {0, 0.6, 0.8};
    auto frame = aerial::prepare_frame<float>(*atmosphere, view, aerial::Model::height);
    if (!frame) return 1;
    const aerial::Scattering<float> s = aerial::scatter(*frame, glm::vec3(20000, 5000, 10));
    auto program = aerial::generate_arb_program({});  // aerial::gl
    auto dome = aerial::mesh::geodesic_dome(2);       // aerial::mesh
    auto root = aerial::scene::make_group("world");   // aerial::scene
    if (!program || !dome || !root) return 1;
    std::printf(
        "consumer_cpp: F_ex %.4f %.4f %.4f, L_in %.4f %.4f %.4f, ARB program %d "
        "instructions, dome %zu vertices\n",
        s.extinction.r, s.extinction.g, s.extinction.b, s.in_scattering.r, s.in_scattering.g,
        s.in_scattering.b, program->instruction_count, aerial::mesh::live_vertices(*dome));
    return s.extinction.b < s.extinction.r && s.in_scattering.b > 0.0f ? 0 : 1;
}
