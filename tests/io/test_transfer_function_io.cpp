#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "io/transfer_function_io.hpp"
#include "scene/input_error.hpp"

namespace prismoid::io {
namespace {

namespace fs = std::filesystem;

fs::path scratch(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / ("prismoid_tfio_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  return dir / name;
}

TEST(TransferFunctionIo, ParaViewFileRoundTrips) {
  volume::TransferFunction tf = volume::preset("black-body");
  tf.opacity = {{0.0, 0.0}, {0.3, 0.7}, {1.0, 0.2}};
  const fs::path path = scratch("bb.json");
  write_paraview_colormap(path.string(), tf);
  const volume::TransferFunction back = read_paraview_colormap(path.string());
  EXPECT_EQ(back.name, "black-body");
  ASSERT_EQ(back.color.size(), tf.color.size());
  for (size_t i = 0; i < tf.color.size(); ++i) {
    EXPECT_NEAR(back.color[i].x, tf.color[i].x, 1e-12);
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(back.color[i].rgb[c], tf.color[i].rgb[c], 1e-12);  // sRGB there and back
  }
  ASSERT_EQ(back.opacity.size(), 3u);
  EXPECT_DOUBLE_EQ(back.opacity[1].opacity, 0.7);
}

TEST(TransferFunctionIo, PositionsAreRescaledToTheColourPointsSpan) {
  const fs::path path = scratch("range.json");
  std::ofstream(path) << R"([{"Name": "m", "RGBPoints": [10, 0, 0, 0, 20, 1, 1, 1, 30, 1, 1, 1], "Points": [15, 0.5, 0.5, 0]}])";
  const volume::TransferFunction tf = read_paraview_colormap(path.string());
  EXPECT_DOUBLE_EQ(tf.color[1].x, 0.5);
  EXPECT_DOUBLE_EQ(tf.opacity[0].x, 0.25);
}

TEST(TransferFunctionIo, BadFilesNameTheFileAndTheProblem) {
  struct Case { std::string text, fragment; };
  const std::vector<Case> cases = {
      {"{not json", "not valid JSON"},
      {R"({"Name": "x"})", "RGBPoints"},
      {R"([{"RGBPoints": [0, 1, 1]}])", "groups of 4"},
      {R"([{"RGBPoints": [0, 1, 1, 2, 1, 0, 0, 0]}])", "[0, 1]"},
      {R"([{"RGBPoints": [1, 0, 0, 0, 0, 1, 1, 1]}])", "sorted"},
      {R"([{"RGBPoints": [0, 0, 0, 0, 1, 1, 1, 1], "Points": [0, 0.5, 0.7, 0]}])", "midpoint"},
  };
  for (size_t i = 0; i < cases.size(); ++i) {
    const fs::path path = scratch("bad" + std::to_string(i) + ".json");
    std::ofstream(path) << cases[i].text;
    try {
      read_paraview_colormap(path.string());
      ADD_FAILURE() << cases[i].text << " was accepted";
    } catch (const InputError& e) {
      const std::string what = e.what();
      EXPECT_NE(what.find(path.string()), std::string::npos) << what;
      EXPECT_NE(what.find(cases[i].fragment), std::string::npos) << what;
    }
  }
  EXPECT_THROW(read_paraview_colormap("/no/such/map.json"), InputError);
  fs::remove_all(scratch("").parent_path());
}

}  // namespace
}  // namespace prismoid::io
