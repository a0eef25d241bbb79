#include "io/inrimage.hpp"
#include "io/path_util.hpp"

#include <bit>
#include <charconv>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <map>
#include <memory>

#include <zlib.h>

#include "scene/input_error.hpp"

namespace prismoid::io::detail {

namespace {

constexpr char kMagic[] = "#INRIMAGE-4#{\n";
constexpr char kEnd[] = "##}";
constexpr size_t kMaxHeaderBytes = 64 * 1024;  // real headers are 256 bytes; this only stops runaway reads

// zlib reads plain files too (gzread passes them through), so one path serves .inr and .inr.gz.
struct GzCloser {
  void operator()(gzFile_s* f) const { gzclose(f); }
};
using GzFile = std::unique_ptr<gzFile_s, GzCloser>;

GzFile open(const std::string& path) {
  require_regular_file(path);
  GzFile file(gzopen(path.c_str(), "rb"));
  if (!file) throw InputError(path, "cannot be opened for reading");
  return file;
}

// Reads exactly `count` bytes; returns how many it got (fewer at the end of the file).
size_t read_bytes(const std::string& path, gzFile_s* file, char* out, size_t count) {
  size_t got = 0;
  while (got < count) {
    const unsigned chunk = static_cast<unsigned>(std::min<size_t>(count - got, 1u << 30));
    const int n = gzread(file, out + got, chunk);
    if (n < 0) throw InputError(path, "is not readable (corrupt gzip data?)");
    if (n == 0) break;
    got += size_t(n);
  }
  return got;
}

// The header's lines, up to and without the "##}" line; leaves the file at the first voxel.
std::vector<std::string> header_lines(const std::string& path, gzFile_s* file) {
  char magic[sizeof kMagic - 1];
  if (read_bytes(path, file, magic, sizeof magic) != sizeof magic || std::memcmp(magic, kMagic, sizeof magic) != 0)
    throw InputError(path, "is not an INRIMAGE-4 file (it does not start with \"#INRIMAGE-4#{\")");
  std::vector<std::string> lines;
  std::string line;
  for (size_t total = sizeof magic; total < kMaxHeaderBytes; ++total) {
    char c;
    if (read_bytes(path, file, &c, 1) != 1) throw InputError(path, "INRIMAGE header ends before its \"##}\" line (truncated file)");
    if (c != '\n') {
      line += c;
      continue;
    }
    if (line == kEnd) return lines;
    if (!line.empty()) lines.push_back(line);
    line.clear();
  }
  throw InputError(path, "INRIMAGE header has no \"##}\" line in its first " + std::to_string(kMaxHeaderBytes) + " bytes");
}

uint64_t parse_count(const std::string& path, const std::string& key, const std::string& value) {
  uint64_t n = 0;
  const auto [end, error] = std::from_chars(value.data(), value.data() + value.size(), n);
  if (error != std::errc() || end != value.data() + value.size() || n == 0)
    throw InputError(path, "INRIMAGE header: " + key + "=" + value + " is not a positive integer");
  return n;
}

double parse_real(const std::string& path, const std::string& key, const std::string& value) {
  double x = 0.0;
  const auto [end, error] = std::from_chars(value.data(), value.data() + value.size(), x);
  if (error != std::errc() || end != value.data() + value.size() || !std::isfinite(x))
    throw InputError(path, "INRIMAGE header: " + key + "=" + value + " is not a finite number");
  return x;
}

double decode(const InrHeader& h, const unsigned char* p) {
  unsigned char b[8];
  const bool swap = h.big_endian != (std::endian::native == std::endian::big);
  for (uint32_t i = 0; i < h.bytes_per_voxel; ++i) b[i] = swap ? p[h.bytes_per_voxel - 1 - i] : p[i];
  auto as = [&b]<typename T>(T) {
    T v;
    std::memcpy(&v, b, sizeof v);
    return static_cast<double>(v);
  };
  switch (h.type) {
    case InrHeader::Type::Float: return h.bytes_per_voxel == 4 ? as(float{}) : as(double{});
    case InrHeader::Type::Signed:
      switch (h.bytes_per_voxel) {
        case 1: return as(int8_t{});
        case 2: return as(int16_t{});
        case 4: return as(int32_t{});
        default: return as(int64_t{});
      }
    case InrHeader::Type::Unsigned:
      switch (h.bytes_per_voxel) {
        case 1: return as(uint8_t{});
        case 2: return as(uint16_t{});
        case 4: return as(uint32_t{});
        default: return as(uint64_t{});
      }
  }
  return 0.0;
}

}  // namespace

InrHeader read_inr_header(const std::string& path) {
  GzFile file = open(path);
  std::map<std::string, std::string> fields;
  for (const std::string& line : header_lines(path, file.get())) {
    if (line[0] == '#') continue;  // comments such as "#GEOMETRY=CARTESIAN"
    const size_t eq = line.find('=');
    if (eq == std::string::npos) throw InputError(path, "INRIMAGE header line \"" + line + "\" is not KEY=value");
    const std::string key = line.substr(0, eq);
    if (!fields.emplace(key, line.substr(eq + 1)).second) throw InputError(path, "INRIMAGE header repeats " + key);
  }
  auto take = [&](const std::string& key) -> std::string {
    const auto found = fields.find(key);
    if (found == fields.end()) return {};
    std::string value = found->second;
    fields.erase(found);
    return value;
  };

  InrHeader h;
  const char* dim_keys[3] = {"XDIM", "YDIM", "ZDIM"};
  for (int a = 0; a < 3; ++a) {
    const std::string value = take(dim_keys[a]);
    if (value.empty()) throw InputError(path, std::string("INRIMAGE header has no ") + dim_keys[a]);
    h.dims[a] = parse_count(path, dim_keys[a], value);
  }
  if (const std::string v = take("VDIM"); !v.empty() && parse_count(path, "VDIM", v) != 1)
    throw InputError(path, "INRIMAGE VDIM=" + v + ": only scalar images (VDIM=1) are supported");

  const std::string type = take("TYPE");
  if (type == "unsigned fixed") h.type = InrHeader::Type::Unsigned;
  else if (type == "signed fixed") h.type = InrHeader::Type::Signed;
  else if (type == "float") h.type = InrHeader::Type::Float;
  else throw InputError(path, "INRIMAGE TYPE=\"" + type + "\" is not supported (unsigned fixed, signed fixed, float)");

  const std::string pixsize = take("PIXSIZE");
  if (pixsize == "8 bits") h.bytes_per_voxel = 1;
  else if (pixsize == "16 bits") h.bytes_per_voxel = 2;
  else if (pixsize == "32 bits") h.bytes_per_voxel = 4;
  else if (pixsize == "64 bits") h.bytes_per_voxel = 8;
  else throw InputError(path, "INRIMAGE PIXSIZE=\"" + pixsize + "\" is not supported (8, 16, 32 or 64 bits)");
  if (h.type == InrHeader::Type::Float && h.bytes_per_voxel < 4)
    throw InputError(path, "INRIMAGE TYPE=float needs PIXSIZE=32 bits or 64 bits, not " + pixsize);

  // Fixed-point data with a scale other than 1 would need rescaling nobody has asked for.
  if (const std::string scale = take("SCALE"); !scale.empty() && scale != "2**0")
    throw InputError(path, "INRIMAGE SCALE=" + scale + " is not supported (only 2**0)");

  const std::string cpu = take("CPU");
  if (cpu == "decm" || cpu == "alpha" || cpu == "pc") h.big_endian = false;
  else if (cpu == "sun" || cpu == "sgi") h.big_endian = true;
  else throw InputError(path, "INRIMAGE CPU=\"" + cpu + "\" is not a known byte order (decm, alpha, pc, sun, sgi)");

  const char* spacing_keys[3] = {"VX", "VY", "VZ"};
  const char* origin_keys[3] = {"TX", "TY", "TZ"};
  for (int a = 0; a < 3; ++a) {
    if (const std::string v = take(spacing_keys[a]); !v.empty()) h.spacing[a] = parse_real(path, spacing_keys[a], v);
    if (h.spacing[a] <= 0.0) throw InputError(path, std::string("INRIMAGE ") + spacing_keys[a] + " must be positive");
    if (const std::string v = take(origin_keys[a]); !v.empty()) h.origin[a] = parse_real(path, origin_keys[a], v);
  }
  // CGAL writes these only when non-zero: an integer voxel offset (XO..) and a rotation (RX..),
  // neither of which this reader places in space.
  for (const char* key : {"XO", "YO", "ZO", "RX", "RY", "RZ"})
    if (const std::string v = take(key); !v.empty() && parse_real(path, key, v) != 0.0)
      throw InputError(path, std::string("INRIMAGE ") + key + "=" + v + ": " + (key[0] == 'R' ? "rotated" : "offset") +
                                 " images are not supported");
  if (!fields.empty()) throw InputError(path, "INRIMAGE header field " + fields.begin()->first + " is not understood");
  return h;
}

std::vector<double> read_inr_voxels(const std::string& path, const InrHeader& h, uint32_t subsample) {
  GzFile file = open(path);
  header_lines(path, file.get());
  const uint64_t nx = h.dims[0], ny = h.dims[1], nz = h.dims[2];
  auto kept = [subsample](uint64_t n) { return (n - 1) / subsample + 1; };
  std::vector<double> values;
  values.reserve(kept(nx) * kept(ny) * kept(nz));
  std::vector<unsigned char> row(nx * h.bytes_per_voxel);
  for (uint64_t k = 0; k < nz; ++k)
    for (uint64_t j = 0; j < ny; ++j) {
      if (read_bytes(path, file.get(), reinterpret_cast<char*>(row.data()), row.size()) != row.size())
        throw InputError(path, "INRIMAGE voxel data is truncated (expected " + std::to_string(nx * ny * nz) + " voxels of " +
                                   std::to_string(h.bytes_per_voxel) + " bytes; it ends in slice " + std::to_string(k) + ")");
      if (k % subsample != 0 || j % subsample != 0) continue;
      for (uint64_t i = 0; i < nx; i += subsample) {
        const double v = decode(h, row.data() + i * h.bytes_per_voxel);
        if (!std::isfinite(v)) throw InputError(path, "INRIMAGE voxel data holds a non-finite value");
        values.push_back(v);
      }
    }
  char extra;
  if (read_bytes(path, file.get(), &extra, 1) != 0)
    throw InputError(path, "has bytes after its " + std::to_string(nx * ny * nz) + " voxels (wrong XDIM/YDIM/ZDIM or PIXSIZE?)");
  return values;
}

}  // namespace prismoid::io::detail
