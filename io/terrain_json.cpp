// Terrain files: reading all three formats, writing grids (see terrain_json.hpp).
#include "io/terrain_json.hpp"

#include <array>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <vector>

#include <unistd.h>

#include "core/model_scale.hpp"
#include "core/terrain_interpolation.hpp"
#include "io/checkpoint.hpp"
#include "io/config_kind.hpp"
#include "io/json_reader.hpp"
#include "io/output_target.hpp"

namespace rover::io {
namespace {

std::string value_text(const Json& v) {
  std::string text = v.dump();
  if (text.size() > 40) text = text.substr(0, 37) + "...";
  return text;
}

// "counts": [nx, ny], two integers >= 2.
std::array<int, 2> read_counts(const JsonReader& r) {
  const Json& v = r.raw("counts");
  if (!v.is_array() || v.size() != 2)
    r.fail("counts", "expected [nx, ny], two integers");
  std::array<int, 2> counts{};
  for (std::size_t k = 0; k < 2; ++k) {
    if (!v[k].is_number_integer()) r.fail("counts", "expected [nx, ny], two integers");
    const long long c = v[k].get<long long>();
    if (c < 2 || c > 100'000'000)
      r.fail("counts", std::string(k == 0 ? "nx" : "ny") + " = " + std::to_string(c) +
                           ": need at least 2 x 2 grid points");
    counts[k] = static_cast<int>(c);
  }
  if (static_cast<double>(counts[0]) * counts[1] > 1e9)
    r.fail("counts", "grid too large (more than 1e9 points)");
  return counts;
}

GridGeometry read_geometry(const JsonReader& r) {
  const auto origin = r.fixed_numbers<2>("origin");
  const auto spacing = r.fixed_numbers<2>("spacing");
  if (!(spacing[0] > 0.0) || !(spacing[1] > 0.0))
    r.fail("spacing", "both spacings must be positive");
  for (std::size_t k = 0; k < 2; ++k) {
    if (const std::string p = beyond_scale(origin[k], kMaxCoordinate_m, "m", kPositionScaleReason); !p.empty())
      r.fail("origin", std::string(k == 0 ? "x " : "y ") + p);
    if (!(spacing[k] >= kMinTerrainSpacing_m))
      r.fail("spacing", std::string(k == 0 ? "x " : "y ") + number_text(spacing[k]) + " m is below " +
                            number_text(kMinTerrainSpacing_m) + " m (the wheel radius is centimetres: metres expected)");
  }
  const auto counts = read_counts(r);
  for (std::size_t k = 0; k < 2; ++k) {
    const double far_edge = origin[k] + spacing[k] * (counts[k] - 1);
    if (const std::string p = beyond_scale(far_edge, kMaxCoordinate_m, "m", kPositionScaleReason); !p.empty())
      r.fail("spacing", std::string("the grid's far ") + (k == 0 ? "x" : "y") + " edge, origin + spacing x (count - 1) = " + p);
  }
  return {origin[0], origin[1], spacing[0], spacing[1], counts[0], counts[1]};
}

// "heights": ny rows of nx finite numbers.
std::vector<double> read_heights(const JsonReader& r, const GridGeometry& g) {
  const Json& rows = r.raw("heights");
  if (!rows.is_array()) r.fail("heights", "expected an array of rows [[..], [..], ...]");
  if (rows.size() != static_cast<std::size_t>(g.ny))
    r.fail("heights", "has " + std::to_string(rows.size()) + " rows, expected ny = " +
                          std::to_string(g.ny) + " (from counts)");
  std::vector<double> heights;
  heights.reserve(static_cast<std::size_t>(g.nx) * static_cast<std::size_t>(g.ny));
  for (std::size_t iy = 0; iy < rows.size(); ++iy) {
    const Json& row = rows[iy];
    if (!row.is_array())
      r.fail("heights", "row " + std::to_string(iy) + " is not an array: " + value_text(row));
    if (row.size() != static_cast<std::size_t>(g.nx))
      r.fail("heights", "row " + std::to_string(iy) + " has " + std::to_string(row.size()) +
                            " values, expected " + std::to_string(g.nx) + " (nx from counts)");
    for (std::size_t ix = 0; ix < row.size(); ++ix) {
      const Json& h = row[ix];
      if (!h.is_number() || !std::isfinite(h.get<double>()))
        r.fail("heights", "row " + std::to_string(iy) + ", value " + std::to_string(ix) + " is " +
                              value_text(h) + ", expected a finite number");
      heights.push_back(h.get<double>());
    }
  }
  return heights;
}

std::vector<Eigen::Vector3d> read_points(const JsonReader& r) {
  const Json& v = r.raw("points");
  if (!v.is_array()) r.fail("points", "expected an array of [x, y, z] points");
  if (v.size() < 3)
    r.fail("points", "has " + std::to_string(v.size()) + " points, need at least 3");
  std::vector<Eigen::Vector3d> points;
  points.reserve(v.size());
  for (std::size_t i = 0; i < v.size(); ++i) {
    const Json& p = v[i];
    if (!p.is_array() || p.size() != 3)
      r.fail("points", "point " + std::to_string(i) + " is " + value_text(p) + ", expected [x, y, z]");
    Eigen::Vector3d point;
    for (std::size_t k = 0; k < 3; ++k) {
      if (!p[k].is_number() || !std::isfinite(p[k].get<double>()))
        r.fail("points", "point " + std::to_string(i) + " is " + value_text(p) +
                             ", expected three finite numbers");
      point[static_cast<Eigen::Index>(k)] = p[k].get<double>();
      if (const std::string problem = beyond_scale(point[static_cast<Eigen::Index>(k)], kMaxCoordinate_m, "m",
                                                   kPositionScaleReason);
          !problem.empty())
        r.fail("points", "point " + std::to_string(i) + ": " + problem);
    }
    points.push_back(point);
  }
  return points;
}

void append_number(std::string& out, double v) {
  char text[32];
  const auto result = std::to_chars(text, text + sizeof text, v);  // shortest exact form
  out.append(text, result.ptr);
}

}  // namespace

Terrain load_terrain(const std::string& path) {
  const Json json = read_config_file(path, ConfigKind::kTerrain);
  const JsonReader r(json, path);
  if (r.has("description")) (void)r.string("description");
  (void)r.has("generator");  // free-form provenance
  const std::string type = r.string("type");
  Terrain terrain;
  try {
    if (type == "flat") {
      const double height = r.number_or("height", 0.0);
      if (const std::string p = beyond_scale(height, kMaxCoordinate_m, "m", kPositionScaleReason); !p.empty())
        r.fail("height", p);
      terrain = Terrain::flat(height);
    } else if (type == "grid") {
      const GridGeometry geometry = read_geometry(r);
      terrain = Terrain::from_grid(grid_with_heights(geometry, read_heights(r, geometry)));
    } else if (type == "control_points") {
      const std::string method = r.string_or("method", "thin_plate_spline");
      if (method != "thin_plate_spline")
        r.fail("method", "unknown interpolation method (known: thin_plate_spline)");
      const std::vector<Eigen::Vector3d> points = read_points(r);
      const JsonReader grid_reader = r.child("grid");
      const GridGeometry geometry = read_geometry(grid_reader);
      grid_reader.finish();
      HeightGrid grid;
      try {
        grid = grid_from_control_points(points, geometry);
      } catch (const std::invalid_argument& e) {
        r.fail("points", e.what());  // collinear or repeated points
      }
      terrain = Terrain::from_grid(std::move(grid));
    } else {
      r.fail("type", "unknown terrain type (known: flat, grid, control_points)");
    }
  } catch (const std::invalid_argument& e) {
    throw ConfigError(path + ": " + e.what());
  }
  r.finish();
  return terrain;
}

void save_terrain_grid(const HeightGrid& grid, const std::string& path, const Json& provenance) {
  validate_height_grid(grid);
  if (!provenance.is_null() && !provenance.is_object())
    throw std::invalid_argument("save_terrain_grid: provenance must be a JSON object or null");
  if (!provenance.is_null())
    for (const auto& [key, value] : provenance.items()) {
      if (key != "description" && key != "generator")
        throw std::invalid_argument("save_terrain_grid: provenance key '" + key +
                                    "' is not one of description, generator");
      if (key == "description" && !value.is_string())
        throw std::invalid_argument("save_terrain_grid: provenance description must be a string");
    }

  std::string out = "{\n  \"type\": \"grid\",\n";
  if (!provenance.is_null())
    for (const char* key : {"description", "generator"})
      if (provenance.contains(key))
        out += "  \"" + std::string(key) + "\": " + provenance.at(key).dump() + ",\n";
  out += "  \"origin\": [";
  append_number(out, grid.origin_x_m);
  out += ", ";
  append_number(out, grid.origin_y_m);
  out += "],\n  \"spacing\": [";
  append_number(out, grid.spacing_x_m);
  out += ", ";
  append_number(out, grid.spacing_y_m);
  out += "],\n  \"counts\": [" + std::to_string(grid.nx) + ", " + std::to_string(grid.ny) +
         "],\n  \"heights\": [\n";
  for (int iy = 0; iy < grid.ny; ++iy) {
    out += "    [";
    for (int ix = 0; ix < grid.nx; ++ix) {
      if (ix > 0) out += ',';
      append_number(out, grid.at(ix, iy));
    }
    out += iy + 1 < grid.ny ? "],\n" : "]\n";
  }
  out += "  ]\n}\n";

  require_output(path, OutputFormat::kSeekable);
  const std::string temp = path + ".tmp." + std::to_string(::getpid());
  create_temporary(temp, path);
  {
    errno = 0;
    std::ofstream file(temp, std::ios::binary | std::ios::trunc);
    file << out;
    file.close();
    if (!file) {
      const std::string reason = errno != 0 ? std::string(" (") + std::strerror(errno) + ")" : "";
      std::error_code ignored;
      std::filesystem::remove(temp, ignored);
      throw std::runtime_error(path + ": cannot write terrain file" + reason);
    }
  }
  std::error_code error;
  std::filesystem::rename(temp, path, error);
  if (error) {
    std::error_code ignored;
    std::filesystem::remove(temp, ignored);
    throw std::runtime_error(path + ": cannot write terrain file: " + error.message());
  }
}

std::string terrain_digest(const Terrain& terrain) {
  std::string text;
  const HeightGrid* grid = terrain.grid();
  // A grid of one height is that plane everywhere (the edge values extend).
  if (grid == nullptr || terrain.min_height() == terrain.max_height()) {
    text = "flat ";
    append_number(text, terrain.max_height() + 0.0);  // + 0.0: -0 and 0 are one height
    return config_fingerprint(text);
  }
  text = "grid";
  for (const double v : {grid->origin_x_m, grid->origin_y_m, grid->spacing_x_m, grid->spacing_y_m,
                         static_cast<double>(grid->nx), static_cast<double>(grid->ny)}) {
    text += ' ';
    append_number(text, v);
  }
  for (const double h : grid->heights_m) {
    text += ' ';
    append_number(text, h + 0.0);
  }
  return config_fingerprint(text);
}

}  // namespace rover::io
