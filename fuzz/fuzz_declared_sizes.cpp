// The declared-size checks (io/declared_sizes): headers of .ply, VTK XML, legacy .vtk, MetaImage
// and netCDF (Exodus II) files read before any reader runs. The first byte picks the kind: the
// digits "1" to "8" pick them in the order of `kinds` (the seeds start so), other bytes modulo 8.
#include <string>

#include "fuzz/fuzz_input.hpp"
#include "io/declared_sizes.hpp"

using namespace prismoid;

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size == 0) return 0;
  static const char* const kinds[] = {".ply", ".vtu", ".vtp", ".vti", ".vtk", ".mha", ".mhd", ".exo"};
  const std::string ext = kinds[uint8_t(data[0] - '1') % (sizeof kinds / sizeof kinds[0])];
  const std::string file(reinterpret_cast<const char*>(data + 1), size - 1);
  fuzz::expect_input_errors_only([&] {
    io::detail::check_declared_sizes("fuzz" + ext, ext, file.size(), [&](uint64_t offset, size_t count) {
      fuzz::require(offset <= file.size() + 4096, "reads start near the file");
      return offset >= file.size() ? std::string() : file.substr(size_t(offset), count);
    });
  });
  return 0;
}
