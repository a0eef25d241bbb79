#pragma once
// The process's exit codes, one list for every verb and for the helpers below them that decide
// one (validation_exit): 0 ok, 2 bad input (one line naming the file or option and the problem),
// 3 no suitable Vulkan device, 4 validation messages under --validate, 130 cancelled (Ctrl-C
// during a long load), 1 anything else (a Vulkan call failed, ...).
namespace prismoid::app {

enum ExitCode : int { kOk = 0, kFailure = 1, kBadInput = 2, kNoDevice = 3, kValidationMessages = 4, kCancelled = 130 };

}  // namespace prismoid::app
