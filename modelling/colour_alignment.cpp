#include "modelling/colour_alignment.h"

#include <algorithm>
#include <cmath>

#include "common/srgb.h"

namespace mopad::modelling {
namespace {

// sRGB level -> linear light, once.
const std::array<float, 256>& LinearTable() {
  static const std::array<float, 256> table = [] {
    std::array<float, 256> t{};
    for (int v = 0; v < 256; ++v)
      t[static_cast<std::size_t>(v)] = static_cast<float>(SrgbToLinear(v / 255.0));
    return t;
  }();
  return table;
}

// The median of `v` (not empty); reorders it.
double Median(std::vector<double>& v) {
  const auto mid = v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2);
  std::nth_element(v.begin(), mid, v.end());
  return *mid;
}

}  // namespace

ColourReference::ColourReference(ColourAlignmentParams params) : params_(params) {}

std::int64_t ColourReference::Key(const Eigen::Vector3f& p) const {
  const double inv = 1.0 / params_.voxel;
  const auto i = static_cast<std::int64_t>(std::floor(p.x() * inv)) & 0x1FFFFF;
  const auto j = static_cast<std::int64_t>(std::floor(p.y() * inv)) & 0x1FFFFF;
  const auto k = static_cast<std::int64_t>(std::floor(p.z() * inv)) & 0x1FFFFF;
  return (i << 42) | (j << 21) | k;
}

std::array<double, 3> ColourReference::Gains(const std::vector<Eigen::Vector3f>& points,
                                             const std::vector<Rgb8>& colours, std::size_t begin,
                                             std::size_t end, int* shared) const {
  if (shared) *shared = 0;
  if (!params_.enabled || cells_.empty()) return {1.0, 1.0, 1.0};
  const auto& lin = LinearTable();
  // The scan's points in cells the room holds, in the order the scan first meets them.
  std::unordered_map<std::int64_t, std::size_t> slot;
  std::vector<Shared> cells;
  for (std::size_t i = begin; i < end; ++i) {
    const std::int64_t key = Key(points[i]);
    const auto room = cells_.find(key);
    if (room == cells_.end()) continue;
    const auto [it, added] = slot.try_emplace(key, cells.size());
    if (added) cells.push_back({&room->second, {}});
    Cell& c = cells[it->second].scan;
    for (std::size_t ch = 0; ch < 3; ++ch) c.sum[ch] += lin[colours[i][ch]];
    ++c.n;
  }
  return GainsOf(cells, shared);
}

std::array<double, 3> ColourReference::Align(const std::vector<Eigen::Vector3f>& points,
                                             std::vector<Rgb8>& colours, std::size_t begin,
                                             std::size_t end, int* shared) {
  if (shared) *shared = 0;
  const std::array<double, 3> none{1.0, 1.0, 1.0};
  if (!params_.enabled) return none;
  const auto& lin = LinearTable();
  const bool first = cells_.empty();
  // Each point's cell of the room, made when new (node addresses stay put); the scan's sums
  // beside each cell it meets, in the order it first meets them.
  std::vector<Shared> cells;
  std::vector<Cell*> met;  // the cells of `cells`, writable: their slots are reset after
  std::vector<Cell*> cell_of(end - begin);
  for (std::size_t i = begin; i < end; ++i) {
    Cell* room = &cells_[Key(points[i])];
    cell_of[i - begin] = room;
    if (first) continue;
    if (room->slot == kNoSlot) {
      room->slot = static_cast<std::uint32_t>(cells.size());
      cells.push_back({room, {}});
      met.push_back(room);
    }
    Cell& c = cells[room->slot].scan;
    for (std::size_t ch = 0; ch < 3; ++ch) c.sum[ch] += lin[colours[i][ch]];
    ++c.n;
  }
  for (Cell* c : met) c->slot = kNoSlot;
  const std::array<double, 3> g = first ? none : GainsOf(cells, shared);
  ApplyColourGains(g, colours, begin, end);
  for (std::size_t i = begin; i < end; ++i) {
    Cell& c = *cell_of[i - begin];
    for (std::size_t ch = 0; ch < 3; ++ch) c.sum[ch] += lin[colours[i][ch]];
    ++c.n;
  }
  return g;
}

std::array<double, 3> ColourReference::GainsOf(const std::vector<Shared>& cells,
                                               int* shared) const {
  const std::array<double, 3> none{1.0, 1.0, 1.0};
  // Per channel the median of the cells' ratios: robust to cells on a depth edge or a colour
  // boundary, where the two scans see different things. Cells the room did not hold before
  // this scan (n = 0) compare nothing.
  std::array<std::vector<double>, 3> ratios;
  const auto min_n = static_cast<std::uint32_t>(params_.min_voxel_points);
  for (const Shared& s : cells) {
    const Cell& c = s.scan;
    const Cell& ref = *s.room;
    if (c.n < min_n || ref.n < min_n) continue;
    std::array<double, 3> a{}, b{};
    bool ok = true;
    for (std::size_t ch = 0; ch < 3; ++ch) {
      a[ch] = ref.sum[ch] / ref.n;
      b[ch] = c.sum[ch] / c.n;
      ok = ok && a[ch] >= params_.min_linear && b[ch] >= params_.min_linear &&
           a[ch] <= params_.max_linear && b[ch] <= params_.max_linear;
    }
    if (!ok) continue;
    for (std::size_t ch = 0; ch < 3; ++ch) ratios[ch].push_back(a[ch] / b[ch]);
  }
  const int n = static_cast<int>(ratios[0].size());
  if (shared) *shared = n;
  if (n < params_.min_voxels) return none;
  std::array<double, 3> g{};
  bool outside = false;
  for (std::size_t ch = 0; ch < 3; ++ch) {
    g[ch] = Median(ratios[ch]);
    outside = outside || std::abs(std::log(g[ch])) > params_.deadband;
  }
  return outside ? g : none;
}

void ApplyColourGains(const std::array<double, 3>& gains, std::vector<Rgb8>& colours,
                      std::size_t begin, std::size_t end) {
  if (gains == std::array<double, 3>{1.0, 1.0, 1.0}) return;
  std::array<std::array<std::uint8_t, 256>, 3> table{};
  const auto& lin = LinearTable();
  for (std::size_t ch = 0; ch < 3; ++ch)
    for (int v = 0; v < 256; ++v)
      table[ch][static_cast<std::size_t>(v)] = static_cast<std::uint8_t>(
          std::lround(255.0 * LinearToSrgb(gains[ch] * lin[static_cast<std::size_t>(v)])));
  for (std::size_t i = begin; i < end; ++i)
    for (std::size_t ch = 0; ch < 3; ++ch) colours[i][ch] = table[ch][colours[i][ch]];
}

}  // namespace mopad::modelling
