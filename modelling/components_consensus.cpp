// SM5's consensus of the two paths (steps 4-6, modelling/components.h): colour and depth
// detections paired by their coherence, confident singles kept, overlaps across classes
// resolved by rank, and signs told apart by the equipment they mark.
#include <algorithm>
#include <string>

#include "modelling/components.h"
#include "modelling/components_internal.h"

namespace mopad::modelling::detail {
namespace {

// An instance of the equipment `sign`'s class marks lies below it on the SE (overlapping it
// along u).
bool MarkedBelow(const PathDetection& sign, const std::vector<PathDetection>& colour,
                 const std::vector<PathDetection>& depth,
                 const interfaces::ObjectModelCatalogue& cat,
                 const std::vector<ConsensusInstance>& instances) {
  const std::string& marks = cat.models[static_cast<std::size_t>(sign.class_index)].marks;
  if (marks.empty()) return false;
  for (const ConsensusInstance& q : instances) {
    if (cat.models[static_cast<std::size_t>(q.class_index)].class_name != marks) continue;
    const PathDetection& b = InstanceBox(q, colour, depth);
    const bool along = std::min(b.col1, sign.col1) > std::max(b.col0, sign.col0);
    if (along && 0.5 * (b.row0 + b.row1) > sign.row1) return true;  // rows run downwards
  }
  return false;
}

}  // namespace

const PathDetection& InstanceBox(const ConsensusInstance& c,
                                 const std::vector<PathDetection>& colour,
                                 const std::vector<PathDetection>& depth) {
  return c.depth >= 0 ? depth[static_cast<std::size_t>(c.depth)]
                      : colour[static_cast<std::size_t>(c.colour)];
}

bool MarkSupport(const std::vector<PathDetection>& depth,
                 const interfaces::ObjectModelCatalogue& cat,
                 const std::vector<ConsensusInstance>& instances,
                 std::vector<PathDetection>& colour) {
  std::vector<bool> used(colour.size(), false);
  for (const ConsensusInstance& c : instances)
    if (c.colour >= 0) used[static_cast<std::size_t>(c.colour)] = true;
  bool any = false;
  for (std::size_t i = 0; i < colour.size(); ++i) {
    if (used[i] || colour[i].marked) continue;
    if (MarkedBelow(colour[i], colour, depth, cat, instances)) colour[i].marked = any = true;
  }
  return any;
}

void ApplyMarks(const std::vector<PathDetection>& colour, const std::vector<PathDetection>& depth,
                const interfaces::ObjectModelCatalogue& cat,
                std::vector<ConsensusInstance>& instances) {
  for (ConsensusInstance& c : instances) {
    if (c.colour < 0 || c.depth >= 0) continue;
    const PathDetection& sign = colour[static_cast<std::size_t>(c.colour)];
    if (MarkedBelow(sign, colour, depth, cat, instances)) continue;
    for (std::size_t j = 0; j < colour.size(); ++j) {
      const PathDetection& alt = colour[j];
      if (alt.class_index == c.class_index ||
          !SameSize(cat.models[static_cast<std::size_t>(alt.class_index)],
                    cat.models[static_cast<std::size_t>(c.class_index)]) ||
          OverlapOfSmaller(alt, sign) < 0.5 || !MarkedBelow(alt, colour, depth, cat, instances))
        continue;
      c.class_index = alt.class_index;
      c.colour = static_cast<int>(j);
      break;
    }
  }
}

}  // namespace mopad::modelling::detail

namespace mopad::modelling {

using detail::InstanceBox;
using detail::OverlapOfSmaller;

double CoherenceAlpha(const PathDetection& c, const PathDetection& d) {
  const double w = std::min(c.col1, d.col1) - std::max(c.col0, d.col0);
  const double h = std::min(c.row1, d.row1) - std::max(c.row0, d.row0);
  if (w <= 0 || h <= 0) return 0.0;
  const double ew = std::max(c.col1, d.col1) - std::min(c.col0, d.col0);
  const double eh = std::max(c.row1, d.row1) - std::min(c.row0, d.row0);
  return std::clamp(w * h / (ew * eh), 0.0, 1.0);
}

std::vector<ConsensusInstance> Consensus(const std::vector<PathDetection>& colour,
                                         const std::vector<PathDetection>& depth,
                                         const ComponentParams& p) {
  std::vector<ConsensusInstance> out;
  std::vector<int> classes;
  for (const auto& d : colour) classes.push_back(d.class_index);
  for (const auto& d : depth) classes.push_back(d.class_index);
  std::sort(classes.begin(), classes.end());
  classes.erase(std::unique(classes.begin(), classes.end()), classes.end());
  for (int k : classes) {
    // R(O): rows = colour detections of k, columns = depth detections of k.
    std::vector<int> rows, cols;
    for (int i = 0; i < static_cast<int>(colour.size()); ++i)
      if (colour[static_cast<std::size_t>(i)].class_index == k) rows.push_back(i);
    for (int j = 0; j < static_cast<int>(depth.size()); ++j)
      if (depth[static_cast<std::size_t>(j)].class_index == k) cols.push_back(j);
    std::vector<std::vector<double>> R(rows.size(), std::vector<double>(cols.size(), 0.0));
    for (std::size_t a = 0; a < rows.size(); ++a)
      for (std::size_t b = 0; b < cols.size(); ++b)
        R[a][b] = CoherenceAlpha(colour[static_cast<std::size_t>(rows[a])],
                                 depth[static_cast<std::size_t>(cols[b])]);
    std::vector<bool> row_used(rows.size(), false), col_used(cols.size(), false);
    std::vector<ConsensusInstance> pairs;
    while (true) {  // iterated maximum over the remaining entries
      double best = -1.0;
      std::size_t ba = 0, bb = 0;
      for (std::size_t a = 0; a < rows.size(); ++a)
        for (std::size_t b = 0; b < cols.size(); ++b)
          if (!row_used[a] && !col_used[b] && R[a][b] > best) best = R[a][b], ba = a, bb = b;
      if (best < std::max(p.min_pair_alpha, 1e-9)) break;
      row_used[ba] = col_used[bb] = true;
      pairs.push_back({k, rows[ba], cols[bb], best});
    }
    out.insert(out.end(), pairs.begin(), pairs.end());
    auto overlaps_pair = [&](const PathDetection& d, bool is_colour) {
      for (const auto& q : pairs) {
        const PathDetection& o = is_colour ? colour[static_cast<std::size_t>(q.colour)]
                                           : depth[static_cast<std::size_t>(q.depth)];
        if (OverlapOfSmaller(d, o) > 0.0) return true;
      }
      return false;
    };
    for (std::size_t a = 0; a < rows.size(); ++a) {
      const PathDetection& d = colour[static_cast<std::size_t>(rows[a])];
      // A colour detection whose box's protrusion supports its class (ColourPath: the
      // object's own, of a colour unlike the wall) on min_depth_samples measured samples needs
      // only the colour path's NCC floor: seen along a corridor an extinguisher leaves depth
      // fragments its template does not match, and its colour NCC stays under
      // single_colour_ncc.
      const bool supported = d.samples >= std::max(1, p.min_depth_samples) || d.marked;
      if (!row_used[a] && d.score >= p.single_colour_score &&
          (d.ncc >= p.single_colour_ncc || supported) && !overlaps_pair(d, true))
        out.push_back({k, rows[a], -1, 0.5});
    }
    for (std::size_t b = 0; b < cols.size(); ++b) {
      const PathDetection& d = depth[static_cast<std::size_t>(cols[b])];
      if (!col_used[b] && d.score >= p.single_depth_ncc && d.samples >= p.min_depth_samples &&
          !overlaps_pair(d, false))
        out.push_back({k, -1, cols[b], 0.5});
    }
  }
  // Step 5: across classes, the larger rank keeps an overlap. Rank = max(alpha, 0.5) x the
  // evidence for the class: the depth score where depth found it (NCC x protrusion agreement:
  // the colour of small white components hardly tells them apart), else the colour NCC (the
  // perceptron's score says "a component", the model template says which). A pair ranks at
  // least as a single path: two boxes that disagree still both saw the object.
  auto rank = [&](const ConsensusInstance& c) {
    const double evidence = c.depth >= 0 ? depth[static_cast<std::size_t>(c.depth)].score
                                         : colour[static_cast<std::size_t>(c.colour)].ncc;
    return std::max(c.alpha, 0.5) * evidence;
  };
  std::stable_sort(out.begin(), out.end(),
                   [&](const auto& a, const auto& b) { return rank(a) > rank(b); });
  std::vector<ConsensusInstance> kept;
  for (const auto& c : out) {
    const PathDetection& bc = InstanceBox(c, colour, depth);
    bool clash = false;
    for (const auto& q : kept)
      clash = clash || OverlapOfSmaller(bc, InstanceBox(q, colour, depth)) > p.max_class_overlap;
    if (!clash) kept.push_back(c);
  }
  return kept;
}

}  // namespace mopad::modelling
