#pragma once
// Checks that every loader runs on what it read. tinygltf (and, less often, assimp) accept files
// the glTF spec forbids: ±Inf positions, indices past the vertex count, nodes that are their own
// ancestors (naive recursion overflows the stack), nodes with two parents. These functions turn
// each such defect into one mopad::InputError line instead of a crash or a silently wrong scene.
// No third-party types: the loaders convert to plain vectors first.

#include <Eigen/Core>
#include <cstddef>
#include <string>
#include <vector>

#include "scenes/scene.h"

namespace mopad::scenes {

/// Checks a node graph before anyone walks it. `children[i]` lists node i's children; `roots` the
/// nodes a scene instances. Rejects: a child or root index out of range, a node listed twice as
/// a child (two parents, or twice under one parent: the glTF spec requires disjoint trees, and a
/// DAG would instance a subtree twice), a root that is also someone's child, and any cycle
/// (including unreachable ones and a node that is its own child). Iterative, O(nodes + edges).
/// Throws InputError("`where`: error: ...").
void CheckNodeForest(const std::string& where, const std::vector<std::vector<int>>& children,
                     const std::vector<int>& roots);

/// True when the triangle has (numerically) zero area: its doubled area is at most 1e-7 times
/// its longest edge squared, i.e. it is a point, a segment or a sliver thinner than float
/// precision can represent. Such triangles cannot be hit by a ray.
bool IsDegenerateTriangle(const Eigen::Vector3f& a, const Eigen::Vector3f& b,
                          const Eigen::Vector3f& c);

/// What ValidateScene changed.
struct SceneValidationStats {
  std::size_t degenerate_triangles_dropped = 0;
  std::size_t empty_parts_removed = 0;  ///< parts left without any triangle
};

/// Final gate of every loader, on the world-frame scene: every position and UV finite; uvs
/// empty or one per position; every triangle index in [0, positions); material and texture
/// indices in range; texture pixel buffers of width*height*4 bytes. Then drops degenerate
/// triangles if asked, removes parts without triangles, and rejects a scene with none left.
/// Messages name `scene->source`.
SceneValidationStats ValidateScene(Scene* scene, bool drop_degenerate_triangles);

}  // namespace mopad::scenes
