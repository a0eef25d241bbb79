#pragma once
// The unit cube [0,1]^3 as an outward-wound OFF surface: TetGen fills it, slowly under a small
// volume bound, which makes it the test's long-running load.
#include <filesystem>
#include <fstream>

namespace prismoid::test {

inline void write_cube_off(const std::filesystem::path& path) {
  std::ofstream out(path);
  out << "OFF\n8 12 0\n";
  for (int i = 0; i < 8; ++i)
    out << (i == 1 || i == 2 || i == 5 || i == 6) << " " << (i == 2 || i == 3 || i == 6 || i == 7) << " " << (i >= 4) << "\n";
  for (const char* f : {"0 2 1", "0 3 2", "4 5 6", "4 6 7", "0 1 5", "0 5 4", "1 2 6", "1 6 5", "2 3 7", "2 7 6", "3 0 4", "3 4 7"})
    out << "3 " << f << "\n";
}

}  // namespace prismoid::test
