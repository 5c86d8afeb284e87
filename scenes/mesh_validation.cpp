#include "scenes/mesh_validation.h"

#include <algorithm>
#include <cmath>
#include <cstdint>

#include "common/error.h"

namespace mopad::scenes {
namespace {

std::string NodeName(int i) { return "node " + std::to_string(i); }

}  // namespace

void CheckNodeForest(const std::string& where, const std::vector<std::vector<int>>& children,
                     const std::vector<int>& roots) {
  const int n = static_cast<int>(children.size());
  // parent[i] = the one node listing i as a child; -1 = none so far.
  std::vector<int> parent(children.size(), -1);
  for (int p = 0; p < n; ++p) {
    for (int c : children[p]) {
      if (c < 0 || c >= n)
        throw InputError(where, NodeName(p) + " has a child index out of range", std::to_string(c),
                         "0.." + std::to_string(n - 1));
      if (c == p)
        throw InputError(where, NodeName(p) + " is its own child (node cycle)", "",
                         "an acyclic node hierarchy");
      if (parent[c] != -1)
        throw InputError(where, NodeName(c) + " has more than one parent",
                         "parents " + std::to_string(parent[c]) + " and " + std::to_string(p),
                         "one parent (glTF node hierarchies are disjoint trees)");
      parent[c] = p;
    }
  }
  // With at most one parent per node, a cycle is a closed parent chain. Walk each chain up
  // iteratively, marking nodes done once their chain reaches a root (memoised: O(n) total).
  enum : std::uint8_t { kUnseen, kOnPath, kDone };
  std::vector<std::uint8_t> state(children.size(), kUnseen);
  std::vector<int> path;
  for (int start = 0; start < n; ++start) {
    path.clear();
    int v = start;
    while (v != -1 && state[v] == kUnseen) {
      state[v] = kOnPath;
      path.push_back(v);
      v = parent[v];
    }
    if (v != -1 && state[v] == kOnPath)
      throw InputError(where, "node cycle through " + NodeName(v), "", "an acyclic node hierarchy");
    for (int p : path) state[p] = kDone;
  }
  for (int r : roots) {
    if (r < 0 || r >= n)
      throw InputError(where, "scene root node index out of range", std::to_string(r),
                       "0.." + std::to_string(n - 1));
    if (parent[r] != -1)
      throw InputError(where, "scene root " + NodeName(r) + " is a child of " + NodeName(parent[r]),
                       "", "scene nodes that are roots");
  }
  for (std::size_t i = 0; i < roots.size(); ++i)
    for (std::size_t j = i + 1; j < roots.size(); ++j)
      if (roots[i] == roots[j])
        throw InputError(where, "scene lists " + NodeName(roots[i]) + " twice", "",
                         "each root once");
}

bool IsDegenerateTriangle(const Eigen::Vector3f& a, const Eigen::Vector3f& b,
                          const Eigen::Vector3f& c) {
  const Eigen::Vector3d ab = (b - a).cast<double>();
  const Eigen::Vector3d ac = (c - a).cast<double>();
  const Eigen::Vector3d bc = (c - b).cast<double>();
  const double longest2 = std::max({ab.squaredNorm(), ac.squaredNorm(), bc.squaredNorm()});
  if (longest2 == 0.0) return true;
  // |ab x ac| = 2 * area = longest edge * height; height / longest edge below 1e-7 is below
  // float resolution (2^-23 ~ 1.2e-7): the triangle is a line.
  return ab.cross(ac).norm() <= 1e-7 * longest2;
}

SceneValidationStats ValidateScene(Scene* scene, bool drop_degenerate_triangles) {
  SceneValidationStats stats;
  const std::string& where = scene->source;
  for (std::size_t t = 0; t < scene->textures.size(); ++t) {
    const Texture& tex = scene->textures[t];
    if (tex.width <= 0 || tex.height <= 0 ||
        tex.rgba.size() != static_cast<std::size_t>(tex.width) * tex.height * 4)
      throw InputError(where, "texture " + std::to_string(t) + " has an inconsistent size",
                       std::to_string(tex.rgba.size()) + " bytes for " + std::to_string(tex.width) +
                           "x" + std::to_string(tex.height),
                       "width*height*4 bytes");
  }
  const int num_textures = static_cast<int>(scene->textures.size());
  for (std::size_t m = 0; m < scene->materials.size(); ++m) {
    const int t = scene->materials[m].base_color_texture;
    if (t < -1 || t >= num_textures)
      throw InputError(where, "material " + std::to_string(m) + " texture index out of range",
                       std::to_string(t), "-1.." + std::to_string(num_textures - 1));
  }
  const int num_materials = static_cast<int>(scene->materials.size());
  std::vector<MeshPart> kept;
  kept.reserve(scene->parts.size());
  for (MeshPart& part : scene->parts) {
    const std::string what = "mesh part '" + part.name + "'";
    if (part.material < -1 || part.material >= num_materials)
      throw InputError(where, what + " material index out of range", std::to_string(part.material),
                       "-1.." + std::to_string(num_materials - 1));
    for (std::size_t i = 0; i < part.positions.size(); ++i)
      if (!part.positions[i].allFinite())
        throw InputError(where, what + " vertex " + std::to_string(i) + " is not finite",
                         "(" + std::to_string(part.positions[i].x()) + ", " +
                             std::to_string(part.positions[i].y()) + ", " +
                             std::to_string(part.positions[i].z()) + ")",
                         "finite coordinates");
    if (!part.uvs.empty() && part.uvs.size() != part.positions.size())
      throw InputError(where, what + " has a UV count unlike its vertex count",
                       std::to_string(part.uvs.size()), std::to_string(part.positions.size()));
    for (std::size_t i = 0; i < part.uvs.size(); ++i)
      if (!part.uvs[i].allFinite())
        throw InputError(where, what + " UV " + std::to_string(i) + " is not finite", "",
                         "finite texture coordinates");
    const long long nv = static_cast<long long>(part.positions.size());
    std::size_t out = 0;
    for (std::size_t t = 0; t < part.triangles.size(); ++t) {
      const Eigen::Vector3i tri = part.triangles[t];
      for (int k = 0; k < 3; ++k)
        if (tri[k] < 0 || tri[k] >= nv)
          throw InputError(where, what + " triangle " + std::to_string(t) + " index out of range",
                           std::to_string(tri[k]), "0.." + std::to_string(nv - 1));
      if (drop_degenerate_triangles &&
          IsDegenerateTriangle(part.positions[tri[0]], part.positions[tri[1]],
                               part.positions[tri[2]])) {
        ++stats.degenerate_triangles_dropped;
        continue;
      }
      part.triangles[out++] = tri;
    }
    part.triangles.resize(out);
    if (part.triangles.empty()) {
      ++stats.empty_parts_removed;
      continue;
    }
    kept.push_back(std::move(part));
  }
  scene->parts = std::move(kept);
  if (scene->parts.empty())
    throw InputError(where, "scene has no triangles",
                     stats.degenerate_triangles_dropped
                         ? std::to_string(stats.degenerate_triangles_dropped) +
                               " degenerate triangles, all dropped"
                         : "0",
                     "at least one non-degenerate triangle");
  return stats;
}

}  // namespace mopad::scenes
