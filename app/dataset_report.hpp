#pragma once
// The text `prismoid info FILE` prints.
#include <string>

#include "io/dataset_info.hpp"
#include "io/vdb_io.hpp"

namespace prismoid::app {

std::string format_dataset_info(const std::string& path, const io::DatasetInfo& info);
std::string format_vdb_info(const io::VdbInfo& info);

}  // namespace prismoid::app
