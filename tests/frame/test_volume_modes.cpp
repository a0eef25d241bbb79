// The volume mode table (renderer/frame/volume_modes): every mode is found by its name and by its
// properties, the defaults follow the quantity, and a device lacking a mode's feature is told so.
#include <gtest/gtest.h>

#include <set>
#include <string>

#include "renderer/frame/volume_modes.hpp"

namespace prismoid {
namespace {

using frame::Ordering;
using frame::VolumeBackend;
using frame::VolumeMode;

TEST(VolumeModes, TheTableHoldsTheModesTheCommandLineHasAlwaysNamed) {
  std::set<std::string> names;
  for (const VolumeMode& m : frame::volume_mode_table()) {
    EXPECT_TRUE(names.insert(std::string(m.name)).second) << m.name << " twice";
    EXPECT_FALSE(m.summary.empty()) << m.name;
    EXPECT_EQ(frame::find_volume_mode(m.name), &m);
    if (m.march) {
      EXPECT_TRUE(m.samples_field) << m.name << ": a march samples the field";
    }
    if (m.gpu()) {
      EXPECT_EQ(frame::find_volume_mode(m.ordering, m.march), &m) << m.name;
    }
  }
  EXPECT_EQ(names, (std::set<std::string>{"interval", "interval-sorted", "interval-exact-order", "interval-march",
                                          "interval-march-exact-order", "reference"}));
  EXPECT_EQ(frame::find_volume_mode("htex"), nullptr);
  EXPECT_EQ(frame::find_volume_mode(""), nullptr);
  EXPECT_EQ(frame::volume_mode_names(),
            "interval, interval-sorted, interval-exact-order, interval-march, interval-march-exact-order, reference");
}

// Found by properties, as the window names the settings it was given and the bench picks its rows.
TEST(VolumeModes, PropertiesPickTheMode) {
  const VolumeMode* sorted = frame::find_volume_mode(Ordering::GpuSort, false);
  ASSERT_NE(sorted, nullptr);
  EXPECT_EQ(sorted->name, "interval-sorted");
  const VolumeMode* march_exact = frame::find_volume_mode(Ordering::Exact, true);
  ASSERT_NE(march_exact, nullptr);
  EXPECT_EQ(march_exact->name, "interval-march-exact-order");
  EXPECT_TRUE(march_exact->march);
  EXPECT_EQ(march_exact->backend, VolumeBackend::Mesh);
  // No mode marches in mesh order: the march's colour is always sorted.
  EXPECT_EQ(frame::find_volume_mode(Ordering::MeshOrder, true), nullptr);
  // The reference is not a GPU mode, so no GPU ordering finds it.
  const VolumeMode* reference = frame::find_volume_mode("reference");
  ASSERT_NE(reference, nullptr);
  EXPECT_FALSE(reference->gpu());
  EXPECT_TRUE(reference->samples_field);
  EXPECT_FALSE(reference->march) << "the reference needs no field";
  EXPECT_STREQ(frame::volume_backend_name(reference->backend), "cpu");
  EXPECT_STREQ(frame::volume_backend_name(VolumeBackend::Mesh), "mesh");
}

TEST(VolumeModes, TheDefaultSortsOnlyWhereTheOrderMatters) {
  EXPECT_EQ(frame::default_volume_mode(volume::Quantity::Transmittance).name, "interval");
  EXPECT_EQ(frame::default_volume_mode(volume::Quantity::OpticalDepth).name, "interval");
  EXPECT_EQ(frame::default_volume_mode(volume::Quantity::Color).name, "interval-sorted");
}

TEST(VolumeModes, ADeviceWithoutMeshShadersDrawsOnlyTheReference) {
  vk::DeviceCapabilities with, without;
  with.mesh_shader = true;
  without.mesh_shader = false;
  for (const VolumeMode& m : frame::volume_mode_table()) {
    EXPECT_EQ(frame::device_problem(m, with), "") << m.name;
    EXPECT_EQ(frame::device_problem(m, without), m.gpu() ? vk::feature_name(vk::Feature::MeshShader) : "") << m.name;
  }
}

}  // namespace
}  // namespace prismoid
