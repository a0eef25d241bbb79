#pragma once
// A scene of shaded triangle surfaces as plain data: meshes, materials, lights, a sky and the
// camera. Every surface backend and the CPU path tracer (renderer/reference/path_tracer.hpp)
// read the same struct, so they shade the same thing.
//
// Units and conventions (all backends follow them):
//  - Radiance in linear RGB. A material's `emission` is the radiance leaving its surface on the
//    front side only: the side the triangle's winding normal (v1 - v0) x (v2 - v0) points to.
//  - Reflection is two-sided: a ray reaching a triangle's back sees the same BSDF with the
//    normal turned towards it.
//  - BSDF = diffuse albedo / pi + GGX specular (Walter et al. 2007) with Schlick's Fresnel from
//    `specular_f0`, Smith's height-correlated masking-shadowing (Heitz 2014) and
//    alpha = roughness^2 (Burley 2012), alpha clamped below at kMinGgxAlpha. The two lobes are
//    simply added; the diffuse albedo is the material's albedo times the mesh's colour there.
//  - Point light: radiant intensity I (radiance-like RGB units per steradian): irradiance
//    I cos(theta) / r^2. Directional light: irradiance E on a surface facing it.
//  - Sky: radiance seen along directions that leave the scene (see Sky::radiance).
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include "scene/bounds.hpp"
#include "scene/camera.hpp"

namespace prismoid {

inline constexpr double kMinGgxAlpha = 1e-3;

struct SurfaceMaterial {
  std::string name;
  glm::dvec3 albedo{0.8};        // Lambertian reflectance per channel, in [0, 1]
  glm::dvec3 specular_f0{0.0};   // GGX Fresnel reflectance at normal incidence, in [0, 1]
  double roughness = 0.5;        // in [0, 1]; GGX alpha = roughness^2
  glm::dvec3 emission{0.0};      // radiance from the front side, >= 0
};

// Where a mesh's colours live. The colour multiplies the material's albedo (callers map a data
// array through a transfer function into it).
enum class ColorBinding { None, PerVertex, PerTriangle };

struct SceneMesh {
  std::string name;
  std::vector<glm::dvec3> positions;
  std::vector<std::array<uint32_t, 3>> triangles;
  std::vector<glm::dvec3> normals;  // empty (flat shading), or one shading normal per position
  ColorBinding color_binding = ColorBinding::None;
  std::vector<glm::dvec3> colors;   // per position or per triangle, as color_binding says
  uint32_t material = 0;            // index into SurfaceScene::materials
};

struct PointLight {
  glm::dvec3 position{0.0};
  glm::dvec3 intensity{1.0};
};

struct DirectionalLight {
  glm::dvec3 direction{0.0, -1.0, 0.0};  // the way the light travels (need not be unit length)
  glm::dvec3 irradiance{1.0};
};

// radiance(d) = bottom + (top - bottom) * (1 + dot(d, up)) / 2 for a unit direction d: a
// constant sky when top == bottom, else a smooth gradient from straight down to straight up.
struct Sky {
  glm::dvec3 top{0.0};
  glm::dvec3 bottom{0.0};
  glm::dvec3 up{0.0, 1.0, 0.0};
  glm::dvec3 radiance(const glm::dvec3& unit_direction) const;
  bool black() const;
};

struct SurfaceScene {
  std::string name;
  std::vector<SceneMesh> meshes;
  std::vector<SurfaceMaterial> materials;
  std::vector<PointLight> point_lights;
  std::vector<DirectionalLight> directional_lights;
  Sky sky;
  Camera camera;
};

// InputError(scene.name, ...) for a scene that cannot be shaded: an index out of range, a
// count that does not match its binding, a non-finite value, an albedo/F0/roughness outside
// [0, 1], negative emission or light power, a zero light direction or sky up vector, no
// materials while there are meshes.
void validate(const SurfaceScene& scene);

// The largest radiometric value (emission, sky radiance, light intensity or irradiance) a scene
// may hold for rendering: float32's largest value over 2^32. The GPU uploads and sums these in
// float32, and every image is float32; a pixel's radiance is such a value times what the
// geometry and the materials bring (BRDF peaks, solid angles, 1/d^2 of a point light, sums
// over lights and bounces: the path tracer's furnace gives Le / (1 - A)), for which 2^32 is the
// headroom kept.
inline constexpr double kMaxRadiometricValue = 3.4028234663852886e38 / 4294967296.0;
// InputError(scene.name, ...) naming the first value above kMaxRadiometricValue, its size and
// the limit: decided from the scene before anything is shaded.
void validate_float_range(const SurfaceScene& scene);

// Bounds of all mesh positions (a point at the origin for an empty scene).
Bounds bounds_of(const SurfaceScene& scene);

// True when something in the scene gives light: a point or directional light with non-zero
// power, a non-degenerate triangle whose material emits, or a sky that is not black.
bool has_light(const SurfaceScene& scene);

// The "never black" rule: a scene without light (has_light false) gets a light rig that shows
// form: a key light and a sky, so every surface the camera sees is lit. The key light is
// directional, arriving from above the camera and to its left (its travel direction is the view
// direction turned by kKeyDown towards the camera's down and kKeySide towards its right, about
// 40 degrees off the view axis): surfaces turned towards it are bright, the others darker, and
// it casts shadows beside and below what it lights, where the camera sees them (a headlight's
// fall behind the objects, out of sight). Its irradiance is pi * kHeadlightScale (a white diffuse
// surface facing it has radiance kHeadlightScale). The sky is kDefaultSkyTop above,
// kDefaultSkyBottom below (up = the camera's up), the fill in the key light's shadows. Scenes
// with light are returned unchanged.
inline constexpr double kHeadlightScale = 0.8;
inline constexpr double kKeyDown = 0.7, kKeySide = 0.45;
inline constexpr double kDefaultSkyTop = 0.3;
inline constexpr double kDefaultSkyBottom = 0.1;
// The default key light's travel direction for a camera (unit length).
glm::dvec3 default_key_direction(const Camera& camera);
SurfaceScene with_default_lighting(SurfaceScene scene, const Camera& camera);

}  // namespace prismoid
