#pragma once
// Output of the metric results: JSON (nlohmann::json; NaN becomes null), Markdown tables for a
// paper or a CI summary, and a self-contained inline SVG line plot of the ISPRS curves (no
// external fonts, scripts or images; drops into Markdown/HTML as is).
// Lengths in JSON are metres, angles degrees (`_deg`); Markdown shows centimetres where noted.
// Number formatting is fixed ("%.4f"-style), so output bytes are deterministic.

#include <nlohmann/json.hpp>
#include <string>

#include "evaluation/metrics_floorplan.h"
#include "evaluation/metrics_isprs.h"
#include "evaluation/metrics_patches.h"
#include "evaluation/metrics_voxels.h"

namespace mopad::evaluation {

nlohmann::json ToJson(const ErrorStats& s);
nlohmann::json ToJson(const PatchEvaluation& e);
nlohmann::json ToJson(const IsprsResult& r);
nlohmann::json ToJson(const FloorplanResult& r);
nlohmann::json ToJson(const ConfusionMatrix& m);

/// Per class: truth N, TP, FP, FN, recognition rate, d_v and d_h mean/max (cm), Phi mean/max
/// (deg), and an "overall" row (d_v/d_h over walls and columns, as the paper).
std::string MarkdownPatchTable(const PatchEvaluation& e);
/// Per class and all: completeness and correctness at `buffer` (m) and accuracy (cm).
std::string MarkdownIsprsTable(const IsprsResult& r, double buffer = 0.10);
/// Rooms (P/R/F1, mean IoU), corners at each threshold, angles.
std::string MarkdownFloorplanTable(const FloorplanResult& r);
/// The confusion matrix (rows truth) and per-label IoU/precision/recall.
std::string MarkdownConfusionTable(const ConfusionMatrix& m);

/// An inline `<svg>` line plot of completeness (solid) and correctness (dashed) against the
/// buffer (cm) for every class that has reference or source area, plus "all".
std::string IsprsSvgPlot(const IsprsResult& r, const std::string& title = "ISPRS surfaces");

}  // namespace mopad::evaluation
