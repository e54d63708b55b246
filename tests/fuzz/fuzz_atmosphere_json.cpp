// libFuzzer target: the atmosphere JSON parser (aerial::atmosphere_from_json). An accepted
// atmosphere must pass validate(), survive to_json and back unchanged, and give finite F_ex,
// L_in and E_sun in every model at a few vertices.
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "aerial/atmosphere.hpp"
#include "aerial/scattering.hpp"
#include "fuzz_check.hpp"

namespace {

/// Without the higher orders' table: a fuzzed atmosphere can take minutes to tabulate
/// (aerial::FrameOptions); the term's math is fuzzed through the stability sweeps.
const aerial::FrameOptions kNoTables{false};

using aerial::fuzz::check;
using aerial::fuzz::finite;

template <class T>
void check_models(const aerial::Atmosphere& atmosphere) {
    aerial::View view;
    view.eye = {0.0, 0.0, 2.0};
    view.sun_dir = {0.0, 0.8660254037844386, 0.5};
    const glm::vec<3, T> vertices[] = {{T(0), T(1000), T(2)},
                                       {T(0), T(50000), T(0)},
                                       {T(0), T(-20000), T(3000)},
                                       {T(2), T(2), T(2)}};
    for (aerial::Model model : aerial::all_models()) {
        // `reference` computes its tables per atmosphere (seconds): checked below at the
        // smallest resolution instead.
        if (model == aerial::Model::reference) continue;
        auto frame = aerial::prepare_frame<T>(atmosphere, view, model, kNoTables);
        if (!frame) continue;
        // The numerical models integrate per vertex: one vertex keeps an input fast.
        const int count = aerial::is_numerical(model) ? 1 : 4;
        for (int i = 0; i < count; ++i) {
            const auto s = aerial::scatter(*frame, vertices[i]);
            check(finite(s.extinction) && finite(s.in_scattering) && finite(s.sun_irradiance),
                  "non-finite scattering from an accepted atmosphere");
        }
    }
    if constexpr (sizeof(T) == sizeof(double)) {
        // `reference` with its smallest tables: the solver and the lookup, not their accuracy.
        aerial::ReferenceOptions smallest;
        smallest.multiple_scattering = true;
        smallest.tables = {4, 4, 5, 3, 2, 2, 2, 0.5, 1e-2, 3};
        const auto s = aerial::reference_scattering(atmosphere, view, {0.0, 1000.0, 2.0}, smallest);
        check(finite(s.extinction) && finite(s.in_scattering) && finite(s.sun_irradiance),
              "non-finite reference scattering from an accepted atmosphere");
    }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string_view text(reinterpret_cast<const char*>(data), size);
    auto atmosphere = aerial::atmosphere_from_json(text);
    if (!atmosphere) {
        check(!atmosphere.error().message.empty(), "an error without a message");
        return 0;
    }
    check(!aerial::validate(*atmosphere), "atmosphere_from_json accepted an invalid atmosphere");
    auto again = aerial::atmosphere_from_json(aerial::to_json(*atmosphere));
    check(again.ok(), "to_json wrote an atmosphere atmosphere_from_json rejects");
    check(*atmosphere == *again, "to_json and back changed the atmosphere");
    check_models<float>(*atmosphere);
    check_models<double>(*atmosphere);
    return 0;
}
