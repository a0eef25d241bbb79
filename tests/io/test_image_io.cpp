#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

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
