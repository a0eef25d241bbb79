#pragma once
// Surface scenes made in code: the Cornell box, the furnace, and a default-material scene for a
// surface read from a file. Names for the CLI: "cornell-box", "furnace:A[:LE]".
#include <cstdint>
#include <string>

#include "scene/surface_mesh.hpp"
#include "scene/surface_scene.hpp"

namespace prismoid {

// The Cornell box with its two blocks, in millimetres, with its camera (278, 273, -800) looking
// along +z, focal length 35 mm on a 25 mm film: fovy = 2 atan(12.5 / 35) = 39.31 degrees.
// Geometry and camera: the Cornell University Program of Computer Graphics, "Cornell Box Data"
// (https://www.graphics.cornell.edu/online/box/data.html). That page gives reflectances as
// spectra; the RGB values here are the common reduction of them used in B. Bitterli's
// "Rendering Resources" (2016) cornell-box scene: white (0.725, 0.71, 0.68), red
// (0.63, 0.065, 0.05), green (0.14, 0.45, 0.091), light radiance (17, 12, 4), light albedo 0.78.
// One change: the published light lies in the ceiling's plane (y = 548.8); here it hangs
// kCornellLightDrop below it so the two never coincide. The light's winding faces down; the box
// is open at the front (z = 0), where the sky is black. Materials: 0 white, 1 red (left wall,
// x ~ 556), 2 green (right wall, x = 0), 3 light.
inline constexpr double kCornellLightDrop = 0.1;
SurfaceScene make_cornell_box();

// The furnace: a closed icosphere of radius 1 about the origin (20 * 4^subdivisions triangles),
// every triangle wound to face the centre, diffuse albedo `albedo` in [0, 1) and uniform
// emission `emission` on its inner side; the camera sits at the centre (fovy 90, looking down
// -z). Every ray from inside hits the surface, so the radiance everywhere inside is exactly
// furnace_radiance(albedo, emission) = emission / (1 - albedo), whatever the tessellation.
SurfaceScene make_furnace(double albedo, double emission = 1.0, uint32_t subdivisions = 3);
inline double furnace_radiance(double albedo, double emission) { return emission / (1.0 - albedo); }

// A surface read from a file, with the default material (kDefaultSurfaceMaterial), flat
// shading, a camera framing it from +z (fit_camera), and no lights: renderers apply
// with_default_lighting with the camera they render from.
SurfaceMaterial default_surface_material();
SurfaceScene make_surface_scene(const SurfaceMesh& surface);

// "cornell-box" or "furnace:A" / "furnace:A:LE" (albedo A in [0, 1), emission LE > 0,
// default 1). is_named_surface_scene says whether a string is meant as one of these names (it
// may still be malformed); make_named_surface_scene throws InputError for a malformed one.
bool is_named_surface_scene(const std::string& spec);
SurfaceScene make_named_surface_scene(const std::string& spec);

}  // namespace prismoid
