#pragma once
// ISPRS Benchmark on Indoor Modelling surface metrics (Khoshelham et al. 2017/2018):
//   completeness(b) = area of reference surfaces within distance b of a source surface / total
//                     reference area;
//   correctness(b)  = area of source surfaces within b of a reference surface / total source area;
//   accuracy        = median distance from source surface points to the nearest reference
//                     surface, over the points whose distance is <= the cut-off r.
// Source = the reconstructed model, reference = the truth.
//
// Areas come from deterministic uniform area sampling: each polygon is sampled at the centres
// of a square grid of spacing `sample_spacing` laid in its PlaneFrame from the polygon's 2D
// bounding-box corner; each sample carries area(polygon) / n_samples, so totals are exact and
// shares carry a discretisation error of about (perimeter * spacing / 2) / area (1 cm spacing,
// 3 m x 2.5 m wall: < 1%). Polygons too small to hold a grid centre get one sample at their
// vertex centroid. "Within b" is distance <= b + 1 nm (a surface offset by exactly b counts).
// Distances are exact point-to-polygon distances (plane distance inside the
// polygon, distance to the boundary in 3D otherwise), capped above max(buffer_max, cutoff).
//
// Per class (same_class_only = true, the default and the benchmark's per-class reading): a
// sample is compared with the other side's surfaces of its own class only. "all" aggregates all
// classes' samples. Note that with this definition the border strip of a patch lies within b of
// the adjacent patches sharing its edge (e.g. a wall's bottom strip near a floor patch when
// same_class_only is false, its side strips near the adjacent walls): a wall displaced by 3 cm
// has completeness equal to that strip's share, not 0, for b < 3 cm.
// Samples are processed in parallel (TBB) into fixed slots: bit-identical with any thread count.

#include <array>
#include <string>
#include <vector>

#include "evaluation/metrics.h"

namespace mopad::evaluation {

struct IsprsParams {
  double sample_spacing = 0.01;  ///< m, area sampling grid, [0.001, 1]
  double buffer_max = 0.15;      ///< m, curves run over b = 0..buffer_max, [0, 1]
  double buffer_step = 0.01;     ///< m, curve step, [0.001, 1]
  double cutoff = 0.10;          ///< m, accuracy cut-off r, (0, 1]
  bool same_class_only = true;   ///< compare each class with the same class only
  PatchValidationParams validation;
  template <class V>
  void Visit(V& v) {
    v("sample_spacing", sample_spacing, Bounds{0.001, 1.0});
    v("buffer_max", buffer_max, Bounds{0.0, 1.0});
    v("buffer_step", buffer_step, Bounds{0.001, 1.0});
    v("cutoff", cutoff, Bounds{1e-6, 1.0});
    v("same_class_only", same_class_only);
    v("validation", validation);
  }
};

/// Completeness and correctness over the buffers, plus accuracy, for one set of surfaces.
/// A value is NaN when its denominator area is zero (e.g. no reference surface of that class).
struct IsprsCurve {
  double reference_area = 0.0;       ///< m^2
  double source_area = 0.0;          ///< m^2
  std::vector<double> completeness;  ///< per buffer
  std::vector<double> correctness;   ///< per buffer
  double accuracy = 0.0;      ///< m, median source->reference distance <= cutoff (NaN if none)
  long accuracy_samples = 0;  ///< source samples within the cut-off
};

struct IsprsResult {
  std::vector<double> buffers;  ///< m, 0, step, ..., buffer_max
  double cutoff = 0.0;
  std::array<IsprsCurve, kNumSurfaceClasses> per_class;  ///< indexed by SurfaceClass
  IsprsCurve all;
  /// Per reference (truth) patch: completeness per buffer; per source patch: correctness.
  std::vector<std::vector<double>> reference_patch_completeness;
  std::vector<std::vector<double>> source_patch_correctness;
  /// Index of the buffer nearest to b (for tables at b = 5 or 10 cm).
  int BufferIndex(double b) const;
};

/// Computes the ISPRS metrics of `source` (model) against `reference` (truth). Validates the
/// patches (InputError). Cost: samples x patches of the compared class (bounding-box pruned).
IsprsResult EvaluateIsprs(const std::vector<Patch>& source, const std::vector<Patch>& reference,
                          const IsprsParams& params = {});

/// Deterministic area samples of one patch (world frame) and the area each one carries.
std::vector<Vec3> SamplePatch(const Patch& patch, double spacing, double* area_per_sample);

}  // namespace mopad::evaluation
