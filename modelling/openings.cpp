// SM4 (modelling/openings.h): its parameters and names, the steps of one wall in order
// (DetectWallOpenings; the steps themselves in openings_wall.cpp, openings_candidates.cpp and
// openings_door_leaf.cpp), doors added from the neighbours' SM4, the room's SM4, and what the
// other models take from it (opening voxels, closed doors' points).
#include "modelling/openings.h"

#include <tbb/parallel_for.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <memory>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>
#include <tuple>

#include "common/error.h"
#include "modelling/openings_internal.h"

namespace mopad::modelling {

using detail::AlongWall;
using detail::BuildWallEdges;
using detail::Candidate;
using detail::FitDoor;
using detail::ForPointsInU;
using detail::KeepHoles;
using detail::Line;
using detail::OneOpeningPerHoleWithLines;
using detail::RectangleCandidates;
using detail::SetCorners;
using detail::ToOpenings;
using detail::WallEdges;
using detail::WallLines;
using detail::WallPoints;

void OpeningParams::Validate() const {
  ValidateParams(*this, "openings.");
  orthoimage.Validate();
  auto order = [](const char* lo_name, double lo, const char* hi_name, double hi) {
    if (lo > hi)
      throw InputError(
          "", std::string("parameter 'openings.") + lo_name + "' exceeds '" + hi_name + "'",
          std::to_string(lo), "<= " + std::to_string(hi));
  };
  order("door_min_width", door_min_width, "door_max_width", door_max_width);
  order("door_min_height", door_min_height, "door_max_height", door_max_height);
  order("window_min_width", window_min_width, "window_max_width", window_max_width);
  order("window_min_height", window_min_height, "window_max_height", window_max_height);
  order("canny_low", canny_low, "canny_high", canny_high);
  order("casing_min", casing_min, "casing_max", casing_max);
  order("leaf_v_low", leaf_v_low, "leaf_v_high", leaf_v_high);
  if (median_kernel % 2 == 0)
    throw InputError("", "parameter 'openings.median_kernel' must be odd",
                     std::to_string(median_kernel), "1, 3, 5, ...");
}

const char* ToString(OpeningType t) { return t == OpeningType::kDoor ? "door" : "window"; }

DoorState DoorStateFromAngleDeg(double lambda_deg, double closed_below_deg,
                                double open_tolerance_deg) {
  if (lambda_deg >= 90.0 - open_tolerance_deg) return DoorState::kOpen;
  if (lambda_deg >= closed_below_deg) return DoorState::kSemiOpen;
  return DoorState::kClosed;
}

namespace {

// A door among `openings` overlaps the hint along the wall.
bool Shown(const HoleHint& h, const std::vector<DetectedOpening>& openings) {
  for (const DetectedOpening& o : openings)
    if (o.type == OpeningType::kDoor && std::min(o.u1, h.u1) > std::max(o.u0, h.u0)) return true;
  return false;
}

// Step 4 on the hint's rectangle (from the floor to its top) of `img`'s wall; leaf_points 0
// unless a leaf opened out of the wall's plane was found (lambda >= closed_below_deg): a
// closed leaf's fit takes any flat wall's surface layer, which is no evidence of a door here.
DetectedOpening DoorOnHint(const HoleHint& h, const std::vector<Line>& vert, const Orthoimage& img,
                           const std::string& host, const WallPoints& points,
                           const OpeningParams& p, double floor_v) {
  DetectedOpening o;
  o.type = OpeningType::kDoor;
  o.host = host;
  o.hole_from = h.room;
  if (!(h.u1 > h.u0) || !(h.v1 > floor_v)) return o;
  const PatchFrame& f = img.Frame();
  o.u0 = h.u0, o.u1 = h.u1, o.v0 = floor_v, o.v1 = h.v1;
  SetCorners(o, f);
  o.confidence = h.confidence;
  const double px = img.Pixel();
  FitDoor(o, vert, img, points, p,
          static_cast<std::uint64_t>(std::max(0L, std::lround(h.u0 / px))) * 100003u +
              static_cast<std::uint64_t>(std::max(0L, std::lround(h.v1 / px))) + 11u);
  if (!detail::LeafOpenedOut(o, p)) o.leaf_points = 0;
  return o;
}

}  // namespace

std::vector<HoleHint> HoleHints(const PatchFrame& frame, const std::string& room,
                                const std::vector<Sm4Model>& others, const OpeningParams& p) {
  std::vector<HoleHint> hints;
  for (const Sm4Model& other : others) {
    if (other.room == room) continue;
    for (const DetectedOpening& o : other.openings) {
      if (o.type != OpeningType::kDoor) continue;
      HoleHint h{other.room, 1e300, -1e300, -1e300, o.confidence};
      bool near = true;
      for (const Vec3& c : o.corners) {
        const double d = frame.Depth(c);
        near = near && d <= p.flush_depth && d >= -p.max_wall_thickness;
        const Vec2 uv = frame.ToUv(c);
        h.u0 = std::min(h.u0, uv.x()), h.u1 = std::max(h.u1, uv.x());
        h.v1 = std::max(h.v1, uv.y());
      }
      if (near && h.u0 >= -p.flush_depth && h.u1 <= frame.width + p.flush_depth) hints.push_back(h);
    }
  }
  return hints;
}

int AddDoorsFromNeighbours(const StructuralModel& sm3, Sm4Model& sm4, const OrthoPoints& points,
                           const std::vector<Sm4Model>& others, const OpeningParams& params) {
  params.Validate();
  int added = 0;
  for (const StructuralPatch& wall : sm3.patches) {
    if (wall.patch_class != PatchClass::kWall) continue;
    const PatchFrame frame = PatchFrame::Of(wall);
    // Step 4 needs the wall's frame only (no image lines: a widened side is not snapped).
    const Orthoimage frame_only(frame, params.orthoimage.finest_pixel, 1, 1);
    std::vector<DetectedOpening> on_wall;
    for (const DetectedOpening& o : sm4.openings)
      if (o.host == wall.id) {
        DetectedOpening q = o;
        const Vec2 a = frame.ToUv(o.corners[0]), b = frame.ToUv(o.corners[2]);
        q.u0 = std::min(a.x(), b.x()), q.u1 = std::max(a.x(), b.x());
        on_wall.push_back(q);
      }
    for (const HoleHint& h : HoleHints(frame, sm3.room, others, params)) {
      if (Shown(h, on_wall)) continue;
      DetectedOpening o =
          DoorOnHint(h, {}, frame_only, wall.id, WallPoints{points, {}}, params, 0.0);
      if (o.leaf_points == 0) continue;
      o.id = "opening_" + std::to_string(sm4.openings.size() + 1);
      on_wall.push_back(o);
      sm4.openings.push_back(std::move(o));
      ++added;
    }
  }
  return added;
}

namespace {

bool StandsInFront(const DetectedOpening& o, const PatchFrame& f, const WallPoints& in,
                   const OpeningParams& p) {
  // 2 cm plan bins along u from casing_max + 0.1 m before u0 to as far after u1; a bin is
  // occupied when points of the upper half of the leaf's v band stand in front of the wall
  // there (a door seen behind a low cabinet shows its frame and leaf above it).
  if (in.in.points == nullptr || o.type != OpeningType::kDoor || !(o.u1 > o.u0)) return false;
  constexpr double kBin = 0.02;
  const double lo = o.u0 - p.casing_max - 0.1, hi = o.u1 + p.casing_max + 0.1, h = o.Height();
  const int nb = static_cast<int>(std::ceil((hi - lo) / kBin));
  std::vector<int> bins(static_cast<std::size_t>(nb), 0);
  const Vec2 nrm(-o.leaf_line_dir.y(), o.leaf_line_dir.x());
  ForPointsInU(in, lo, hi, [&](const Vec3& q) {
    const double d = f.Depth(q);
    if (d <= p.flush_depth || d > p.front_depth) return;
    const Vec2 uv = f.ToUv(q);
    if (uv.x() < lo || uv.x() >= hi) return;
    if (uv.y() < o.v0 + 0.5 * (p.leaf_v_low + p.leaf_v_high) * h ||
        uv.y() > o.v0 + p.leaf_v_high * h)
      return;
    // The leaf's own points (either face) are not in front of the doorway: it swung there.
    if (o.leaf_points > 0 &&
        std::abs(nrm.dot(Vec2(uv.x(), d) - o.leaf_line_point)) <= p.leaf_thickness + p.leaf_inlier)
      return;
    ++bins[std::min(nb - 1, static_cast<int>((uv.x() - lo) / kBin))];
  });
  const int b0 = static_cast<int>((o.u0 - lo) / kBin);
  const int b1 = std::min(nb, static_cast<int>((o.u1 - lo) / kBin));
  int occupied = 0;
  for (int b = b0; b < b1; ++b) occupied += bins[b] > 0;
  if (b1 <= b0 || occupied < p.front_min_share * (b1 - b0)) return false;
  // The occupied run (one-bin gaps bridged) holding most of the door's occupied bins: an
  // object in front of a door frame seen beside it ends away from the door's sides.
  double a = 0.0, b = 0.0;
  int best_in = 0;
  for (int k = 0; k < nb;) {
    if (bins[k] == 0) {
      ++k;
      continue;
    }
    int e = k, in_door = 0;
    while (e < nb && (bins[e] > 0 || (e + 1 < nb && bins[e + 1] > 0))) {
      in_door += e >= b0 && e < b1 && bins[e] > 0;
      ++e;
    }
    if (in_door > best_in) best_in = in_door, a = lo + k * kBin, b = lo + e * kBin;
    k = e;
  }
  return std::abs(a - o.u0) <= p.casing_max && std::abs(b - o.u1) <= p.casing_max;
}

// DetectedOpening::sky_share of the hole [u0, u1] x [v0, v1] of frame f: the rays that crossed
// it rising, from the points beyond the wall (further than p.max_wall_thickness behind its
// plane: the hole's reveals and lintel are the wall's, not its far side) and the rays without
// a return where BuildOrthoimage counts them passed (NoReturnRule).
double SkyShare(const DetectedOpening& o, const PatchFrame& f, const OrthoPoints& in,
                const OpeningParams& p) {
  const double wall = p.max_wall_thickness;
  if (in.points == nullptr || in.scan_index == nullptr) return std::nan("");
  std::vector<double> origin_depth;
  for (const Vec3& c : in.scan_origins) origin_depth.push_back(f.Depth(c));
  std::size_t rising = 0, none = 0;
  const auto cross = [&](const Vec3& c, const Vec3& x) {
    if (x.z() <= c.z()) return false;
    const Vec2 uv = f.ToUv(x);
    return uv.x() >= o.u0 && uv.x() <= o.u1 && uv.y() >= o.v0 && uv.y() <= o.v1;
  };
  const auto& pts = *in.points;
  for (std::size_t i = 0; i < pts.size(); ++i) {
    const std::size_t s = (*in.scan_index)[i];
    const double dc = origin_depth[s];
    if (dc <= 0.0) continue;
    const Vec3 p = pts[i].cast<double>();
    const double dp = f.Depth(p);
    if (dp >= -wall) continue;
    const Vec3& c = in.scan_origins[s];
    rising += cross(c, c + dc / (dc - dp) * (p - c));
  }
  const NoReturnRule rule(p.orthoimage);
  for (std::size_t i = 0; i < in.no_return_dirs.size(); ++i) {
    const std::size_t s = in.no_return_scan[i];
    const Vec3& c = in.scan_origins[s];
    Vec3 x;
    if (rule.Crossing(c, origin_depth[s], in.no_return_dirs[i].cast<double>().normalized(), f,
                      &x) &&
        cross(c, x))
      ++rising, ++none;
  }
  return rising > 0 ? static_cast<double>(none) / static_cast<double>(rising) : std::nan("");
}

}  // namespace

bool StandsInFrontOfTheWall(const DetectedOpening& o, const PatchFrame& f, const OrthoPoints& in,
                            const OpeningParams& p) {
  return StandsInFront(o, f, WallPoints{in, {}}, p);
}

std::vector<DetectedOpening> DetectWallOpenings(const Orthoimage& img, const std::string& host,
                                                const OrthoPoints& room_points,
                                                const OpeningParams& p, double floor_v,
                                                const std::vector<HoleHint>& hints) {
  p.Validate();
  const int cols = img.Cols(), rows = img.Rows();
  if (cols < 3 || rows < 3) return {};
  const double px = img.Pixel();
  const WallPoints points = AlongWall(room_points, img.Frame());
  const WallArea area = SegmentWallArea(img, p);
  const WallEdges we = BuildWallEdges(img, area, p);
  const auto [vert, horz] = WallLines(we, px, p);
  // Rectangles, the kept holes, the openings.
  const int floor_row =
      std::clamp(static_cast<int>(std::lround(rows - (floor_v + img.Margin()) / px)), 0, rows);
  const int ceiling_row = std::clamp(
      static_cast<int>(std::lround(rows - (img.Frame().height + img.Margin()) / px)), 0, rows);
  const std::vector<Candidate> cands =
      RectangleCandidates(vert, horz, we.m, p, px, floor_row, ceiling_row);
  std::vector<Candidate> kept = KeepHoles(cands, we.m, p, px);
  std::vector<DetectedOpening> out =
      OneOpeningPerHoleWithLines(ToOpenings(kept, vert, horz, we.m, img, host, points, p, floor_v),
                                 vert, we.m, img, points, p);
  for (const HoleHint& h : hints)
    if (!Shown(h, out)) {
      DetectedOpening o = DoorOnHint(h, vert, img, host, points, p, floor_v);
      if (o.leaf_points > 0) out.push_back(std::move(o));
    }
  std::stable_sort(out.begin(), out.end(),
                   [](const DetectedOpening& a, const DetectedOpening& b) { return a.u0 < b.u0; });
  // A door whose front is occupied by one object ending at its sides is that object's outline;
  // one whose head reaches the wall's top has no lintel (the rule of the candidates, for the
  // head the leaf fit moved it to, door_head_clearance).
  out.erase(std::remove_if(out.begin(), out.end(),
                           [&](const DetectedOpening& o) {
                             return StandsInFront(o, img.Frame(), points, p) ||
                                    (o.type == OpeningType::kDoor &&
                                     o.v1 > img.Frame().height - p.door_head_clearance);
                           }),
            out.end());
  for (DetectedOpening& o : out)
    if (o.type == OpeningType::kDoor) o.sky_share = SkyShare(o, img.Frame(), room_points, p);
  return out;
}

std::vector<DetectedOpening> OneOpeningPerHole(std::vector<DetectedOpening> openings,
                                               const Orthoimage& image, const OrthoPoints& points,
                                               const OpeningParams& params) {
  params.Validate();
  if (image.Cols() < 3 || image.Rows() < 3) return openings;
  const WallEdges we = BuildWallEdges(image, SegmentWallArea(image, params), params);
  const auto lines = WallLines(we, image.Pixel(), params);
  return OneOpeningPerHoleWithLines(std::move(openings), lines.first, we.m, image,
                                    AlongWall(points, image.Frame()), params);
}

Sm4Model DetectOpenings(const StructuralModel& sm3, const OrthoPoints& points,
                        const OpeningParams& params,
                        std::vector<std::pair<std::string, Orthoimage>>* images,
                        const std::vector<Sm4Model>& neighbours) {
  params.Validate();
  Sm4Model out;
  out.room = sm3.room;
  std::vector<const StructuralPatch*> walls;
  for (const StructuralPatch& patch : sm3.patches)
    if (patch.patch_class == PatchClass::kWall) walls.push_back(&patch);
  // One task per wall (each wall's steps read only its own image and the shared points; its
  // leaf streams are keyed by its own rectangles), gathered in wall order: the same bytes on
  // any number of threads.
  std::vector<std::vector<DetectedOpening>> found(walls.size());
  std::vector<std::unique_ptr<Orthoimage>> wall_images(walls.size());
  tbb::parallel_for(std::size_t{0}, walls.size(), [&](std::size_t i) {
    const PatchFrame frame = PatchFrame::Of(*walls[i]);
    auto img = std::make_unique<Orthoimage>(BuildOrthoimage(points, frame, params.orthoimage));
    found[i] = DetectWallOpenings(*img, walls[i]->id, points, params, 0.0,
                                  HoleHints(frame, sm3.room, neighbours, params));
    if (images != nullptr) wall_images[i] = std::move(img);
  });
  for (std::size_t i = 0; i < walls.size(); ++i) {
    for (auto& o : found[i]) out.openings.push_back(std::move(o));
    if (images != nullptr) images->emplace_back(walls[i]->id, std::move(*wall_images[i]));
  }
  for (std::size_t i = 0; i < out.openings.size(); ++i)
    out.openings[i].id = "opening_" + std::to_string(i + 1);
  return out;
}

int MarkOpeningVoxels(const std::vector<DetectedOpening>& openings, VoxelSpace& voxels,
                      double band) {
  if (voxels.empty()) return 0;
  const double size = voxels.Size();
  if (band <= 0.0) band = size;
  const double inset = 0.375 * size;
  int marked = 0;
  for (const DetectedOpening& o : openings) {
    const Vec3 c0 = o.corners[0];
    const Vec3 du = o.corners[1] - c0, dv = o.corners[3] - c0;
    const double w = du.norm(), h = dv.norm();
    if (w <= 2 * inset || h <= 2 * inset) continue;
    const Vec3 eu = du / w, ev = dv / h, n = eu.cross(ev).normalized();
    // Bounding box of the rectangle thickened by the band, in voxel indices.
    Vec3 lo = c0, hi = c0;
    for (const Vec3& c : o.corners)
      for (const Vec3& q : {Vec3(c + band * n), Vec3(c - band * n)})
        lo = lo.cwiseMin(q), hi = hi.cwiseMax(q);
    const Eigen::Vector3i a = voxels.VoxelOf(lo), b = voxels.VoxelOf(hi);
    for (int k = std::max(0, a.z()); k <= std::min(voxels.Nz() - 1, b.z()); ++k)
      for (int j = std::max(0, a.y()); j <= std::min(voxels.Ny() - 1, b.y()); ++j)
        for (int i = std::max(0, a.x()); i <= std::min(voxels.Nx() - 1, b.x()); ++i) {
          const std::size_t idx = voxels.Index(i, j, k);
          std::uint8_t& f = voxels.MutableFlags(idx);
          if (!(f & VoxelSpace::kStructural) || (f & VoxelSpace::kOpeningFace)) continue;
          const Vec3 r = voxels.Centre(i, j, k) - c0;
          if (std::abs(n.dot(r)) > band) continue;
          const double pu = eu.dot(r), pv = ev.dot(r);
          if (pu < inset || pu > w - inset || pv < inset || pv > h - inset) continue;
          f |= VoxelSpace::kOpeningFace;
          ++marked;
        }
  }
  return marked;
}

std::vector<std::uint8_t> ClosedDoorPointMask(const std::vector<Eigen::Vector3f>& points,
                                              const std::vector<StructuralPatch>& patches,
                                              const std::vector<DetectedOpening>& openings,
                                              double margin, double band) {
  std::vector<std::uint8_t> mask(points.size(), 0);
  for (const DetectedOpening& o : openings) {
    if (o.type != OpeningType::kDoor || o.state != DoorState::kClosed) continue;
    const auto it = std::find_if(patches.begin(), patches.end(),
                                 [&](const StructuralPatch& s) { return s.id == o.host; });
    if (it == patches.end()) continue;
    const PatchFrame f = PatchFrame::Of(*it);
    // The rectangle from the map-frame corners, so a refitted host still finds its door.
    double u0 = 1e300, u1 = -1e300, v0 = 1e300, v1 = -1e300;
    for (const Vec3& c : o.corners) {
      const Vec2 uv = f.ToUv(c);
      u0 = std::min(u0, uv.x()), u1 = std::max(u1, uv.x());
      v0 = std::min(v0, uv.y()), v1 = std::max(v1, uv.y());
    }
    for (std::size_t i = 0; i < points.size(); ++i) {
      const Vec3 q = points[i].cast<double>();
      if (std::abs(f.Depth(q)) > band) continue;
      const Vec2 uv = f.ToUv(q);
      if (uv.x() >= u0 - margin && uv.x() <= u1 + margin && uv.y() >= v0 - margin &&
          uv.y() <= v1 + margin)
        mask[i] = 1;
    }
  }
  return mask;
}

}  // namespace mopad::modelling
