#pragma once
// The report's wall orthoimages: an HTML fragment with one <figure class='wall'> per wall of the
// robot's models in a run folder (rooms/<ID>/, or a room folder itself), each an inline SVG
// of the wall's colour orthoimage (rooms/<ID>/orthoimages/<wall>_colour.png, downscaled to
// kWallImageRows pixels high and embedded as a JPEG data URI) with the room's SM4 openings
// (sm4.json: <rect class='opening door|window'>, doors coloured by state, labelled with id and
// state) and SM5 components hosted by the wall (sm5.json: <rect class='component'>, labelled
// with their class) drawn over it in the wall's (u, v) frame (modelling/orthoimage.h). The
// robot's models only, never the truth. Rooms in folder-name order, walls in sm3.json order.
// The image's pixel size is recovered from its size and the wall's extent (orthoimage margin
// 0, pixel a whole number of millimetres, as BuildOrthoimage makes them). Deterministic bytes.

#include <string>

namespace mopad::report {

/// Height (pixels) of the embedded images: the budget of a wall in the report.
inline constexpr int kWallImageRows = 160;
/// JPEG quality of the embedded images, [0, 100].
inline constexpr int kWallImageJpegQuality = 80;

/// The fragment for `run_dir`; "" when no wall has an orthoimage. A room whose model files are
/// malformed gets a one-line note instead of its figures.
std::string WallImagesHtml(const std::string& run_dir);

}  // namespace mopad::report
