#pragma once
// Internal to scenes/: the types and helpers the steps of the scene generator share
// (scenes/generator.h). The Generator's steps live by concept in generator_structure.cpp (rooms,
// wall faces, floors, ceilings, facades, columns), generator_openings.cpp (doors and windows:
// placement, leaves, frames), generator_bscs.cpp (building service components),
// generator_furniture.cpp (furniture and the robot's free path) and generator.cpp (the run,
// materials, the final truth, the public API). Never include from a public header.

#include <Eigen/Geometry>
#include <cstddef>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "common/rng.h"
#include "scenes/bsc_catalogue.h"
#include "scenes/generator.h"
#include "scenes/geometry.h"

namespace mopad::scenes::gen {

using Eigen::Vector2d;
using Eigen::Vector3d;

// Tuning choices of the generator, in one place (docs/scene-spec.md explains them).
constexpr double kTol = 1e-6;            // m, geometric comparisons of spec coordinates
constexpr double kAdjacencyTol = 1e-4;   // m, wall-thickness match for facing room edges
constexpr double kOpeningMargin = 0.02;  // m, casing to wall end / other openings
constexpr double kBscMargin = 0.03;      // m, BSC to BSC / opening frame on a wall
constexpr double kRobotInflation = 0.4;  // m, half of the 0.8 m free path kept for the robot
constexpr double kGridRes = 0.1;         // m, free-path grid cell
constexpr double kSeedReach = 1.2;       // m, farthest free cell taken for a door's seed
constexpr double kLeafGap = 0.003;       // m, leaf-to-frame clearance
constexpr double kDoorZoneDepth = 1.0;   // m, furniture-free depth in front of every door
constexpr int kPlacementAttempts = 400;  // random tries per BSC / furniture item

inline Vector3d Lift(const Vector2d& p, double z) { return {p.x(), p.y(), z}; }
inline Vector3d Flat(const Vector2d& p) { return {p.x(), p.y(), 0.0}; }

/// Part of one face that faces another room across the wall: u in [s0, s1] on this face maps
/// to u' = c - u on face `other`.
struct Adjacency {
  double s0 = 0.0, s1 = 0.0;
  int other = -1;
  double c = 0.0;
};

/// One interior wall face (one room polygon edge): the paper's wall_1A.
struct Face {
  std::string id;
  int room = -1;
  int edge = -1;
  Vector2d a, b, dir, n_in;
  double length = 0.0;
  double z0 = 0.0, z1 = 0.0;
  std::vector<Adjacency> adj;
  std::vector<Rect2> holes;     // cut-outs, (u, v above the floor)
  std::vector<Rect2> keep_out;  // BSC placement: openings with frames, placed BSCs

  double height() const { return z1 - z0; }
  Vector2d Plan(double u, double w = 0.0) const { return a + u * dir + w * n_in; }
  /// Point at u along the face, v above the floor, w along the inward normal.
  Vector3d P(double u, double v, double w = 0.0) const { return Lift(Plan(u, w), z0 + v); }
  const Adjacency* AdjacentTo(double u0, double u1, int other_room,
                              const std::vector<Face>& faces) const {
    for (const auto& ad : adj)
      if (faces[ad.other].room == other_room && ad.s0 <= u0 + kTol && u1 <= ad.s1 + kTol)
        return &ad;
    return nullptr;
  }
};

struct RoomData {
  const RoomSpec* spec = nullptr;
  std::string id;
  Polygon2 poly;
  double z0 = 0.0, z1 = 0.0;
  std::vector<int> faces;
  double area = 0.0, perimeter = 0.0;
};

struct DoorData {
  const DoorSpec* spec = nullptr;
  int face = -1;   // host face in room_a
  int other = -1;  // host face in room_b, -1 for doors to the outside
  Rect2 hole;      // on `face`
  double c = 0.0;  // u' = c - u on `other`
  bool swing_into_a = true;
  bool hinge_high_u = true;  // hinge at hole.u1 of `face` (else at hole.u0)
  double lambda = 0.0;       // rad
};

struct WindowData {
  const WindowSpec* spec = nullptr;
  int face = -1;
  Rect2 hole;
};

struct WallBsc {
  std::string id, cls, room;
  int face = -1;
  Rect2 rect;  // footprint on the face
  double depth = 0.0;
  bool stacked = false;  // another BSC was placed above it
  int reservation = -1;  // keep_out index held free for the BSC to be stacked above it
};

struct CeilingBsc {
  int room = -1;
  Vector2d p;
};

struct FurnitureBox {
  int room = -1;
  Polygon2 footprint;  // CCW
};

/// Plan rectangle w x d centred at `c`, its width along yaw (rad), CCW.
Polygon2 OrientedRect(const Vector2d& c, double yaw, double w, double d);
/// 0 inside the convex polygon, else the distance to its boundary, m.
double DistanceToConvex(const Vector2d& p, const Polygon2& poly);
/// Index drawn with probability proportional to its weight (one draw from `rng`).
std::size_t PickWeighted(CounterRng& rng, const std::vector<double>& w);
/// Oriented box: lo/hi in the frame (o; ex, ey, ez); a left-handed frame is mirrored so the
/// faces still point outward. `skip` as PartBuilder::AddBox.
void AddOrientedBox(PartBuilder& pb, const Vector3d& o, Vector3d ex, const Vector3d& ey,
                    const Vector3d& ez, Vector3d lo, Vector3d hi, int skip = 0);
/// Appends "_<v>", 3 decimals: material names tell overridden colours and transmissions apart.
void AppendNumber(double v, std::string* name);

/// One generation: Run() takes the steps in order, each reading what the earlier ones made.
class Generator {
 public:
  explicit Generator(const SceneSpec& spec) : spec_(spec), t_(spec.wall_thickness) {}

  GeneratedScene Run();

 private:
  /// Door `d`'s leaf at its opening angle. Hinged on the swing-room face: with n the normal
  /// into the swing room and d the direction from the hinge jamb to the latch jamb, "left"
  /// (hinge on the left seen from the swing room, facing the door) gives d = z x n. The leaf
  /// spans a in [0, width] along rd = cos(lambda) d + sin(lambda) n and b in [-thickness, 0]
  /// along rn = cos(lambda) n - sin(lambda) d; the hinge axis is d x n, so +lambda opens the
  /// leaf into the swing room. The hinge stands just in front of the casing (at the floor) so
  /// the opened leaf clears it.
  struct Leaf {
    Vector3d hinge, rd, rn, axis;
    double width = 0.0, thickness = 0.0;  // m
  };
  /// A candidate wall spot of a rule-placed BSC (beside_door, above_door, under_window, above).
  struct Spot {
    int face;
    double u, v;
    int target;  // wall_bscs_ index for "above"
  };
  struct FurnitureShape {
    double w, d, h;
  };
  /// How a door looks beyond its spec (the spec's details): frame_shade > 0 paints its frame
  /// in the wall's colour times that shade; glazed puts a pane in its leaf.
  struct DoorLook {
    double frame_shade = 0.0;
    bool glazed = false;
  };
  /// A glazed leaf's pane: a in [a0, a1] along the leaf's width, z in [z0, z1], `pane` thick.
  struct Glazing {
    double a0, a1, z0, z1, pane;
  };

  // ---- materials and parts (generator.cpp) ----
  int Mat(const std::string& name, const MaterialSpec& m);
  static MeshPart NewPart(const std::string& name, const std::string& id, ElementClass cls,
                          const std::string& subclass, const std::string& room, int material);
  void Push(MeshPart&& p);
  /// Appends facades and rooms to the truth and checks that all ids are unique.
  void Finish();

  // ---- rooms, walls, floors, ceilings, facades, columns (generator_structure.cpp) ----
  void BuildRooms();
  void ComputeAdjacency();
  /// Outer (non-adjacent) intervals of a face.
  std::vector<std::pair<double, double>> OuterPortions(const Face& f) const;
  int RoomIndex(const std::string& id) const { return room_index_.at(id); }
  Polygon2 ColumnFootprint(const ColumnSpec& c) const;
  void CheckColumns();
  void EmitWalls();
  /// Signed extension of an exterior face beyond a polygon vertex (mitre), halved when the
  /// neighbouring edge is shared with another room at that vertex.
  double VertexExtension(const Face& f, bool at_end) const;
  void EmitFacades();
  void EmitFloorsAndCeilings();
  void EmitColumns();

  // ---- doors and windows (generator_openings.cpp) ----
  /// Finds the face of `room` and the centre u for an opening of `width` described by `pos`.
  /// other_room = -1: must be on an outer portion; otherwise on a wall shared with it.
  std::pair<int, double> LocateOpening(int room, const WallPosition& pos, double width,
                                       int other_room, double end_margin, const std::string& what,
                                       const std::string& where) const;
  void AddHole(int face, const Rect2& hole, double frame, const std::string& id,
               const std::string& where);
  void ResolveDoors();
  Leaf LeafOf(const DoorData& d) const;
  /// Plan footprint of an opened leaf (in its swing room).
  Polygon2 LeafFootprint(const DoorData& d) const;
  int SwingRoom(const DoorData& d) const;
  /// Plan rectangle bounding the floor the leaf sweeps from closed to its angle (shrunk by
  /// 1 cm so that neighbouring zones may touch).
  Polygon2 SwingZone(const DoorData& d) const;
  void ResolveWindows();
  /// Plan rectangle kept free of furniture and columns in front of a door, in room `room`.
  Polygon2 DoorZone(const DoorData& d, int room) const;
  /// Point inside `room` in front of a door, where the robot enters.
  Vector2d DoorSeed(const DoorData& d, int room) const;
  std::vector<int> DoorsOfRoom(int room) const;
  /// Hole of door `d` on face `face` and whether its hinge is at the high-u end there.
  std::pair<Rect2, bool> DoorOnFace(const DoorData& d, int face) const;
  /// Casing boxes around a hole on one side of the wall; `w_lo..w_hi` is the box extent along
  /// face `f`'s inward normal, `back_skip` the bit of the face against the wall.
  static void AddCasing(PartBuilder& pb, const Face& f, const Rect2& h, double fw, double w_lo,
                        double w_hi, int back_skip, bool door);
  /// Lining of the opening through the wall thickness (jambs, head, sill/threshold).
  void AddReveals(PartBuilder& pb, const Face& f, const Rect2& h) const;
  void EmitDoors();
  void EmitWindows();

  // ---- building service components (generator_bscs.cpp) ----
  /// Adds the catalogue model of `cls` (materials and textures once per class) transformed by
  /// (origin; ex, ey, ez) with ex x ey = ez (the model's own right-handed frame).
  void AddBscGeometry(const std::string& id, const std::string& cls, const std::string& room,
                      const Vector3d& o, const Vector3d& ex, const Vector3d& ey,
                      const Vector3d& ez);
  std::string NextBscId(const std::string& cls);
  bool WallSpotFree(int face, const Rect2& rect, double depth) const;
  /// Where a BSC of class `stack` (placement `above`) would go over one at `rect`.
  static Rect2 StackRect(const Rect2& rect, const BscSpec& stack, double v_default);
  /// The later entry that stacks components above class `cls`, or nullptr.
  const BscSpecEntry* StackedOver(const std::string& cls, std::size_t after) const;
  void PlaceWallBsc(const BscSpec& cat, int face, double u, double v, const std::string& room,
                    const Rect2* reserve = nullptr);
  void PlaceCeilingBsc(const BscSpec& cat, int room, const Vector2d& p);
  bool CeilingSpotFree(int room, const Vector2d& p, const BscSpec& cat) const;
  std::vector<int> CandidateRooms(const BscSpecEntry& e) const;
  [[noreturn]] void CannotPlace(const BscSpecEntry& e, int k, const std::string& why) const;
  void PlaceBscs();
  void PlaceExplicitBsc(const BscSpecEntry& e, const BscSpec& cat, double v_default);
  void PlaceRandomBscs(std::size_t ei, const BscSpecEntry& e, const BscSpec& cat,
                       const std::vector<int>& rooms, const std::string& placement,
                       double v_default);
  bool TryCeilingBsc(CounterRng& rng, const BscSpec& cat, const std::vector<int>& rooms);
  bool TryWallBsc(CounterRng& rng, const BscSpec& cat, const std::vector<int>& rooms,
                  double v_default, const BscSpecEntry* stack);
  void PlaceRuleBscs(std::size_t ei, const BscSpecEntry& e, const BscSpec& cat,
                     const std::vector<int>& rooms, const std::string& placement, double v_default);
  void RuleSpots(const BscSpecEntry& e, const BscSpec& cat, const std::vector<int>& rooms,
                 const std::string& placement, double v_default, std::vector<Spot>* spots,
                 std::vector<Spot>* second) const;
  bool TakeRuleSpot(const BscSpec& cat, const Spot& s);

  // ---- building details (generator_details.cpp) ----
  /// One draw per door from the details' seed and the door's id (the same door looks the same
  /// whatever else the spec holds).
  DoorLook LookOfDoor(const DoorSpec& ds) const;
  static Glazing GlazingOf(double leaf_width, double leaf_top);
  /// Skirting boards, ceiling trims, ducts, pipes and posters, after the furniture (they keep
  /// clear of openings, components, door swings and the furniture standing at the walls).
  void PlaceDetails();
  /// Adds one detail: a part of class clutter and its truth box (centre, yaw, size in the
  /// frame of face `f`: u along the face, w into the room, v up).
  void AddDetail(const std::string& type, const Face& f, const Vector3d& lo, const Vector3d& hi,
                 int material, int skip = 0);
  /// One of the room's wall faces, drawn with probability proportional to its length.
  Face& WallOfRoom(CounterRng& rng, const RoomData& r);
  void AddSkirtingAndTrims();
  void AddDucts(CounterRng& rng);
  void AddPipes(CounterRng& rng);
  void AddPosters(CounterRng& rng);
  /// Longest stretch [u0, u1] of face `f` at heights [v0, v1] clear of its keep-out zones (by
  /// `margin`), or {0, 0}.
  std::pair<double, double> FreeStretch(const Face& f, double v0, double v1, double margin) const;
  /// Pieces of [0, length] of face `f` at heights [v0, v1] clear of keep-out zones.
  std::vector<std::pair<double, double>> FreePieces(const Face& f, double v0, double v1,
                                                    double margin) const;

  // ---- furniture (generator_furniture.cpp) ----
  static FurnitureShape ShapeOf(const std::string& type, CounterRng& rng);
  void BuildFurnitureMesh(MeshPart* part, const std::string& type, const FurnitureShape& s,
                          const Vector2d& c, double yaw, double z0) const;
  void PlaceFurniture();
  /// Furniture footprint clear of other furniture, columns, door zones, BSCs it would hit or
  /// hide (any wall BSC whose bottom is below the item's top + 0.1 m, within 0.6 m of its wall)
  /// and windows it would block.
  bool FurnitureSpotFree(int room, const Polygon2& fp, double height,
                         const std::vector<Polygon2>& zones) const;

  const SceneSpec& spec_;
  const double t_;
  GeneratedScene out_;
  std::vector<RoomData> rooms_;
  std::map<std::string, int> room_index_;
  std::vector<Face> faces_;
  std::vector<DoorData> doors_;
  std::vector<WindowData> windows_;
  std::vector<FurnitureBox> columns_;
  std::vector<FurnitureBox> furniture_;
  std::vector<WallBsc> wall_bscs_;
  std::vector<CeilingBsc> ceiling_bscs_;
  std::vector<StructuralElement> facades_;
  std::map<std::string, int> materials_;
  std::map<std::string, Scene> bsc_models_;
  std::map<std::string, int> bsc_counts_;
  std::map<std::string, int> detail_counts_;
};

}  // namespace mopad::scenes::gen
