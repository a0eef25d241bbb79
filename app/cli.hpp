#pragma once
// The command line: `prismoid VERB [options]`, returning an ExitCode (app/common/exit_code.hpp).
#include <string>
#include <vector>

#include "app/common/exit_code.hpp"

namespace prismoid::app {

int run_cli(const std::vector<std::string>& args);

}  // namespace prismoid::app
