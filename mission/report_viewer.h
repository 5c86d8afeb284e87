#pragma once
// The report's 3D view: an HTML fragment (heading, class toggles, a <canvas> and an inline
// script, no external files) that draws a run folder's building model (exports::SemanticScene:
// the same elements as model.glb, in the export frame) coloured by class. Drag to turn, wheel to
// zoom; the ceiling starts hidden so the rooms can be seen from above. With the scene's truth,
// a toggle draws the true walls, floors, columns, openings and components as black outlines
// over the model (world -> export frame by the first room's run.json X_WM). Drawn with the
// canvas 2D API (painter's algorithm, flat shading), so it needs no WebGL. Deterministic text
// (mm coordinates).

#include <string>

#include "scenes/ground_truth.h"

namespace mopad::mission {

/// The fragment for the run folder `run_dir` (rooms/<ID>/sm3.json, a room folder's sm3.json or
/// floor/sm3.json); "" when the folder has none, a one-line note when a model file is malformed.
/// `truth`, when not null, adds the truth toggle.
std::string ModelViewerHtml(const std::string& run_dir, const scenes::GroundTruth* truth = nullptr);

}  // namespace mopad::mission
