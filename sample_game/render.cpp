#include "render.hpp"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <thread>

#include <glm/geometric.hpp>

namespace sample {
namespace {

constexpr double kPi = aerial::kPi;
/// First sample of a column march, m from the eye (horizontally).
constexpr double kNearM = 1.0;
/// March step: at least this many metres, and at least this fraction of the distance so far.
constexpr double kMinStepM = 2.0;
constexpr double kRelativeStep = 0.0025;
/// Bisection steps that place a hit between the last two samples of a march.
constexpr int kRefineSteps = 10;
/// Angular radius of the sun seen from the earth, rad; its disk adds E_sun F_ex / solid angle.
constexpr double kSunAngularRadius = 0.004654;
/// Directions averaged (cosine-weighted, stratified) for the ambient sky irradiance.
constexpr int kSkyStrata = 8;

/// Sky irradiance on a level surface at the eye, pi times the cosine-weighted mean of L_in
/// over the upper hemisphere (terrain occlusion ignored).
glm::vec3 sky_irradiance(const aerial::Frame<float>& frame, const glm::dvec3& eye_m) {
    glm::dvec3 sum{0.0};
    for (int i = 0; i < kSkyStrata; ++i) {
        for (int j = 0; j < kSkyStrata; ++j) {
            const double r = std::sqrt((i + 0.5) / kSkyStrata);  // sin(zenith angle)
            const double phi = 2.0 * kPi * (j + 0.5) / kSkyStrata;
            const glm::dvec3 dir{r * std::cos(phi), r * std::sin(phi), std::sqrt(1.0 - r * r)};
            const glm::vec3 far_point(eye_m + dir * kSkyDistanceM);
            sum += glm::dvec3(aerial::scatter(frame, far_point).in_scattering);
        }
    }
    return glm::vec3(kPi * sum / double(kSkyStrata * kSkyStrata));
}

struct ColumnRenderer {
    const RenderSettings& settings;
    const aerial::Frame<float>& frame;
    glm::dvec3 eye_m;
    glm::vec3 sky_irradiance;
    std::vector<Pixel>& pixels;

    /// Marches one image column bottom-up. Rays of a column share a vertical plane and climb
    /// with the row, so the first hit of a row is never nearer (horizontally) than the one
    /// below it: each column is one sweep of samples, not one per pixel.
    void operator()(int column) const {
        const Camera& cam = settings.camera;
        const double tan_half_fov = std::tan(0.5 * cam.horizontal_fov_rad);
        const double aspect = double(settings.height) / settings.width;
        const double pixel_angle = 2.0 * tan_half_fov / settings.width;  // rad, at the centre
        const glm::dvec3 forward{std::sin(cam.heading_rad), std::cos(cam.heading_rad), 0.0};
        const glm::dvec3 right{std::cos(cam.heading_rad), -std::sin(cam.heading_rad), 0.0};
        const double u = (2.0 * (column + 0.5) / settings.width - 1.0) * tan_half_fov;
        const glm::dvec3 heading = glm::normalize(forward + u * right);
        const double heading_norm = std::sqrt(1.0 + u * u);
        const double radius_m = settings.atmosphere.planet_radius_m;

        const auto footprint = [&](double rho) { return std::max(0.5, rho * pixel_angle); };
        // Height of the ray above the surface at horizontal distance rho; <= 0 is a hit.
        const auto clearance = [&](double rho, double slope) {
            const glm::dvec3 q = eye_m + heading * rho;
            return eye_m.z + slope * rho - surface_z_m(q.x, q.y, footprint(rho), radius_m);
        };

        double rho = kNearM, rho_before = 0.0;
        for (int row = settings.height - 1; row >= 0; --row) {
            const double v =
                (2.0 * cam.horizon_row_fraction - 2.0 * (row + 0.5) / settings.height) *
                tan_half_fov * aspect;
            const double slope = v / heading_norm;  // rise per metre of horizontal distance
            while (rho <= kSkyDistanceM && clearance(rho, slope) > 0.0) {
                rho_before = rho;
                rho += std::max(kMinStepM, kRelativeStep * rho);
            }
            Pixel& pixel = pixels[size_t(row) * settings.width + column];
            if (rho <= kSkyDistanceM) {
                double lo = rho_before, hi = rho;
                for (int i = 0; i < kRefineSteps; ++i) {
                    const double mid = 0.5 * (lo + hi);
                    (clearance(mid, slope) > 0.0 ? lo : hi) = mid;
                }
                shade_ground(pixel, heading, slope, hi, footprint(hi));
            } else {
                shade_sky(pixel, glm::normalize(heading + slope * glm::dvec3(0.0, 0.0, 1.0)));
            }
        }
    }

    void shade_ground(Pixel& pixel, const glm::dvec3& heading, double slope, double rho,
                      double footprint_m) const {
        const glm::dvec3 point = eye_m + heading * rho + glm::dvec3(0.0, 0.0, slope * rho);
        const double height_m = terrain_height_m(point.x, point.y, footprint_m);
        pixel.surface = height_m > 0.0 ? Surface::ground : Surface::water;
        const glm::dvec3 normal = pixel.surface == Surface::water
                                      ? glm::dvec3(0.0, 0.0, 1.0)
                                      : terrain_normal(point.x, point.y, footprint_m);
        const glm::vec3 albedo(terrain_albedo(pixel.surface, height_m, normal));

        pixel.scattering = aerial::scatter(frame, glm::vec3(point));
        pixel.distance_m = float(glm::length(point - eye_m));
        const float cos_sun = float(std::max(0.0, glm::dot(normal, settings.sun_dir)));
        const glm::vec3 irradiance = pixel.scattering.sun_irradiance * cos_sun + sky_irradiance;
        const glm::vec3 surface_radiance = albedo * irradiance * float(1.0 / kPi);
        pixel.radiance =
            surface_radiance * pixel.scattering.extinction + pixel.scattering.in_scattering;
    }

    void shade_sky(Pixel& pixel, const glm::dvec3& direction) const {
        pixel.surface = Surface::sky;
        pixel.scattering = aerial::scatter(frame, glm::vec3(eye_m + direction * kSkyDistanceM));
        pixel.distance_m = float(kSkyDistanceM);
        pixel.radiance = pixel.scattering.in_scattering;
        if (glm::dot(direction, settings.sun_dir) >= std::cos(kSunAngularRadius)) {
            const double solid_angle = 2.0 * kPi * (1.0 - std::cos(kSunAngularRadius));
            pixel.radiance += glm::vec3(settings.atmosphere.sun_irradiance / solid_angle) *
                              pixel.scattering.extinction;
        }
    }
};

}  // namespace

aerial::Result<Image> render(const RenderSettings& settings) {
    const auto start = std::chrono::steady_clock::now();
    const Camera& cam = settings.camera;
    aerial::View view;
    view.eye = {cam.x_m, cam.y_m,
                terrain_height_m(cam.x_m, cam.y_m, 0.5) + cam.height_above_ground_m};
    view.sun_dir = settings.sun_dir;
    view.up = {0.0, 0.0, 1.0};
    auto frame = aerial::prepare_frame<float>(settings.atmosphere, view, settings.model);
    if (!frame) return frame.error();

    Image image;
    image.width = settings.width;
    image.height = settings.height;
    image.eye_m = view.eye;
    image.pixels.resize(size_t(settings.width) * settings.height);
    image.sky_irradiance = sky_irradiance(*frame, view.eye);

    const ColumnRenderer renderer{settings, *frame, view.eye, image.sky_irradiance, image.pixels};
    std::atomic<int> next_column{0};
    const auto work = [&] {
        for (int c = next_column++; c < settings.width; c = next_column++) renderer(c);
    };
    std::vector<std::thread> workers;
    for (int t = 1; t < settings.threads; ++t) workers.emplace_back(work);
    work();
    for (std::thread& w : workers) w.join();

    image.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return image;
}

}  // namespace sample
