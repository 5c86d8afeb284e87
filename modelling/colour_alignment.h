#pragma once
// Radiometric alignment of a room's scans: a camera's exposure and white balance change from
// scan to scan, so the same wall comes out lighter in one scan than in the next, and an
// orthoimage fused from both shows seams that look like objects. Each new scan's colours are
// brought to the room's by one gain per channel, estimated where the scan sees surfaces the room
// already holds — the gain compensation of panorama stitching (M. Brown, D. G. Lowe, "Automatic
// panoramic image stitching using invariant features", IJCV 74(1), 2007, section 6), here over
// 3D voxels instead of image overlaps. The room's first scan is the reference.
//
// Robot side: colours and points of the robot's own scans only.

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <unordered_map>
#include <vector>

#include "common/params.h"

namespace mopad::modelling {

struct ColourAlignmentParams {
  bool enabled = true;
  double voxel = 0.04;       ///< m, cell in which two scans' colours are compared, [0.005, 1]
  int min_voxel_points = 3;  ///< points a cell needs from each side, [1, 1000]
  int min_voxels = 200;      ///< cells shared with the room below which a scan is kept as is
  double min_linear = 0.02;  ///< linear light below which a cell is too dark to compare, [0, 1]
  double max_linear = 0.85;  ///< linear light above which a cell may be clipped, [0, 1]
  /// A gain within this of 1 (|ln g|) is left alone: below one 8-bit level at mid-grey
  /// (~1 %), it is the colour noise's, not the camera's. [0, 1]
  double deadband = 0.01;

  template <class V>
  void Visit(V& v) {
    v("enabled", enabled);
    v("voxel", voxel, Bounds{0.005, 1.0});
    v("min_voxel_points", min_voxel_points, Bounds{1, 1000});
    v("min_voxels", min_voxels, Bounds{1, 10000000});
    v("min_linear", min_linear, Bounds{0.0, 1.0});
    v("max_linear", max_linear, Bounds{0.0, 1.0});
    v("deadband", deadband, Bounds{0.0, 1.0});
  }
};

using Rgb8 = std::array<std::uint8_t, 3>;

/// The room's colours by voxel (mean linear light per channel) and the alignment of new scans
/// against them.
class ColourReference {
 public:
  explicit ColourReference(ColourAlignmentParams params = {});

  /// The gains (linear light, per channel) that bring a scan's colours to the room's, from the
  /// cells both see; {1, 1, 1} when disabled, for the first scan, with fewer than min_voxels
  /// shared cells, or within the deadband. `shared` (optional): the cells compared.
  std::array<double, 3> Gains(const std::vector<Eigen::Vector3f>& points,
                              const std::vector<Rgb8>& colours, std::size_t begin, std::size_t end,
                              int* shared = nullptr) const;
  /// The room model's step for a new scan: its gains (as Gains), applied to colours
  /// [begin, end) (ApplyColourGains), and the aligned points added to the room's cells. One
  /// cell lookup a point. Returns the gains.
  std::array<double, 3> Align(const std::vector<Eigen::Vector3f>& points,
                              std::vector<Rgb8>& colours, std::size_t begin, std::size_t end,
                              int* shared = nullptr);

 private:
  struct Cell {
    std::array<float, 3> sum{0.0f, 0.0f, 0.0f};  // linear light
    std::uint32_t n = 0;
    std::uint32_t slot = kNoSlot;  // Align's scratch: the cell's index among the scan's, or none
  };
  static constexpr std::uint32_t kNoSlot = 0xFFFFFFFFu;
  // A cell of the room (n = 0: new with this scan) beside the scan's own sums in it.
  struct Shared {
    const Cell* room = nullptr;
    Cell scan;
  };
  std::int64_t Key(const Eigen::Vector3f& p) const;
  // Per channel the median of the shared cells' ratios (see Gains).
  std::array<double, 3> GainsOf(const std::vector<Shared>& cells, int* shared) const;
  ColourAlignmentParams params_;
  std::unordered_map<std::int64_t, Cell> cells_;
};

/// Scales colours [begin, end) by `gains` in linear light (sRGB in and out, clipped at white).
void ApplyColourGains(const std::array<double, 3>& gains, std::vector<Rgb8>& colours,
                      std::size_t begin, std::size_t end);

}  // namespace mopad::modelling
