// End-to-end: `prismoid render SCENE --mode htex --gi ...` as a user runs it.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <string>

#include "io/image_io.hpp"
#include "support/cli_run.hpp"

namespace prismoid {
namespace {

namespace fs = std::filesystem;

using test::cli::work_dir;  // (including test::cli registers the scratch clean-up)

// The Cornell box with biased GI: exits 0, every pixel finite, the image brighter than the same
// render without GI (the one bounce only adds light; the box's sky is black), stats with the GI
// settings and the reservoir and persistent-layer bytes, validation clean.
TEST(CliHtexGi, RendersTheCornellBoxWithBiasedGi) {
  const fs::path off = work_dir() / "htex_gi_off.pfm", on = work_dir() / "htex_gi_on.pfm",
                 stats = work_dir() / "htex_gi.json";
  const test::CliRun a = test::run_cli("render cornell-box --mode htex --size 24x16 --pool-pages 16 --texels-per-unit 0.02 --validate --output " +
                                       off.string());
  ASSERT_EQ(a.code, 0) << a.err;
  const test::CliRun b = test::run_cli("render cornell-box --mode htex --gi biased --gi-frames 2 --gi-neighbours 3 --size 24x16 --pool-pages 16 "
                                       "--texels-per-unit 0.02 --validate --output " + on.string() + " --stats " + stats.string());
  ASSERT_EQ(b.code, 0) << b.err;
  const io::FloatImage x = io::read_pfm(off.string()), y = io::read_pfm(on.string());
  ASSERT_EQ(y.width, 24u);
  ASSERT_EQ(y.height, 16u);
  double sx = 0.0, sy = 0.0;
  for (size_t i = 0; i < y.pixels.size(); ++i) {
    ASSERT_TRUE(std::isfinite(y.pixels[i]));
    sx += double(x.pixels[i]);
    sy += double(y.pixels[i]);
  }
  EXPECT_GT(sy, 1.02 * sx);
  const std::string js = test::slurp(stats);
  for (const char* key : {"\"gi\": \"biased\"", "\"gi_frames\": 2", "\"gi_neighbours\": 3", "\"gi_fallback\": true", "\"gi_reservoir_bytes\": 16777216",
                          "\"gi_persistent_bytes\": ", "\"name\": \"gi spatial\"", "\"validation_messages\": 0"})
    EXPECT_NE(js.find(key), std::string::npos) << key << " in " << js;
}

TEST(CliHtexGi, BadGiOptionsExitWithUsageErrors) {
  const fs::path out = work_dir() / "htex_gi_bad.pfm";
  for (const std::string opts : {"--gi sometimes", "--gi biased --gi-frames 0", "--gi biased --gi-neighbours 17", "--gi biased --gi-fallback maybe",
                                 "--gi-frames 4"}) {
    const test::CliRun r = test::run_cli("render cornell-box --mode htex --size 8x8 " + opts + " --output " + out.string());
    EXPECT_EQ(r.code, 2) << opts << ": " << r.err;
    EXPECT_NE(r.err.find("--gi"), std::string::npos) << opts << ": " << r.err;
  }
}

}  // namespace
}  // namespace prismoid
