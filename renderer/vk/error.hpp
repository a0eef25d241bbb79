#pragma once
// Vulkan failures carry the call that failed and its result code.
#include <stdexcept>
#include <string>
#include <vulkan/vulkan.h>

namespace prismoid::vk {

const char* result_name(VkResult result);

class VulkanError : public std::runtime_error {
 public:
  VulkanError(const std::string& call, VkResult result);
  VkResult result() const { return result_; }

 private:
  VkResult result_;
};

// No Vulkan device offers what the requested work needs (CLI exit code 3).
class NoSuitableDevice : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

inline void check(VkResult result, const char* call) {
  if (result != VK_SUCCESS) throw VulkanError(call, result);
}

}  // namespace prismoid::vk

#define PRISMOID_VK(call) ::prismoid::vk::check((call), #call)
