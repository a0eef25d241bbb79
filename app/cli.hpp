#pragma once
// The command line: `prismoid VERB [options]`. Exit codes: 0 ok, 2 bad input (one line
// naming the file or option and the problem), 3 no suitable Vulkan device, 4 validation
// messages under --validate, 1 anything else (a Vulkan call failed, ...).
#include <string>
#include <vector>

namespace prismoid::app {

enum ExitCode : int { kOk = 0, kFailure = 1, kBadInput = 2, kNoDevice = 3, kValidationMessages = 4, kCancelled = 130 };

int run_cli(const std::vector<std::string>& args);

}  // namespace prismoid::app
