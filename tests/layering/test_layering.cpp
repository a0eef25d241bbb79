// The layering of docs/architecture.md ("Dependencies point one way"), checked on every #include
// of the source tree: a lower layer never includes a higher one, and the modules that must stay
// free of Vulkan or VTK include neither. A violation fails Layering.SourceTreeKeepsTheRules with
// the file, the line, the include and the rule's reason.
//
// The rules are the table below. A rule covers the files whose path (from the repository root)
// starts with one of `files` and with none of `except`; those files may not include anything
// whose name starts with one of `forbidden` unless it also starts with one of `allowed`. A quoted include is named by its path from the
// repository root (resolved against the including file's folder first, as the compiler does, so
// GLSL's "../shared/x.h" counts as shaders/shared/x.h); an angled one by its name as written
// (<vulkan/vulkan.h>, <vtkPolyData.h>).
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>
#include <string_view>
#include <vector>

namespace prismoid::test {
namespace {

struct Rule {
  std::vector<std::string_view> files;      // path prefixes the rule covers
  std::vector<std::string_view> except;     // ... except these
  std::vector<std::string_view> forbidden;  // include prefixes those files may not use
  std::vector<std::string_view> allowed;    // ... except these
  std::string_view why;
};

// "vulkan/" is Vulkan's headers, "vtk" VTK's (vtk*.h).
const std::vector<Rule> kRules = {
    {{""}, {"app/", "tests/"}, {"app/"}, {},
     "app/ is the top layer: only app/ and the tests include it"},
    {{"app/common/"}, {}, {"app/"}, {"app/common/"},
     "app/common is the bottom of app/: the verbs, the window and the bench build on it, so it includes none of them"},
    {{"app/viewer/"}, {}, {"app/"}, {"app/common/", "app/viewer/"},
     "the window builds on app/common only: the verbs (app/ itself) sit above it and the bench beside it"},
    {{"app/bench/"}, {}, {"app/"}, {"app/common/", "app/bench/"},
     "the bench builds on app/common only: the verbs (app/ itself) sit above it and the window beside it"},
    {{"scene/"}, {}, {"io/", "renderer/", "vulkan/", "vtk"}, {},
     "scene/ is the plain data io and the renderers speak: it includes neither, nor Vulkan or VTK"},
    {{"io/"}, {}, {"renderer/vk/", "renderer/rt/", "vulkan/"}, {},
     "io/ never touches Vulkan"},
    {{"renderer/"}, {}, {"io/", "vtk"}, {},
     "renderers never parse files, and VTK types stay inside io/"},
    {{"renderer/reference/", "renderer/metrics/"}, {}, {"renderer/vk/", "renderer/rt/", "vulkan/"}, {},
     "the CPU references and the image metrics run without Vulkan"},
    {{"renderer/vk/"}, {}, {"renderer/volume/", "renderer/rt/", "renderer/frame/", "renderer/surface/", "renderer/reference/", "renderer/metrics/",
                          "renderer/sort/", "renderer/timing/"}, {},
     "renderer/vk is the bottom of the renderer: everything else is built on it"},
    {{"renderer/rt/"}, {}, {"renderer/volume/", "renderer/frame/", "renderer/surface/", "renderer/reference/", "renderer/metrics/"}, {},
     "renderer/rt depends on vk and scene only"},
    {{"renderer/sort/"}, {}, {"renderer/volume/", "renderer/frame/", "renderer/surface/", "renderer/mixed/", "renderer/rt/"}, {},
     "renderer/sort holds GPU algorithms any backend may link: it depends on vk only"},
    {{"renderer/timing/"}, {}, {"renderer/volume/", "renderer/frame/", "renderer/surface/", "renderer/mixed/", "renderer/rt/", "renderer/sort/"}, {},
     "renderer/timing times frames of any renderer: it depends on vk's pass timings only"},
    {{"renderer/surface/"}, {}, {"renderer/volume/"}, {},
     "surface backends share GPU algorithms through renderer/sort, not through the volume backends"},
    {{"renderer/volume/"}, {}, {"renderer/frame/frame_renderer", "renderer/mixed/", "renderer/surface/"}, {},
     "the volume backends sit below the frame renderer and the mixed scenes that draw through them"},
    {{"renderer/volume/mesh/"}, {}, {"renderer/volume/compute/", "renderer/volume/cpu/"}, {},
     "a volume backend reads what every backend shares (renderer/volume/), never another backend"},
    {{"renderer/volume/compute/"}, {}, {"renderer/volume/mesh/", "renderer/volume/cpu/"}, {},
     "a volume backend reads what every backend shares (renderer/volume/), never another backend"},
    {{"renderer/volume/cpu/"}, {}, {"renderer/volume/mesh/", "renderer/volume/compute/", "renderer/vk/"}, {},
     "the CPU reference backend shares no GPU backend's code and draws without a device"},
    {{"paraview/"}, {}, {"io/"}, {},
     "the ParaView plugin links ParaView's own VTK: io/, built on the system VTK 9.1, stays out of it"},
    {{"paraview/plugin/PrismoidVolume/prismoid_session"}, {}, {"vtk"}, {},
     "the plugin's Prismoid half includes no VTK: the boundary between ParaView's VTK and Prismoid's core is vtk_to_prismoid"},
};

struct Include {
  int line = 0;
  std::string name;  // as written, between the quotes or brackets
  bool angled = false;
};

struct Violation {
  std::string file;
  int line = 0;
  std::string include;
  std::string_view why;
};

bool starts_with_any(std::string_view s, const std::vector<std::string_view>& prefixes) {
  for (std::string_view p : prefixes)
    if (s.starts_with(p)) return true;
  return false;
}

// The #include lines of a source file (C++ or GLSL), with their line numbers.
std::vector<Include> includes_of(const std::string& text) {
  static const std::regex kInclude(R"(^\s*#\s*include\s*([<"])([^>"]+)[>"])");
  std::vector<Include> out;
  std::istringstream in(text);
  std::string line;
  for (int n = 1; std::getline(in, line); ++n) {
    std::smatch m;
    if (std::regex_search(line, m, kInclude)) out.push_back({n, m[2].str(), m[1].str() == "<"});
  }
  return out;
}

// The name the rules match: an existing file relative to the includer's folder, else the quoted
// path as written (the project includes from the repository root); angled names as written.
std::string resolved_name(const std::filesystem::path& root, const std::string& file, const Include& inc) {
  if (inc.angled) return inc.name;
  const std::filesystem::path beside = (std::filesystem::path(file).parent_path() / inc.name).lexically_normal();
  if (!beside.empty() && *beside.begin() != ".." && std::filesystem::is_regular_file(root / beside)) return beside.generic_string();
  return inc.name;
}

// The rules `file` breaks by including `name` (already resolved).
std::vector<Violation> check(const std::string& file, int line, const std::string& name) {
  std::vector<Violation> out;
  for (const Rule& r : kRules)
    if (starts_with_any(file, r.files) && !starts_with_any(file, r.except) && starts_with_any(name, r.forbidden) &&
        !starts_with_any(name, r.allowed))
      out.push_back({file, line, name, r.why});
  return out;
}

bool is_source(const std::filesystem::path& p) {
  static const std::vector<std::string> kExtensions = {".cpp", ".hpp", ".h", ".cc", ".inl", ".glsl", ".comp", ".frag", ".vert",
                                                       ".mesh", ".task", ".rgen", ".rchit", ".rmiss", ".rahit"};
  for (const std::string& e : kExtensions)
    if (p.extension() == e) return true;
  return false;
}

// Folders that hold no source of ours: build trees, git, fetched data, outputs.
bool skipped_folder(const std::string& name) {
  return name.starts_with(".") || name.starts_with("build") || name == "datasets" || name == "out" || name == "bundle";
}

struct Scan {
  size_t files = 0;
  size_t includes = 0;
  std::vector<Violation> violations;
};

Scan scan_tree(const std::filesystem::path& root) {
  Scan scan;
  namespace fs = std::filesystem;
  for (auto it = fs::recursive_directory_iterator(root); it != fs::recursive_directory_iterator(); ++it) {
    if (it->is_directory()) {
      if (skipped_folder(it->path().filename().string())) it.disable_recursion_pending();
      continue;
    }
    if (!it->is_regular_file() || !is_source(it->path())) continue;
    const std::string file = it->path().lexically_relative(root).generic_string();
    std::ifstream in(it->path(), std::ios::binary);
    std::ostringstream text;
    text << in.rdbuf();
    ++scan.files;
    for (const Include& inc : includes_of(text.str())) {
      ++scan.includes;
      for (Violation& v : check(file, inc.line, resolved_name(root, file, inc))) scan.violations.push_back(std::move(v));
    }
  }
  return scan;
}

// Every forbidden prefix of every rule fires for a file the rule covers.
TEST(LayeringRules, EachRuleCatchesWhatItForbids) {
  for (const Rule& r : kRules)
    for (std::string_view from : r.files)
      for (std::string_view forbidden : r.forbidden) {
        const std::string file = std::string(from) + "example.cpp";
        const std::string name = std::string(forbidden) + "example.hpp";
        ASSERT_FALSE(starts_with_any(file, r.except)) << file;
        const std::vector<Violation> v = check(file, 7, name);
        ASSERT_FALSE(v.empty()) << file << " including " << name << " should break: " << r.why;
        EXPECT_EQ(v.front().line, 7);
        EXPECT_EQ(v.front().file, file);
      }
}

// What docs/architecture.md allows passes: the arrows point down, and tests may include anything.
TEST(LayeringRules, AllowsWhatTheArchitectureAllows) {
  const std::vector<std::pair<std::string, std::string>> allowed = {
      {"tests/app/test_cli.cpp", "app/cli.hpp"},
      {"app/cmd_render.cpp", "renderer/vk/device.hpp"},
      {"app/cmd_view.cpp", "app/viewer/viewer.hpp"},
      {"app/cmd_bench.cpp", "app/bench/bench_table.hpp"},
      {"app/cmd_render.cpp", "app/common/volume_options.hpp"},
      {"app/cli.cpp", "app/commands.hpp"},
      {"app/common/volume_options.hpp", "app/common/cli_args.hpp"},
      {"app/common/cli_args.hpp", "renderer/vk/timer.hpp"},
      {"app/viewer/viewer.cpp", "app/common/dataset_loader.hpp"},
      {"app/viewer/viewer.cpp", "app/viewer/window_loop.hpp"},
      {"app/bench/surface_bench.cpp", "app/common/surface_args.hpp"},
      {"app/bench/bench_table.cpp", "app/bench/pareto.hpp"},
      {"app/viewer/viewer.cpp", "io/surface_io.hpp"},
      {"app/bench/vtk_peers.cpp", "vtkUnstructuredGrid.h"},
      {"io/transfer_function_io.hpp", "renderer/volume/transfer_function.hpp"},
      {"io/vtk_grid.cpp", "vtkUnstructuredGrid.h"},
      {"renderer/volume/interval_shading.cpp", "renderer/vk/device.hpp"},
      {"renderer/volume/interval_shading.cpp", "vulkan/vulkan.h"},
      {"renderer/reference/htex_reference.hpp", "renderer/surface/htex/htex_layout.hpp"},
      {"renderer/rt/ray_caster.cpp", "renderer/vk/device.hpp"},
      {"renderer/surface/fastatlas/fastatlas_pass.hpp", "renderer/sort/radix_sort.hpp"},
      {"renderer/volume/compute_intervals.hpp", "renderer/sort/radix_sort.hpp"},
      {"renderer/sort/radix_sort.cpp", "renderer/vk/device.hpp"},
      {"renderer/vk/pipeline.cpp", "shaders/registry.hpp"},
      {"scene/camera.hpp", "glm/vec3.hpp"},
      {"shaders/surface/htex/htex.glsl", "shaders/shared/htex.h"},
  };
  for (const auto& [file, name] : allowed) EXPECT_TRUE(check(file, 1, name).empty()) << file << " including " << name;
}

// The layers inside app/: the verbs on top, the window and the bench beside each other, app/common
// at the bottom. Each of these includes breaks exactly the rule named.
TEST(LayeringRules, AppLayersPointDown) {
  struct Case {
    std::string file, name, rule_files;
  };
  const std::vector<Case> forbidden = {
      {"app/common/cli_args.cpp", "app/cli.hpp", "app/common/"},
      {"app/common/volume_options.cpp", "app/viewer/view_state.hpp", "app/common/"},
      {"app/common/frame_image.cpp", "app/bench/bench_cases.hpp", "app/common/"},
      {"app/common/dataset_loader.cpp", "app/dataset_report.hpp", "app/common/"},
      {"app/viewer/viewer.cpp", "app/cli.hpp", "app/viewer/"},
      {"app/viewer/viewer.cpp", "app/commands.hpp", "app/viewer/"},
      {"app/viewer/viewer.cpp", "app/cmd_render.cpp", "app/viewer/"},
      {"app/viewer/mode_panel.cpp", "app/bench/bench_table.hpp", "app/viewer/"},
      {"app/bench/surface_bench.cpp", "app/commands.hpp", "app/bench/"},
      {"app/bench/surface_bench.cpp", "app/cli.hpp", "app/bench/"},
      {"app/bench/bench_table.cpp", "app/viewer/viewer.hpp", "app/bench/"},
  };
  for (const Case& c : forbidden) {
    const std::vector<Violation> v = check(c.file, 3, c.name);
    ASSERT_EQ(v.size(), 1u) << c.file << " including " << c.name;
    const auto rule = std::find_if(kRules.begin(), kRules.end(), [&](const Rule& r) { return r.why == v.front().why; });
    ASSERT_NE(rule, kRules.end());
    EXPECT_EQ(rule->files.front(), c.rule_files) << c.file << " including " << c.name << ": " << v.front().why;
  }
}

// Include lines are read as the preprocessor reads them, and relative quoted names resolve
// against the includer's folder.
TEST(LayeringRules, ReadsIncludeLinesAndResolvesRelativeNames) {
  const std::vector<Include> inc = includes_of(
      "#pragma once\n#include \"app/cli.hpp\"\n  #  include <vulkan/vulkan.h>\n// #include \"io/x.hpp\" is a comment\n"
      "const char* s = \"#include \\\"app/x.hpp\\\"\";\n#include\"scene/camera.hpp\"\n");
  ASSERT_EQ(inc.size(), 3u);
  EXPECT_EQ(inc[0].line, 2);
  EXPECT_EQ(inc[0].name, "app/cli.hpp");
  EXPECT_FALSE(inc[0].angled);
  EXPECT_EQ(inc[1].line, 3);
  EXPECT_EQ(inc[1].name, "vulkan/vulkan.h");
  EXPECT_TRUE(inc[1].angled);
  EXPECT_EQ(inc[2].line, 6);
  EXPECT_EQ(inc[2].name, "scene/camera.hpp");

  const std::filesystem::path root = PRISMOID_SOURCE_DIR;
  EXPECT_EQ(resolved_name(root, "shaders/surface/htex/htex.glsl", {1, "../../shared/htex.h", false}), "shaders/shared/htex.h");
  EXPECT_EQ(resolved_name(root, "renderer/vk/device.cpp", {1, "renderer/vk/device.hpp", false}), "renderer/vk/device.hpp");
  EXPECT_EQ(resolved_name(root, "renderer/vk/device.cpp", {1, "vulkan/vulkan.h", true}), "vulkan/vulkan.h");
}

TEST(Layering, SourceTreeKeepsTheRules) {
  const Scan scan = scan_tree(PRISMOID_SOURCE_DIR);
  // The scan saw the tree (a wrong root would pass with nothing read).
  EXPECT_GT(scan.files, 300u);
  EXPECT_GT(scan.includes, 2000u);
  for (const Violation& v : scan.violations)
    ADD_FAILURE() << v.file << ":" << v.line << ": includes \"" << v.include << "\": " << v.why;
}

}  // namespace
}  // namespace prismoid::test
