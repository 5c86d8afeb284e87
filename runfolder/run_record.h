#pragma once
// run.json, the record beside each room's files (docs/models.md): which scene and doors the run
// used, its room and seed, where its map frame sits in the world (X_WM, the harness's record of
// the robot's true start, never something the robot estimated) and its model files. The one
// writer and the one reader of the file.
//
//   {"format": "mopad-room-run", "version": 1, "scene": "...", "doors": ["ID=DEG", ...],
//    "room": "R1", "seed": 1, "X_WM": [[4 numbers] x 4],
//    "files": {"sm1": "sm1.ply", "sm2": "sm2.json", "sm3": "sm3.json", "sm4": "sm4.json",
//              "dsm3": "dsm3.ply"}}

#include <cstdint>
#include <string>
#include <vector>

#include "common/frames.h"

namespace mopad::runfolder {

struct RunRecord {
  std::string dir;                 ///< folder holding run.json (filled by the reader)
  std::string scene;               ///< scene folder, scene file or spec, as the run was given it
  std::vector<std::string> doors;  ///< door-angle overrides "ID=DEG" the run used
  std::string room;                ///< the scene's id of the room (never empty)
  std::uint64_t seed = 0;
  Pose3 X_WM = Pose3::Identity();  ///< map -> world
  /// Model files, resolved against `dir` by the reader (absolute or dir-relative); "" = absent.
  std::string sm1, sm2, sm3, sm4, dsm3;
};

/// run.json's text (2-space JSON; the writer adds the final newline) of `record`; its file names
/// are the layout's (runfolder/layout.h), whatever `record`'s say.
std::string RunJsonText(const RunRecord& record);

/// Writes `dir`/run.json. InputError naming the file when it cannot be written.
void WriteRunJson(const std::string& dir, const RunRecord& record);

/// Reads `path` (a run.json). InputError naming the file and the field for a wrong format or
/// version, a missing or mistyped field, an empty room, an X_WM that is not a rigid transform.
RunRecord ReadRunJson(const std::string& path);

}  // namespace mopad::runfolder
