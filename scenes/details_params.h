#pragma once
// The parameters of a building's details (scenes/generator.h places them): what a finished
// office has on and around its walls that is neither structure nor a service component nor
// furniture — skirting boards, ceiling trims, cable ducts, pipes, posters and whiteboards — and
// the two openings the paper's real building failed on: door frames painted close to the wall's
// colour and glazed door leaves. Kept in a scene spec (`details:`) and in a run's realism
// profile (`realism.details`); docs/realism.md gives each value's source.

#include <cstdint>

#include "common/params.h"

namespace mopad::scenes {

struct DetailsParams {
  /// m, height of the skirting board along every wall at the floor, [0, 0.3]; 0 = none
  double skirting_height = 0.0;
  double skirting_depth = 0.015;  ///< m, how far it stands proud of the wall, [0.005, 0.05]
  /// m, height of the trim (cornice) along every wall at the ceiling, [0, 0.3]; 0 = none
  double ceiling_trim_height = 0.0;
  double ceiling_trim_depth = 0.03;  ///< m, how far it stands proud of the wall, [0.005, 0.1]
  /// Mean number of cable ducts per room (0.12 m x 0.06 m trunking under the ceiling along the
  /// free stretch of one wall, at least 1 m long), [0, 10]
  double ducts_per_room = 0.0;
  /// Mean number of vertical pipes per room (risers 0.05-0.11 m across, floor to ceiling, in a
  /// corner), [0, 4]
  double pipes_per_room = 0.0;
  /// Mean number of posters, pictures and whiteboards per room (flat colour on the walls, 3-15
  /// mm proud, 0.4-1.5 m wide), [0, 20]
  double posters_per_room = 0.0;
  /// Probability that a door's frame is painted close to its wall's colour (unless the spec
  /// gives the door a frame colour), [0, 1]
  double frames_in_wall_colour = 0.0;
  /// Probability that a door's leaf is glazed (a wooden frame round an 8 mm pane from 0.3 m
  /// above the floor to 0.2 m below the leaf's top), [0, 1]
  double glazed_doors = 0.0;
  std::uint64_t seed = 1;  ///< the details' draw (a run sets its own seed)

  bool Enabled() const {
    return skirting_height > 0.0 || ceiling_trim_height > 0.0 || ducts_per_room > 0.0 ||
           pipes_per_room > 0.0 || posters_per_room > 0.0 || frames_in_wall_colour > 0.0 ||
           glazed_doors > 0.0;
  }

  template <class V>
  void Visit(V& v) {
    v("skirting_height", skirting_height, Bounds{0, 0.3});
    v("skirting_depth", skirting_depth, Bounds{0.005, 0.05});
    v("ceiling_trim_height", ceiling_trim_height, Bounds{0, 0.3});
    v("ceiling_trim_depth", ceiling_trim_depth, Bounds{0.005, 0.1});
    v("ducts_per_room", ducts_per_room, Bounds{0, 10});
    v("pipes_per_room", pipes_per_room, Bounds{0, 4});
    v("posters_per_room", posters_per_room, Bounds{0, 20});
    v("frames_in_wall_colour", frames_in_wall_colour, Bounds{0, 1});
    v("glazed_doors", glazed_doors, Bounds{0, 1});
    v("seed", seed);
  }
};

}  // namespace mopad::scenes
