#pragma once
// A Vulkan instance (validation layer on) and the device Prismoid would choose. Any message
// from the validation layer during a test fails that test.
#include <gtest/gtest.h>

#include <memory>

#include "renderer/vk/device.hpp"
#include "renderer/vk/instance.hpp"

namespace prismoid::test {

class GpuTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite();
  static void TearDownTestSuite();
  void SetUp() override;
  void TearDown() override;

  static vk::Instance& instance() { return *instance_; }
  static vk::Device& device() { return *device_; }

 private:
  static std::unique_ptr<vk::Instance> instance_;
  static std::unique_ptr<vk::Device> device_;
};

}  // namespace prismoid::test
