#pragma once
// Transfer functions in ParaView's colour-map JSON format (File > Export/Import colour maps):
// an array of objects with "Name", "RGBPoints" [x, r, g, b, ...] and optionally "Points"
// [x, opacity, midpoint, sharpness, ...]. The points' positions are rescaled so the colour
// points span [0, 1], as ParaView does when it applies a preset to a data range.
#include <cstddef>
#include <istream>
#include <string>

#include "renderer/volume/transfer_function.hpp"

namespace prismoid::io {

// Colour and opacity points a file may hold: published colour maps hold a few hundred, and every
// point is a breakpoint the renderer's tables are built over.
inline constexpr size_t kMaxTransferFunctionPoints = 4096;

// The first colour map in the file. Throws InputError naming the file: unreadable, not JSON,
// no "RGBPoints", point lists of the wrong length, longer than kMaxTransferFunctionPoints or
// not sorted, values outside [0, 1],
// midpoint/sharpness other than ParaView's linear defaults (0.5, 0).
volume::TransferFunction read_paraview_colormap(const std::string& path);
// The same from a stream; errors name `name`.
volume::TransferFunction parse_paraview_colormap(std::istream& in, const std::string& name);

// Writes `tf` as a one-entry ParaView colour-map file (positions in [0, 1], sRGB colours) to
// `path` itself (putting the file in place whole is the caller's, app/common/output_files.hpp);
// InputError when it cannot.
void write_paraview_colormap(const std::string& path, const volume::TransferFunction& tf);

// A preset name, or else a path to a ParaView JSON colour map.
volume::TransferFunction transfer_function_from(const std::string& preset_or_path);

}  // namespace prismoid::io
