#pragma once
// The Htex backend's geometry: every mesh of a SurfaceScene as a halfedge mesh, their quads in
// one virtual atlas (htex::AtlasLayout), and the same on the GPU as flat global tables
// (shaders/shared/htex.h): the mesh layout table, twin / edge_of per halfedge, the primary
// halfedge per edge, face <-> triangle maps and the per-shadel region table. Built once per
// scene; the passes (htex_pass.hpp) and the GLSL twins' test read them.
#include <cstdint>
#include <vector>

#include "renderer/surface/htex/htex_layout.hpp"
#include "renderer/vk/memory.hpp"
#include "renderer/vk/pipeline.hpp"
#include "scene/halfedge_mesh.hpp"
#include "scene/surface_scene.hpp"
#include "shaders/shared/htex.h"

namespace prismoid::vk {
class Device;
}

namespace prismoid::surface {

// CPU side. Mesh i of the scene is meshes[i] (non-manifold edges split, triangles naming a point
// twice dropped: scene/halfedge_mesh.hpp); its faces' corners are its triangles' in order, so a
// triangle's barycentric weights are its face's.
struct HtexGeometry {
  HtexGeometry(const SurfaceScene& scene, const htex::LayoutOptions& options);

  std::vector<HalfedgeMesh> meshes;
  htex::AtlasLayout layout;
  std::vector<uint32_t> first_face;      // per mesh: global face of its face 0
  std::vector<uint32_t> first_triangle;  // per mesh: global triangle of its triangle 0 (GpuSurfaceScene's order)
  uint32_t face_count = 0, triangle_count = 0;
  uint32_t max_levels = 1;               // the longest mip chain of any mesh
  uint32_t group_columns() const { return layout.width() / htex::kGroupTexels; }
  uint32_t group_count() const { return group_columns() * (layout.height() / htex::kGroupTexels); }
};

// GPU side (device-local storage buffers).
struct HtexTables {
  vk::Buffer meshes, twin, edge_of, edge_halfedge, face_of_triangle, triangle_of_face, shadel_region, vertex_corner;
  uint64_t bytes = 0;
};
// `capacity_pages` goes into HtexAtlasGpu::counts.z.
HtexTables upload_htex_tables(const vk::Device& device, const HtexGeometry& geometry, uint32_t capacity_pages);

// The table bindings (PRISMOID_HTEX_BINDING_MESHES .. SHADEL_REGION, VERTEX_CORNER) for `stages`, and their writes.
std::vector<vk::DescriptorBinding> htex_table_bindings(VkShaderStageFlags stages);
void write_htex_table_descriptors(const vk::Device& device, VkDescriptorSet set, const HtexTables& tables);

// The flat GPU tables as host data (what upload_htex_tables uploads; tests read them).
struct HtexTableData {
  gpu::HtexAtlasGpu atlas{};
  std::vector<gpu::HtexMeshGpu> meshes;
  std::vector<int32_t> twin;
  std::vector<uint32_t> edge_of;
  std::vector<int32_t> edge_halfedge;
  std::vector<int32_t> vertex_corner;
  std::vector<uint32_t> face_of_triangle, triangle_of_face, shadel_region;
};
HtexTableData htex_table_data(const HtexGeometry& geometry, uint32_t capacity_pages);

}  // namespace prismoid::surface
