#pragma once
// The volume backends: one table from which `--volume-backend` is parsed and listed in the
// help, `auto` chooses among the GPU ones, `devices` says which a device runs, and the frame
// renderer makes the backend a frame asks for. A backend is a folder under renderer/volume/
// with a VolumeBackendInfo (volume_backend.hpp) and a line of this table.
#include <string>
#include <string_view>
#include <vector>

#include "renderer/vk/capabilities.hpp"
#include "renderer/volume/volume_backend.hpp"

namespace prismoid::volume {

// Every volume backend: the GPU ones first, the CPU reference last.
const std::vector<const VolumeBackendInfo*>& volume_backend_table();
// The backend of that name; nullptr for a name that is not one.
const VolumeBackendInfo* find_volume_backend(std::string_view name);
// The CPU reference every GPU backend is measured against: the table's backend without a device.
const VolumeBackendInfo& reference_backend();
// Every name, ", "-separated, for messages.
std::string volume_backend_names();
// What `caps` lacks of `needs` ("mesh shader, ..."); empty when it has them all. The volume
// modes' table asks it too.
std::string missing_features(const std::vector<vk::Feature>& needs, const vk::DeviceCapabilities& caps);
// What `caps` lacks for the backend; empty when it can run it.
std::string device_problem(const VolumeBackendInfo& backend, const vk::DeviceCapabilities& caps);

}  // namespace prismoid::volume
