#include "mission/faults.h"

#include <algorithm>
#include <cmath>

#include "common/error.h"
#include "common/format.h"

namespace mopad::mission {
namespace {

bool Contains(const std::vector<int>& list, std::uint64_t index) {
  return std::any_of(list.begin(), list.end(),
                     [index](int k) { return k >= 0 && static_cast<std::uint64_t>(k) == index; });
}

}  // namespace

void FaultParams::Validate() const {
  if (lrf_silent_at >= 0.0 && lrf_silent_for <= 0.0)
    throw InputError("", "parameter 'lrf_silent_for' must be positive when lrf_silent_at is set",
                     FormatShortest(lrf_silent_for), "(0, 1e6] s");
  if (slip_at >= 0.0 && slip_for <= 0.0)
    throw InputError("", "parameter 'slip_for' must be positive when slip_at is set",
                     FormatShortest(slip_for), "(0, 1e6] s");
  if (slip_at >= 0.0 && slip_factor == 1.0)
    throw InputError("", "parameter 'slip_factor' of 1 is no slip", "1",
                     "a factor other than 1 in [0, 10]");
  if (kidnap_at >= 0.0 && kidnap_distance <= 0.0)
    throw InputError("", "parameter 'kidnap_distance' must be positive when kidnap_at is set",
                     FormatShortest(kidnap_distance), "(0, 5] m");
  if (door_close_id.empty() != (door_close_at < 0.0))
    throw InputError("", "parameters 'door_close_id' and 'door_close_at' go together",
                     "'" + door_close_id + "' at " + FormatShortest(door_close_at),
                     "a door id and a time >= 0, or neither");
}

std::optional<DoorFaultWorld> DoorFaultOf(const sim::SceneWorld& mw, const FaultParams& faults) {
  if (faults.door_close_id.empty()) return std::nullopt;
  const std::vector<std::string>& ids = mw.world->DoorIds();
  const scenes::Opening* door = mw.truth ? mw.truth->FindOpening(faults.door_close_id) : nullptr;
  if (!door || std::find(ids.begin(), ids.end(), faults.door_close_id) == ids.end()) {
    std::string names;
    for (const std::string& id : ids) names += (names.empty() ? "" : ", ") + id;
    throw InputError("faults", "parameter 'door_close_id' names no door with a leaf",
                     "'" + faults.door_close_id + "'", "one of " + names);
  }
  return DoorFaultWorld{mw.world.get(), *door};
}

Eigen::Isometry3d SwungLeaf(const scenes::Opening& door, const Eigen::Isometry3d& X_WD,
                            double from_angle, double to_angle) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.translate(door.hinge_point);
  T.rotate(Eigen::AngleAxisd(to_angle - from_angle, door.hinge_axis.normalized()));
  T.translate(-door.hinge_point);
  return T * X_WD;
}

bool FaultParams::Any() const {
  return !tls_empty_scans.empty() || !tls_partial_scans.empty() || lrf_silent_at >= 0.0 ||
         slip_at >= 0.0 || kidnap_at >= 0.0 || !door_close_id.empty();
}

ScanFault ScanFaultOf(const FaultParams& faults, std::uint64_t index) {
  if (Contains(faults.tls_empty_scans, index)) return ScanFault::kEmpty;
  if (Contains(faults.tls_partial_scans, index)) return ScanFault::kPartial;
  return ScanFault::kNone;
}

std::size_t ApplyScanFault(ScanFault fault, double partial_fraction, interfaces::TlsScan& scan,
                           sim::TlsTruth* truth) {
  if (fault == ScanFault::kNone) return 0;
  // Columns from `first_lost` on return nothing.
  std::uint32_t first_lost = 0;
  if (fault == ScanFault::kPartial)
    first_lost = static_cast<std::uint32_t>(
        std::clamp(std::floor(partial_fraction * scan.columns), 0.0, double(scan.columns)));
  std::size_t lost = 0;
  for (std::size_t i = 0; i < scan.points.size(); ++i) {
    interfaces::TlsPoint& p = scan.points[i];
    if (p.column < first_lost) continue;
    if (p.valid()) ++lost;
    interfaces::TlsPoint none;
    none.row = p.row;
    none.column = p.column;
    none.timestamp = p.timestamp;
    p = none;
    if (truth && i < truth->points.size() && truth->points[i].true_range > 0.0f)
      truth->points[i].flags |= sim::kTruthDropped;
  }
  return lost;
}

Pose2 SlippedMotion(const Pose2& delta, double factor) {
  return {delta.x * factor, delta.y * factor, delta.yaw * factor};
}

bool KidnapTarget(const Pose2& from, double direction, double distance,
                  const std::function<bool(const Pose2&)>& free, Pose2* to) {
  constexpr double kRingStep = 0.05, kSlideStep = 0.02;  // m
  constexpr int kDirections = 72;
  const double tx = from.x + distance * std::cos(direction);
  const double ty = from.y + distance * std::sin(direction);
  auto slides_free = [&](const Pose2& end) {
    const double length = std::hypot(end.x - from.x, end.y - from.y);
    const int n = std::max(1, static_cast<int>(std::ceil(length / kSlideStep)));
    for (int k = 1; k <= n; ++k) {
      const double s = static_cast<double>(k) / n;
      if (!free({from.x + s * (end.x - from.x), from.y + s * (end.y - from.y), from.yaw}))
        return false;
    }
    return true;
  };
  const int rings = static_cast<int>(std::round(kKidnapSearchRadius / kRingStep));
  for (int ring = 0; ring <= rings; ++ring) {
    const double r = ring * kRingStep;
    bool found = false;
    Pose2 best;
    double best_d = 1e300;
    for (int k = 0; k < (ring == 0 ? 1 : kDirections); ++k) {
      const double a = 2.0 * kPi * k / kDirections;
      const Pose2 c{tx + r * std::cos(a), ty + r * std::sin(a), from.yaw};
      // Of one ring, the candidate that moves the base least beyond the intended push.
      const double d = std::abs(std::hypot(c.x - from.x, c.y - from.y) - distance);
      if (d >= best_d || !slides_free(c)) continue;
      best = c, best_d = d, found = true;
    }
    if (found) {
      *to = best;
      return true;
    }
  }
  return false;
}

}  // namespace mopad::mission
