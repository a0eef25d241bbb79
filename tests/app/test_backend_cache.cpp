// --volume-backend auto's cache: a device is calibrated once and its numbers reused; a cache
// that is missing, corrupt or not ours is replaced, never trusted and never fatal.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <unistd.h>

#include <nlohmann/json.hpp>

#include "app/common/backend_cache.hpp"
#include "renderer/frame/backend_choice.hpp"
#include "support/gpu_fixture.hpp"

namespace prismoid {
namespace {

namespace fs = std::filesystem;

class BackendCacheTest : public test::GpuTest {
 protected:
  void SetUp() override {
    test::GpuTest::SetUp();
    dir_ = fs::temp_directory_path() / ("prismoid-backend-cache-" + std::to_string(::getpid()));
    fs::remove_all(dir_);
    cache_ = dir_ / "sub" / "backends.json";
  }
  void TearDown() override {
    fs::remove_all(dir_);
    test::GpuTest::TearDown();
  }
  nlohmann::json read() const {
    std::ifstream in(cache_);
    std::stringstream s;
    s << in.rdbuf();
    return nlohmann::json::parse(s.str());
  }
  fs::path dir_, cache_;
};

TEST_F(BackendCacheTest, CalibratesOnceThenReusesTheDevicesNumbers) {
  bool cached = true;
  const frame::BackendChoice first = app::auto_backend(device(), cache_, &cached);
  EXPECT_FALSE(cached);
  ASSERT_TRUE(fs::exists(cache_));
  const nlohmann::json j = read();
  const std::string key = frame::device_key(device());
  ASSERT_TRUE(j.contains(key)) << j.dump();
  EXPECT_GT(j[key]["mesh_ms"].get<double>(), 0.0);
  EXPECT_GT(j[key]["compute_ms"].get<double>(), 0.0);
  const frame::BackendChoice second = app::auto_backend(device(), cache_, &cached);
  EXPECT_TRUE(cached);
  EXPECT_EQ(second.backend, first.backend);
  EXPECT_NE(second.reason.find("calibrated earlier"), std::string::npos) << second.reason;
}

// The cache's numbers decide: an entry saying mesh shaders are 100x faster picks them.
TEST_F(BackendCacheTest, TheChoiceFollowsTheCachedNumbers) {
  fs::create_directories(cache_.parent_path());
  nlohmann::json j;
  j[frame::device_key(device())] = {{"mesh_ms", 1.0}, {"compute_ms", 100.0}, {"cells", 10368}, {"width", 128}, {"height", 128}};
  std::ofstream(cache_) << j.dump();
  bool cached = false;
  EXPECT_EQ(app::auto_backend(device(), cache_, &cached).backend, frame::IntervalBackend::Mesh);
  EXPECT_TRUE(cached);
  j[frame::device_key(device())]["compute_ms"] = 0.01;
  std::ofstream(cache_) << j.dump();
  EXPECT_EQ(app::auto_backend(device(), cache_, &cached).backend, frame::IntervalBackend::Compute);
}

// Corrupt, wrongly typed or another device's entries: calibrated again, the file made whole.
TEST_F(BackendCacheTest, ACorruptCacheIsReplaced) {
  fs::create_directories(cache_.parent_path());
  for (const std::string& text : {std::string("{not json"), std::string("[1, 2]"),
                                 "{\"" + frame::device_key(device()) + "\": {\"mesh_ms\": \"fast\"}}"}) {
    std::ofstream(cache_) << text;
    testing::internal::CaptureStderr();
    bool cached = true;
    const frame::BackendChoice choice = app::auto_backend(device(), cache_, &cached);
    const std::string err = testing::internal::GetCapturedStderr();
    EXPECT_FALSE(cached) << text;
    EXPECT_FALSE(choice.reason.empty());
    EXPECT_NE(err.find(cache_.string()), std::string::npos) << err;
    const nlohmann::json j = read();
    EXPECT_TRUE(j.contains(frame::device_key(device()))) << text;
    EXPECT_FALSE(fs::exists(cache_.string() + ".partial"));
  }
}

TEST_F(BackendCacheTest, NoPathCachesNothing) {
  bool cached = true;
  const frame::BackendChoice choice = app::auto_backend(device(), fs::path(), &cached);
  EXPECT_FALSE(cached);
  EXPECT_NE(choice.reason.find("auto:"), std::string::npos);
  EXPECT_FALSE(fs::exists(dir_));
}

}  // namespace
}  // namespace prismoid
