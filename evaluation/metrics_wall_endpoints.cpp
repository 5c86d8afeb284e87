#include "evaluation/metrics_wall_endpoints.h"

#include <Eigen/Core>
#include <algorithm>
#include <cmath>

#include "common/error.h"
#include "common/frames.h"
#include "evaluation/hungarian.h"
#include "evaluation/json_number.h"

namespace mopad::evaluation {

WallSegment WallSegmentOf(const Patch& wall) {
  Vec2 n(wall.normal.x(), wall.normal.y());
  if (!(n.norm() > 1e-9))
    throw InputError("wall '" + wall.id + "'", "not vertical", "normal without plan component",
                     "a wall face");
  n.normalize();
  const Vec2 u(-n.y(), n.x());  // z x n: left to right seen from the room
  double u0 = 1e300, u1 = -1e300, offset = 0.0;
  for (const Vec3& v : wall.polygon) {
    const Vec2 p(v.x(), v.y());
    u0 = std::min(u0, u.dot(p));
    u1 = std::max(u1, u.dot(p));
    offset += n.dot(p);
  }
  if (wall.polygon.empty() || !(u1 - u0 > 1e-9))
    throw InputError("wall '" + wall.id + "'", "no horizontal extent", "", "a wall face");
  offset /= static_cast<double>(wall.polygon.size());
  WallSegment s;
  s.id = wall.id;
  s.normal = n;
  // Seen from the room (looking along -n), u points to the right: the left end has the larger u.
  s.a = u1 * u + offset * n;
  s.b = u0 * u + offset * n;
  return s;
}

WallEndpointEvaluation EvaluateWallEndpoints(const std::vector<Patch>& model,
                                             const std::vector<Patch>& truth,
                                             const WallEndpointParams& params) {
  auto walls = [](const std::vector<Patch>& patches) {
    std::vector<WallSegment> out;
    for (const Patch& p : patches)
      if (p.cls == SurfaceClass::kWall) out.push_back(WallSegmentOf(p));
    return out;
  };
  const std::vector<WallSegment> m = walls(model), t = walls(truth);
  WallEndpointEvaluation e;
  e.model_walls = static_cast<int>(m.size());
  e.truth_walls = static_cast<int>(t.size());
  const double cos_max = std::cos(params.max_normal_angle_deg * kPi / 180.0);
  Eigen::MatrixXd cost = Eigen::MatrixXd::Constant(t.size(), m.size(), kForbiddenCost);
  for (std::size_t i = 0; i < t.size(); ++i) {
    const Vec2 dir = (t[i].b - t[i].a).normalized();
    const double len = (t[i].b - t[i].a).norm();
    for (std::size_t j = 0; j < m.size(); ++j) {
      if (t[i].normal.dot(m[j].normal) < cos_max) continue;
      const Vec2 mid = 0.5 * (m[j].a + m[j].b);
      if (std::abs(t[i].normal.dot(mid - t[i].a)) > params.max_plane_distance) continue;
      const double s0 = dir.dot(m[j].a - t[i].a), s1 = dir.dot(m[j].b - t[i].a);
      if (std::min(std::max(s0, s1), len) - std::max(std::min(s0, s1), 0.0) <= 0.0) continue;
      cost(i, j) = (m[j].a - t[i].a).norm() + (m[j].b - t[i].b).norm();
    }
  }
  const std::vector<int> assign = SolveAssignment(cost);
  std::vector<int> within(params.thresholds.size(), 0);
  for (std::size_t i = 0; i < t.size(); ++i) {
    if (assign[i] < 0) continue;
    const WallSegment& w = m[static_cast<std::size_t>(assign[i])];
    WallEndpointPair pair{w.id, t[i].id, (w.a - t[i].a).norm(), (w.b - t[i].b).norm()};
    for (double err : {pair.error_a, pair.error_b}) {
      e.endpoint_error.Add(err);
      for (std::size_t k = 0; k < params.thresholds.size(); ++k)
        if (err <= params.thresholds[k]) ++within[k];
    }
    e.pairs.push_back(pair);
  }
  for (std::size_t k = 0; k < params.thresholds.size(); ++k)
    e.scores.push_back({params.thresholds[k],
                        PrecisionRecall::From(within[k], 2 * e.model_walls, 2 * e.truth_walls)});
  return e;
}

nlohmann::ordered_json ToJson(const WallEndpointEvaluation& e) {
  nlohmann::ordered_json j;
  j["model_walls"] = e.model_walls;
  j["truth_walls"] = e.truth_walls;
  j["pairs"] = static_cast<int>(e.pairs.size());
  j["endpoint_error_mean_m"] = Num<nlohmann::ordered_json>(e.endpoint_error.mean);
  j["endpoint_error_max_m"] = Num<nlohmann::ordered_json>(e.endpoint_error.max);
  nlohmann::ordered_json scores = nlohmann::ordered_json::array();
  for (const auto& s : e.scores)
    scores.push_back({{"threshold_m", s.threshold},
                      {"within", s.endpoints.tp},
                      {"precision", s.endpoints.precision},
                      {"recall", s.endpoints.recall},
                      {"f1", s.endpoints.f1}});
  j["endpoints"] = scores;
  nlohmann::ordered_json pairs = nlohmann::ordered_json::array();
  for (const auto& p : e.pairs)
    pairs.push_back({{"model", p.model_id},
                     {"truth", p.truth_id},
                     {"error_a_m", Num<nlohmann::ordered_json>(p.error_a)},
                     {"error_b_m", Num<nlohmann::ordered_json>(p.error_b)}});
  j["walls"] = pairs;
  return j;
}

}  // namespace mopad::evaluation
