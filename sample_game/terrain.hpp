// sample_game/terrain.hpp — a procedural landscape to look at: value-noise hills and ridged
// mountains around a sea at altitude 0, bent down by the planet's curvature so that it has a
// real horizon.
//
// How to use this:
//   1. `terrain_height_m(x, y, footprint_m)` is the height above sea level (>= 0, the sea is
//      flat) of the ground at horizontal position (x, y), metres, z up. `footprint_m` is the size
//      of the area one sample stands for: octaves finer than it are left out (no aliasing far
//      away, and less work).
//   2. `surface_z_m` adds the curvature drop, so that the world position of the surface is
//      (x, y, surface_z_m(...)) on the sphere that aerial::scattering uses (planet centre at
//      -planet_radius_m * up, sea level through the origin).
//   3. `terrain_normal` and `terrain_albedo` give what a shader needs.
#pragma once

#include <glm/vec3.hpp>

namespace sample {

/// What the ground is made of at a point, for shading and for the CSV.
enum class Surface { sky, ground, water };

/// Height of the ground above sea level at (x_m, y_m), metres, >= 0.
double terrain_height_m(double x_m, double y_m, double footprint_m);

/// World z of the surface at (x_m, y_m): terrain height minus the drop of the sphere of radius
/// planet_radius_m below the tangent plane at the origin, (x^2 + y^2) / (2 R).
double surface_z_m(double x_m, double y_m, double footprint_m, double planet_radius_m);

/// Unit normal of the terrain height field (the sea is flat), z up.
glm::dvec3 terrain_normal(double x_m, double y_m, double footprint_m);

/// Diffuse albedo (linear RGB, 0..1): grass on gentle slopes, rock on steep ones, snow on high
/// gentle ground, dark water at sea level.
glm::dvec3 terrain_albedo(Surface surface, double height_m, const glm::dvec3& normal);

}  // namespace sample
