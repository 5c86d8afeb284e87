#pragma once
// SM4 (paper §3.3, Figure 9; method of its ref. [62]): doors and windows in each SM3 wall, and
// each door's opening angle lambda and state, from the wall's orthoimage J_CD
// (modelling/orthoimage.h) and the room's points.
//
// Per wall:
//  1. Wall area: the wall colour is the densest cluster of coherent colour seeds (a 8x8x8 RGB
//     histogram of the pixels on the plane, |depth| <= flush_depth; the mode bin and its
//     neighbours); every pixel is then classified as
//       wall       on the plane and of the wall colour,
//       off_colour on the plane, another colour (a flush door leaf, a casing, a picture),
//       recessed   depth < -recess_depth (a leaf or glass set into the wall, the far side),
//       protruding depth > flush_depth (furniture, an opened leaf: unknown for openings),
//       through    no point, but rays passed the plane here or returned nothing beyond it
//                  (an open door, a window),
//       occluded   no point, rays stopped in front (a cabinet), or unseen (nothing).
//     Evidence of an opening: off_colour, recessed, through (windows: recessed, through).
//  2. Straight lines: Canny edges of J_C (grey), of J_D (depth quantised to depth_step) and
//     of the evidence mask, OR-ed; because u is horizontal and v vertical, an opening's sides
//     are columns and rows of the image, so lines are runs of edge pixels along columns
//     (vertical) and rows (horizontal), gaps up to line_gap, at least min_line long, merged
//     when parallel and within 2 pixels.
//  3. Rectangles from two vertical lines and a top line, the bottom either the floor (v = 0)
//     or a horizontal line; kept when their size is a typical door's (bottom at the floor) or
//     window's (a sill at least min_sill above the floor). Each is validated by its interior
//     (enough of it known, most of the known part evidence, at most max_interior_lines
//     horizontal lines across it: a shelf is not a door), its frame (the share of each
//     side's visible, i.e. not occluded, length that has edge pixels: a partly occluded frame
//     still counts), and its location (a window's sill has wall below it; a door reaches the
//     floor). Overlapping accepted rectangles keep the best score; a kept rectangle becomes the
//     valid one inside it whose every side is the same line or inset over a strip that is a
//     casing (casing_min..casing_max wide, on the wall's surface) or hidden (an occlusion
//     boundary is no frame): the hole, not the casing. After step 4, one opening per hole:
//     door rectangles that overlap or nearly touch (door_merge_gap) and together are no wider
//     than a door (an opened leaf splits a doorway into a part seen through and a part behind
//     the leaf) become their union, and its door step runs again; so do two window
//     rectangles that share columns over most of their rows (a window's casements either side
//     of its mullion); other overlapping openings keep the more confident.
//  4. Doors: the leaf is a vertical plane through a jamb; its plan line (u, depth) is fitted to
//     the points in front of and behind the opening (either side of the wall) by a seeded
//     RANSAC and least squares (the fitted line, not only the hypotheses, passes a jamb), the
//     leaf being the most populated gap-free run of inliers.
//     Each jamb's reveal (the hole's side, a plan line perpendicular to the wall from its face
//     into the wall) is left out first: a leaf opened near 90 deg lies a leaf's thickness
//     beside it and a line through both would lean towards the wall by several degrees;
//     lambda is its angle to the wall (over 90 deg when the free end swings past the hinge
//     jamb). The hole's top is the lintel's underside where it was seen: a horizontal face
//     inside the wall's slab, seen from below through the hole (the densest 5 mm height bin
//     of the slab's points in the hole's middle, within lintel_search of the rectangle's top,
//     lintel_min_points and lintel_peak_ratio times its window's mean bin); the images put
//     the top at a casing's outer edge or a leaf's top edge by up to 12 cm.
//     A door narrower than its leaf by more than leaf_widen_margin widens to the leaf's
//     width from the hinge (its latch jamb hidden behind the opened leaf). A door side beside
//     hidden pixels (an occlusion boundary: the part of the doorway behind an opened leaf) is no
//     jamb: the door with that side moved out to the nearest vertical line where the wall
//     resumes (hole-like strip crossed, within door_max_width) replaces it when a leaf hinged at
//     the moved side is found there (the occluder is the door's own leaf). State: open lambda >= 90
//     deg, semi_open 5 <= lambda < 90, closed lambda < 5 (paper §3.3), with open from 90 -
//     open_tolerance_deg (measurement). No leaf found: open (angle unknown) if open_through_share
//     of its seen (known) interior is seen through, else closed: a closed leaf shows as a surface
//     across the hole wherever the hole is seen, while the parts of an open doorway that are not
//     seen through are mostly unseen (rays at a slant end on the far reveal). Clear width = width
//     - (width cos lambda + leaf_thickness sin lambda), 0 when closed.
//
// Robot side only (no truth). Deterministic (ordered loops, CounterRng(seed, "sm4_leaf", k) keyed
// by each wall's own rectangles); DetectOpenings runs the walls in parallel (TBB) and gathers
// them in wall order, so the result does not depend on the number of threads.

#include <array>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "common/door_state.h"
#include "common/frames.h"
#include "common/params.h"
#include "modelling/orthoimage.h"
#include "modelling/structural_model.h"
#include "modelling/voxel_space.h"

namespace mopad::modelling {

struct OpeningParams {
  OrthoimageParams orthoimage;     ///< J_CD of every wall
  double flush_depth = 0.05;       ///< m, |depth| on the wall's surface layer, [0.005, 0.2]
  double recess_depth = 0.025;     ///< m, depth below which a pixel is recessed, [0.005, 0.5]
  double colour_tolerance = 45.0;  ///< RGB distance (0-255 units) from the wall colour, [1, 255]
  /// m, a seen-through pixel counts for a door when a ray that returned from beyond the plane
  /// passed within this square around it (rays without a return alone: windows only), [0, 2]
  double through_window = 0.15;
  double depth_step = 0.01;          ///< m per grey level of the depth edge image, [0.001, 0.1]
  double canny_low = 30.0;           ///< Canny hysteresis thresholds (grey levels), [1, 1000]
  double canny_high = 60.0;          ///< [1, 1000]
  double min_line = 0.25;            ///< m, shortest straight line kept, [0.02, 5]
  double line_gap = 0.04;            ///< m, gaps bridged inside a line, [0, 0.5]
  int max_lines = 60;                ///< longest lines kept per direction, [2, 1000]
  double door_min_width = 0.55;      ///< m, [0.1, 5]
  double door_max_width = 2.2;       ///< m, [0.1, 5]
  double door_min_height = 1.7;      ///< m, [0.5, 5]
  double door_max_height = 2.7;      ///< m, [0.5, 5]
  /// m, a door's head lies at least this far below the wall's top edge (the ceiling): a
  /// rectangle up to that edge has no lintel, and the edge runs along every wall (in a
  /// corridor under 2.55 m, beside a scanner's minimum-range disc, such rectangles were false
  /// doors). Doors measured: heads 0.12-0.65 m under the ceiling. [0, 1]
  double door_head_clearance = 0.05;
  double floor_tolerance = 0.06;     ///< m, a door's bottom is this close to the floor, [0, 0.5]
  double window_min_width = 0.3;     ///< m, [0.05, 10]
  double window_max_width = 4.0;     ///< m, [0.05, 10]
  double window_min_height = 0.3;    ///< m, [0.05, 5]
  double window_max_height = 2.5;    ///< m, [0.05, 5]
  double min_sill = 0.15;            ///< m, lowest window sill above the floor, [0, 3]
  double min_known_share = 0.12;     ///< interior share not occluded/unseen/protruding, [0, 1]
  double min_evidence_share = 0.75;  ///< evidence share of the known interior, [0, 1]
  double min_evidence_area = 0.08;   ///< m^2, least evidence area of an opening, [0, 10]
  double min_side_support = 0.5;     ///< edge share of each side's visible length, [0, 1]
  double side_band = 0.02;           ///< m, edge pixels this close to a side support it, [0, 0.2]
  double min_sill_wall_share = 0.5;  ///< wall share of the band under a window's sill, [0, 1]
  double ring = 0.04;             ///< m, width of the bands checked around a rectangle, [0.01, 0.5]
  double casing_min = 0.04;       ///< m, smallest casing width between hole and outline, [0, 0.5]
  double casing_max = 0.15;       ///< m, largest casing width, [0, 0.5]
  double min_casing_share = 0.8;  ///< share of a casing strip on the wall's surface, [0, 1]
  double max_overlap = 0.2;       ///< overlap (of the smaller) above which the worse goes, [0, 1]
  /// m, two door rectangles on one wall that overlap or lie closer than this, and together are
  /// no wider than door_max_width, are one hole (distinct doors are kept apart by their
  /// casings and a strip of wall), [0, 0.5]
  double door_merge_gap = 0.04;
  // Door leaf.
  double leaf_inlier = 0.015;       ///< m, plan distance of a leaf point to its line, [0.001, 0.2]
  double leaf_v_low = 0.25;         ///< share of the door height where leaf points start, [0, 1]
  double leaf_v_high = 0.85;        ///< share of the door height where they end, [0, 1]
  double leaf_u_margin = 0.4;       ///< share of the width searched beyond each jamb, [0, 2]
  double max_wall_thickness = 0.5;  ///< m, deepest hinge behind the wall face, [0.05, 2]
  double leaf_hinge_front = 0.05;   ///< m, farthest hinge in front of the wall face, [0, 0.5]
  double leaf_jamb_reach = 0.1;     ///< m, a leaf's line passes this close to a jamb, [0, 1]
  double leaf_run_gap = 0.10;       ///< m, gap that ends the leaf's run of points, [0.01, 1]
  /// m, a jamb's reveal (the hole's side through the wall) is sought this far from the
  /// rectangle's side (an opened leaf may hide the jamb's edge in the images), [0, 0.5]
  double reveal_search = 0.25;
  double reveal_band = 0.012;  ///< m, half width of a reveal's plan line, [0.001, 0.1]
  /// m, a door's lintel (the hole's top through the wall) is sought this far above and below
  /// the rectangle's top (a casing of the wall's colour, or an opened leaf's top edge, may
  /// have moved it in the images), [0, 0.5]
  double lintel_search = 0.15;
  int lintel_min_points = 15;  ///< points a lintel's 5 mm height bin needs, [1, 1e6]
  /// The lintel's bin holds at least this many times the mean bin of its search window, [1, 100]
  double lintel_peak_ratio = 4.0;
  /// Share of a door's seen interior seen through that makes it open when no leaf is found,
  /// [0, 1]
  double open_through_share = 0.3;
  int median_kernel = 5;  ///< px, odd, median before the edges (1 = none), [1, 15]
  /// m, a pixel without points, passed or blocked rays takes the mean of its seen neighbours
  /// up to this far (sampling gaps), before the edges, [0, 0.2]
  double gap_fill = 0.03;
  double leaf_min_extent = 0.3;  ///< share of the width the leaf's points must span, [0, 1]
  /// The same share when the run starts within leaf_jamb_reach of a jamb (its hinge), [0, 1]
  double leaf_min_extent_hinged = 0.15;
  int leaf_min_points = 40;      ///< inliers a leaf needs, [3, 1e7]
  int leaf_iterations = 400;     ///< RANSAC hypotheses, [1, 1e6]
  int leaf_max_points = 4000;    ///< points sampled for the fit (even stride), [10, 1e8]
  double leaf_thickness = 0.04;  ///< m, assumed for the clear width, [0, 0.2]
  /// m, a door narrower than its leaf's points span by more than this widens to the leaf's
  /// width (its latch jamb hidden behind the opened leaf), [0, 1]
  double leaf_widen_margin = 0.15;
  double closed_below_deg = 5.0;  ///< deg, paper's epsilon, [0, 45]
  /// deg, a leaf measured this close below 90 deg is open (a leaf at 90 deg measures 90 +- 1),
  /// [0, 10]
  double open_tolerance_deg = 2.0;
  /// Horizontal lines across at least half an opening's width allowed strictly inside it (a
  /// transom, an occluder's top edge); shelves and cabinets have more, [0, 100]
  int max_interior_lines = 3;
  /// m, farthest in front of the wall a point stands on a door's front
  /// (StandsInFrontOfTheWall), [0.1, 3]
  double front_depth = 0.6;
  /// Share of a door's width with an object standing in front of it (StandsInFrontOfTheWall)
  /// from which, the object ending at the door's sides, the door is that object, [0, 1]
  double front_min_share = 0.8;
  std::uint64_t seed = 1;  ///< leaf RANSAC stream

  template <class V>
  void Visit(V& v) {
    v("orthoimage", orthoimage);
    v("flush_depth", flush_depth, Bounds{0.005, 0.2});
    v("recess_depth", recess_depth, Bounds{0.005, 0.5});
    v("colour_tolerance", colour_tolerance, Bounds{1.0, 255.0});
    v("through_window", through_window, Bounds{0.0, 2.0});
    v("depth_step", depth_step, Bounds{0.001, 0.1});
    v("canny_low", canny_low, Bounds{1.0, 1000.0});
    v("canny_high", canny_high, Bounds{1.0, 1000.0});
    v("min_line", min_line, Bounds{0.02, 5.0});
    v("line_gap", line_gap, Bounds{0.0, 0.5});
    v("max_lines", max_lines, Bounds{2, 1000});
    v("door_min_width", door_min_width, Bounds{0.1, 5.0});
    v("door_max_width", door_max_width, Bounds{0.1, 5.0});
    v("door_min_height", door_min_height, Bounds{0.5, 5.0});
    v("door_max_height", door_max_height, Bounds{0.5, 5.0});
    v("door_head_clearance", door_head_clearance, Bounds{0.0, 1.0});
    v("floor_tolerance", floor_tolerance, Bounds{0.0, 0.5});
    v("window_min_width", window_min_width, Bounds{0.05, 10.0});
    v("window_max_width", window_max_width, Bounds{0.05, 10.0});
    v("window_min_height", window_min_height, Bounds{0.05, 5.0});
    v("window_max_height", window_max_height, Bounds{0.05, 5.0});
    v("min_sill", min_sill, Bounds{0.0, 3.0});
    v("min_known_share", min_known_share, Bounds{0.0, 1.0});
    v("min_evidence_share", min_evidence_share, Bounds{0.0, 1.0});
    v("min_evidence_area", min_evidence_area, Bounds{0.0, 10.0});
    v("min_side_support", min_side_support, Bounds{0.0, 1.0});
    v("side_band", side_band, Bounds{0.0, 0.2});
    v("min_sill_wall_share", min_sill_wall_share, Bounds{0.0, 1.0});
    v("ring", ring, Bounds{0.01, 0.5});
    v("casing_min", casing_min, Bounds{0.0, 0.5});
    v("casing_max", casing_max, Bounds{0.0, 0.5});
    v("min_casing_share", min_casing_share, Bounds{0.0, 1.0});
    v("max_overlap", max_overlap, Bounds{0.0, 1.0});
    v("door_merge_gap", door_merge_gap, Bounds{0.0, 0.5});
    v("leaf_inlier", leaf_inlier, Bounds{0.001, 0.2});
    v("leaf_v_low", leaf_v_low, Bounds{0.0, 1.0});
    v("leaf_v_high", leaf_v_high, Bounds{0.0, 1.0});
    v("leaf_u_margin", leaf_u_margin, Bounds{0.0, 2.0});
    v("max_wall_thickness", max_wall_thickness, Bounds{0.05, 2.0});
    v("leaf_hinge_front", leaf_hinge_front, Bounds{0.0, 0.5});
    v("leaf_jamb_reach", leaf_jamb_reach, Bounds{0.0, 1.0});
    v("leaf_run_gap", leaf_run_gap, Bounds{0.01, 1.0});
    v("reveal_search", reveal_search, Bounds{0.0, 0.5});
    v("reveal_band", reveal_band, Bounds{0.001, 0.1});
    v("lintel_search", lintel_search, Bounds{0.0, 0.5});
    v("lintel_min_points", lintel_min_points, Bounds{1, 1000000});
    v("lintel_peak_ratio", lintel_peak_ratio, Bounds{1.0, 100.0});
    v("open_through_share", open_through_share, Bounds{0.0, 1.0});
    v("median_kernel", median_kernel, Bounds{1, 15});
    v("gap_fill", gap_fill, Bounds{0.0, 0.2});
    v("leaf_min_extent", leaf_min_extent, Bounds{0.0, 1.0});
    v("leaf_min_extent_hinged", leaf_min_extent_hinged, Bounds{0.0, 1.0});
    v("leaf_min_points", leaf_min_points, Bounds{3, 10000000});
    v("leaf_iterations", leaf_iterations, Bounds{1, 1000000});
    v("leaf_max_points", leaf_max_points, Bounds{10, 100000000});
    v("leaf_thickness", leaf_thickness, Bounds{0.0, 0.2});
    v("leaf_widen_margin", leaf_widen_margin, Bounds{0.0, 1.0});
    v("closed_below_deg", closed_below_deg, Bounds{0.0, 45.0});
    v("open_tolerance_deg", open_tolerance_deg, Bounds{0.0, 10.0});
    v("max_interior_lines", max_interior_lines, Bounds{0, 100});
    v("front_depth", front_depth, Bounds{0.1, 3.0});
    v("front_min_share", front_min_share, Bounds{0.0, 1.0});
    v("seed", seed);
  }
  void Validate() const;
};

enum class OpeningType : std::uint8_t { kDoor = 0, kWindow = 1 };
using DoorState = mopad::DoorState;  // common/door_state.h
const char* ToString(OpeningType t);
using mopad::ToString;
/// The paper's thresholds: open >= 90 deg - open_tolerance_deg, semi_open >= closed_below_deg,
/// else closed.
DoorState DoorStateFromAngleDeg(double lambda_deg, double closed_below_deg = 5.0,
                                double open_tolerance_deg = 0.0);

/// One recognised opening (SM4). Rectangle in the host wall's PatchFrame (u, v) and, the same,
/// as map-frame corners on the wall plane, counter-clockwise seen from the room, starting at
/// (u0, v0): (u0,v0) (u1,v0) (u1,v1) (u0,v1).
struct DetectedOpening {
  std::string id;  ///< "opening_1", ... (numbered per room in wall order, then u)
  OpeningType type = OpeningType::kDoor;
  std::string host;                       ///< SM3 patch id, e.g. "wall_3"
  double u0 = 0, u1 = 0, v0 = 0, v1 = 0;  ///< m, host frame: the hole, not the casing
  std::array<Vec3, 4> corners{};          ///< map frame, on the wall plane
  // Doors only:
  DoorState state = DoorState::kClosed;
  double opening_angle_deg = std::numeric_limits<double>::quiet_NaN();  ///< lambda; NaN unknown
  double clear_width_m = 0.0;                                           ///< m, passable width
  double confidence = 0.0;  ///< [0, 1], the validation score
  /// A door seen from two rooms (floor model, ShareDoorStates): the room whose reading of it
  /// is better observed when that is not this room's own; state, opening_angle_deg and
  /// clear_width_m are then that room's, and own_* keep this room's. Empty: this room's own.
  std::string state_from;
  DoorState own_state = DoorState::kClosed;
  double own_opening_angle_deg = std::numeric_limits<double>::quiet_NaN();  ///< deg; NaN unknown
  double own_clear_width_m = 0.0;                                           ///< m
  /// A door this room did not find, on its face of a wall whose other face's room found it
  /// (floor model, ShareDoors): that room's name. Empty: found in this room's own data.
  std::string found_from;
  /// A door this room's images did not show whose hole another room found on the other face
  /// of the wall (DetectOpenings' neighbours) and whose leaf this room's points measured: that
  /// room's name; the state, angle and clear width are this room's. Empty otherwise.
  std::string hole_from;
  /// Doors: the share of the rays that crossed the hole rising (above their scanner's centre)
  /// and returned nothing. About 1 where nothing stands above the far side (the outside: the
  /// sky, or a storey standing in nothing), near 0 where a room's walls and ceiling return them;
  /// NaN where no ray rose through the hole. Not in sm4.json.
  double sky_share = std::numeric_limits<double>::quiet_NaN();
  // Diagnostics (not in sm4.json): shares of the interior.
  double known_share = 0.0, evidence_share = 0.0, through_share = 0.0, side_support = 0.0;
  int leaf_points = 0;  ///< inliers of the leaf fit (0: none)
  /// The leaf's plan line (u, depth) in the host frame where leaf_points > 0
  Vec2 leaf_line_point = Vec2::Zero(), leaf_line_dir = Vec2::UnitX();

  double Width() const { return u1 - u0; }
  double Height() const { return v1 - v0; }
};

/// SM4 of one room: SM3 plus its openings.
struct Sm4Model {
  std::string room;
  std::vector<DetectedOpening> openings;
};

/// Per-pixel classes of step 1 (see the file comment).
enum class OrthoClass : std::uint8_t {
  kWall = 0,
  kOffColour = 1,
  kRecessed = 2,
  kProtruding = 3,
  kThrough = 4,
  kOccluded = 5
};

/// Step 1 of one wall: the wall colour and the class of every pixel (Orthoimage::Index order).
struct WallArea {
  std::array<double, 3> wall_rgb{0, 0, 0};
  std::vector<OrthoClass> classes;
  /// 1 where a kThrough pixel's passed rays all returned nothing and no ray returned from
  /// beyond the plane within through_window of it: evidence of a window (glass, the outside)
  /// but not of a door, since a dark occluder in front of the wall (a black cabinet) returns
  /// nothing either; a door's far side is a room whose points come back.
  std::vector<std::uint8_t> through_no_return;
  double wall_share = 0.0;  ///< share of the image's pixels that are wall
};
WallArea SegmentWallArea(const Orthoimage& image, const OpeningParams& params);

/// A door hole another room found on the other face of a wall, in this wall's frame (m): its
/// sides u0 < u1 and its top v1 (DetectOpenings' neighbours).
struct HoleHint {
  std::string room;  ///< the room that found it
  double u0 = 0.0, u1 = 0.0, v1 = 0.0;
  double confidence = 0.0;  ///< that room's validation score
};

/// The openings of one wall from its orthoimage (steps 1-3) and its doors' leaves (step 4,
/// from `points`, which may be the same as the image's). `floor_v` is the floor's v in the
/// image's frame (0 for an SM3 wall). Each hint no door found here overlaps is a door of this
/// wall when a leaf opened out of the wall's plane is found in `points` (step 4 on the
/// hint's rectangle, lambda >= closed_below_deg; hole_from names the hint's room): a leaf opened
/// into this room can hide its own doorway's frame from it (the latch jamb and the top in its
/// shadow), while the leaf itself is in plain view. Ids are left empty (DetectOpenings numbers
/// them).
std::vector<DetectedOpening> DetectWallOpenings(const Orthoimage& image, const std::string& host,
                                                const OrthoPoints& points,
                                                const OpeningParams& params, double floor_v = 0.0,
                                                const std::vector<HoleHint>& hints = {});

/// One opening per hole (the last part of step 3, after step 4; DetectWallOpenings calls it):
/// door rectangles of one wall that overlap or lie closer than door_merge_gap and together are
/// no wider than door_max_width become their union, whose door step (leaf, reveals, state) runs
/// again on `points`; two window rectangles that share columns over at least half the rows of
/// the shorter one and together are no wider than window_max_width (the casements either side of
/// a mullion) become their union; any other pair overlapping by more than max_overlap of the
/// smaller keeps the more confident. All of `openings` on `image`'s wall (u, v in its frame).
/// Ordered by u0.
/// (Called here, a widened door's sides are not snapped to the image's lines.)
std::vector<DetectedOpening> OneOpeningPerHole(std::vector<DetectedOpening> openings,
                                               const Orthoimage& image, const OrthoPoints& points,
                                               const OpeningParams& params);

/// The doors of `others` (rooms other than `room`, same map frame) whose corners lie on the
/// plane of `frame`'s wall or up to max_wall_thickness behind it (the other face of the wall),
/// within its extent along u (flush_depth slack): hints in that wall's frame.
std::vector<HoleHint> HoleHints(const PatchFrame& frame, const std::string& room,
                                const std::vector<Sm4Model>& others, const OpeningParams& params);

/// The same hints for a room modelled before the rooms that found them (the floor model): each
/// hint on a wall of `sm3` that no door of `sm4` overlaps becomes a door of `sm4` (next free
/// id, hole_from set) when a leaf opened out of the wall's plane is found in `points` (step 4
/// only: no image; see DetectWallOpenings). Returns the doors added.
int AddDoorsFromNeighbours(const StructuralModel& sm3, Sm4Model& sm4, const OrthoPoints& points,
                           const std::vector<Sm4Model>& others, const OpeningParams& params);

/// SM4 of one room: every wall patch of `sm3` imaged (BuildOrthoimage) and searched. InputError
/// for bad params or point arrays. `images`, when not null, receives the walls' orthoimages
/// (same order as the wall patches) for writing (WriteOrthoimagePngs) or SM5. `neighbours`:
/// the SM4 of rooms modelled before (same map frame); their doors whose corners lie on a
/// wall's plane or up to max_wall_thickness behind it, within the wall's image, are that
/// wall's hints (DetectWallOpenings).
Sm4Model DetectOpenings(const StructuralModel& sm3, const OrthoPoints& points,
                        const OpeningParams& params,
                        std::vector<std::pair<std::string, Orthoimage>>* images = nullptr,
                        const std::vector<Sm4Model>& neighbours = {});

/// The leaf of a door in [u0, u1] x [v0, v1] of `frame` (step 4): lambda (deg, NaN when no
/// leaf is found) and the inlier count.
struct LeafFit {
  double lambda_deg = std::numeric_limits<double>::quiet_NaN();
  int inliers = 0;
  double extent = 0.0;  ///< m, span of the inliers along the fitted line
  /// m, u of the leaf's hinge: where its line meets the jamb it passes (the other jamb far
  /// from the line), else the end of its seen run nearer a jamb
  double hinge_u = 0.0;
  Vec2 line_point = Vec2::Zero(), line_dir = Vec2::UnitX();  ///< the fitted line in (u, depth)
  /// m, u of each jamb's reveal (the hole's side through the wall) where one was seen, NaN where
  /// not; set whether or not a leaf was found
  std::array<double, 2> reveal_u{std::numeric_limits<double>::quiet_NaN(),
                                 std::numeric_limits<double>::quiet_NaN()};
  /// m, v of the lintel's underside (the hole's top through the wall) where it was seen, NaN
  /// where not; set whether or not a leaf was found
  double lintel_v = std::numeric_limits<double>::quiet_NaN();
};
LeafFit FitDoorLeaf(const OrthoPoints& points, const PatchFrame& frame, double u0, double u1,
                    double v0, double v1, const OpeningParams& params, std::uint64_t index = 0);

/// True when the door rectangle `door` on the wall `frame` is the outline of an object standing
/// in front of the wall (a shelf, a cabinet), not a hole behind it: points of the upper half of
/// its leaf's v band stand in front of the wall (flush_depth < depth <= front_depth), the leaf's
/// own points left out, over front_min_share of its width, in one run whose ends lie within
/// casing_max of its sides. A leaf that swung open swept its doorway's front clear; a door seen
/// behind an object has its frame beside or above the object. DetectWallOpenings drops such
/// doors.
bool StandsInFrontOfTheWall(const DetectedOpening& door, const PatchFrame& frame,
                            const OrthoPoints& points, const OpeningParams& params);

/// DSM3 with SM4: flags VoxelSpace::kOpeningFace on every structural voxel
/// whose centre lies within `band` (m; <= 0: one voxel edge) of an opening's plane and inside
/// its rectangle shrunk by 3/8 of a voxel edge (every 4 x 4 surface sample of the voxel inside
/// the opening, the evaluator's truth DSM3 rule), so it reads as `opening`. Apply it to a copy of
/// RoomModel::Voxels() (RoomModel rebuilds its flags on every scan). Returns the voxels flagged.
int MarkOpeningVoxels(const std::vector<DetectedOpening>& openings, VoxelSpace& voxels,
                      double band = 0.0);

/// Indices-in-order mask (1 = drop) of the points that lie on a closed door or on its casing:
/// within `margin` (m) of the door's rectangle in its host wall's (u, v) and within `band` (m)
/// of the host plane. For the wall refit, so a closed door never moves its wall. Openings whose
/// host is not a patch of `patches` are ignored.
std::vector<std::uint8_t> ClosedDoorPointMask(const std::vector<Eigen::Vector3f>& points,
                                              const std::vector<StructuralPatch>& patches,
                                              const std::vector<DetectedOpening>& openings,
                                              double margin = 0.12, double band = 0.2);

}  // namespace mopad::modelling
