#pragma once
// Readers of the robot's model files (docs/models.md, format version 1) into evaluation types:
// sm3.json (SM3 patches), dsm3.ply (DSM3 voxels) and scan_poses.tum (the scanner poses the
// robot used). Written from the spec, independently of the writers (modelling/model_io.h), so a
// writer bug shows up as a failure.
//
// Frames: everything these files hold is in the robot's map frame M; RunInfo::X_WM maps it into
// the world W. Metres. Malformed or missing input throws mopad::InputError naming the file and
// the field ("sm3.json: error: patches[2].plane.n: missing field").

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "common/frames.h"
#include "evaluation/metrics.h"
#include "runfolder/run_record.h"

namespace mopad::evaluation {

inline constexpr int kModelFormatVersion = 1;

/// run.json of one room run (runfolder/run_record.h reads it): model paths resolved against
/// its folder, "" for a model the run did not write.
using RunInfo = runfolder::RunRecord;

/// One SM3 patch: an evaluation Patch (map frame, CCW seen from the normal, normal into the
/// room) plus the fit figures of the file.
struct Sm3Patch {
  Patch patch;
  Vec3 plane_n = Vec3::UnitZ();  ///< unit normal of the plane n.x + d = 0
  double plane_d = 0.0;
  long support = 0;  ///< points that supported the fit
  double rms = 0.0;  ///< m
  bool fitted = true;
};

struct Sm3Model {
  std::string room;
  double floor_z = 0.0, ceiling_z = 0.0;  ///< m, map frame
  std::vector<Sm3Patch> patches;
  std::vector<std::array<int, 2>> adjacency;  ///< patch index pairs sharing an edge
  std::vector<Patch> Patches() const;         ///< the evaluation patches only
};
/// Reads sm3.json. InputError for a wrong format/version, a missing or mistyped field, a class
/// other than wall|floor|ceiling|column, a polygon with < 3 vertices or non-finite numbers, an
/// adjacency index out of range.
Sm3Model ReadSm3(const std::string& path);

/// A regular voxel grid in the map frame: voxel (i, j, k) covers
/// origin + [i, i+1) s x [j, j+1) s x [k, k+1) s.
struct VoxelGrid {
  Vec3 origin = Vec3::Zero();  ///< m, corner of voxel (0, 0, 0)
  double voxel_size = 0.1;     ///< m
  std::array<int, 3> dims{0, 0, 0};
  Vec3 Centre(const std::array<int, 3>& ijk) const {
    return origin + voxel_size * Vec3(ijk[0] + 0.5, ijk[1] + 0.5, ijk[2] + 0.5);
  }
};

/// The voxels of dsm3.ply. `labels` are VoxelLabel codes of metrics_voxels.h (the file's own
/// values are mapped through the label names of its header).
struct Dsm3Voxels {
  VoxelGrid grid;
  std::vector<std::array<int, 3>> ijk;
  std::vector<std::uint8_t> labels;  ///< VoxelLabel values, one per voxel
};
/// Reads dsm3.ply (binary little-endian or ASCII PLY). InputError for a missing header comment
/// or property, an unknown label name or value, indices outside the grid, truncated data.
Dsm3Voxels ReadDsm3(const std::string& path);

/// Scanner positions (map frame) of a TUM trajectory file "t x y z qx qy qz qw" per line
/// (scan_poses.tum). '#' lines and blank lines are skipped. InputError on a malformed line.
std::vector<Vec3> ReadTumPositions(const std::string& path);

}  // namespace mopad::evaluation
