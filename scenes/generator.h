#pragma once
// Procedural office-storey generator: from a SceneSpec (scenes/scene_spec.h) it builds the
// triangle geometry (every triangle labelled with its truth id and class) and the exact ground
// truth (scenes/ground_truth.h), as in the paper's simulated case (§4.3): rooms bounded by
// per-room wall faces (the paper's wall_1A), floors, ceilings, columns, doors with protruding
// frames and hinged leaves at their opening angle lambda (§3.3), windows with glass, building
// service components from the catalogue (scenes/bsc_catalogue.h) and furniture clutter.
//
// Geometry conventions (docs/scene-format.md):
//  - one wall element per room polygon edge, id `wall_<room>_<edge>`, from the floor to the
//    room's ceiling, holes cut where openings are;
//  - rooms are separated by `wall_thickness`; openings are lined through the thickness
//    (door_frame / window_frame class, id = the opening id);
//  - outer wall portions get an exterior face `facade_<room>_<edge>` (class other, subclass
//    facade) offset by the wall thickness;
//  - floors `floor_<room>`, ceilings `ceiling_<room>`; columns `<column id>`; BSCs
//    `<class>_<n>`; furniture `<type>_<room>_<n>`.
// Deterministic: the same spec (including its seed) gives the same Scene, truth and bytes.

#include <string>

#include "scenes/ground_truth.h"
#include "scenes/scene.h"
#include "scenes/scene_spec.h"

namespace mopad::scenes {

struct GeneratedScene {
  Scene scene;        ///< world frame, Z-up, metres; labelled per part
  GroundTruth truth;  ///< the sidecar
  SceneSpec spec;     ///< the effective spec it was generated from
};

/// Builds the scene. Throws InputError (at the spec item's file:line) when the spec cannot be
/// realised: a door not on a wall shared by its rooms, overlapping openings, BSCs or furniture
/// that do not fit, ...
GeneratedScene Generate(const SceneSpec& spec);

/// Writes DIR/scene.glb, DIR/scene.truth.json and DIR/spec.effective.yaml (DIR is created).
void WriteGeneratedScene(const GeneratedScene& generated, const std::string& dir);

}  // namespace mopad::scenes
