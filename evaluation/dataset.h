#pragma once
// `mopad dataset RUN_DIR -o DIR`: what a learning or offline method needs from a run, in one
// documented layout (docs/dataset.md): every registered TLS scan of every room as a PLY with
// per-point semantic and instance labels from the truth, the scanner poses, the label tables and
// the scene's truth.
//
//   DIR/dataset.json                 index: frames, label tables, scans (file, pose, counts)
//   DIR/scans/<room>/<k>.ply         scan k of the room: x y z (map frame, as registered),
//                                    red green blue, intensity, semantic, instance, sm1_label
//   DIR/truth.json                   the scene's truth (scene.truth.json), world frame
//
// Points are the room's SM1 cloud (rooms/<room>/sm1.ply) split by its `scalar_scan`; poses are
// the registered X_MS of rooms/<room>/scans.json. Labels come from the truth, not the robot: a
// point is traced from its scanner's true centre (X_WM X_MS) towards its world position
// (X_WM p) through the run's world; the element the beam meets within `tolerance` of the point
// gives its semantic class and instance; a point with no element there (a mixed pixel at an
// edge, a multipath echo) is unlabelled. The robot's own SM1 label is kept beside them
// (`sm1_label`). Deterministic: the same run gives the same bytes.

#include <string>

namespace mopad::evaluation {

struct DatasetSummary {
  int rooms = 0, scans = 0;
  long long points = 0, unlabelled = 0;
  std::string text;  ///< what `mopad dataset` prints
};

/// Writes the dataset of `run_dir` (a main-job folder or a room run) to `out`. `tolerance`
/// (m, (0, 1]) bounds the distance between a point and the truth surface its beam meets.
/// InputError on a bad run folder, before any file is written.
DatasetSummary WriteDataset(const std::string& run_dir, const std::string& out,
                            double tolerance = 0.05);

}  // namespace mopad::evaluation
