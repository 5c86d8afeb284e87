#pragma once
// A plan-view picture of a scene and its truth, for a human to check an import or a generated
// scene at a glance (`mopad scene plan DIR -o plan.png`):
//  - what lies below the cut height seen from above (z-buffered): floors tinted per room,
//    furniture, door leaves, window sills, everything else light grey;
//  - the section of every steep face at the cut height in black (walls and their openings);
//  - the truth on top: wall faces as red lines one pixel inside their room, door openings green
//    with the hinge point as a dot, windows blue, service components magenta, room polygons'
//    vertices as small squares.
// North (+y) is up. Pure function of its inputs: the same scene gives the same pixels.

#include "common/params.h"
#include "scenes/ground_truth.h"
#include "scenes/scene.h"

namespace mopad::scenes {

struct PlanViewParams {
  double pixel_size = 0.02;  ///< m per pixel, (0, 1]
  double cut_height = 1.2;   ///< m above z = 0, the section plane, any finite value
  double margin = 1.0;       ///< m around the rooms' bounding box, [0, 20]
  void Validate() const;     ///< throws InputError naming the field

  template <class V>
  void Visit(V& v) {
    v("pixel_size", pixel_size, Bounds{1e-9, 1.0});
    v("cut_height", cut_height);
    v("margin", margin, Bounds{0.0, 20.0});
  }
};

/// Renders the picture (RGBA8, top row = north). Throws InputError when the truth has no rooms
/// or the picture would exceed 8000 x 8000 pixels.
Texture RenderPlanView(const Scene& scene, const GroundTruth& truth,
                       const PlanViewParams& params = {});

}  // namespace mopad::scenes
