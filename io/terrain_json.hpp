// Terrain files (docs/model.md §6, "Terrain"; paper section 2.2.3: terrains
// are saved to a .json file and loaded at simulation start-up).
//
// Three formats, told apart by "type" (lengths in metres):
//
//   {"type": "flat", "height": 0.0}
//       The plane z = height ("height" optional, default 0).
//
//   {"type": "grid", "origin": [x0, y0], "spacing": [dx, dy], "counts": [nx, ny],
//    "heights": [[row iy = 0: nx values], ..., [row iy = ny - 1]]}
//       Heights on a regular grid, interpolated bilinearly: heights[iy][ix] is
//       the height at (x0 + ix dx, y0 + iy dy). nx, ny >= 2, dx, dy > 0. Outside
//       the grid the edge values extend.
//
//   {"type": "control_points", "points": [[x, y, z], ...],
//    "grid": {"origin": [x0, y0], "spacing": [dx, dy], "counts": [nx, ny]},
//    "method": "thin_plate_spline"}
//       Scattered control points (at least 3, distinct, not all on one line)
//       interpolated onto the grid by a thin-plate spline (exact at the points,
//       reproduces planes; see core/terrain_interpolation.hpp), then as "grid".
//       "method" is optional; thin_plate_spline is the only one.
//
// Every type may carry provenance: "description" (a string) and "generator"
// (any JSON, e.g. the command and parameters that made the file). Any other key
// is an error (a misspelt key must not be silently ignored).
#pragma once

#include <string>

#include "io/json_reader.hpp"

#include "core/terrain.hpp"

namespace rover::io {

// Reads a terrain file; a bad file throws ConfigError naming the file, the
// field and the problem.
Terrain load_terrain(const std::string& path);

// Writes `grid` as a "grid" terrain file. `provenance` is null or an object
// with optional "description" (string) and "generator" keys, written first.
// Heights are written in the shortest form that reads back to the identical
// double (so save/load is lossless; 0 is written as 0). The file is written to
// a temporary file and renamed, so a failure leaves nothing half-written.
// Throws std::invalid_argument for an invalid grid or provenance and
// std::runtime_error if the file cannot be written.
void save_terrain_grid(const HeightGrid& grid, const std::string& path,
                       const Json& provenance = nullptr);

// A short digest (16 hex digits) of the ground a terrain describes: the
// plane's height, or the grid's origin, spacing, counts and heights, each
// number exactly (a grid of one height is that plane). Equal for files that
// differ only in layout, description or type ("control_points" against the
// "grid" it interpolates onto, a constant grid against "flat"); recorded
// with a study's runs so that runs made on other ground are recognised.
std::string terrain_digest(const Terrain& terrain);
// The root attribute of a result that holds its runs' terrain_digest().
inline constexpr const char* kTerrainDigestAttribute = "terrain_digest";

}  // namespace rover::io
