#include "renderer/surface/htex/htex_tables.hpp"

#include <algorithm>
#include <cstring>
#include <span>
#include <stdexcept>

#include "renderer/vk/device.hpp"
#include "scene/input_error.hpp"
#include "scene/setting_names.hpp"

namespace prismoid::surface {

namespace {

std::vector<HalfedgeMesh> halfedge_meshes(const SurfaceScene& scene) {
  std::vector<HalfedgeMesh> meshes;
  for (const SceneMesh& m : scene.meshes) meshes.push_back(build_halfedge_mesh(m, NonManifold::Split));
  return meshes;
}

template <typename T>
vk::Buffer storage(const vk::Device& device, std::vector<T> items, uint64_t& bytes) {
  if (items.empty()) items.resize(1);  // storage buffers cannot be empty
  bytes += items.size() * sizeof(T);
  return vk::upload_buffer(device, std::as_bytes(std::span<const T>(items)), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT);
}

}  // namespace

HtexGeometry::HtexGeometry(const SurfaceScene& scene, const htex::LayoutOptions& options)
    : meshes(halfedge_meshes(scene)), layout(meshes, options) {
  uint64_t faces = 0, triangles = 0;
  for (size_t m = 0; m < meshes.size(); ++m) {
    first_face.push_back(static_cast<uint32_t>(faces));
    first_triangle.push_back(static_cast<uint32_t>(triangles));
    faces += meshes[m].face_count();
    triangles += scene.meshes[m].triangles.size();
    max_levels = std::max(max_levels, layout.meshes()[m].levels);
  }
  if (3 * faces > uint64_t(INT32_MAX)) throw InputError(scene.name, "too many triangles for the Htex backend's 32-bit halfedge ids");
  face_count = static_cast<uint32_t>(faces);
  triangle_count = static_cast<uint32_t>(triangles);
  if (max_levels > PRISMOID_HTEX_MAX_LEVELS) throw std::logic_error("htex: more mip levels than the GPU table holds");
}

HtexTableData htex_table_data(const HtexGeometry& g, uint32_t capacity_pages) {
  HtexTableData d;
  const htex::AtlasLayout& layout = g.layout;
  d.atlas.size = glm::uvec4(layout.width(), layout.height(), layout.shadel_columns(), g.group_columns());
  d.atlas.counts = glm::uvec4(g.group_count(), static_cast<uint32_t>(g.meshes.size()), capacity_pages, g.max_levels);
  d.face_of_triangle.assign(g.triangle_count, PRISMOID_HTEX_NONE);
  d.triangle_of_face.assign(g.face_count, 0u);
  for (size_t mi = 0; mi < g.meshes.size(); ++mi) {
    const HalfedgeMesh& mesh = g.meshes[mi];
    const htex::MeshLayout& ml = layout.meshes()[mi];
    gpu::HtexMeshGpu m{};
    m.info = glm::uvec4(ml.first_quad, ml.quad_count, ml.log2_side, ml.levels);
    m.grid = glm::uvec4(ml.columns, ml.rows, g.first_face[mi], g.first_triangle[mi]);
    for (uint32_t level = 0; level < ml.levels; ++level) {
      glm::uvec4& o = m.origin[level / 2];
      if (level % 2 == 0) {
        o.x = ml.origin[level].x;
        o.y = ml.origin[level].y;
      } else {
        o.z = ml.origin[level].x;
        o.w = ml.origin[level].y;
      }
    }
    d.meshes.push_back(m);
    const auto h0 = static_cast<int32_t>(3 * g.first_face[mi]);
    for (size_t h = 0; h < mesh.halfedge_count(); ++h) {
      d.twin.push_back(mesh.twin[h] == kNoHalfedge ? -1 : h0 + mesh.twin[h]);
      d.edge_of.push_back(ml.first_quad + mesh.edge_of[h]);
      d.vertex_corner.push_back(h0 + htex::canonical_corner(mesh, int32_t(h)));
    }
    for (size_t e = 0; e < mesh.edge_count(); ++e) d.edge_halfedge.push_back(h0 + mesh.edge_halfedge[e]);
    for (size_t f = 0; f < mesh.face_count(); ++f)
      d.triangle_of_face[g.first_face[mi] + f] = g.first_triangle[mi] + mesh.triangle_of_face[f];
    for (size_t t = 0; t < mesh.face_of_triangle.size(); ++t)
      if (mesh.face_of_triangle[t] >= 0) d.face_of_triangle[g.first_triangle[mi] + t] = g.first_face[mi] + uint32_t(mesh.face_of_triangle[t]);
  }
  const uint32_t shadels = layout.shadel_columns() * layout.shadel_rows();
  d.shadel_region.assign(shadels, PRISMOID_HTEX_NONE);
  for (uint32_t s = 0; s < shadels; ++s)
    if (const auto r = layout.region_of_shadel(s)) d.shadel_region[s] = r->mesh * 16u + r->level;
  return d;
}

HtexTables upload_htex_tables(const vk::Device& device, const HtexGeometry& geometry, uint32_t capacity_pages) {
  HtexTableData d = htex_table_data(geometry, capacity_pages);
  HtexTables t;
  std::vector<std::byte> meshes(sizeof(gpu::HtexAtlasGpu) + d.meshes.size() * sizeof(gpu::HtexMeshGpu));
  std::memcpy(meshes.data(), &d.atlas, sizeof(d.atlas));
  if (!d.meshes.empty()) std::memcpy(meshes.data() + sizeof(d.atlas), d.meshes.data(), d.meshes.size() * sizeof(gpu::HtexMeshGpu));
  t.bytes += meshes.size();
  t.meshes = vk::upload_buffer(device, meshes, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT);
  const uint64_t limit = device.capabilities().max_storage_buffer_range;
  if (uint64_t(d.shadel_region.size()) * 4 > limit || uint64_t(d.twin.size()) * 4 > limit)
    throw InputError("htex", "the virtual atlas's tables exceed the device's storage-buffer range: lower " + setting("texels-per-unit"));
  t.twin = storage(device, std::move(d.twin), t.bytes);
  t.edge_of = storage(device, std::move(d.edge_of), t.bytes);
  t.edge_halfedge = storage(device, std::move(d.edge_halfedge), t.bytes);
  t.face_of_triangle = storage(device, std::move(d.face_of_triangle), t.bytes);
  t.triangle_of_face = storage(device, std::move(d.triangle_of_face), t.bytes);
  t.shadel_region = storage(device, std::move(d.shadel_region), t.bytes);
  t.vertex_corner = storage(device, std::move(d.vertex_corner), t.bytes);
  return t;
}

std::vector<vk::DescriptorBinding> htex_table_bindings(VkShaderStageFlags stages) {
  std::vector<vk::DescriptorBinding> b;
  for (uint32_t binding = PRISMOID_HTEX_BINDING_MESHES; binding <= PRISMOID_HTEX_BINDING_SHADEL_REGION; ++binding)
    b.push_back({binding, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, stages});
  b.push_back({PRISMOID_HTEX_BINDING_VERTEX_CORNER, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, stages});
  return b;
}

void write_htex_table_descriptors(const vk::Device& device, VkDescriptorSet set, const HtexTables& t) {
  const VkDescriptorType s = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
  vk::write_buffer_descriptor(device, set, PRISMOID_HTEX_BINDING_MESHES, s, t.meshes.get());
  vk::write_buffer_descriptor(device, set, PRISMOID_HTEX_BINDING_TWIN, s, t.twin.get());
  vk::write_buffer_descriptor(device, set, PRISMOID_HTEX_BINDING_EDGE_OF, s, t.edge_of.get());
  vk::write_buffer_descriptor(device, set, PRISMOID_HTEX_BINDING_EDGE_HALFEDGE, s, t.edge_halfedge.get());
  vk::write_buffer_descriptor(device, set, PRISMOID_HTEX_BINDING_FACE_OF_TRIANGLE, s, t.face_of_triangle.get());
  vk::write_buffer_descriptor(device, set, PRISMOID_HTEX_BINDING_TRIANGLE_OF_FACE, s, t.triangle_of_face.get());
  vk::write_buffer_descriptor(device, set, PRISMOID_HTEX_BINDING_SHADEL_REGION, s, t.shadel_region.get());
  vk::write_buffer_descriptor(device, set, PRISMOID_HTEX_BINDING_VERTEX_CORNER, s, t.vertex_corner.get());
}

}  // namespace prismoid::surface
