#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <sys/stat.h>
#include <utility>
#include <vector>

#include "io/image_io.hpp"
#include "scene/input_error.hpp"

namespace prismoid {
namespace {

std::string temp_path(const std::string& name) {
  return (std::filesystem::temp_directory_path() / ("prismoid_test_" + std::to_string(::getpid()) + "_" + name)).string();
}

TEST(Pfm, RoundTripsFloatsBitExactlyWithRowOrder) {
  io::FloatImage img;
  img.width = 3;
  img.height = 2;
  img.channels = 1;
  img.pixels = {0.0f, 1.5f, -2.25f, 1e-30f, 3.4e38f, 7.0f};
  const std::string path = temp_path("a.pfm");
  io::write_pfm(path, img);
  const io::FloatImage back = io::read_pfm(path);
  EXPECT_EQ(back.width, 3u);
  EXPECT_EQ(back.height, 2u);
  EXPECT_EQ(back.pixels, img.pixels);
  EXPECT_EQ(back.at(2, 0), -2.25f);  // row 0 is the top row on both sides
  std::filesystem::remove(path);
}

TEST(Pfm, TruncatedFileIsAnInputErrorNamingTheFile) {
  const std::string path = temp_path("short.pfm");
  std::ofstream(path) << "Pf\n4 4\n-1.0\nabc";
  try {
    io::read_pfm(path);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(e.source(), path);
    EXPECT_NE(std::string(e.what()).find("truncated"), std::string::npos);
  }
  std::filesystem::remove(path);
}

// What the header gets wrong is said, and what is not a file is not opened (a FIFO would hang the
// read, /dev/zero grow the header's first word without end).
TEST(Pfm, BadHeadersAndWhatIsNotAFileAreNamed) {
  const std::string dir = temp_path("pfm-dir");
  std::filesystem::create_directories(dir);
  const std::string fifo = temp_path("pfm.fifo");
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  const std::string nan_scale = temp_path("nan.pfm"), zero_scale = temp_path("zero.pfm"), big = temp_path("big.pfm"),
                    words = temp_path("words.pfm");
  std::ofstream(nan_scale) << "Pf\n1 1\nnan\nabcd";
  std::ofstream(zero_scale) << "Pf\n1 1\n0\nabcd";
  std::ofstream(big) << "Pf\n1 1\n1.0\nabcd";
  std::ofstream(words) << "Pf\nwide high\n-1.0\nabcd";
  const std::vector<std::pair<std::string, std::string>> cases = {
      {dir, "is not a regular file (it is a folder)"},
      {fifo, "is not a regular file"},
      {"/dev/zero", "is not a regular file"},
      {nan_scale, "the scale 'nan' is not a finite non-zero number"},
      {zero_scale, "the scale '0' is not a finite non-zero number"},
      {big, "big-endian PFM (positive scale) is not supported"},
      {words, "the width and height must be whole numbers"},
  };
  for (const auto& [path, says] : cases) {
    try {
      io::read_pfm(path);
      ADD_FAILURE() << path << " was read";
    } catch (const InputError& e) {
      EXPECT_EQ(e.source(), path);
      EXPECT_NE(std::string(e.what()).find(says), std::string::npos) << e.what();
    }
  }
  for (const std::string& p : {dir, fifo, nan_scale, zero_scale, big, words}) std::filesystem::remove(p);
}

TEST(ImageWrite, UnwritablePathFailsCleanlyAndLeavesNothing) {
  io::FloatImage img{2, 2, 1, {0, 0, 0, 0}};
  const std::string path = "/nonexistent-folder/x.png";
  EXPECT_THROW(io::write_image(path, img), InputError);
  EXPECT_FALSE(std::filesystem::exists(path + ".partial"));
  EXPECT_THROW(io::write_image(temp_path("x.jpg"), img), InputError);
}

TEST(ImageWrite, PngIsWrittenWithItsSignature) {
  io::FloatImage img{2, 1, 4, {1, 0, 0, 1, 0, 0.5f, 1, 1}};
  const std::string path = temp_path("x.png");
  io::write_image(path, img);
  std::ifstream in(path, std::ios::binary);
  char sig[8];
  in.read(sig, 8);
  EXPECT_EQ(std::string(sig + 1, 3), "PNG");
  std::filesystem::remove(path);
}

}  // namespace
}  // namespace prismoid
