#include "renderer/volume/analytic_field.hpp"

#include <algorithm>
#include <cmath>
#include <glm/geometric.hpp>
#include <limits>
#include <numbers>

#include "scene/generators.hpp"
#include "scene/input_error.hpp"
#include "scene/tet_mesh.hpp"

namespace prismoid::volume {

namespace {

constexpr double kPi = std::numbers::pi;

double marschner_lobb_value(double f_m, double alpha, const glm::dvec3& p) {
  const double r = std::sqrt(p.x * p.x + p.y * p.y);
  const double radial = std::cos(2.0 * kPi * f_m * std::cos(kPi * r / 2.0));
  return (1.0 - std::sin(kPi * p.z / 2.0) + alpha * (1.0 + radial)) / (2.0 * (1.0 + alpha));
}

glm::dvec3 marschner_lobb_gradient(double f_m, double alpha, const glm::dvec3& p) {
  const double r = std::sqrt(p.x * p.x + p.y * p.y);
  const double g = 2.0 * kPi * f_m * std::cos(kPi * r / 2.0);
  // d/dr of cos(g) is sin(g) pi^2 f_M sin(pi r / 2); d r / d x = x / r, and sin(pi r/2) / r -> pi/2.
  const double sin_over_r = r > 1e-12 ? std::sin(kPi * r / 2.0) / r : kPi / 2.0;
  const double radial = alpha * std::sin(g) * kPi * kPi * f_m * sin_over_r;
  const double scale = 1.0 / (2.0 * (1.0 + alpha));
  return scale * glm::dvec3(radial * p.x, radial * p.y, -kPi / 2.0 * std::cos(kPi * p.z / 2.0));
}

}  // namespace

double evaluate(const AnalyticField& field, const glm::dvec3& p) {
  switch (field.kind) {
    case FieldKind::Linear: return glm::dot(glm::dvec3(field.params[0]), p) + field.params[0].w;
    case FieldKind::MarschnerLobb: return marschner_lobb_value(field.params[0].x, field.params[0].y, p);
    case FieldKind::GaussianBlobs: {
      double sum = 0.0;
      for (const glm::dvec4& b : field.params) {
        const glm::dvec3 d = p - glm::dvec3(b);
        sum += std::exp(-glm::dot(d, d) / (2.0 * b.w * b.w));
      }
      return sum;
    }
    case FieldKind::Grid: return evaluate(*field.grid, p);
  }
  return 0.0;
}

glm::dvec3 gradient(const AnalyticField& field, const glm::dvec3& p) {
  switch (field.kind) {
    case FieldKind::Linear: return glm::dvec3(field.params[0]);
    case FieldKind::MarschnerLobb: return marschner_lobb_gradient(field.params[0].x, field.params[0].y, p);
    case FieldKind::GaussianBlobs: {
      glm::dvec3 sum(0.0);
      for (const glm::dvec4& b : field.params) {
        const glm::dvec3 d = p - glm::dvec3(b);
        sum -= d / (b.w * b.w) * std::exp(-glm::dot(d, d) / (2.0 * b.w * b.w));
      }
      return sum;
    }
    case FieldKind::Grid: return gradient(*field.grid, p);
  }
  return glm::dvec3(0.0);
}

double second_derivative_bound(const AnalyticField& field) {
  switch (field.kind) {
    case FieldKind::Linear: return 0.0;
    case FieldKind::MarschnerLobb: {
      // The Hessian is block diagonal: z alone (|d2/dz2| <= pi^2/4) and the radial term of
      // (x, y), whose eigenvalues are h''(r) and h'(r)/r for h = cos(2 pi f_M cos(pi r / 2)):
      // |h''| <= (pi^2 f_M)^2 + pi^3 f_M / 2 and |h'/r| <= pi^3 f_M / 2.
      const double f_m = field.params[0].x, alpha = field.params[0].y;
      const double radial = std::pow(kPi * kPi * f_m, 2) + kPi * kPi * kPi * f_m / 2.0;
      return std::max(kPi * kPi / 4.0, alpha * radial) / (2.0 * (1.0 + alpha));
    }
    case FieldKind::GaussianBlobs: {
      // One blob's Hessian is f (d d^T / w^4 - I / w^2): along u, f ((d.u)^2 / w^2 - 1) / w^2,
      // between -1/w^2 (at the centre) and 2 / (e w^2) (at |d| = sqrt(2) w).
      double sum = 0.0;
      for (const glm::dvec4& b : field.params) sum += 1.0 / (b.w * b.w);
      return sum;
    }
    case FieldKind::Grid: return std::numeric_limits<double>::infinity();
  }
  return 0.0;
}

std::optional<AnalyticField> translated(const AnalyticField& field, const glm::dvec3& origin) {
  AnalyticField moved = field;
  switch (field.kind) {
    case FieldKind::Linear: moved.params[0].w += glm::dot(glm::dvec3(field.params[0]), origin); return moved;
    case FieldKind::GaussianBlobs:
      for (glm::dvec4& b : moved.params) b = glm::dvec4(glm::dvec3(b) - origin, b.w);
      return moved;
    case FieldKind::Grid: {
      auto grid = std::make_shared<SampledGrid>(*field.grid);
      grid->origin -= origin;
      moved.grid = std::move(grid);
      return moved;
    }
    case FieldKind::MarschnerLobb: return std::nullopt;
  }
  return std::nullopt;
}

std::optional<AnalyticField> placed(const AnalyticField& field, const glm::dvec3& origin, double scale) {
  AnalyticField moved = field;
  switch (field.kind) {
    case FieldKind::Linear: {
      const glm::dvec3 g(field.params[0]);
      moved.params[0] = glm::dvec4(g * scale, field.params[0].w + glm::dot(g, origin));
      return moved;
    }
    case FieldKind::GaussianBlobs:
      for (glm::dvec4& b : moved.params) b = glm::dvec4((glm::dvec3(b) - origin) / scale, b.w / scale);
      return moved;
    case FieldKind::Grid:
    case FieldKind::MarschnerLobb: return std::nullopt;
  }
  return std::nullopt;
}

AnalyticField marschner_lobb(double f_m, double alpha) {
  return {"marschner-lobb", FieldKind::MarschnerLobb, {glm::dvec4(f_m, alpha, 0.0, 0.0)}};
}

AnalyticField gaussian_blobs(const std::vector<glm::dvec4>& blobs) { return {"blobs", FieldKind::GaussianBlobs, blobs}; }

AnalyticField linear_field(const glm::dvec3& g, double value_at_origin) {
  return {"linear", FieldKind::Linear, {glm::dvec4(g, value_at_origin)}};
}

AnalyticField grid_field(std::shared_ptr<const SampledGrid> grid) {
  AnalyticField f{grid ? grid->name : "grid", FieldKind::Grid, {}, nullptr};
  f.grid = std::move(grid);
  return f;
}

SampledGrid sample_onto_grid(const AnalyticField& field, const glm::uvec3& dims, const glm::dvec3& lo, const glm::dvec3& hi) {
  validate(field);
  SampledGrid grid;
  grid.name = field.name;
  grid.dims = dims;
  grid.origin = lo;
  for (int a = 0; a < 3; ++a) grid.spacing[a] = dims[a] > 1 ? (hi[a] - lo[a]) / double(dims[a] - 1) : 1.0;
  grid.values.reserve(size_t(dims.x) * dims.y * dims.z);
  for (uint32_t k = 0; k < dims.z; ++k)
    for (uint32_t j = 0; j < dims.y; ++j)
      for (uint32_t i = 0; i < dims.x; ++i) grid.values.push_back(float(evaluate(field, grid.position(glm::dvec3(i, j, k)))));
  validate(grid);
  return grid;
}

std::vector<std::string> field_names() { return {"marschner-lobb", "blobs", "sphere", "linear"}; }

AnalyticField field_from_name(const std::string& name) {
  AnalyticField f;
  if (name == "marschner-lobb") f = marschner_lobb();
  else if (name == "blobs")
    f = gaussian_blobs({{-0.35, 0.25, 0.0, 0.3}, {0.4, -0.2, 0.2, 0.25}, {0.1, 0.55, -0.4, 0.18}});
  else if (name == "sphere") f = gaussian_blobs({{0.1, -0.05, 0.05, 0.35}});  // level sets: spheres round (0.1, -0.05, 0.05)
  else if (name == "linear") f = linear_field({0.3, -0.2, 0.25}, 1.0);      // in [0.25, 1.75] on the box
  else {
    std::string known;
    for (const auto& n : field_names()) known += (known.empty() ? "" : ", ") + n;
    throw InputError("field:" + name, "unknown analytic field (available: " + known + ")");
  }
  f.name = name;
  return f;
}

void validate(const AnalyticField& field) {
  if (field.kind == FieldKind::Grid) {
    if (!field.grid) throw InputError(field.name, "a grid field needs its samples");
    if (!field.params.empty()) throw InputError(field.name, "a grid field takes no parameter vectors");
    return validate(*field.grid);
  }
  const size_t n = field.params.size();
  if (n == 0 || n > PRISMOID_FIELD_MAX_PARAMS)
    throw InputError(field.name, "needs 1 to " + std::to_string(PRISMOID_FIELD_MAX_PARAMS) + " parameter vectors");
  for (const auto& p : field.params)
    for (int i = 0; i < 4; ++i)
      if (!std::isfinite(p[i])) throw InputError(field.name, "has a non-finite parameter");
  if (field.kind == FieldKind::GaussianBlobs)
    for (const auto& p : field.params)
      if (!(p.w > 0.0)) throw InputError(field.name, "blob widths must be positive");
  if (field.kind == FieldKind::MarschnerLobb && (n != 1 || !(field.params[0].y > -1.0)))
    throw InputError(field.name, "Marschner-Lobb takes one parameter vector (f_M, alpha) with alpha > -1");
  if (field.kind == FieldKind::Linear && n != 1) throw InputError(field.name, "a linear field takes one parameter vector");
}

TetMesh make_field_mesh(const AnalyticField& field, uint32_t n, double density_scale) {
  validate(field);
  TetMesh mesh = make_box_mesh(glm::dvec3(-1.0), glm::dvec3(1.0), n,
                               [&](const glm::dvec3& p) { return std::max(density_scale * evaluate(field, p), 0.0); });
  mesh.point_extinction = mesh.point_scalars;  // density_scale * field (clamped at 0)
  for (size_t i = 0; i < mesh.points.size(); ++i) mesh.point_scalars[i] = evaluate(field, mesh.points[i]);
  mesh.name = "field:" + field.name + " (" + std::to_string(mesh.tets.size()) + " tetrahedra bounding an analytic field)";
  return mesh;
}

}  // namespace prismoid::volume
