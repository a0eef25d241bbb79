// The .off reader (VTK has none, so it is ours).
#include <sstream>

#include "fuzz/fuzz_input.hpp"
#include "io/off_reader.hpp"

using namespace prismoid;

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  std::istringstream in(std::string(reinterpret_cast<const char*>(data), size));
  fuzz::expect_input_errors_only([&] {
    const io::detail::OffPolygons off = io::detail::parse_off(in, "fuzz.off");
    for (const auto& face : off.faces)
      for (uint32_t v : face) fuzz::require(v < off.points.size(), "face indices name existing vertices");
  });
  return 0;
}
