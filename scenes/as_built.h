#pragma once
// As-built geometry: a building as it stands, not as it was drawn. Real walls are neither flat
// nor plumb, corners are off square and slabs are not level; DIN 18202 (tolerances in building
// construction) bounds by how much. Here the building's departure from its design is one smooth
// displacement field D(p) over the world (m -> m), and every vertex of every surface, frame,
// leaf, component and piece of furniture is moved by it: what meets in the design meets as
// built, nothing opens or interpenetrates, and components stay on their (moved) walls.
//
//   D(p) = sum_k A_k sin(w_k . p + phi_k)            flatness: bows and waves, slabs not level
//        + z * sum_j (g_j, 0) sin(q_j . (x, y) + psi_j)   lean: vertical surfaces not plumb
//
// k < 12 terms with random directions w_k (|w_k| = 2 pi / lambda, lambda uniform in
// [wavelength, 3 wavelength]) and vector amplitudes A_k (each component's stationary 1 sigma is
// `flatness_mm`); j < 6 lean terms with horizontal q_j (lambda in [2, 6] x wavelength) and
// horizontal g_j (each component's 1 sigma is `lean_sigma_deg`, as a slope). Corners off
// square follow from the field's horizontal variation of horizontal displacement. z is world z,
// the height above the generated storey's floor (at 0); a building of several storeys, each
// built plumb on the one below within its own tolerance, needs the lean per storey.
//
// The surfaces are subdivided first (every triangle to edges <= mesh_spacing), so the field's
// curvature shows. Where two surfaces meet without shared vertices (a wall's edge against a
// ceiling's) the gap opened is at most the field's deviation from linear over one
// mesh_spacing, |D''| s^2 / 8: over 400 000 random 0.25 m segments at most 0.22 mm for the
// `typical` profile and 0.43 mm for `hard` (24 mm over a 3 m edge left whole).
//
// The truth keeps the design (planes, corners, centres); `AsBuiltTruth` gives the as-built one
// (each element's best-fit plane through its moved surface, corners and centres moved), so an
// evaluator can score against both. Deterministic: the field is a pure function of the params.

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <vector>

#include "scenes/as_built_params.h"
#include "scenes/ground_truth.h"
#include "scenes/scene.h"

namespace mopad::scenes {

/// The displacement field of one as-built building.
class AsBuiltField {
 public:
  explicit AsBuiltField(const AsBuiltParams& params);
  /// m, the as-built position of design point p is p + Displacement(p).
  Eigen::Vector3d Displacement(const Eigen::Vector3d& p) const;
  Eigen::Vector3d Moved(const Eigen::Vector3d& p) const { return p + Displacement(p); }

 private:
  struct Term {
    Eigen::Vector3d amplitude, omega;
    double phase = 0.0;
  };
  std::vector<Term> flat_, lean_;  // lean_: amplitude and omega horizontal (z = 0)
};

/// Subdivides every triangle of the scene to edges <= params.mesh_spacing (uvs interpolated)
/// and moves every vertex by the field. No-op when !params.Enabled().
void ApplyAsBuilt(const AsBuiltParams& params, Scene* scene);

/// The truth as built: every structural element's polygons moved and flattened onto the
/// best-fit plane of its moved surface (normal refitted), openings' corners and centres and
/// service components' centres moved. Returns `design` unchanged when !params.Enabled().
GroundTruth AsBuiltTruth(const GroundTruth& design, const AsBuiltParams& params);

/// How far one element's as-built surface departs from its design plane, sampled on a grid of
/// its polygons: the normal component of D (mm) and the tilt of its best-fit plane (deg).
struct SurfaceDeviation {
  double rms_mm = 0.0, max_mm = 0.0;
  double tilt_deg = 0.0;
};
SurfaceDeviation MeasureDeviation(const StructuralElement& e, const AsBuiltField& field);

}  // namespace mopad::scenes
