// The voxel space of the RoI (RoomModel::UpdateVoxels, modelling/voxel_space.h): voxels passed by
// the scans' beams, occupied by points, inside the room, and the structural layer of each face.
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

#include "modelling/room_model.h"
#include "modelling/room_model_internal.h"

namespace mopad::modelling {

using detail::kRayCastBit;

void RoomModel::UpdateVoxels(bool new_scan_only) {
  if (roi_.empty()) return;
  const double v = params_.voxel_size;
  Vec2 lo(1e300, 1e300), hi(-1e300, -1e300);
  for (const auto& p : roi_.perimeter) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  lo -= Vec2::Constant(params_.voxel_margin);
  hi += Vec2::Constant(params_.voxel_margin);
  // Layer 1 holds the floor, centred in it unless that leaves the ceiling within a quarter of
  // a voxel of a layer boundary: a face on a boundary is labelled in the layer its estimate
  // happens to fall in, and a fraction of a millimetre then moves a whole layer of structure
  // (2.65 m under a 0.1 m grid centred on the floor puts the ceiling on a boundary). Then the
  // floor moves within its layer so that both lie a quarter of a voxel or more from one.
  const double height = (roi_.ceiling_z - roi_.floor_z) / v;  // in voxels
  const double frac = height - std::floor(height);
  double floor_in_layer = 0.5;  // the floor's place in its layer, [0.25, 0.75]
  if (frac > 0.25 && frac <= 0.5) floor_in_layer = 0.5 - 0.5 * frac;
  if (frac > 0.5 && frac < 0.75) floor_in_layer = 1.0 - 0.5 * frac;
  const double oz = roi_.floor_z - (1.0 + floor_in_layer) * v;
  bool reuse = new_scan_only && !voxels_.empty() &&
               std::abs(voxels_.Origin().z() - oz) < 0.25 * v && voxels_.Origin().x() <= lo.x() &&
               voxels_.Origin().y() <= lo.y() &&
               voxels_.Origin().x() + v * voxels_.Nx() >= hi.x() &&
               voxels_.Origin().y() + v * voxels_.Ny() >= hi.y() &&
               voxels_.Origin().z() + v * voxels_.Nz() >= roi_.ceiling_z + v;
  if (!reuse) {
    const double extra = params_.voxel_growth;  // m, growth room before the next re-cast
    const Vec3 origin(std::floor((lo.x() - extra) / v) * v, std::floor((lo.y() - extra) / v) * v,
                      oz);
    const int nx = static_cast<int>(std::ceil((hi.x() + extra - origin.x()) / v));
    const int ny = static_cast<int>(std::ceil((hi.y() + extra - origin.y()) / v));
    const int nz = static_cast<int>(std::ceil((roi_.ceiling_z + 1.5 * v - oz) / v));
    voxels_ = VoxelSpace(origin, v, nx, ny, nz);
  } else {
    for (std::size_t i = 0; i < voxels_.VoxelCount(); ++i) {
      voxels_.MutableFlags(i) &= VoxelSpace::kPassed;
    }
  }
  // Beams (every ray_stride-th row and column) mark the voxels they pass.
  const std::size_t s0 = reuse ? scans_.size() - 1 : 0;
  for (std::size_t s = s0; s < scans_.size(); ++s) {
    const ScanRecord& rec = scans_[s];
    tbb::parallel_for(tbb::blocked_range<std::size_t>(rec.begin, rec.end, 1 << 12),
                      [&](const tbb::blocked_range<std::size_t>& r) {
                        for (std::size_t i = r.begin(); i < r.end(); ++i) {
                          if (!(column_index_[i] & kRayCastBit)) continue;
                          voxels_.MarkPassed(rec.origin, points_[i].cast<double>());
                        }
                      });
  }
  // Occupied: any working point.
  for (const auto& p : work_points_) {
    const Eigen::Vector3i q = voxels_.VoxelOf(p.cast<double>());
    if (voxels_.Contains(q.x(), q.y(), q.z())) {
      voxels_.MutableFlags(voxels_.Index(q.x(), q.y(), q.z())) |= VoxelSpace::kOccupied;
    }
  }
  // Structural: the single voxel layer containing a RoI face, as in the evaluator's truth DSM3
  // (which nudges a face on a voxel boundary to the room side). The face is taken
  // structure_tolerance into the room so that the robot's few-mm error does not flip a face
  // lying on a boundary to the layer behind it; a voxel whose centre lies more than half a
  // voxel behind a face is never structure. Inside: voxel centres inside the prism.
  const double eps = std::min(params_.structure_tolerance, 0.45 * v) + 1e-9 * v;
  const int kf = voxels_.VoxelOf(Vec3(0, 0, roi_.floor_z + eps)).z();
  const int kc = voxels_.VoxelOf(Vec3(0, 0, roi_.ceiling_z - eps)).z();
  for (int j = 0; j < voxels_.Ny(); ++j) {
    for (int i = 0; i < voxels_.Nx(); ++i) {
      const Vec3 c = voxels_.Centre(i, j, 0);
      if (!roi_.ContainsPlan(c.head<2>())) continue;
      for (int k = kf; k <= kc; ++k) {
        if (!voxels_.Contains(i, j, k)) continue;
        std::uint8_t& f = voxels_.MutableFlags(voxels_.Index(i, j, k));
        f |= VoxelSpace::kInside;
        if (k == kf || k == kc) f |= VoxelSpace::kStructural;
      }
    }
  }
  // `room_left`: the room lies to the left of each edge (CCW perimeter, CW column) or right.
  auto mark_loop = [&](const std::vector<Vec2>& loop, bool room_left) {
    const std::size_t m = loop.size();
    for (std::size_t e = 0; e < m; ++e) {
      const Vec2 a = loop[e], b = loop[(e + 1) % m];
      if ((b - a).norm() < 1e-12) continue;
      const Vec2 t = (b - a).normalized();
      const Vec2 in = room_left ? Vec2(-t.y(), t.x()) : Vec2(t.y(), -t.x());
      const int steps = std::max(1, static_cast<int>(std::ceil((b - a).norm() / (v / 8))));
      for (int s = 0; s <= steps; ++s) {
        const Vec2 p = a + (b - a) * (static_cast<double>(s) / steps) + eps * in;
        const Eigen::Vector3i q = voxels_.VoxelOf(Vec3(p.x(), p.y(), roi_.floor_z));
        const Vec3 c = voxels_.Centre(q.x(), q.y(), 0);
        if ((c.head<2>() - a).dot(in) < -0.5 * v) continue;  // centre too far outside the face
        for (int k = kf; k <= kc; ++k) {
          if (voxels_.Contains(q.x(), q.y(), k)) {
            voxels_.MutableFlags(voxels_.Index(q.x(), q.y(), k)) |= VoxelSpace::kStructural;
          }
        }
      }
    }
  };
  auto ccw = [](const std::vector<Vec2>& loop) {
    double a = 0.0;
    for (std::size_t i = 0; i < loop.size(); ++i) {
      const Vec2& p = loop[i];
      const Vec2& q = loop[(i + 1) % loop.size()];
      a += p.x() * q.y() - q.x() * p.y();
    }
    return a > 0.0;
  };
  mark_loop(roi_.perimeter, ccw(roi_.perimeter));
  for (const auto& c : roi_.columns) mark_loop(c, !ccw(c));
}

}  // namespace mopad::modelling
