#pragma once
// The grid:NAME[:N] dataset: an analytic field sampled onto a grid, marched as voxel data is
// (FieldKind::Grid), inside the blocks of samples where it has density (as OpenVDB's active
// leaves are).
#include <memory>
#include <string>

#include "io/vdb_io.hpp"
#include "renderer/volume/analytic_field.hpp"
#include "renderer/volume/sampled_grid.hpp"
#include "scene/tet_mesh_fwd.hpp"

namespace prismoid::app {

bool is_grid_spec(const std::string& spec);

// The field NAME (volume::field_names) at N^3 samples spanning [-1, 1]^3 (N from 2 to 512,
// default 32). The last spec's grid is kept, so the several callers of one command share it.
std::shared_ptr<const volume::SampledGrid> grid_from_spec(const std::string& spec);

// An OpenVDB float grid sampled densely over its active voxels, for marching inside the
// intervals of its active regions (leaf nodes and tiles). A level set (negative inside) is
// marched as the fog volume OpenVDB's sdfToFogVolume makes of it, clamp(-sdf / background, 0, 1),
// so inside is dense; its regions are then the whole dense box, since the active voxels of a
// level set are only the narrow band around the surface. The last file's grid is kept.
std::shared_ptr<const volume::SampledGrid> grid_from_vdb(const std::string& path, const io::VdbReadOptions& options);

// The region mesh of a grid from grid_from_spec or grid_from_vdb: a .vdb grid's active regions,
// else blocks of 8^3 samples holding a sample above a thousandth of the largest |value| (where
// sigma = density_scale max(field, 0) is not negligible), as a region mesh.
TetMesh grid_dataset_mesh(const volume::SampledGrid& grid, double density_scale);

}  // namespace prismoid::app
