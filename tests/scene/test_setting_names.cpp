// Messages name settings by their keys, and a front end spells them (scene/setting_names.hpp): the
// renderer's refusals read as the command line's flags where the CLI installed its spelling, and
// as plain setting names (what the ParaView plugin shows) where none is installed.
#include <gtest/gtest.h>

#include <string>

#include "renderer/volume/float_limits.hpp"
#include "scene/camera.hpp"
#include "scene/generators.hpp"
#include "scene/input_error.hpp"
#include "scene/setting_names.hpp"
#include "scene/tet_mesh.hpp"

namespace prismoid {
namespace {

std::string flag(std::string_view key, std::string_view value) {
  std::string s = "--";
  s.append(key);
  if (!value.empty()) s.append(" ").append(value);
  return s;
}

// The refusal of a ball whose optical depth float32 cannot hold: it names two settings.
std::string refusal() {
  const TetMesh ball = make_ball_mesh(glm::dvec3(0.0), 1.0, 1, 1e300);
  Camera camera;
  camera.eye = {0.0, 0.0, 5.0};
  volume::ResolveSettings settings;
  settings.quantity = volume::Quantity::OpticalDepth;
  try {
    volume::check_float_limits(volume::float_facts(ball), camera, 16, 16, settings);
  } catch (const InputError& e) {
    return e.what();
  }
  return "not refused";
}

TEST(SettingNames, KeysShowAsTheyAreUntilAFrontEndSpellsThem) {
  EXPECT_EQ(setting("tetlet-size"), "tetlet-size");
  EXPECT_EQ(setting("shadows", "off"), "shadows off");
  const std::string plain = refusal();
  EXPECT_NE(plain.find("(density-scale) or ask for quantity transmittance"), std::string::npos) << plain;
  EXPECT_EQ(plain.find("--"), std::string::npos) << plain;

  set_setting_spelling(&flag);
  EXPECT_EQ(setting("tetlet-size"), "--tetlet-size");
  EXPECT_EQ(setting("shadows", "off"), "--shadows off");
  const std::string spelled = refusal();
  EXPECT_NE(spelled.find("(--density-scale) or ask for --quantity transmittance"), std::string::npos) << spelled;

  set_setting_spelling(nullptr);
  EXPECT_EQ(setting("shadows", "off"), "shadows off");
}

}  // namespace
}  // namespace prismoid
