#pragma once
// Internal to scenes/: the layout types random_floor.cpp (the public API, doors, openings,
// components, furniture) and random_floor_layouts.cpp (the corridor, junction and hall
// families) share. Never include from a public header.

#include <Eigen/Geometry>
#include <cmath>
#include <vector>

#include "common/rng.h"
#include "scenes/geometry.h"

namespace mopad::scenes::random_floor {

// Layout happens on wall centre lines: cells tile the footprint and each room's interior
// outline is its cell shrunk by half the wall thickness, so neighbours face each other at
// exactly one wall thickness (what the generator's adjacency expects).
constexpr double kWall = 0.2;            // m
constexpr double kMinCell = 3.0;         // m, smallest office side (centre lines)
constexpr double kMinDoorOverlap = 1.8;  // m, shared centre-line length needed for a door

struct Cell {
  double x0, y0, x1, y1;
  double w() const { return x1 - x0; }
  double h() const { return y1 - y0; }
};

/// What a room is for: offices hang off a hub (a corridor or a hall) when the floor has one.
enum class BlockKind { kOffice, kCorridor, kHall };

/// A room on centre lines: an orthogonal CCW polygon.
struct Block {
  Polygon2 poly;
  BlockKind kind = BlockKind::kOffice;
  bool hub() const { return kind != BlockKind::kOffice; }
};

/// The floor's footprint [0, W] x [0, D] (centre lines) and its rooms, the hub (if any) first.
struct Layout {
  double W = 0.0, D = 0.0;
  std::vector<Block> blocks;
  /// Open doors: every office next to the hub gets its own door to it (a corridor's offices
  /// are entered from the corridor), the rest by a random spanning tree; extra doors between
  /// neighbours appear with this probability.
  bool doors_from_hub = false;
  double extra_door_probability = 0.45;
  /// m, the hub's ceiling height above its floor; 0 = the floor's.
  double hub_ceiling = 0.0;
};

Polygon2 RectPoly(const Cell& c);
/// `v` rounded to a multiple of q (5 cm: the generator's plan grid).
inline double Round(double v, double q = 0.05) { return std::round(v / q) * q; }
/// Cuts [lo, hi] into n pieces of at least min_len at random positions (rounded to 5 cm).
std::vector<double> Cuts(CounterRng& rng, double lo, double hi, int n, double min_len);

/// A long corridor (up to 40 m, 1.5-2.5 m wide) with offices up to 9 m wide on both sides.
Layout CorridorLayout(CounterRng& rng, int rooms);
/// An L or T corridor junction: a corridor across the floor and an arm off it, offices on
/// both sides of both.
Layout JunctionLayout(CounterRng& rng, int rooms);
/// A hall of at least 20 m x 14 m under a 3.4-4.0 m ceiling with offices along one side.
Layout HallLayout(CounterRng& rng, int rooms);
/// Columns on a grid of about 6 m in the hall (block `hall`), at least 1.5 m from its walls.
std::vector<Eigen::Vector2d> HallColumnGrid(const Polygon2& hall_interior);

}  // namespace mopad::scenes::random_floor
