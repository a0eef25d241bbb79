#include "support/gpu_fixture.hpp"

#include "renderer/vk/capabilities.hpp"

namespace prismoid::test {

std::unique_ptr<vk::Instance> GpuTest::instance_;
std::unique_ptr<vk::Device> GpuTest::device_;

void GpuTest::SetUpTestSuite() {
  instance_ = std::make_unique<vk::Instance>(vk::InstanceOptions{.validation = true});
  const auto devices = vk::query_devices(instance_->get());
  device_ = std::make_unique<vk::Device>(*instance_, vk::select_device(devices, std::nullopt), vk::DeviceOptions{});
}

void GpuTest::TearDownTestSuite() {
  device_.reset();
  instance_.reset();
}

void GpuTest::SetUp() { instance_->validation_log().clear(); }

void GpuTest::TearDown() {
  device_->wait_idle();
  const auto messages = instance_->validation_log().messages();
  EXPECT_TRUE(messages.empty()) << messages.size() << " validation message(s), first: " << messages.front();
}

}  // namespace prismoid::test
