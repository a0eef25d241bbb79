#pragma once
// The Vulkan instance, with the Khronos validation layer and a message log when asked.
#include <memory>
#include <mutex>
#include <string>
#include <vector>
#include <vulkan/vulkan.h>

namespace prismoid::vk {

// Every message the validation layer reports (warnings and errors), kept for tests and
// for `--validate`, which prints them and fails the command.
class ValidationLog {
 public:
  void add(std::string message);
  std::vector<std::string> messages() const;
  size_t count() const;
  void clear();

 private:
  mutable std::mutex mutex_;
  std::vector<std::string> messages_;
};

struct InstanceOptions {
  bool validation = false;
  // Instance extensions a presentation path needs (GLFW's list for a window).
  std::vector<std::string> extensions;
  // Print validation messages to stderr as they arrive.
  bool echo_validation = true;
};

class Instance {
 public:
  explicit Instance(const InstanceOptions& options);
  ~Instance();
  Instance(const Instance&) = delete;
  Instance& operator=(const Instance&) = delete;

  VkInstance get() const { return instance_; }
  bool validation_enabled() const { return messenger_ != VK_NULL_HANDLE; }
  const ValidationLog& validation_log() const { return *log_; }
  ValidationLog& validation_log() { return *log_; }

 private:
  VkInstance instance_ = VK_NULL_HANDLE;
  VkDebugUtilsMessengerEXT messenger_ = VK_NULL_HANDLE;
  std::unique_ptr<ValidationLog> log_;
  bool echo_ = true;
  friend VkBool32 VKAPI_PTR validation_callback(VkDebugUtilsMessageSeverityFlagBitsEXT,
                                                VkDebugUtilsMessageTypeFlagsEXT,
                                                const VkDebugUtilsMessengerCallbackDataEXT*, void*);
};

}  // namespace prismoid::vk
