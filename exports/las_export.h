#pragma once
// sm1.las: the rooms' SM1 clouds (rooms/<ID>/sm1.ply) in the export frame as LAS 1.4 point
// format 7 (io::LasWriter; docs/exports.md): 16-bit RGB (8-bit colour x 257), intensity
// (scalar_intensity in [0, 1] x 65535), GPS time = the scan's simulation time from scans.json
// (the scan index when scans.json is absent), point source id = scan index in its room, user
// data = the room's position in the sorted room list, and a classification in the LAS user
// range (LasCode below) from the SM1 label and, for inliers, the SM3 class of the nearest patch.
// Rooms in id order, points in sm1.ply order. Deterministic.

#include <array>
#include <cstdint>
#include <string>

#include "common/params.h"
#include "exports/run_folder.h"

namespace mopad::exports {

/// Classification codes (LAS user range 64-255; docs/exports.md).
enum class LasCode : std::uint8_t {
  kUnlabelled = 64,  ///< SM1 label none
  kOutlier = 65,     ///< SM1 outlier: beyond the room's structure
  kClutter = 66,     ///< SM1 clutter: inside the room, off the structure
  kInlier = 67,      ///< SM1 inlier with no SM3 patch within patch_band
  kWall = 68,        ///< inlier nearest an SM3 wall patch
  kFloor = 69,       ///< inlier nearest the SM3 floor
  kCeiling = 70,     ///< inlier nearest the SM3 ceiling
  kColumn = 71,      ///< inlier nearest an SM3 column face
};
inline constexpr int kLasCodeFirst = 64, kLasCodeLast = 71;
const char* ToString(LasCode code);

struct LasExportParams {
  double patch_band = 0.10;  ///< m, an inlier takes the class of a patch this close, (0, 1]

  template <class V>
  void Visit(V& v) {
    v("patch_band", patch_band, Bounds{1e-6, 1.0});
  }
};

struct LasExportSummary {
  std::uint64_t points = 0;
  std::array<std::uint64_t, 256> histogram{};  ///< points per classification code
  Eigen::Vector3d min = Eigen::Vector3d::Zero(), max = Eigen::Vector3d::Zero();  ///< m, E
  int rooms = 0;  ///< rooms with an sm1.ply
};

/// Writes `path`. InputError when no room has an sm1.ply, a PLY lacks x y z or its label or scan
/// fields, or the file cannot be written.
LasExportSummary WriteSm1Las(const RunFolder& run, const std::string& path,
                             const LasExportParams& params = {});

}  // namespace mopad::exports
