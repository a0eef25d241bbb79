#pragma once
// Sizes a file's header declares, checked against the bytes the file holds before any reader
// allocates for them (internal to io/). A 300-byte file declaring two billion points is refused
// at once, naming what it declares, instead of a reader reserving memory for them.
//
// The bound is the least data an honest file of that kind can hold for the declared counts:
// one byte per value in binary, two in ASCII (a digit and a separator), and for compressed XML
// data that divided by the compressor's largest ratio (zlib 1032:1, LZ4 255:1; LZMA has no small
// bound, 65536:1 is far above what xz reaches). An honest file never falls below it; a header
// declaring more than its file can hold is truncated or corrupt.
#include <cstdint>
#include <functional>
#include <string>

namespace prismoid::io::detail {

// Checks the declared counts of a .ply (element counts), VTK XML .vtu .vtp .vti (every data
// array's tuples and components, from NumberOfPoints, NumberOfCells, NumberOfPolys, Extent,
// NumberOfTuples, NumberOfComponents), legacy .vtk (POINTS, CELLS, CELL_TYPES) or MetaImage
// .mha/.mhd (NDims, and DimSize times the element size of data in the file itself) or netCDF
// classic Exodus II (.exo .e .ex2 .exii .g .gen: every variable's offset and size, records
// included) file; other kinds pass. InputError(path, ...) names the count and the bytes there are.
void check_declared_sizes(const std::string& path);

// The same on bytes: `read_at(offset, count)` returns up to `count` of the file's bytes from
// `offset` (fewer at its end); `file_bytes` is its size. For tests and the fuzzer.
using ReadAt = std::function<std::string(uint64_t offset, size_t count)>;
void check_declared_sizes(const std::string& path, const std::string& ext, uint64_t file_bytes, const ReadAt& read_at);

}  // namespace prismoid::io::detail
