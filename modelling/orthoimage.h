#pragma once
// The 4D orthoimage J_CD of a planar patch (paper §3.3, Figure 9a; §3.4 reuses it for service
// components): the room's SM1 points within +-band of the patch plane, projected orthogonally
// onto it and rasterised. Per pixel: mean colour (RGB; HSV derivable with Hsv()), mean signed
// depth (distance to the plane along its normal, positive into the room: protruding casings
// and furniture > 0, a recessed leaf or glass < 0), point count, and two ray counts that tell
// the holes apart:
//  - passed: rays from a scanner in front of the plane that crossed it at this pixel and ended
//    more than `band` behind it or returned nothing (seen through an open door, a window);
//  - blocked: rays that ended more than `band` in front of the plane and whose extension meets
//    it at this pixel (the wall is occluded there, e.g. by a cabinet).
// A pixel without points, passed or blocked rays was simply not seen.
//
// Frames: the patch frame P is (origin, u, v, n), right-handed (u x v = n), n the patch
// normal into the room. For a wall or column face (|n.z| < 0.9) v is the upward direction in
// the plane (+z for a vertical wall) and u is horizontal, running left to right seen from the
// room; for a ceiling or floor u is +x projected on the plane. The origin is the corner
// (min u, min v) of the patch polygon's bounding box in (u, v), so a wall's v is the height
// above its bottom edge (the floor). Image: column c covers u in [c, c+1) * pixel, row r
// covers v in (rows - r - 1, rows - r] * pixel (row 0 at the top, as a person views an
// image). Map frame in, metres.
//
// Robot side: input is the robot's own points, colours and scanner centres. Deterministic
// (one pass in point order, sums in fixed order). Not thread-safe to build into one image
// concurrently; const access is.

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "common/frames.h"
#include "common/params.h"
#include "interfaces/tls_scan.h"
#include "modelling/structural_model.h"

namespace mopad::modelling {

struct OrthoimageParams {
  double band = 0.20;            ///< m, points within +-band of the plane are imaged, [0.01, 1]
  double finest_pixel = 0.01;    ///< m, smallest pixel chosen, [0.002, 0.2]
  double coarsest_pixel = 0.05;  ///< m, largest pixel chosen, [finest_pixel, 0.5]
  /// Points per pixel the pixel size aims at, in the median 10 cm cell of the imaged points
  /// (pixel = sqrt(points_per_pixel / median density), clamped), [0.1, 100]
  double points_per_pixel = 2.0;
  double density_cell = 0.10;   ///< m, cell of the density estimate, [0.01, 1]
  double margin = 0.0;          ///< m, image extends this far beyond the patch in u and v, [0, 2]
  int max_pixels = 20'000'000;  ///< refuse larger images (InputError), [1, 1e9]
  /// m, a ray without a return counts as passed only where it crosses the plane at least this
  /// far from the scanner: nearer, the surface may simply be inside the scanner's minimum
  /// range. The TLS's minimum range (1.5 m, `nbs.range_min`) plus 0.1 m: a wall beyond it
  /// returns, so a ray that crossed it there and returned nothing went through a hole (a window
  /// seen from 1.6-2 m), [0, 100]
  double no_return_min_range = 1.6;
  /// Share of the returns bordering a region of the scan grid without returns that lie nearer
  /// than no_return_min_range, above which the region met a surface inside the scanner's
  /// minimum range (an opened leaf beside the scanner) and its rays pass nothing
  /// (AddNoReturnRays), [0, 1]
  double no_return_near_border_share = 0.5;
  /// deg, a ray without a return counts as passed only where it meets the plane at most this
  /// far from the plane's normal: a surface met at a grazing angle may return nothing (a weak
  /// echo, a dropout), so such a ray says nothing about a hole there, [1, 90]
  double no_return_max_incidence_deg = 80.0;
  /// m, cell of the occupancy grid in which DropNoReturnRaysThroughSeenSurfaces looks for a
  /// surface the room's points show on a ray's way inside the minimum range, [0.005, 1]
  double no_return_blocker_cell = 0.05;
  /// m, largest beam footprint a sample fills the pixels of. A point, or a ray's crossing of
  /// the plane, stands for the square of plane around it that its beam covers: range x angular
  /// step / cos(incidence) across (OrthoPoints::scan_steps), the surfel size of point-based
  /// fusion (Keller et al., 3DV 2013). Where beams meet the plane farther apart than a pixel, a
  /// pixel between samples takes the nearest one whose footprint covers it instead of reading
  /// unseen (occluded) — a window seen obliquely every 2-3 pixels. A sample whose footprint is
  /// larger fills nothing: at a grazing angle a 2 cm casing's shadow is wider than the spacing,
  /// and what lies between two samples is not known. 0: pixels hold only what falls in them,
  /// [0, 0.5]
  double footprint_max = 0.05;

  template <class V>
  void Visit(V& v) {
    v("band", band, Bounds{0.01, 1.0});
    v("finest_pixel", finest_pixel, Bounds{0.002, 0.2});
    v("coarsest_pixel", coarsest_pixel, Bounds{0.002, 0.5});
    v("points_per_pixel", points_per_pixel, Bounds{0.1, 100.0});
    v("density_cell", density_cell, Bounds{0.01, 1.0});
    v("margin", margin, Bounds{0.0, 2.0});
    v("max_pixels", max_pixels, Bounds{1, 1e9});
    v("no_return_min_range", no_return_min_range, Bounds{0.0, 100.0});
    v("no_return_near_border_share", no_return_near_border_share, Bounds{0.0, 1.0});
    v("no_return_max_incidence_deg", no_return_max_incidence_deg, Bounds{1.0, 90.0});
    v("no_return_blocker_cell", no_return_blocker_cell, Bounds{0.005, 1.0});
    v("footprint_max", footprint_max, Bounds{0.0, 0.5});
  }
  /// Bounds of every field and finest_pixel <= coarsest_pixel (InputError naming the field).
  void Validate() const;
};

/// The (u, v, n) frame of a patch and its extent (see the file comment).
struct PatchFrame {
  Vec3 origin = Vec3::Zero();  ///< map frame, (u, v) = (0, 0)
  Vec3 u = Vec3::UnitX(), v = Vec3::UnitZ(), n = -Vec3::UnitY();
  double width = 0.0;   ///< m, extent of the patch polygon along u
  double height = 0.0;  ///< m, extent along v

  /// Frame of a patch: normal from its plane, extent from its polygon. InputError when the
  /// polygon has fewer than 3 vertices or the normal is not finite and non-zero.
  static PatchFrame Of(const Vec3& normal, const std::vector<Vec3>& polygon);
  static PatchFrame Of(const StructuralPatch& patch) { return Of(patch.plane.n, patch.polygon); }

  Vec2 ToUv(const Vec3& p_M) const { return {u.dot(p_M - origin), v.dot(p_M - origin)}; }
  double Depth(const Vec3& p_M) const { return n.dot(p_M - origin); }
  Vec3 ToMap(double pu, double pv, double depth = 0.0) const {
    return origin + pu * u + pv * v + depth * n;
  }
};

/// The robot's points a patch is imaged from (SM1: RoomModel::Points(), Colours(),
/// ScanIndices() and the scanner centres of ScanPoses()). Pointers are not owned and must
/// outlive the call. scan_index and scan_origins are optional (both or neither): without them
/// the passed and blocked counts stay 0.
struct OrthoPoints {
  const std::vector<Eigen::Vector3f>* points = nullptr;               ///< map frame
  const std::vector<std::array<std::uint8_t, 3>>* colours = nullptr;  ///< RGB, one per point
  const std::vector<std::uint16_t>* scan_index = nullptr;             ///< scan of each point
  std::vector<Vec3> scan_origins;                                     ///< map frame, per scan
  /// Optional (needs scan_origins): rays that returned nothing (AddNoReturnRays), as unit
  /// directions in the map frame with their scan. Such a ray passed every plane it crossed (a
  /// window to the outside, an open door to far space) and counts as passed there.
  std::vector<Eigen::Vector3f> no_return_dirs;
  std::vector<std::uint16_t> no_return_scan;
  /// Optional (needs scan_origins; empty, or one per scan): the angle between neighbouring
  /// beams of each scan, rad (its azimuth and elevation steps, the larger). With them a pixel
  /// that no sample falls in takes the nearest sample whose beam footprint covers it
  /// (BuildOrthoimage, OrthoimageParams::footprint_max).
  std::vector<double> scan_steps;
};

/// Appends the rays of `scan` without a return (range 0), directions from their grid indices
/// (row r at elevation_max - r * elevation_step, column c at azimuth_min + c * azimuth_step,
/// x forward, y left, z up in the scanner frame) rotated into the map frame by X_MS. The rays
/// of a region of the grid without returns (8-connected) whose bordering returns lie nearer
/// than params.no_return_min_range for more than params.no_return_near_border_share of them
/// are left out: such a region met a surface inside the scanner's minimum range. InputError if
/// the scan's grid and point count disagree or the params are out of range.
void AddNoReturnRays(const interfaces::TlsScan& scan, const Pose3& X_MS, std::uint16_t scan_index,
                     OrthoPoints& out, const OrthoimageParams& params = {});

/// Leaves out the rays without a return (in.no_return_dirs, no_return_scan) that pass through a
/// surface the robot's points (in.points, all scans) show within the scanner's minimum range of
/// their scanner: such a ray met that surface (a desk or a chair beside the scan position, which
/// the room's other scans saw) and returned nothing because it was too near, not because a hole
/// in a wall behind let it through. The points are binned in `no_return_blocker_cell` cells;
/// each ray is sampled every half cell from one cell out to no_return_min_range less two cells
/// (the minimum range; a wall the ray crosses beyond it is not reached). Deterministic, the
/// order of the kept rays unchanged. Returns the number left out; InputError on inconsistent
/// input or params.
std::size_t DropNoReturnRaysThroughSeenSurfaces(OrthoPoints& in, const OrthoimageParams& params);

class Orthoimage {
 public:
  Orthoimage() = default;
  /// An empty image of cols x rows pixels of size `pixel` on `frame`.
  Orthoimage(const PatchFrame& frame, double pixel, int cols, int rows);
  Orthoimage(const Orthoimage&) = default;
  Orthoimage& operator=(const Orthoimage&) = default;
  Orthoimage(Orthoimage&&) noexcept = default;
  Orthoimage& operator=(Orthoimage&&) noexcept = default;

  const PatchFrame& Frame() const { return frame_; }
  double Pixel() const { return pixel_; }  ///< m
  int Cols() const { return cols_; }
  int Rows() const { return rows_; }
  std::size_t Index(int col, int row) const {
    return static_cast<std::size_t>(row) * static_cast<std::size_t>(cols_) + col;
  }
  bool Inside(int col, int row) const { return col >= 0 && row >= 0 && col < cols_ && row < rows_; }
  /// Pixel containing (u, v); may be outside the image (check Inside). Beyond an edge, the
  /// index is one past it (-1 or Cols()/Rows()) however far the point lies.
  std::array<int, 2> PixelOf(double pu, double pv) const;
  /// (u, v) of a pixel's centre.
  Vec2 CentreUv(int col, int row) const {
    return {(col + 0.5) * pixel_ - margin_, (rows_ - row - 0.5) * pixel_ - margin_};
  }
  /// u of a column's left edge and v of a row's top edge (m); used for rectangle corners.
  double ColU(double col) const { return col * pixel_ - margin_; }
  double RowV(double row) const { return (rows_ - row) * pixel_ - margin_; }

  std::uint32_t Count(std::size_t i) const { return count_[i]; }
  /// Mean colour (0,0,0 where Count is 0).
  std::array<std::uint8_t, 3> Rgb(std::size_t i) const { return rgb_[i]; }
  /// Hue [0, 360) deg, saturation and value [0, 1] of Rgb(i).
  std::array<float, 3> Hsv(std::size_t i) const;
  /// Mean signed depth, m (NaN where Count is 0).
  float Depth(std::size_t i) const { return depth_[i]; }
  /// Largest signed depth of the pixel's points (the surface nearest the room side; NaN where
  /// Count is 0), m.
  float FrontDepth(std::size_t i) const { return front_[i]; }
  std::uint32_t Passed(std::size_t i) const { return passed_[i]; }
  /// The part of Passed(i) from rays without a return (weaker: a dark or grazing surface may
  /// return nothing).
  std::uint32_t PassedNoReturn(std::size_t i) const { return passed_no_return_[i]; }
  std::uint32_t Blocked(std::size_t i) const { return blocked_[i]; }

  /// Adds one imaged point (depth within the band) at (u, v): running mean of colour and depth.
  void AddPoint(double pu, double pv, double depth, const std::array<std::uint8_t, 3>& rgb);
  /// Sets the margin (m) the pixel grid starts before the frame's origin.
  void SetMargin(double margin) { margin_ = margin; }
  double Margin() const { return margin_; }

 private:
  friend Orthoimage BuildOrthoimage(const OrthoPoints&, const PatchFrame&, const OrthoimageParams&,
                                    double);
  /// AddPoint's sums at pixel i without its means; SetMean(i) sets pixel i's mean colour and
  /// depth from its sums (AddPoint after each point, BuildOrthoimage once per pixel through
  /// FinishMeans: the same sums, so the same means).
  void AccumulatePoint(std::size_t i, double depth, const std::array<std::uint8_t, 3>& rgb);
  void SetMean(std::size_t i);
  void FinishMeans();

  PatchFrame frame_;
  double pixel_ = 0.01, margin_ = 0.0;
  int cols_ = 0, rows_ = 0;
  std::vector<std::uint32_t> count_, passed_, blocked_, passed_no_return_;
  std::vector<std::array<std::uint8_t, 3>> rgb_;
  std::vector<std::array<double, 3>> rgb_sum_;
  std::vector<float> depth_;
  std::vector<double> depth_sum_;
  std::vector<float> front_;
};

/// InputError unless `in` holds points and one colour each, and its optional scan and
/// no-return arrays agree with them (what BuildOrthoimage checks).
void CheckOrthoPoints(const OrthoPoints& in);

/// Pixel size for `frame` from the density of the points within the band over the patch
/// (median over the occupied density cells), clamped to [finest_pixel, coarsest_pixel] and
/// rounded to 1 mm.
double ChoosePixelSize(const OrthoPoints& points, const PatchFrame& frame,
                       const OrthoimageParams& params);

/// BuildOrthoimage's rule for a ray without a return: from `origin` (`origin_depth` in front of
/// the plane of `frame`) along the unit `dir`, it counts as passing the plane where it meets it
/// when it heads for it, within no_return_max_incidence_deg of its normal (at a grazing angle the
/// plane may not have echoed) and no_return_min_range or more from the scanner (nearer, the
/// plane may lie inside the minimum range). Crossing() is false when the ray says nothing.
class NoReturnRule {
 public:
  explicit NoReturnRule(const OrthoimageParams& params);
  bool Crossing(const Vec3& origin, double origin_depth, const Vec3& dir, const PatchFrame& frame,
                Vec3* crossing) const;

 private:
  double min_cos_ = 0.0, min_range_ = 0.0;
};

/// Builds J_CD of one patch (see the file comment). `pixel` <= 0 chooses it with
/// ChoosePixelSize. InputError for missing or mismatched point arrays, bad params, or an image
/// over max_pixels.
Orthoimage BuildOrthoimage(const OrthoPoints& points, const PatchFrame& frame,
                           const OrthoimageParams& params, double pixel = 0.0);

/// Writes the image for a person: `<stem>_colour.png` (8-bit RGB, unseen pixels black,
/// seen-through pixels blue-grey (passed rays only), occluded ones dark red (blocked rays
/// only)) and `<stem>_depth.png` (16-bit grey: 0 = no point, else 32768 + depth / 0.1 mm,
/// clamped to [1, 65535]). InputError if a file cannot be written.
void WriteOrthoimagePngs(const Orthoimage& image, const std::string& stem);

}  // namespace mopad::modelling
