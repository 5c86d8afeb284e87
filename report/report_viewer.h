#pragma once
// The report's 3D view: an HTML fragment (heading, class toggles, a <canvas> and inline
// scripts, no external files) that draws a run folder's building model (exports::SemanticScene:
// the same elements as model.glb, in the export frame, z up) coloured by class. The ceiling
// starts hidden so the rooms can be seen from above. With the scene's truth, a toggle draws the
// true walls, floors, columns, openings and components as black outlines over the model
// (world -> export frame by the first room's run.json X_WM).
// Drawn with three.js (WebGL, OrbitControls: drag to turn, wheel to zoom, right-drag to pan),
// the library inlined from Debian's libjs-three (r111, ~0.88 MB). When the library files are
// missing when the report is written, or the browser gives no WebGL context, the view falls
// back to the canvas 2D API (painter's algorithm, flat shading) with a one-line note; the
// canvas's data-renderer attribute names the renderer used. Deterministic text (mm
// coordinates; the library as installed).

#include <string>

#include "scenes/ground_truth.h"

namespace mopad::report {

/// Where Debian's libjs-three installs three.js, and its two files the view inlines.
inline constexpr const char* kThreeJsDir = "/usr/share/javascript/three";
inline constexpr const char* kThreeJsFile = "three.min.js";
inline constexpr const char* kOrbitControlsFile = "examples/js/controls/OrbitControls.js";

/// The fragment for the run folder `run_dir` (rooms/<ID>/sm3.json, a room folder's sm3.json or
/// floor/sm3.json); "" when the folder has none, a one-line note when a model file is malformed.
/// `truth`, when not null, adds the truth toggle. `three_dir` holds kThreeJsFile and
/// kOrbitControlsFile; without them the 2D view and its note.
std::string ModelViewerHtml(const std::string& run_dir, const scenes::GroundTruth* truth = nullptr,
                            const std::string& three_dir = kThreeJsDir);

}  // namespace mopad::report
