// --volume-backend auto's cache: a device is calibrated once and its numbers reused; a cache
// that is missing, corrupt or not ours is replaced, never trusted and never fatal.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <sys/stat.h>
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
  // Entries in the cache's folder.
  size_t entries_beside() const {
    size_t n = 0;
    for ([[maybe_unused]] const auto& e : fs::directory_iterator(cache_.parent_path())) ++n;
    return n;
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
    EXPECT_EQ(entries_beside(), 1u) << text;  // the cache alone: no temporary left
  }
}

// Numbers no calibration measures (the file is anyone's to edit) are not believed: the device is
// calibrated again and its entry replaced with what it measures.
TEST_F(BackendCacheTest, ImplausibleNumbersAreCalibratedAgain) {
  fs::create_directories(cache_.parent_path());
  const std::string key = frame::device_key(device());
  const nlohmann::json good = {{"mesh_ms", 1.0}, {"compute_ms", 2.0}, {"cells", 10368}, {"width", 128}, {"height", 128}};
  nlohmann::json tiny = good, zeros = good, negative = good, huge = good;
  tiny["compute_ms"] = 1e-320;  // once "infx faster"
  zeros["mesh_ms"] = 0.0;       // once mesh shaders for ever
  zeros["compute_ms"] = 0.0;
  negative["cells"] = -5;
  huge["mesh_ms"] = 1e300;
  for (const nlohmann::json& entry : {tiny, zeros, negative, huge}) {
    std::ofstream(cache_) << nlohmann::json{{key, entry}}.dump();
    testing::internal::CaptureStderr();
    bool cached = true;
    const frame::BackendChoice choice = app::auto_backend(device(), cache_, &cached);
    const std::string err = testing::internal::GetCapturedStderr();
    EXPECT_FALSE(cached) << entry.dump();
    EXPECT_NE(err.find("no plausible numbers"), std::string::npos) << err;
    EXPECT_EQ(choice.reason.find("inf"), std::string::npos) << choice.reason;
    const nlohmann::json j = read();
    EXPECT_GT(j[key]["mesh_ms"].get<double>(), 1e-3) << j.dump();
    EXPECT_GT(j[key]["compute_ms"].get<double>(), 1e-3) << j.dump();
  }
}

// What is not a regular file where the cache should be (a folder, a FIFO, a link to /dev/zero)
// is neither read (no hang, no unbounded read) nor replaced; the frame goes on, calibrated, and
// the warning says what is there. A link planted at the old fixed temporary name is not followed.
TEST_F(BackendCacheTest, WhatIsNotAFileIsNeitherReadNorReplaced) {
  fs::create_directories(cache_.parent_path());
  const fs::path victim = dir_ / "victim.txt";
  std::ofstream(victim) << "the user's";
  fs::create_symlink(victim, cache_.string() + ".partial");
  bool cached = true;
  app::auto_backend(device(), cache_, &cached);
  EXPECT_FALSE(cached);
  std::ifstream in(victim);
  std::string kept;
  std::getline(in, kept);
  EXPECT_EQ(kept, "the user's");
  EXPECT_TRUE(read().contains(frame::device_key(device())));
  fs::remove(cache_);

  for (const std::string kind : {"folder", "fifo", "zero"}) {
    if (kind == "folder") fs::create_directories(cache_);
    if (kind == "fifo") {
      ASSERT_EQ(::mkfifo(cache_.c_str(), 0600), 0);
    }
    if (kind == "zero") fs::create_symlink("/dev/zero", cache_);
    testing::internal::CaptureStderr();
    const frame::BackendChoice choice = app::auto_backend(device(), cache_, &cached);
    const std::string err = testing::internal::GetCapturedStderr();
    EXPECT_FALSE(cached) << kind;
    EXPECT_FALSE(choice.reason.empty()) << kind;
    EXPECT_NE(err.find("is not a regular file"), std::string::npos) << kind << ": " << err;
    EXPECT_EQ(err.find("Success"), std::string::npos) << kind << ": " << err;
    const fs::file_status after = fs::symlink_status(cache_);
    EXPECT_TRUE(kind == "folder" ? fs::is_directory(after) : kind == "fifo" ? fs::is_fifo(after) : fs::is_symlink(after)) << kind;
    EXPECT_EQ(entries_beside(), 2u) << kind;  // the thing itself and the planted link: no temporary
    fs::remove_all(cache_);
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
