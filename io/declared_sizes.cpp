#include "io/declared_sizes.hpp"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <vector>

#include <zlib.h>

#include "io/path_util.hpp"
#include "scene/input_error.hpp"

namespace prismoid::io::detail {

namespace {

// Counts and byte totals: a declared count times bytes per value can pass 2^64.
using Amount = long double;

// The largest ratios of the compressors VTK writes with: zlib's is 1032:1; LZ4's about 255:1;
// LZMA has no small bound, and 65536:1 is far beyond what xz reaches (about 7000:1 on zeros).
constexpr Amount kZlibRatio = 1032, kLz4Ratio = 255, kLzmaRatio = 65536;

// Headers are read this far at most; an honest header is far shorter.
constexpr size_t kHeadBytes = size_t(1) << 20;

// Counts as written: an unsigned whole number, or nothing (the reader then refuses the text).
// A number too large for 64 bits counts as the largest.
bool parse_count(const std::string& word, Amount& count) {
  uint64_t value = 0;
  const auto [end, error] = std::from_chars(word.data(), word.data() + word.size(), value);
  if (end != word.data() + word.size() || word.empty()) return false;
  count = error == std::errc::result_out_of_range ? 1.8446744073709551615e19L : Amount(value);
  return error == std::errc() || error == std::errc::result_out_of_range;
}

std::string count_text(Amount count) {
  std::ostringstream s;
  s.precision(0);
  s << std::fixed << count;
  return s.str();
}

std::vector<std::string> words_of(const std::string& line) {
  std::istringstream in(line);
  std::vector<std::string> words;
  for (std::string w; in >> w;) words.push_back(w);
  return words;
}

std::string upper(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return char(std::toupper(c)); });
  return s;
}

// The line starting at `at` (without its end) and where the next one starts.
std::string line_at(const std::string& text, size_t at, size_t& next) {
  const size_t end = text.find('\n', at);
  next = end == std::string::npos ? text.size() : end + 1;
  std::string line = text.substr(at, (end == std::string::npos ? text.size() : end) - at);
  if (!line.empty() && line.back() == '\r') line.pop_back();
  return line;
}

[[noreturn]] void refuse(const std::string& path, const std::string& declared, Amount need, Amount have) {
  throw InputError(path, "declares " + declared + ", at least " + count_text(need) + " bytes of data, but holds " + count_text(have) +
                             " bytes for them: the file is truncated or corrupt");
}

// ---- PLY: element counts times the least bytes of one element ---------------------------------

size_t ply_type_bytes(const std::string& type) {
  if (type == "char" || type == "uchar" || type == "int8" || type == "uint8") return 1;
  if (type == "short" || type == "ushort" || type == "int16" || type == "uint16") return 2;
  if (type == "int" || type == "uint" || type == "int32" || type == "uint32" || type == "float" || type == "float32") return 4;
  if (type == "double" || type == "float64") return 8;
  return 1;  // unknown: the reader refuses it
}

void check_ply(const std::string& path, uint64_t file_bytes, const ReadAt& read_at) {
  const std::string head = read_at(0, kHeadBytes);
  struct Element {
    std::string name;
    Amount count = 0;
    size_t least_bytes = 0;
  };
  std::vector<Element> elements;
  bool ascii = true, ended = false;
  size_t at = 0, next = 0;
  while (at < head.size()) {
    const std::vector<std::string> w = words_of(line_at(head, at, next));
    at = next;
    if (w.empty()) continue;
    if (w[0] == "end_header") {
      ended = true;
      break;
    }
    if (w[0] == "format" && w.size() > 1) ascii = w[1] == "ascii";
    if (w[0] == "element" && w.size() > 2) {
      Element e;
      e.name = w[1];
      if (!parse_count(w[2], e.count)) throw InputError(path, "declares element '" + w[1] + "' with the count '" + w[2] + "', not a whole number");
      elements.push_back(e);
    }
    if (w[0] == "property" && !elements.empty()) {
      // ASCII: each value is at least a digit and a separator; binary: the type's bytes (a
      // list at least its count).
      const bool list = w.size() > 1 && w[1] == "list";
      elements.back().least_bytes += ascii ? 2 : ply_type_bytes(list ? (w.size() > 2 ? w[2] : "") : (w.size() > 1 ? w[1] : ""));
    }
  }
  if (!ended) {
    if (head.size() < kHeadBytes) throw InputError(path, "has no end_header line: the PLY header is truncated or corrupt");
    throw InputError(path, "has no end_header line in its first MiB: not a PLY file, or a corrupt one");
  }
  const Amount have = Amount(file_bytes) - Amount(at);
  Amount need = 0;
  std::string declared;
  for (const Element& e : elements) {
    // An element is at least one byte (a line in ASCII), whatever its properties.
    need += e.count * Amount(std::max<size_t>(1, e.least_bytes));
    declared += (declared.empty() ? "" : " and ") + count_text(e.count) + " '" + e.name + "' elements";
  }
  if (need > have) refuse(path, declared, need, have);
}

// ---- VTK XML: NumberOfPoints and cell counts of each piece ------------------------------------

// The attribute's value in the tag starting at `tag` (up to its '>'), or "".
std::string attribute(const std::string& text, size_t tag, const std::string& name) {
  const size_t end = text.find('>', tag);
  const std::string key = " " + name + "=\"";
  const size_t at = text.find(key, tag);
  if (at == std::string::npos || (end != std::string::npos && at > end)) return "";
  const size_t start = at + key.size(), stop = text.find('"', start);
  return stop == std::string::npos ? "" : text.substr(start, stop - start);
}

// The tag's name at `at` (just after its '<').
std::string tag_name(const std::string& text, size_t at) {
  const size_t end = text.find_first_of(" \t\r\n/>", at);
  return text.substr(at, (end == std::string::npos ? text.size() : end) - at);
}

// The points and cells of a piece: its counts, or for image data (.vti) its extent's voxels.
void piece_counts(const std::string& text, size_t tag, Amount& points, Amount& cells, Amount (&kinds)[4]) {
  points = cells = 0;
  for (Amount& k : kinds) k = 0;
  parse_count(attribute(text, tag, "NumberOfPoints"), points);
  parse_count(attribute(text, tag, "NumberOfCells"), cells);
  const char* const kind_names[4] = {"NumberOfVerts", "NumberOfLines", "NumberOfStrips", "NumberOfPolys"};
  for (int k = 0; k < 4; ++k) parse_count(attribute(text, tag, kind_names[k]), kinds[k]);
  std::istringstream extent(attribute(text, tag, "Extent"));
  long double lo = 0, hi = 0;
  Amount voxels = 1, cubes = 1;
  int axes = 0;
  while (extent >> lo >> hi && hi >= lo) {
    voxels *= hi - lo + 1;
    cubes *= hi - lo;
    ++axes;
  }
  if (axes == 3) {
    points = voxels;
    cells = cubes;
  }
}

// Every DataArray declares its tuples (NumberOfTuples, or the piece's points or cells for the
// section it is in) and components; the file must hold each value, at least a byte of it before
// compression.
void check_xml(const std::string& path, uint64_t file_bytes, const ReadAt& read_at) {
  std::string head = read_at(0, kHeadBytes);
  if (const size_t appended = head.find("<AppendedData"); appended != std::string::npos) head.resize(appended);
  const size_t file_tag = head.find("<VTKFile");
  if (file_tag == std::string::npos) return;  // the reader says what it is not
  Amount ratio = 1;
  if (const std::string compressor = attribute(head, file_tag, "compressor"); !compressor.empty())
    ratio = compressor.find("ZLib") != std::string::npos ? kZlibRatio : compressor.find("LZ4") != std::string::npos ? kLz4Ratio : kLzmaRatio;
  Amount points = 0, cells = 0, values = 0;  // over all pieces
  Amount piece_points = 0, piece_cells = 0, kinds[4] = {0, 0, 0, 0};
  Amount section_tuples = 0;  // of the section the next DataArray is in
  for (size_t at = head.find('<'); at != std::string::npos; at = head.find('<', at + 1)) {
    const std::string name = tag_name(head, at + 1);
    if (name == "Piece") {
      piece_counts(head, at, piece_points, piece_cells, kinds);
      points += piece_points;
      cells += piece_cells;
      section_tuples = 0;
    } else if (name == "Points" || name == "PointData") {
      section_tuples = piece_points;
    } else if (name == "Cells" || name == "CellData") {
      section_tuples = piece_cells;
    } else if (name == "Verts" || name == "Lines" || name == "Strips" || name == "Polys") {
      section_tuples = kinds[name == "Verts" ? 0 : name == "Lines" ? 1 : name == "Strips" ? 2 : 3];
    } else if (name == "FieldData") {
      section_tuples = 0;  // only arrays that say NumberOfTuples
    } else if (name == "DataArray") {
      Amount tuples = section_tuples, components = 1;
      parse_count(attribute(head, at, "NumberOfTuples"), tuples);
      parse_count(attribute(head, at, "NumberOfComponents"), components);
      // A cell's connectivity holds its points: how many is not declared (at least none).
      if (attribute(head, at, "Name") == "connectivity") tuples = 0;
      values += tuples * std::max<Amount>(components, 1);
    }
  }
  const Amount need = values / ratio;
  if (need > Amount(file_bytes))
    refuse(path,
           count_text(points) + " points and " + count_text(cells) + " cells with arrays of " + count_text(values) + " values" +
               (ratio > 1 ? " (compressed at most " + count_text(ratio) + ":1)" : ""),
           need, Amount(file_bytes));
}

// ---- legacy VTK: POINTS, CELLS and CELL_TYPES ------------------------------------------------

size_t legacy_type_bytes(const std::string& type) {
  const std::string t = upper(type);
  if (t == "CHAR" || t == "UNSIGNED_CHAR" || t == "BIT") return 1;
  if (t == "SHORT" || t == "UNSIGNED_SHORT") return 2;
  if (t == "INT" || t == "UNSIGNED_INT" || t == "FLOAT") return 4;
  if (t == "LONG" || t == "UNSIGNED_LONG" || t == "DOUBLE" || t == "VTKIDTYPE" || t == "VTKTYPEINT64" || t == "VTKTYPEUINT64") return 8;
  return 1;
}

void check_legacy(const std::string& path, uint64_t file_bytes, const ReadAt& read_at) {
  const std::string head = read_at(0, kHeadBytes);
  size_t at = 0, next = 0;
  std::string lines[3];
  for (std::string& line : lines) {
    line = line_at(head, at, next);
    at = next;
  }
  if (lines[0].rfind("# vtk DataFile", 0) != 0) return;  // the reader says what it is not
  const bool binary = upper(lines[2]).rfind("BINARY", 0) == 0;
  // In ASCII every value is at least a digit and a separator; in binary integers of the cell
  // lists are at least four bytes.
  const size_t index_bytes = binary ? 4 : 2;
  // The section's least bytes, refused when more than the file holds after `data_start`; 0 for a
  // line that is not one of those sections.
  auto check_at = [&](const std::string& line, uint64_t data_start) -> Amount {
    const std::vector<std::string> w = words_of(line);
    if (w.size() < 2) return 0;
    const std::string key = upper(w[0]);
    const Amount have = Amount(file_bytes) - Amount(data_start);
    Amount n = 0;
    if (key == "POINTS" && parse_count(w[1], n)) {
      const Amount need = 3 * n * Amount(binary ? legacy_type_bytes(w.size() > 2 ? w[2] : "") : 2);
      if (need > have) refuse(path, count_text(n) + " points", need, have);
      return need;
    }
    // CELLS N SIZE: SIZE integers follow (VTK 5.1's files: SIZE connectivity entries, and N offsets).
    if (key == "CELLS" && w.size() > 2 && parse_count(w[2], n)) {
      const Amount need = n * Amount(index_bytes);
      if (need > have) refuse(path, "cells of " + count_text(n) + " indices", need, have);
      return need;
    }
    if (key == "CELL_TYPES" && parse_count(w[1], n)) {
      const Amount need = n * Amount(index_bytes);
      if (need > have) refuse(path, count_text(n) + " cell types", need, have);
      return need;
    }
    return 0;
  };
  // The text before the point data: DATASET, POINTS.
  while (at < head.size()) {
    const std::string line = line_at(head, at, next);
    const std::vector<std::string> w = words_of(line);
    if (!w.empty() && upper(w[0]) == "POINTS") {
      const Amount points_bytes = check_at(line, next);
      if (binary) {
        // The next section starts after the point data (and its line end); binary data can hold
        // any bytes, so only that place is read as text.
        const uint64_t after = uint64_t(next) + uint64_t(points_bytes);
        const std::string text = after < file_bytes ? read_at(after, 4096) : std::string();
        if (const size_t skip = text.find_first_not_of("\r\n \t"); skip != std::string::npos) {
          size_t line_end = 0;
          const std::string cells_line = line_at(text, skip, line_end);
          check_at(cells_line, after + line_end);
        }
      }
      break;
    }
    if (!w.empty() && upper(w[0]) == "FIELD") break;  // field data may be binary: not read as text
    at = next;
  }
  if (binary) return;
  // ASCII: the cell sections' lines, wherever they are in the first MiB.
  for (const char* key : {"\nCELLS ", "\nCELL_TYPES "})
    if (const size_t found = head.find(key); found != std::string::npos) {
      const std::string line = line_at(head, found + 1, next);
      check_at(line, next);
    }
}

// ---- MetaImage: NDims, DimSize and the element type of LOCAL data ------------------------------

size_t meta_type_bytes(const std::string& type) {
  if (type == "MET_CHAR" || type == "MET_UCHAR") return 1;
  if (type == "MET_SHORT" || type == "MET_USHORT") return 2;
  if (type == "MET_INT" || type == "MET_UINT" || type == "MET_FLOAT") return 4;
  if (type == "MET_LONG_LONG" || type == "MET_ULONG_LONG" || type == "MET_DOUBLE" || type == "MET_LONG" || type == "MET_ULONG") return 8;
  return 1;
}

// Compressed LOCAL data: the zlib stream from `offset` must inflate to every byte the header
// declares. MetaIO fills an image with what the stream gives and leaves the rest as the allocator
// left it: a truncated stream was read as an image whose missing voxels held whatever memory held
// (a different refusal, or none, from run to run). Inflated in pieces and counted, never kept.
void check_inflated(const std::string& path, const ReadAt& read_at, uint64_t offset, uint64_t file_bytes, Amount declared) {
  z_stream z{};
  if (inflateInit(&z) != Z_OK) return;  // no memory for zlib: MetaIO will say so itself
  std::vector<unsigned char> out(size_t(1) << 18);
  Amount inflated = 0;
  int status = Z_OK;
  std::string in;
  while (status == Z_OK && inflated < declared) {
    if (z.avail_in == 0) {
      if (offset >= file_bytes) break;  // the file ends inside the stream
      in = read_at(offset, size_t(1) << 20);
      if (in.empty()) break;
      offset += in.size();
      z.next_in = reinterpret_cast<unsigned char*>(in.data());
      z.avail_in = unsigned(in.size());
    }
    z.next_out = out.data();
    z.avail_out = unsigned(out.size());
    status = inflate(&z, Z_NO_FLUSH);
    inflated += Amount(out.size() - z.avail_out);
    if (status == Z_BUF_ERROR) status = Z_OK;  // no progress possible until more input comes
  }
  const std::string message = z.msg ? z.msg : "";
  inflateEnd(&z);
  if (inflated >= declared) return;
  if (status == Z_DATA_ERROR || status == Z_NEED_DICT || status == Z_MEM_ERROR || status == Z_STREAM_ERROR)
    throw InputError(path, "its compressed voxel data is corrupt (zlib: " + (message.empty() ? std::string("error") : message) + ")");
  throw InputError(path, "its compressed voxel data inflate to " + count_text(inflated) + " bytes; the header declares " +
                             count_text(declared) + ": the file is truncated or corrupt");
}

// MetaIO keeps at most 10 dimensions; a header asking for more is corrupt (MetaIO loops on it).
constexpr Amount kMaxMetaDims = 10;

void check_metaimage(const std::string& path, uint64_t file_bytes, const ReadAt& read_at) {
  const std::string head = read_at(0, kHeadBytes);
  Amount dims = 0, channels = 1, voxels = 1;
  size_t type_bytes = 1;
  bool compressed = false, local = false;
  std::vector<std::string> sizes;
  size_t at = 0, next = 0;
  while (at < head.size()) {
    const std::string line = line_at(head, at, next);
    at = next;
    const size_t eq = line.find('=');
    if (eq == std::string::npos) continue;
    std::vector<std::string> key = words_of(line.substr(0, eq)), value = words_of(line.substr(eq + 1));
    if (key.empty() || value.empty()) continue;
    if (key[0] == "NDims" && parse_count(value[0], dims) && dims > kMaxMetaDims)
      throw InputError(path, "declares NDims = " + value[0] + "; MetaImage images have at most 10 dimensions: the header is corrupt");
    if (key[0] == "DimSize") sizes = value;
    if (key[0] == "ElementNumberOfChannels") parse_count(value[0], channels);
    if (key[0] == "ElementType") type_bytes = meta_type_bytes(value[0]);
    if (key[0] == "CompressedData") compressed = value[0] == "True" || value[0] == "true";
    if (key[0] == "ElementDataFile") {
      local = value[0] == "LOCAL";
      break;  // the data (LOCAL) or nothing follows
    }
  }
  if (!local) return;  // the data is in other files: MetaIO says when they are short
  for (size_t i = 0; i < sizes.size() && Amount(i) < dims; ++i) {
    Amount n = 0;
    if (!parse_count(sizes[i], n)) return;  // MetaIO refuses the text
    voxels *= n;
  }
  const Amount need = voxels * std::max<Amount>(channels, 1) * Amount(type_bytes) / (compressed ? Amount(kZlibRatio) : 1);
  const Amount have = Amount(file_bytes) - Amount(at);
  if (need > have) refuse(path, count_text(voxels) + " voxels" + (compressed ? " (compressed)" : ""), need, have);
  if (compressed) check_inflated(path, read_at, at, file_bytes, voxels * std::max<Amount>(channels, 1) * Amount(type_bytes));
}

// ---- netCDF classic (Exodus II): each variable's values at its offset, within the file -------
// The header (NetCDF Classic and 64-bit Offset Format, and CDF-5) lists dimensions and variables
// with their offsets; a file cut short still opens, and netCDF then reads the missing values as
// fill values (a truncated Exodus file's time values all read 0). Big-endian throughout.

class NetcdfHeader {
 public:
  NetcdfHeader(std::string bytes, int version) : bytes_(std::move(bytes)), wide_(version == 5) {}
  bool ok() const { return ok_; }
  uint64_t word(size_t size) {
    if (!ok_ || at_ + size > bytes_.size()) return fail();
    uint64_t v = 0;
    for (size_t i = 0; i < size; ++i) v = (v << 8) | uint8_t(bytes_[at_ + i]);
    at_ += size;
    return v;
  }
  uint64_t tag() { return word(4); }
  uint64_t count() { return word(wide_ ? 8 : 4); }  // nelems, dimension lengths, vsize
  std::string name() {
    const uint64_t n = count();
    if (!ok_ || n > bytes_.size() - at_) return fail(), std::string();
    std::string text = bytes_.substr(at_, size_t(n));
    at_ += padded(size_t(n));
    return text;
  }
  void skip(Amount bytes) {
    if (!ok_ || bytes > Amount(bytes_.size() - at_)) return void(fail());
    at_ += padded(size_t(bytes));
  }
  static size_t padded(size_t n) { return (n + 3) / 4 * 4; }

 private:
  uint64_t fail() {
    ok_ = false;
    return 0;
  }
  std::string bytes_;
  size_t at_ = 4;
  bool wide_;
  bool ok_ = true;
};

size_t netcdf_type_bytes(uint64_t type) {
  switch (type) {
    case 1: case 2: case 7: return 1;  // byte, char, ubyte
    case 3: case 8: return 2;          // short, ushort
    case 4: case 5: case 9: return 4;  // int, float, uint
    case 6: case 10: case 11: return 8;  // double, int64, uint64
    default: return 0;
  }
}

void skip_attributes(NetcdfHeader& h) {
  const uint64_t tag = h.tag();
  const uint64_t n = h.count();
  if (tag == 0) return;  // ABSENT
  for (uint64_t i = 0; i < n && h.ok(); ++i) {
    h.name();
    const size_t bytes = netcdf_type_bytes(h.tag());
    h.skip(Amount(h.count()) * Amount(bytes));
  }
}

void check_netcdf(const std::string& path, uint64_t file_bytes, const ReadAt& read_at) {
  std::string head = read_at(0, size_t(std::min<uint64_t>(file_bytes, kHeadBytes)));
  if (head.size() < 8 || head.compare(0, 3, "CDF") != 0) return;  // HDF5-based netCDF-4, or not netCDF: the reader says
  const int version = head[3];
  if (version != 1 && version != 2 && version != 5) return;
  NetcdfHeader h(std::move(head), version);
  const uint64_t records = h.word(version == 5 ? 8 : 4);
  const bool streaming = records == (version == 5 ? ~uint64_t(0) : 0xFFFFFFFFu);
  std::vector<uint64_t> dims;
  h.tag();  // NC_DIMENSION, or zero with no dimensions
  const uint64_t dim_count = h.count();
  for (uint64_t i = 0; i < dim_count && h.ok() && i < kHeadBytes; ++i) {
    h.name();
    dims.push_back(h.count());
  }
  skip_attributes(h);  // the global attributes
  struct Var {
    std::string name;
    Amount values = 1;  // per record for a record variable
    bool record = false;
    size_t type_bytes = 0;
    uint64_t begin = 0;
  };
  std::vector<Var> vars;
  h.tag();  // NC_VARIABLE
  const uint64_t var_count = h.count();
  for (uint64_t i = 0; i < var_count && h.ok() && i < kHeadBytes; ++i) {
    Var v;
    v.name = h.name();
    const uint64_t rank = h.count();
    for (uint64_t d = 0; d < rank && h.ok() && d < kHeadBytes; ++d) {
      const uint64_t id = h.count();
      if (h.ok() && id >= dims.size()) return;  // a corrupt header: netCDF refuses it
      if (!h.ok()) break;
      if (d == 0 && dims[id] == 0) v.record = true;
      else v.values *= Amount(dims[id]);
    }
    skip_attributes(h);
    v.type_bytes = netcdf_type_bytes(h.tag());
    h.count();  // vsize: netCDF caps it for large variables, so the size is computed from the dimensions
    v.begin = h.word(version == 1 ? 4 : 8);
    if (h.ok() && v.type_bytes == 0) return;  // an unknown type: netCDF refuses it
    vars.push_back(v);
  }
  if (!h.ok()) {
    if (file_bytes < kHeadBytes) throw InputError(path, "holds a netCDF header that ends before its variables are listed: the file is truncated or corrupt");
    return;  // a header longer than we read: left to the reader
  }
  const size_t record_vars = size_t(std::count_if(vars.begin(), vars.end(), [](const Var& v) { return v.record; }));
  Amount record_bytes = 0;  // one record: each record variable's values padded to 4 bytes, unless there is one
  for (const Var& v : vars)
    if (v.record) record_bytes += record_vars == 1 ? v.values * Amount(v.type_bytes) : std::ceil(v.values * Amount(v.type_bytes) / 4) * 4;
  for (const Var& v : vars) {
    const Amount bytes = v.values * Amount(v.type_bytes);
    if (v.record && (streaming || records == 0)) continue;
    const Amount end = Amount(v.begin) + (v.record ? Amount(records - 1) * record_bytes + bytes : bytes);
    if (end > Amount(file_bytes))
      refuse(path, "the netCDF variable '" + v.name + "' (" + count_text(v.values) + " values" +
                       (v.record ? " in each of " + std::to_string(records) + " records" : std::string()) + ")",
             end, Amount(file_bytes));
  }
}

}  // namespace

void check_declared_sizes(const std::string& path, const std::string& ext, uint64_t file_bytes, const ReadAt& read_at) {
  if (ext == ".ply") check_ply(path, file_bytes, read_at);
  else if (ext == ".vtu" || ext == ".vtp" || ext == ".vti") check_xml(path, file_bytes, read_at);
  else if (ext == ".vtk") check_legacy(path, file_bytes, read_at);
  else if (ext == ".mha" || ext == ".mhd") check_metaimage(path, file_bytes, read_at);
  else if (ext == ".exo" || ext == ".e" || ext == ".ex2" || ext == ".exii" || ext == ".g" || ext == ".gen") check_netcdf(path, file_bytes, read_at);
}

void check_declared_sizes(const std::string& path) {
  std::error_code ec;
  const uint64_t bytes = uint64_t(std::filesystem::file_size(path, ec));
  if (ec) return;  // the reader names the problem
  std::ifstream in(path, std::ios::binary);
  check_declared_sizes(path, lower_extension(path), bytes, [&in](uint64_t offset, size_t count) {
    in.clear();
    in.seekg(std::streamoff(offset));
    std::string text(count, '\0');
    in.read(text.data(), std::streamsize(count));
    text.resize(size_t(in.gcount()));
    return text;
  });
}

}  // namespace prismoid::io::detail
