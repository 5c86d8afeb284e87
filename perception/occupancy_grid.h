#pragma once
// The robot's 2D obstacle map (paper §3.1 step (2): "the robot obtains an obstacle map from the
// previously acquired point cloud").
//
// A log-odds occupancy grid in the map frame (REP-105 `map`, Z up, floor at z = 0): built from
// a height band of the robot's own registered 3D points and updated by LRF scans (Bresenham ray
// tracing of free space, Probabilistic Robotics ch. 9, Thrun/Burgard/Fox 2005). Cell (i, j) —
// column i along +x, row j along +y — covers [origin + (i, j) * resolution, + resolution);
// when the origin is a multiple of the resolution (Covering) a point is placed by its global
// cell floor(x / resolution), so grids of one site and CloudEvidence agree on boundaries.
// Cells start unknown (log-odds 0). A cell is occupied when its probability exceeds
// `occupied_thresh`, free below `free_thresh`, unknown between (ROS map_server semantics).
//
// DistanceField turns a grid into clearances (Euclidean distance transform), used for
// inflation by the footprint radius, the planner's validity checks and AMCL's likelihood field.
// Maps are written and read as PNG + YAML in ROS map_server conventions (ReadMap/WriteMap).
// Not thread-safe for concurrent writes; const queries may run concurrently.

#include <Eigen/Core>
#include <cstdint>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include "common/frames.h"
#include "common/params.h"
#include "interfaces/lrf_scan.h"

namespace mopad::perception {

enum class CellState : std::uint8_t { kUnknown = 0, kFree = 1, kOccupied = 2 };

struct OccupancyGridParams {
  double resolution = 0.05;       ///< m per cell, [0.005, 1]
  double obstacle_z_min = 0.08;   ///< m, lower edge of the obstacle band (map z), [-1, 5]
  double obstacle_z_max = 1.90;   ///< m, upper edge of the obstacle band (map z), [-1, 10]
  double floor_z_max = 0.04;      ///< m, points with |z| <= this are floor: free evidence, [0, 0.5]
  int min_points_per_cell = 2;    ///< obstacle points of one batch needed to mark a cell, [1, 1000]
  double log_odds_hit = 0.85;     ///< added to a cell with an obstacle return, (0, 10]
  double log_odds_miss = -0.4;    ///< added to a cell a beam passed through, [-10, 0)
  double log_odds_min = -2.0;     ///< clamp (keeps the map able to change), [-20, 0)
  double log_odds_max = 3.5;      ///< clamp, (0, 20]
  double occupied_thresh = 0.65;  ///< probability above which a cell is occupied, (0.5, 1)
  double free_thresh = 0.196;     ///< probability below which a cell is free, (0, 0.5)
  double cloud_log_odds_hit = 2.0;     ///< InsertPoints: added to a cell with band points, (0, 20]
  double cloud_log_odds_floor = -2.0;  ///< InsertPoints: added to a floor-only cell, [-20, 0)
  bool clear_on_no_return = false;     ///< LRF: trace free space along no-return beams
  /// LRF beams may clear cells with 3D band evidence. Default false: a planar beam at one
  /// height passes under a desk top or over a low cabinet the cloud saw; it proves nothing
  /// about the rest of the band the body occupies.
  bool lrf_clears_cloud_obstacles = false;
  /// InsertRays: a TLS beam clears the cells its plan projection crosses while it runs at most
  /// this high (m, map z): a cell it crosses that low holds nothing taller there, and no
  /// obstacle below it (other than an occluded one lower than this) was missed, [0, 5]
  double ray_clear_z_max = 0.4;
  double ray_bin_deg = 0.1;  ///< InsertRays: azimuth bins whose beams share a direction, [0.001, 5]

  template <class V>
  void Visit(V& v) {
    v("resolution", resolution, Bounds{0.005, 1.0});
    v("obstacle_z_min", obstacle_z_min, Bounds{-1.0, 5.0});
    v("obstacle_z_max", obstacle_z_max, Bounds{-1.0, 10.0});
    v("floor_z_max", floor_z_max, Bounds{0.0, 0.5});
    v("min_points_per_cell", min_points_per_cell, Bounds{1, 1000});
    v("log_odds_hit", log_odds_hit, Bounds{1e-6, 10.0});
    v("log_odds_miss", log_odds_miss, Bounds{-10.0, -1e-6});
    v("log_odds_min", log_odds_min, Bounds{-20.0, -1e-6});
    v("log_odds_max", log_odds_max, Bounds{1e-6, 20.0});
    v("occupied_thresh", occupied_thresh, Bounds{0.5 + 1e-6, 1.0 - 1e-6});
    v("free_thresh", free_thresh, Bounds{1e-6, 0.5 - 1e-6});
    v("cloud_log_odds_hit", cloud_log_odds_hit, Bounds{1e-6, 20.0});
    v("cloud_log_odds_floor", cloud_log_odds_floor, Bounds{-20.0, -1e-6});
    v("clear_on_no_return", clear_on_no_return);
    v("lrf_clears_cloud_obstacles", lrf_clears_cloud_obstacles);
    v("ray_clear_z_max", ray_clear_z_max, Bounds{0.0, 5.0});
    v("ray_bin_deg", ray_bin_deg, Bounds{0.001, 5.0});
  }
  /// ValidateParams plus cross-field checks (band order); throws InputError.
  void Validate() const;
};

/// Integer cell index; (0, 0) is the cell at the origin (lower-left).
struct Cell {
  int i = 0;  ///< column, along +x
  int j = 0;  ///< row, along +y
  bool operator==(const Cell&) const = default;
};

/// One batch of 3D points (a registered TLS scan) as occupancy evidence, computed once in
/// global cells of `resolution` (cell (i, j) covers [i, i + 1) x [j, j + 1) times the
/// resolution, map frame): what InsertPoints and InsertRays would add to any grid of that
/// resolution whose origin is a multiple of it, so a map rebuilt from many scans does not go
/// back to their points. OccupancyGrid::Evidence makes it; InsertPoints/InsertRays apply it.
struct CloudEvidence {
  double resolution = 0.0;  ///< m
  struct PointCell {
    int i = 0, j = 0;                      ///< global cell
    std::uint32_t band = 0, floor = 0;     ///< band and floor points in the cell
    float dx = 0, dy = 0;                  ///< sums of band point offsets from the centre, m
    float xx = 0, xy = 0, yy = 0;          ///< sums of their products, m^2
    /// The lowest and the highest band point (map frame, m): two of the surfaces it saw.
    float lo[3] = {0, 0, 0}, hi[3] = {0, 0, 0};
    /// Its band points were seen through by another scan (perception/range_image.h): gone
    /// when that scan looked, so no evidence of an obstacle (set by the map's owner).
    bool transient = false;
  };
  std::vector<PointCell> cells;                  ///< cells with band or floor points
  std::vector<std::pair<int, int>> crossed;      ///< cells the beams clear (no repeats)
  Vec2 lo = Vec2::Constant(std::numeric_limits<double>::infinity());   ///< x-y extent of the
  Vec2 hi = Vec2::Constant(-std::numeric_limits<double>::infinity());  ///< finite points, m
  bool empty() const { return cells.empty() && crossed.empty(); }
};

/// Points are line-like when the smaller principal variance of their spread is at most this
/// share of the larger (a cell's returns; an LRF sweep's neighbourhood in AMCL's refinement).
inline constexpr double kLineLikeRatio = 0.1;

class OccupancyGrid {
 public:
  /// An all-unknown grid of width x height cells whose lower-left corner is `origin` (map, m).
  OccupancyGrid(const OccupancyGridParams& params, const Vec2& origin, int width, int height);
  /// A grid covering the x-y extent of `points_M` plus `margin` (m) on every side.
  static OccupancyGrid Covering(const OccupancyGridParams& params,
                                const std::vector<Eigen::Vector3d>& points_M, double margin);
  /// A grid covering the box [lo, hi] (map, m) plus `margin` on every side; its origin is a
  /// multiple of the resolution. InputError for a non-finite or empty box.
  static OccupancyGrid Covering(const OccupancyGridParams& params, const Vec2& lo, const Vec2& hi,
                                double margin);
  /// The evidence of one batch of points (map frame) as InsertPoints (band and floor points)
  /// and, when `origin_M` is given, InsertRays (beams from that scanner centre) use it.
  static CloudEvidence Evidence(const OccupancyGridParams& params,
                                const std::vector<Eigen::Vector3d>& points_M,
                                const Eigen::Vector3d* origin_M = nullptr);
  OccupancyGrid(const OccupancyGrid&) = default;
  OccupancyGrid& operator=(const OccupancyGrid&) = default;
  OccupancyGrid(OccupancyGrid&&) noexcept = default;
  OccupancyGrid& operator=(OccupancyGrid&&) noexcept = default;

  // Geometry.
  const OccupancyGridParams& Params() const { return params_; }
  double Resolution() const { return params_.resolution; }
  const Vec2& Origin() const { return origin_; }
  int Width() const { return width_; }
  int Height() const { return height_; }
  bool Contains(const Cell& c) const {
    return c.i >= 0 && c.j >= 0 && c.i < width_ && c.j < height_;
  }
  Cell CellOf(const Vec2& p_M) const;
  Vec2 CentreOf(const Cell& c) const;
  std::size_t Index(const Cell& c) const {
    return static_cast<std::size_t>(c.j) * static_cast<std::size_t>(width_) +
           static_cast<std::size_t>(c.i);
  }

  // Updates.
  /// Adds a batch of 3D points (map frame, m), e.g. one registered TLS scan: a cell with at
  /// least `min_points_per_cell` points in the obstacle band gains `cloud_log_odds_hit` once
  /// (after discarding free evidence it had: band beats floor, in any batch order); a cell with
  /// floor points and no band points gains `cloud_log_odds_floor` once, unless an earlier batch
  /// marked it with band points. Points outside the grid are ignored.
  void InsertPoints(const std::vector<Eigen::Vector3d>& points_M);
  /// InsertPoints of the batch `e` was made from (its resolution must be the grid's and the
  /// origin a multiple of it: grids from Covering; InputError otherwise).
  void InsertPoints(const CloudEvidence& e);
  /// Free space from the beams of one registered TLS scan taken from `origin_M` (scanner
  /// centre, map frame): each return at most `obstacle_z_max` high clears (`cloud_log_odds_floor`,
  /// once per cell) the cells its plan projection crosses while the beam is below
  /// `ray_clear_z_max`, up to a cell short of the return. Beams are grouped in azimuth bins of
  /// `ray_bin_deg` and their cleared intervals merged, so the cost is per bin, not per point.
  /// A cell where any TLS band point fell (InsertPoints, call those first) is never cleared.
  /// This fills the far floor, where floor returns are too sparse to mark every cell.
  void InsertRays(const Eigen::Vector3d& origin_M, const std::vector<Eigen::Vector3d>& points_M);
  /// InsertRays of the batch and origin `e` was made from (conditions as InsertPoints).
  void InsertRays(const CloudEvidence& e);
  /// Ray-traces one LRF scan taken with the base at `X_MB` (map frame): cells along each beam
  /// become freer, the end cell of each return more occupied. Beams outside the grid are clipped;
  /// returns beyond `max_range` (m) only clear up to it.
  void InsertScan(const interfaces::LrfScan& scan, const Pose2& X_MB,
                  double max_range = std::numeric_limits<double>::infinity());
  /// This grid's cells within the box [lo, hi] (map, m) become `base` with `evidence` laid over
  /// it: log-odds clamp(base + e), where e is the evidence grid's log-odds at the same place
  /// (LRF sweeps gathered apart, e.g. while driving), raised to at least 0 on cells the base's
  /// 3D band points marked unless lrf_clears_cloud_obstacles (an LRF beam does not clear what the
  /// cloud saw); their returns add up. `base` has this grid's geometry; `evidence` the same
  /// resolution and an origin on the same lattice (InputError otherwise); cells outside it
  /// take the base's values.
  void Compose(const OccupancyGrid& base, const OccupancyGrid& evidence, const Vec2& lo,
               const Vec2& hi);
  /// A grid with this one's parameters covering [lo, hi] (as Covering, no margin) holding this
  /// grid's cells where the two overlap (others unknown, without returns).
  OccupancyGrid Resized(const Vec2& lo, const Vec2& hi) const;
  /// Sets a cell's state directly (maps drawn in code, closing a door in a test).
  void SetState(const Cell& c, CellState state);
  /// Marks every cell whose centre lies in the axis-aligned box [lo, hi] (map, m).
  void FillBox(const Vec2& lo, const Vec2& hi, CellState state);

  // Queries.
  CellState State(const Cell& c) const;  ///< kUnknown outside the grid
  CellState StateAt(const Vec2& p_M) const { return State(CellOf(p_M)); }
  bool IsFree(const Vec2& p_M) const { return StateAt(p_M) == CellState::kFree; }
  bool IsOccupied(const Vec2& p_M) const { return StateAt(p_M) == CellState::kOccupied; }
  /// Mean position (map, m) of the obstacle returns that fell into the cell (band points and
  /// LRF hits), or its centre if none did (e.g. maps read from PNG). Sub-cell obstacle
  /// positions keep the likelihood field free of the half-cell bias a 5 cm grid would add.
  Vec2 ObstaclePosition(const Cell& c) const;
  /// The returns of a cell as a short segment: centre (map, m), unit direction and half
  /// length (m). When the returns are not line-like (fewer than 3, or the smaller principal
  /// variance above kLineLikeRatio times the larger) the half length is 0: a point.
  struct ReturnSegment {
    Vec2 centre = Vec2::Zero();
    Vec2 direction = Vec2::UnitX();
    double half_length = 0.0;
  };
  ReturnSegment ObstacleSegment(const Cell& c) const;
  const std::vector<float>& LogOddsData() const { return log_odds_; }
  /// A copy in which every cell within `radius` (m) of an occupied cell (and of an unknown
  /// one if `unknown_is_obstacle`) is occupied: the map inflated by the footprint.
  OccupancyGrid Inflated(double radius, bool unknown_is_obstacle) const;
  /// A copy at `factor` times finer cells (same origin and extent) whose obstacles sit where
  /// the returns do: a free or unknown cell's sub-cells keep its state; an occupied cell's
  /// sub-cells are free except those its returns cover (the ObstacleSegment of line-like
  /// returns, sampled every half sub-cell; else the sub-cells within sqrt(3) standard
  /// deviations of their mean), and all occupied when it holds no returns (a map
  /// read from PNG). The inside of a solid behind its returns reads free, which no disc of a
  /// robot's radius can reach. A 5 cm cell puts an obstacle's surface up to 5 cm in front of where it
  /// is; at 1.7 cm with sub-cell returns, a passage reads within about 2.5 cm of its width.
  /// factor in [1, 8]; InputError otherwise.
  OccupancyGrid Refined(int factor) const;
  /// Counts of cells per state (for summaries and tests).
  int Count(CellState state) const;

 private:
  void Add(const Cell& c, double delta);
  void AddReturn(const Cell& c, const Vec2& p);
  /// Cell index q of this grid takes everything cell index k of `from` holds.
  void CopyCell(const OccupancyGrid& from, std::size_t k, std::size_t q);
  /// Global cell of this grid's cell (0, 0) for evidence of `resolution`; InputError when the
  /// resolution differs or the origin is off its lattice.
  Cell LatticeOffset(double resolution, const Vec2& origin, const char* what) const;
  OccupancyGridParams params_;
  Vec2 origin_;
  int width_ = 0, height_ = 0;
  float l_occ_ = 0.0f, l_free_ = 0.0f;  // log-odds thresholds
  bool on_lattice_ = false;  // origin is a multiple of the resolution
  Cell lattice_;             // then: the global cell (floor(x / resolution), ...) of cell (0, 0)
  std::vector<float> log_odds_;
  std::vector<float> return_dx_, return_dy_;  // sums of return offsets from the cell centre, m
  std::vector<float> return_xx_, return_xy_, return_yy_;  // sums of their products, m^2
  std::vector<std::uint32_t> return_n_;
  std::vector<std::uint8_t>
      cloud_obstacle_;  // bit 0: marked by 3D band points; bit 1: any band point
};

/// Clearance of every cell: distance (m) from its centre to the boundary of the nearest
/// obstacle cell, i.e. the centre-to-centre Euclidean distance minus half a cell (exact
/// Euclidean distance transform, OpenCV DIST_MASK_PRECISE). 0 on obstacle cells and outside
/// the grid; capped at `max_distance`.
class DistanceField {
 public:
  /// Obstacles are occupied cells, plus unknown cells if `unknown_is_obstacle`.
  DistanceField(const OccupancyGrid& grid, bool unknown_is_obstacle, double max_distance = 1e9);
  DistanceField(const DistanceField&) = default;
  DistanceField& operator=(const DistanceField&) = default;
  DistanceField(DistanceField&&) noexcept = default;
  DistanceField& operator=(DistanceField&&) noexcept = default;

  /// Clearance of the cell containing `p_M` (m); 0 outside.
  double Clearance(const Vec2& p_M) const;
  /// Bilinear interpolation between cell centres of the centre-to-centre distance (m; not
  /// reduced by half a cell). `outside` is returned beyond the grid.
  double CentreDistance(const Vec2& p_M, double outside) const;
  /// Distance (m) from `p_M` to the returns of the obstacle cell nearest to p's cell (the
  /// segment of OccupancyGrid::ObstacleSegment: a wall's returns give a short line, so the
  /// distance is perpendicular to the wall), capped at `max_distance` — the field AMCL's
  /// likelihood model uses. `outside` is returned beyond the grid.
  double ObstacleDistance(const Vec2& p_M, double outside) const;
  /// The return nearest to `p_M` as ObstacleDistance finds it: `distance` (m, capped as
  /// there), and `normal`, the unit vector from the nearest point of that segment to p (the
  /// segment's normal when p lies on it): moving p by d changes the distance by about
  /// normal . d. `found` is false beyond the grid or with no obstacle within the cap.
  struct Nearest {
    bool found = false;
    double distance = 0.0;
    Vec2 normal = Vec2::Zero();  ///< unit, from the nearest return towards the query point
    /// Unit normal of the mapped surface at that return (sign arbitrary) where its cell's
    /// returns are line-like; zero where they are a point (no orientation known).
    Vec2 surface_normal = Vec2::Zero();
  };
  Nearest NearestReturn(const Vec2& p_M) const;
  /// True if the cell is known free (not an obstacle) and its clearance is >= `radius`.
  bool IsFree(const Vec2& p_M, double radius) const;
  double ClearanceOfCell(const Cell& c) const;  ///< m; 0 outside or on obstacles
  const Vec2& Origin() const { return origin_; }
  double Resolution() const { return resolution_; }
  int Width() const { return width_; }
  int Height() const { return height_; }
  Cell CellOf(const Vec2& p_M) const;

 private:
  Vec2 origin_;
  double resolution_ = 0.0;
  int width_ = 0, height_ = 0;
  double max_distance_ = 0.0;
  std::vector<float> centre_distance_;  // m, centre to nearest obstacle centre
  std::vector<std::uint32_t> nearest_;  // per cell: index into segments_ (UINT32_MAX = none)
  std::vector<OccupancyGrid::ReturnSegment> segments_;
  std::vector<std::uint8_t> free_;  // known free (for IsFree)
};

/// Writes `yaml_path` and the PNG beside it (same stem), ROS map_server "trinary" convention:
/// free 254, occupied 0, unknown 205, top image row = highest y, origin [x, y, 0], negate 0.
/// Throws InputError if a file cannot be written.
void WriteMap(const OccupancyGrid& grid, const std::string& yaml_path);
/// Reads a map_server YAML + image (path relative to the YAML). Pixels are classified with the
/// file's occupied/free thresholds and `negate`; cells get log-odds at the clamps (or 0).
/// `params` supplies everything the file does not (the file's resolution wins). Throws
/// InputError with file:line for malformed files, a non-zero yaw, or an unsupported mode.
OccupancyGrid ReadMap(const std::string& yaml_path, const OccupancyGridParams& params = {});

}  // namespace mopad::perception
