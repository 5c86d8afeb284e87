#pragma once
// What `mopad scene info` reports (and `mopad run` of its scene): geometry counts per class and,
// when a truth sidecar is present, rooms, walls, openings (doors by state) and service components
// per class.

#include <Eigen/Geometry>
#include <map>
#include <optional>
#include <string>

#include "scenes/ground_truth.h"
#include "scenes/scene.h"

namespace mopad::scenes {

struct ClassCount {
  std::size_t elements = 0;  ///< distinct element ids (parts without id count one each)
  std::size_t triangles = 0;
};

struct SceneSummary {
  std::string path;
  std::size_t parts = 0, triangles = 0, materials = 0, textures = 0;
  Eigen::AlignedBox3d bounds;
  std::map<std::string, ClassCount> per_class;  ///< by element class name
  bool has_truth = false;
  std::size_t rooms = 0, walls = 0, floors = 0, ceilings = 0, columns = 0;
  std::size_t doors = 0, doors_open = 0, doors_semi_open = 0, doors_closed = 0, windows = 0;
  std::size_t furniture = 0, connections = 0;
  std::map<std::string, std::size_t> bsc_per_class;
  std::size_t bsc_total = 0;
};

SceneSummary Summarise(const scenes::Scene& scene, const scenes::GroundTruth* truth,
                       const std::string& path);
std::string FormatSceneSummary(const SceneSummary& s);
std::string SceneSummaryJson(const SceneSummary& s);

}  // namespace mopad::scenes
