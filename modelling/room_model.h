#pragma once
// The robot's model of one room while it scans it (paper §3.1 steps (3)-(5), Figures 5-6):
// registered TLS scans accumulated in the map frame, and after every scan
//  - floor and ceiling heights (the two maxima of the Z-histogram, §3.2);
//  - the ceiling perimeter in plan view (per azimuth, the ceiling seen contiguously from the
//    scanner up to the wall that stops it; the union over scans, simplified, each edge refit to
//    its wall points). The scanner's blind cone above itself and the floor it cannot see
//    within ~1.7 m are inside the per-scan outline by construction, so they never read as holes;
//  - columns (vertical floor-to-ceiling structures inside the perimeter);
//  - per-point labels: inlier (on the floor, ceiling, a perimeter wall or a column), outlier
//    (outside the perimeter: through doors and windows, reflections), clutter (the rest);
//  - the RoI B-rep (modelling/roi.h) with faces classified as holding structural data or not,
//    each rasterised into sensed / unsensed / opening cells;
//  - the voxel space of the RoI (modelling/voxel_space.h);
//  - coverage figures for the stopping rule (modelling/stopping.h).
// SM1 (§3.1) is the labelled coloured full-resolution cloud (WriteSm1).
//
// Inputs are the robot's own: organised scans in the scanner frame and the registered pose
// X_MS of each. Deterministic (TBB loops write disjoint outputs; reductions in fixed order).
// Not thread-safe for concurrent AddScan; const accessors may run concurrently.

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <memory>
#include <limits>
#include <string>
#include <unordered_map>
#include <vector>

#include "common/frames.h"
#include "common/params.h"
#include "interfaces/tls_scan.h"
#include "io/scan_io.h"
#include "modelling/colour_alignment.h"
#include "modelling/roi.h"
#include "modelling/voxel_space.h"

namespace mopad::modelling {

/// Per-point SM1 labels (values written to the PLY `scalar_label`; the evaluator uses the same).
enum class PointLabel : std::uint8_t { kNone = 0, kInlier = 1, kOutlier = 2, kClutter = 3 };
const char* ToString(PointLabel label);

/// The floor and ceiling heights (paper §3.2): the strong peaks of the working cloud's
/// Z-histogram below and above the scanners' mean height.
struct HeightSearchParams {
  /// m, the histogram spans the scanners' mean height +- this, [1, 100]
  double search_range = 10.0;
  /// m, no floor or ceiling peak is looked for closer than this to the scanners' mean height,
  /// [0, 5]
  double scanner_guard = 0.3;
  double peak_share = 0.3;  ///< a peak counts at this share of the highest one, [0.01, 1]
  /// bins, a peak's height is the mean z of the working points within this many bins of it,
  /// [0.5, 10]
  double refine_bins = 1.5;
  /// m, the floor (ceiling) lies this far below (above) the scanners where no peak is found,
  /// [0, 10]
  double fallback_offset = 1.4;
  /// m, the ceiling is the highest strong peak over the scanners: one whose working points
  /// come within this of the disc around a scanner that it cannot see: the larger of what its
  /// minimum range hides (radius sqrt(range_min^2 - (z - scanner z)^2)) and what lies above
  /// the top of its field of view (radius (z - scanner z) / tan(top elevation), from the scan's
  /// steepest return). A higher ceiling seen only through a door (the next room's) starts well
  /// beyond the wall, under the door's head; a room's own ceiling starts at that disc's edge.
  /// [0, 100]
  double ceiling_over_scanner = 0.5;
  /// Of the eight 45 deg azimuth sectors around a scanner, those its ceiling's points within
  /// that reach must lie in: a room's own ceiling surrounds the scanner (a corridor's too, along
  /// it and across it), the next room's ceiling seen through a door beside it spans the one or
  /// two sectors of the door. [1, 8]
  int ceiling_sectors = 3;
  /// m, the floor is the strong peak within this of the floor the robot stands on (the base's
  /// height under the scanner, from the scan's calibrated mount: base_link lies on the floor),
  /// else that floor itself: the robot stands on it, whether or not the scanner sees it. In a
  /// washroom of 2-3 m^2 the floor lies outside the -40 deg field of view up to 1.7 m from the
  /// scanner and the lowest strong peak is a bathtub's or a toilet's top. Scans without a mount
  /// (identity X_BS: read from a file) keep the lowest strong peak below the scanners.
  /// 0 = off. [0, 2]
  double floor_from_base = 0.1;

  template <class V>
  void Visit(V& v) {
    v("search_range", search_range, Bounds{1.0, 100.0});
    v("scanner_guard", scanner_guard, Bounds{0.0, 5.0});
    v("peak_share", peak_share, Bounds{0.01, 1.0});
    v("refine_bins", refine_bins, Bounds{0.5, 10.0});
    v("fallback_offset", fallback_offset, Bounds{0.0, 10.0});
    v("ceiling_over_scanner", ceiling_over_scanner, Bounds{0.0, 100.0});
    v("ceiling_sectors", ceiling_sectors, Bounds{1, 8});
    v("floor_from_base", floor_from_base, Bounds{0.0, 2.0});
  }
};

/// One scan's outline of its ceiling view (RoomModel::TraceOutline): per azimuth column the
/// walk down from the top row over the ceiling up to the wall that stops it.
struct CeilingOutlineParams {
  /// m, a change of the ceiling height beyond this retraces every scan's outline (else only the
  /// new scan's), [0, 1]
  double retrace_change = 0.01;
  /// rows without a return before a point that make a gap in its column (a single dropout of
  /// a dark or specular surface is none; a wall closer than the minimum range is), [1, 1000]
  int gap_rows = 2;
  /// m, things hanging this far below the ceiling continue the walk, [0, 2]
  double hang_depth = 0.25;
  /// m, a point below the ceiling this much nearer than the farthest ceiling seen so far in its
  /// column occludes the ceiling and is stepped over, [0, 1]
  double occluder_margin = 0.05;
  /// m, 3D range under which a return may be followed by surfaces too close to return
  /// (scanners' minimum ranges are 0.5-1.5 m), [0, 10]
  double near_range = 2.0;
  /// m, a return this close to the scan's shortest one lies at the scanner's minimum range,
  /// [0, 1]
  double min_range_slack = 0.1;
  /// m, the outline's reach in a direction the scan saw nothing in: about the robot's own
  /// half-width around the scanner, the only space known to be free there, [0, 2]
  double blind_radius = 0.25;
  /// m, a jump in the ceiling's reach between neighbouring azimuths beyond this is stepped
  /// around radially (above the reach's noise along a wall), [0, 1]
  double shadow_step = 0.05;

  template <class V>
  void Visit(V& v) {
    v("retrace_change", retrace_change, Bounds{0.0, 1.0});
    v("gap_rows", gap_rows, Bounds{1, 1000});
    v("hang_depth", hang_depth, Bounds{0.0, 2.0});
    v("occluder_margin", occluder_margin, Bounds{0.0, 1.0});
    v("near_range", near_range, Bounds{0.0, 10.0});
    v("min_range_slack", min_range_slack, Bounds{0.0, 1.0});
    v("blind_radius", blind_radius, Bounds{0.0, 2.0});
    v("shadow_step", shadow_step, Bounds{0.0, 1.0});
  }
};

/// Each perimeter edge moved onto its wall (RoomModel::RefitPerimeter): the outermost strong
/// peak of the offsets across the edge of the working points between the floor and ceiling
/// bands, then a total least-squares line through the points near that offset.
struct WallRefitParams {
  /// m, each end of an edge longer than three times this is left out of its refit (the
  /// corners), [0, 1]
  double end_guard = 0.1;
  double floor_clearance = 0.2;    ///< m, refit points lie above floor + this, [0, 2]
  double ceiling_clearance = 0.1;  ///< m, and below ceiling - this, [0, 2]
  /// m above the floor: points higher are above door heads (2.0-2.1 m), where only the wall
  /// itself reaches (a lintel, the wall over a cabinet); its offset is looked for there first,
  /// [0, 10]
  double high_band = 2.2;
  double offset_bin = 0.005;  ///< m, bin of the histogram of offsets across an edge, [0.001, 0.1]
  double peak_share = 0.5;    ///< the wall's peak has at least this share of the highest, [0.01, 1]
  /// m, stretch of an edge that counts as covered when one of the wall's points lies in it,
  /// [0.01, 1]
  double support_bin = 0.1;
  /// share of an edge's stretches its wall's points must cover (and at least two), [0, 1]
  double min_coverage = 0.2;
  /// the points above door heads alone give the line where they cover this share of the
  /// stretches all points cover, [0, 1]
  double high_coverage = 0.5;
  /// deg, a fitted line turned more than this off the traced edge keeps the edge's direction,
  /// only shifted, [0, 90]
  double max_turn_deg = 10.0;
  /// the line is refit about the wall's peak on the points within this share of
  /// wall_tolerance of it, [0, 1]
  double tighten_first = 0.6;
  double tighten_second = 0.4;  ///< then within this share of wall_tolerance, [0, 1]
  /// a tightened refit is taken while at least this share of the band's points (and
  /// refit_min_points) remain, [0, 1]
  double tighten_keep_share = 0.2;

  template <class V>
  void Visit(V& v) {
    v("end_guard", end_guard, Bounds{0.0, 1.0});
    v("floor_clearance", floor_clearance, Bounds{0.0, 2.0});
    v("ceiling_clearance", ceiling_clearance, Bounds{0.0, 2.0});
    v("high_band", high_band, Bounds{0.0, 10.0});
    v("offset_bin", offset_bin, Bounds{0.001, 0.1});
    v("peak_share", peak_share, Bounds{0.01, 1.0});
    v("support_bin", support_bin, Bounds{0.01, 1.0});
    v("min_coverage", min_coverage, Bounds{0.0, 1.0});
    v("high_coverage", high_coverage, Bounds{0.0, 1.0});
    v("max_turn_deg", max_turn_deg, Bounds{0.0, 90.0});
    v("tighten_first", tighten_first, Bounds{0.0, 1.0});
    v("tighten_second", tighten_second, Bounds{0.0, 1.0});
    v("tighten_keep_share", tighten_keep_share, Bounds{0.0, 1.0});
  }
};

/// The refit perimeter's corners from its edges' lines (JoinPerimeterLines).
struct PerimeterCornerParams {
  /// deg, lines nearer than this to parallel are not intersected, [0.1, 45]
  double parallel_deg = 5.0;
  /// m, an edge shorter than this between two fitted walls, left unfitted, is the tracer
  /// cutting their corner: the walls meet in one corner instead, [0, 2]
  double chamfer_max = 0.3;
  double wall_end_max = 0.6;  ///< m, a wall's end face is at most this wide (thick walls), [0, 5]
  /// deg, two walls within this of antiparallel hold the end face of a wall standing into the
  /// room between them, [0, 45]
  double antiparallel_deg = 5.0;
  /// deg, the walls at a corner are at least this far from parallel, [0, 90]
  double corner_min_deg = 45.0;
  /// deg, a short fitted edge whose points run within this of a neighbour's wall line (and lie
  /// on it) carries that wall's own points, [0, 45]
  double on_wall_deg = 10.0;
  /// m, a corner moves at most this far to its lines' intersection; farther (or nearly
  /// parallel lines) it is projected onto both lines, [0, 5]
  double max_corner_shift = 0.5;
  /// m, both projections are kept when further apart than this, [0, 1]
  double split_corner = 0.02;

  template <class V>
  void Visit(V& v) {
    v("parallel_deg", parallel_deg, Bounds{0.1, 45.0});
    v("chamfer_max", chamfer_max, Bounds{0.0, 2.0});
    v("wall_end_max", wall_end_max, Bounds{0.0, 5.0});
    v("antiparallel_deg", antiparallel_deg, Bounds{0.0, 45.0});
    v("corner_min_deg", corner_min_deg, Bounds{0.0, 90.0});
    v("on_wall_deg", on_wall_deg, Bounds{0.0, 45.0});
    v("max_corner_shift", max_corner_shift, Bounds{0.0, 5.0});
    v("split_corner", split_corner, Bounds{0.0, 1.0});
  }
};

/// The shape of a detour of the perimeter that is a view through an opening in a wall
/// (RoomModelParams::seal_depth, seal_width and seal_inward give its size).
struct OpeningSealParams {
  double min_wall = 0.3;  ///< m, the wall edges either side of the detour are this long, [0, 5]
  double on_line = 0.03;  ///< m, the detour ends this close to the wall's line, [0, 0.5]
  /// m, the detour passes this far behind the wall's line (or jog_tolerance, if smaller):
  /// beyond the wall's own noise, [0, 1]
  double min_depth = 0.05;
  int max_vertices = 12;  ///< vertices of the detour, [1, 1000]
  /// deg, the wall edge after the detour runs within this of the wall's direction, [0, 45]
  double parallel_deg = 5.0;
  /// m, a detour deeper than seal_depth is still a view through an opening when the wall's face
  /// goes on above its mouth (a lintel: points on the wall's line above door heads, over at
  /// least `lintel_coverage` of the mouth): a room's ceiling ends at a wall with a head over
  /// its opening, and what lies beyond is the next room's, seen through the door from a
  /// scanner too near the wall to see the lintel itself (inside the minimum range). Up to
  /// this depth, [0, 100]
  double lintel_depth = 10.0;
  /// share of the mouth's 5 cm bins holding such a point, (0, 1]
  double lintel_coverage = 0.5;

  template <class V>
  void Visit(V& v) {
    v("min_wall", min_wall, Bounds{0.0, 5.0});
    v("on_line", on_line, Bounds{0.0, 0.5});
    v("min_depth", min_depth, Bounds{0.0, 1.0});
    v("max_vertices", max_vertices, Bounds{1, 1000});
    v("parallel_deg", parallel_deg, Bounds{0.0, 45.0});
    v("lintel_depth", lintel_depth, Bounds{0.0, 100.0});
    v("lintel_coverage", lintel_coverage, Bounds{0.01, 1.0});
  }
};

/// Columns (RoomModel::DetectColumns): plan cells with working points in the top height slice,
/// grouped; a group small enough and seen over most of the height is a column.
struct ColumnSearchParams {
  double cell = 0.05;  ///< m, plan cell, [0.01, 0.5]
  /// height slices between floor_clearance and ceiling_clearance (column_min_height_share of
  /// them must hold points), [1, 16]
  int slices = 8;
  double floor_clearance = 0.1;     ///< m, the slices begin this far above the floor, [0, 2]
  double ceiling_clearance = 0.05;  ///< m, and end this far below the ceiling, [0, 2]
  /// m, cells nearer than this to the perimeter are wall (a column touching a wall is a
  /// pilaster, part of the perimeter), [0, 2]
  double wall_clearance = 0.15;
  int min_points = 20;              ///< working points of a column, [3, 100000]
  double outline_tolerance = 0.01;  ///< m, simplification of the footprint's hull, [0, 0.5]
  double min_area = 0.01;           ///< m^2, smallest footprint, [0, 10]

  template <class V>
  void Visit(V& v) {
    v("cell", cell, Bounds{0.01, 0.5});
    v("slices", slices, Bounds{1, 16});
    v("floor_clearance", floor_clearance, Bounds{0.0, 2.0});
    v("ceiling_clearance", ceiling_clearance, Bounds{0.0, 2.0});
    v("wall_clearance", wall_clearance, Bounds{0.0, 2.0});
    v("min_points", min_points, Bounds{3, 100000});
    v("outline_tolerance", outline_tolerance, Bounds{0.0, 0.5});
    v("min_area", min_area, Bounds{0.0, 10.0});
  }
};

/// Sloped ceilings (a roof's underside over an attic): planes found in the top surface of the
/// working cloud, its highest point per plan cell, where the cells' neighbourhoods fit tilted
/// planes that join into one of at least `min_area` and `min_width` (docs/room-scanning.md,
/// step 2). A stair's treads and risers fit no plane locally, its flight's underside is too
/// narrow; a level ceiling is not tilted.
struct SlopedCeilingParams {
  double cell = 0.1;           ///< m, plan cell of the top surface, [0.02, 1]
  double min_tilt_deg = 10.0;  ///< deg, least tilt from level, [1, 80]
  double max_tilt_deg = 60.0;  ///< deg, most tilt from level, [1, 89]
  /// m, rms of a cell's 3 x 3 neighbourhood about its local plane, [0.001, 0.1]
  double local_rms = 0.01;
  double max_turn_deg = 5.0;  ///< deg, a neighbour cell's local plane joins within this, [0.1, 45]
  double tolerance = 0.03;    ///< m, a top point on the joined plane, [0.005, 0.2]
  /// m^2, least plan area of a sloped ceiling; 0 = none is sought, [0, 1000]
  double min_area = 2.0;
  /// m, least extent of a sloped ceiling across its slope (along its level lines): a roof
  /// spans its room, a stair flight's underside is 0.8-1.3 m wide, [0, 100]
  double min_width = 1.5;
  /// m, a top point this high over the floor at least counts (not the floor, a desk), [0, 3]
  double min_height = 0.3;

  template <class V>
  void Visit(V& v) {
    v("cell", cell, Bounds{0.02, 1.0});
    v("min_tilt_deg", min_tilt_deg, Bounds{1.0, 80.0});
    v("max_tilt_deg", max_tilt_deg, Bounds{1.0, 89.0});
    v("local_rms", local_rms, Bounds{0.001, 0.1});
    v("max_turn_deg", max_turn_deg, Bounds{0.1, 45.0});
    v("tolerance", tolerance, Bounds{0.005, 0.2});
    v("min_area", min_area, Bounds{0.0, 1000.0});
    v("min_width", min_width, Bounds{0.0, 100.0});
    v("min_height", min_height, Bounds{0.0, 3.0});
  }
};

struct RoomModelParams {
  double working_voxel = 0.02;  ///< m, working-cloud downsampling, [0.005, 0.2]
  double histogram_bin = 0.01;  ///< m, Z-histogram bin, [0.002, 0.1]
  double plane_tolerance =
      0.03;  ///< m, |z - floor| or |z - ceiling| of structural points, [0.005, 0.2]
  double wall_tolerance =
      0.015;  ///< m, plan distance to a wall/column face of its points, [0.005, 0.2]
  double ceiling_tolerance = 0.05;  ///< m, |z - ceiling| for the perimeter trace, [0.01, 0.3]
  /// Points just beyond a wall face (in the reveal of a door or window: frames, glass, a closed
  /// leaf) up to this depth and between floor and ceiling are clutter, not outliers. 0 = the
  /// paper's rule (everything outside the perimeter is an outlier). [0, 1]
  double reveal_depth = 0.0;
  double perimeter_raster = 0.025;  ///< m, plan raster of the ceiling outline, [0.005, 0.2]
  double perimeter_epsilon = 0.04;  ///< m, polygon simplification tolerance, [0.005, 0.5]
  /// m: after the refit, a vertex this close to the segment joining its neighbours is dropped
  /// (a short edge fitted across a doorway can leave such a jog, splitting the wall). 0 = off.
  /// [0, 0.5]
  double jog_tolerance = 0.04;
  double min_edge_length = 0.1;  ///< m, shorter simplified edges are merged, [0, 2]
  /// deg, a vertex whose edges turn less than this is dropped, [0, 45]
  double collinear_deg = 3.0;
  /// m, a perimeter detour that leaves a wall line, passes up to this far behind it and comes
  /// back onto the same line is a view through an opening in that wall (the trace walked into
  /// a door's or window's reveal under a head close to the ceiling) and is cut off by the
  /// straight wall; 0 = off. Wall reveals are 0.1-0.5 m deep. [0, 2]
  double seal_depth = 0.6;
  /// m, widest such detour along the wall line (a double door's clear width), [0, 10]
  double seal_width = 3.0;
  /// m, how far such a detour may also reach into the room (the leaf of a door opened inwards,
  /// which hides the wall beside the doorway), [0, 5]
  double seal_inward = 1.2;
  OpeningSealParams seal;     ///< the detour's shape
  /// m, how far something without a wall face that hides a wall from every scan may stand
  /// into the room and still be taken for clutter in front of it (the wall goes on behind it):
  /// a spiral stair's diameter, a wardrobe's depth. A wall standing into the room shows a
  /// face; its shadow from a single scan can lack one and reaches farther. [0, 10]
  double shadow_depth = 2.0;
  double refit_band = 0.1;    ///< m, wall points gathered around an edge for its refit, [0.01, 1]
  int refit_min_points = 30;  ///< points an edge needs to be refit, [3, 100000]
  WallRefitParams refit;      ///< each edge moved onto its wall
  PerimeterCornerParams corners;         ///< the refit edges' corners
  double column_max_size = 1.5;          ///< m, largest column footprint side, [0.1, 10]
  double column_min_height_share = 0.7;  ///< share of the floor-ceiling height seen, [0.1, 1]
  ColumnSearchParams columns;            ///< the column search
  /// m, RoI face raster cell, [0.02, 1]. 5 cm: a cell counts as sensed from one point, so
  /// larger cells overstate sparse far coverage (the evaluator scores 5 cm cells).
  double face_cell = 0.05;
  double structural_share = 0.05;  ///< sensed share that makes a face structural, [0, 1]
  double voxel_size = 0.1;         ///< m, voxel space edge, [0.02, 1]
  double voxel_margin = 0.5;       ///< m, grid margin around the RoI, [0, 5]
  /// m, the grid reaches this beyond the margin, so that the next scans, which grow the RoI a
  /// little, reuse it instead of casting every scan's rays again, [0, 10]
  double voxel_growth = 1.0;
  /// m, a RoI face is taken this far into the room when picking its voxel layer, so a face the
  /// robot places a few mm behind a voxel boundary still lands on the room side as the truth's
  /// does (DSM3: one structural layer per face), [0, 0.45 * voxel_size]
  double structure_tolerance = 0.01;
  int ray_stride = 2;            ///< every n-th row and column is ray-cast into voxels, [1, 64]
  HeightSearchParams heights;    ///< the floor and ceiling heights
  CeilingOutlineParams outline;  ///< each scan's ceiling outline
  SlopedCeilingParams slopes;    ///< sloped ceilings (attics)
  ColourAlignmentParams colour_alignment;  ///< each scan's colours brought to the room's

  template <class V>
  void Visit(V& v) {
    v("working_voxel", working_voxel, Bounds{0.005, 0.2});
    v("histogram_bin", histogram_bin, Bounds{0.002, 0.1});
    v("plane_tolerance", plane_tolerance, Bounds{0.005, 0.2});
    v("wall_tolerance", wall_tolerance, Bounds{0.005, 0.2});
    v("ceiling_tolerance", ceiling_tolerance, Bounds{0.01, 0.3});
    v("reveal_depth", reveal_depth, Bounds{0.0, 1.0});
    v("perimeter_raster", perimeter_raster, Bounds{0.005, 0.2});
    v("perimeter_epsilon", perimeter_epsilon, Bounds{0.005, 0.5});
    v("jog_tolerance", jog_tolerance, Bounds{0.0, 0.5});
    v("min_edge_length", min_edge_length, Bounds{0.0, 2.0});
    v("collinear_deg", collinear_deg, Bounds{0.0, 45.0});
    v("seal_depth", seal_depth, Bounds{0.0, 2.0});
    v("seal_width", seal_width, Bounds{0.0, 10.0});
    v("seal_inward", seal_inward, Bounds{0.0, 5.0});
    v("seal", seal);
    v("shadow_depth", shadow_depth, Bounds{0.0, 10.0});
    v("refit_band", refit_band, Bounds{0.01, 1.0});
    v("refit_min_points", refit_min_points, Bounds{3, 100000});
    v("refit", refit);
    v("corners", corners);
    v("column_max_size", column_max_size, Bounds{0.1, 10.0});
    v("column_min_height_share", column_min_height_share, Bounds{0.1, 1.0});
    v("columns", columns);
    v("face_cell", face_cell, Bounds{0.02, 1.0});
    v("structural_share", structural_share, Bounds{0.0, 1.0});
    v("voxel_size", voxel_size, Bounds{0.02, 1.0});
    v("voxel_margin", voxel_margin, Bounds{0.0, 5.0});
    v("voxel_growth", voxel_growth, Bounds{0.0, 10.0});
    v("structure_tolerance", structure_tolerance, Bounds{0.0, 0.45});
    v("colour_alignment", colour_alignment);
    v("ray_stride", ray_stride, Bounds{1, 64});
    v("heights", heights);
    v("outline", outline);
    v("slopes", slopes);
  }
  void Validate() const { ValidateParams(*this, "room_model."); }
};

/// The perimeter's last pass after its edges were refit onto their walls (plan polygon, CCW,
/// map frame, m): vertices closer than `jog_tolerance` to the segment joining their neighbours
/// dropped, detours behind a wall line deeper than that and at most `seal_depth` (views through
/// an opening) cut across, short and collinear edges merged. `above_heads`: the plan positions
/// of the working points above door heads (WallRefitParams::high_band) and below the ceiling
/// band; with them, a deeper detour whose mouth a lintel spans is cut across too
/// (OpeningSealParams::lintel_depth).
void TidyPerimeter(std::vector<Vec2>& poly, const RoomModelParams& params,
                   const std::vector<Vec2>& above_heads = {});

/// One perimeter edge's wall line after the refit (plan, map frame): a point `p` of it, its unit
/// direction `t`, `fitted` false where no wall's points carried the edge (it keeps the traced
/// line), and `support` the principal direction of the points that carried it (`t` keeps the
/// traced direction, only shifted, where they run more than refit.max_turn_deg off the edge).
struct PerimeterLine {
  Vec2 p = Vec2::Zero();
  Vec2 t = Vec2::UnitX();
  bool fitted = false;
  Vec2 support = Vec2::UnitX();
};

/// The refit perimeter's corners from its edges' lines (`lines[i]` for the edge poly[i] ->
/// poly[i+1]): a short end face of a wall standing into the room squared to it, short edges
/// that cut a corner (unfitted, or fitted onto a neighbour's wall) collapsed into the corner of
/// their neighbours, the other neighbours re-intersected.
std::vector<Vec2> JoinPerimeterLines(const std::vector<Vec2>& poly,
                                     const std::vector<PerimeterLine>& lines,
                                     const RoomModelParams& params);

/// The refit perimeter's shadows, dropped before JoinPerimeterLines (`lines[i]` for the edge
/// poly[i] -> poly[i+1], `band` the plan points between the floor and ceiling bands, both kept
/// in step): a run of edges between two fitted edges on one wall line (parallel within
/// parallel_deg, their offsets within twice the wall tolerance) that stands in front of that
/// line and goes on along it is something standing in the room in front of that wall: it hides
/// the ceiling from some scans, and no scan saw past it at the ceiling. It is no part of the
/// room's outline when
/// - it stays in front of the line (no vertex more than the wall tolerance behind it) and wall
///   points lie on the line behind it (over seal.lintel_coverage of its 5 cm bins, the test of a
///   lintel over a view through an opening): the wall was seen going on behind it, under it or
///   between its parts (a hanging duct, a bulkhead, a stair's open flights); or
/// - none of its edges in front of the line has a wall face (none fitted), and it stands more
///   than refit_band (the band a wall's own points fill; shallower jogs are the tracer's) and at
///   most shadow_depth into the room: what stands there shows no vertical plane to the scanner
///   (a spiral stair's steps at every depth and height), so it is clutter, and the wall is taken
///   to go on along its line behind it (the continuation of occluded walls that room
///   reconstruction from cluttered scans rests on; docs/room-scanning.md). A window's or door's
///   reveal beside it (vertices up to seal_depth behind the line) is part of the run.
/// The run's vertices are dropped and the two edges become one, on the first's line (SM3's walls
/// are planes over their occluded parts, the paper's occluded structure). Something with a face
/// standing against the wall and hiding it (a pilaster, a cupboard, a shaft, a wall standing
/// into the room) stays; a run that only passes behind the line is a view through an opening
/// (SealOpenings). In a corner, a run between two fitted walls that turn left (a convex corner,
/// by at least corners.corner_min_deg) and whose lines meet behind it, more than refit_band
/// beyond the end of each (both stop short of the corner), hides that corner when it
/// stands in front of both walls and is faceless, more than refit_band out of the corner both
/// ways and at most shadow_depth from either wall (a stair in the corner), or when both walls
/// are seen going on behind it: its vertices go and the two walls meet at the corner.
void BridgeShadows(std::vector<Vec2>& poly, std::vector<PerimeterLine>& lines,
                   const std::vector<Vec2>& band, const RoomModelParams& params);

/// Coverage of the structural elements after a scan (areas in m^2).
struct CoverageFigures {
  int scans = 0;
  double sensed_area = 0.0;   ///< sensed cells of all RoI faces
  double total_area = 0.0;    ///< estimated structural area: RoI face area minus openings
  double opening_area = 0.0;  ///< face cells seen through (doors, windows)
  double ratio = 0.0;         ///< sensed_area / total_area
  /// (sensed_area - previous sensed_area) / total_area; equals ratio for the first scan.
  double increment = 0.0;
  /// m^2, unsensed area of structural faces that no position the robot can reach sees (hidden
  /// behind clutter it has scanned, out of the scanner's elevation range); set by the room loop
  /// (autonomy::EstimateHiddenArea), 0 until then. [0, total_area]
  double hidden_area = 0.0;
  /// sensed_area / (total_area - hidden_area): the sensed share of the structure the robot can
  /// observe, what the stopping rule compares with epsilon1; equals ratio while hidden_area = 0.
  double observable_ratio = 0.0;
  /// Sets hidden_area (clamped to [0, total_area - sensed_area]) and observable_ratio.
  void SetHiddenArea(double area);
};

/// Per-point label counts.
struct LabelCounts {
  std::int64_t none = 0, inlier = 0, outlier = 0, clutter = 0;
};

class RoomModel {
 public:
  /// Validates `params` (InputError).
  explicit RoomModel(RoomModelParams params = {});
  RoomModel(const RoomModel&) = default;
  RoomModel& operator=(const RoomModel&) = default;
  RoomModel(RoomModel&&) noexcept = default;
  RoomModel& operator=(RoomModel&&) noexcept = default;

  /// Adds one scan with its registered scanner pose (map frame) and recomputes everything.
  /// Throws InputError if the scan's grid is inconsistent (points != rows * columns) or it
  /// has no valid return, or X_MS is not finite.
  void AddScan(const interfaces::TlsScan& scan, const Pose3& X_MS);
  /// From now on AddScan adds points, labels, face sensing, voxels and coverage but keeps the
  /// structure as it is: heights, perimeter, columns, RoI (for scans taken for data quality
  /// after the structural stopping rule, autonomy/detail_pass.h). Not undone.
  void FreezeStructure() { structure_frozen_ = true; }
  bool StructureFrozen() const { return structure_frozen_; }

  const RoomModelParams& Params() const { return params_; }
  int ScanCount() const { return static_cast<int>(scans_.size()); }
  const std::vector<Pose3>& ScanPoses() const { return scan_poses_; }
  /// Per scan, the angle between its neighbouring beams (the larger of its azimuth and
  /// elevation steps), rad.
  const std::vector<double>& ScanAngularSteps() const { return scan_steps_; }
  double FloorZ() const { return roi_.floor_z; }
  double CeilingZ() const { return roi_.ceiling_z; }
  /// Simplified ceiling perimeter, CCW, map frame plan (m).
  const std::vector<Vec2>& Perimeter() const { return roi_.perimeter; }
  const std::vector<std::vector<Vec2>>& Columns() const { return roi_.columns; }
  const Roi& GetRoi() const { return roi_; }
  const VoxelSpace& Voxels() const { return voxels_; }
  const CoverageFigures& Coverage() const { return coverage_.back(); }
  /// One entry per AddScan.
  const std::vector<CoverageFigures>& CoverageHistory() const { return coverage_; }

  /// Label of a map-frame point against the current model (the rule used for every point).
  PointLabel Classify(const Vec3& p_M) const;

  // Full-resolution cloud (every valid return of every scan, map frame, scan order).
  std::size_t PointCount() const { return points_.size(); }
  const std::vector<Eigen::Vector3f>& Points() const { return points_; }
  /// Colours as aligned to the room's first scan (modelling/colour_alignment.h).
  const std::vector<std::array<std::uint8_t, 3>>& Colours() const { return colours_; }
  /// The gains (linear light, per channel) each scan's colours were multiplied by; one per
  /// AddScan.
  const std::vector<std::array<double, 3>>& ColourGains() const { return colour_gains_; }
  const std::vector<float>& Intensities() const { return intensity_; }
  const std::vector<std::uint16_t>& ScanIndices() const { return scan_index_; }
  const std::vector<PointLabel>& Labels() const { return labels_; }
  LabelCounts CountLabels() const;
  /// Working cloud: centroids of the occupied working voxels (map frame).
  const std::vector<Eigen::Vector3f>& WorkingPoints() const { return work_points_; }

  /// SM1 as a cloud: x y z red green blue scalar_intensity scalar_label scalar_scan, with the
  /// scan poses and heights in header comments.
  io::PointCloud Sm1Cloud() const;
  /// Writes Sm1Cloud() as binary PLY (InputError on I/O failure).
  void WriteSm1(const std::string& path) const;
  /// The figures (heights, perimeter, columns, faces, voxel label counts, coverage history,
  /// label counts) as a JSON object, for the mission log.
  std::string FiguresJson() const;

  /// Implementation detail (room_model_internal.h): plan boundary for the signed-distance
  /// lookups.
  struct Boundary;

 private:
  struct ScanRecord {
    std::size_t begin = 0, end = 0;  // range in the full-resolution arrays
    Vec3 origin = Vec3::Zero();      // scanner centre, map
    std::vector<Vec2> outline;       // plan outline of its ceiling view (map)
    double min_range = 0.0;          // m, the shortest return of the scan (its minimum range)
    /// the steepest return above the scanner's horizon, as z / horizontal distance in the
    /// scanner frame (the top of its field of view); infinite when a return is straight above
    double max_up_slope = std::numeric_limits<double>::infinity();
    /// m, map z of the floor under the scanner's base (X_MS X_BS^-1); NaN without a mount
    double base_z = std::numeric_limits<double>::quiet_NaN();
    std::uint32_t columns = 0;       // azimuth columns of the scan
    double azimuth_min = 0.0, azimuth_step = 0.0;        // rad, scanner frame
    Eigen::Matrix3d R_MS = Eigen::Matrix3d::Identity();  // scanner orientation in map
  };

  void UpdateWorkingCloud(std::size_t begin, std::size_t end);
  void EstimateHeights();
  // roi_.slopes and roi_.level_ceiling from the working cloud (room_slopes.cpp); true when
  // they changed.
  bool DetectSlopes();
  void TraceOutline(ScanRecord& rec) const;
  void BuildPerimeter();
  /// The plan positions of the working points between the refit's floor and ceiling bands, and
  /// which of them lie above door heads (WallRefitParams::high_band).
  void WallBand(std::vector<Vec2>& band, std::vector<std::uint8_t>& high) const;
  void RefitPerimeter(std::vector<Vec2>& poly, const std::vector<Vec2>& band,
                      const std::vector<std::uint8_t>& high) const;
  void DetectColumns();
  void BuildRoi();
  void LabelAll();
  void UpdateFaces();
  void UpdateVoxels(bool new_scan_only);
  void UpdateCoverage();

  RoomModelParams params_;
  std::vector<ScanRecord> scans_;
  std::vector<Pose3> scan_poses_;
  std::vector<double> scan_steps_;  // rad, ScanAngularSteps()
  // Full resolution (structure of arrays).
  std::vector<Eigen::Vector3f> points_;
  std::vector<std::array<std::uint8_t, 3>> colours_;
  ColourReference colour_reference_;
  std::vector<std::array<double, 3>> colour_gains_;
  std::vector<float> intensity_;
  std::vector<std::uint16_t> scan_index_;
  std::vector<std::uint32_t> column_index_;  // azimuth column of each point in its scan
  std::vector<PointLabel> labels_;
  // Working cloud.
  std::unordered_map<std::int64_t, std::uint32_t>
      work_slot_;  // voxel key -> slot (insertion order)
  std::vector<Eigen::Vector3d> work_sum_;
  std::vector<std::uint32_t> work_count_;
  std::vector<Eigen::Vector3f> work_points_;
  std::vector<PointLabel> work_labels_;
  std::vector<std::int32_t> work_face_;
  // Model.
  Roi roi_;
  bool structure_frozen_ = false;             // FreezeStructure()
  std::shared_ptr<const Boundary> boundary_;  // of roi_, rebuilt with it
  VoxelSpace voxels_;
  std::vector<CoverageFigures> coverage_;
};

}  // namespace mopad::modelling
