#pragma once
// The text `prismoid info FILE` prints.
#include <string>

#include "io/dataset_info.hpp"

namespace prismoid::app {

std::string format_dataset_info(const std::string& path, const io::DatasetInfo& info);

}  // namespace prismoid::app
