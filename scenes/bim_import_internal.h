#pragma once
// Internal to scenes/: the types and helpers the steps of the BIM import share
// (docs/scene-import.md). The Importer's steps live by concept in bim_reading.cpp (STEP text,
// node names, loading), bim_rooms.cpp (storey and spaces to rooms), bim_surfaces.cpp (walls,
// floors, ceilings, columns), bim_openings.cpp (doors, windows, passages), bim_components.cpp
// (service components, furniture) and bim_import.cpp (the run, the output, the public API).
// Never include from a public header.

#include <Eigen/Geometry>
#include <cstddef>
#include <map>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "common/ceiling_planes.h"
#include "scenes/bim_import.h"
#include "scenes/geometry.h"
#include "scenes/ground_truth.h"
#include "scenes/scene.h"

namespace mopad::scenes::bim {

using Eigen::Vector2d;
using Eigen::Vector3d;
using Poly3 = std::vector<Vector3d>;

constexpr double kMinPieceArea = 1e-8;      // m^2: clipped slivers below this are dropped
constexpr double kLeafGap = 0.003;          // m, leaf-to-hole clearance (as the generator's)
constexpr double kFacingCos = 0.999;        // a face is parallel to a room plane (2.6 deg)
constexpr double kOpeningReach = 0.8;       // m: an opening's centre lies this deep behind a face
constexpr double kFarFromOrigin = 1e4;      // m: beyond this, float loses the millimetre
constexpr double kFullCover = 0.995;        // share of a room a floor/ceiling must cover
constexpr double kSlopedCeilingCos = 0.5;   // a face facing down within 60 deg of level: ceiling
constexpr double kPassageTolerance = 0.01;  // m: two rooms' edges on one line
constexpr std::size_t kGuidLength = 22;     // IFC GlobalId, base64 of 128 bits

/// Fixed-point text of `v` with `precision` decimals, never "-0.000".
std::string Fmt(double v, int precision = 3);
/// ASCII lower case.
std::string Lower(std::string s);

inline Vector3d Lift(const Vector2d& p, double z) { return {p.x(), p.y(), z}; }

// --- STEP (ISO 10303-21) text: an index of entity instances, attributes, strings
// (bim_reading.cpp). ---

struct StepIndex {
  std::map<unsigned long, std::string> bodies;  // #id -> "IFCWALL('guid',#13,...)"
};

StepIndex IndexStep(const std::string& text);
/// Upper-case entity name of an instance body ("IFCWALL").
std::string EntityOf(const std::string& body);
/// Top-level attributes of "ENTITY(a,b,(c,d),'e,f')".
std::vector<std::string> Attributes(const std::string& body);
/// A STEP string literal 'Eingangst\S\|r' decoded to UTF-8 ('' quotes, \S\ Latin-1,
/// \X2\ UTF-16); "" for $ or a non-string.
std::string StepString(const std::string& attr);
/// Metres per file length unit, all of it (SI prefix and conversion factor): for attributes
/// read from the STEP text (assimp applies the prefix to geometry itself).
double FullLengthScale(const std::string& text, const StepIndex& index, const std::string& where);
/// The whole file; throws InputError if it cannot be opened.
std::string ReadText(const std::string& path);
/// The whole file, which must be IFC 2x3 or IFC4 STEP text (InputError otherwise).
std::string ReadIfcStepText(const std::string& path);
/// The #ids an attribute references, in order ("(#12,#15)" -> 12, 15).
std::vector<unsigned long> StepRefs(const std::string& attr);
/// An IfcOpeningElement's body: the corners (m, the file's world frame) of its extruded
/// rectangles or closed polylines under their placements; a body of anything else is only its
/// placement's origin (`complete` false).
struct OpeningBody {
  std::string filling;  // GlobalId of the door or window filling it (IfcRelFillsElement), or ""
  std::vector<Vector3d> corners;
  bool complete = true;
};
/// Every IfcOpeningElement whose placement can be read (bim_opening_bodies.cpp).
std::vector<OpeningBody> OpeningBodies(const StepIndex& step, double scale);

// --- node names: `<IfcClass>_<Name without spaces>_<GlobalId>` (bim_reading.cpp) ---

/// The GlobalId at the end of a node name, "" if there is none.
std::string NodeGuid(const std::string& node);
/// The name part between the IFC class and the GlobalId.
std::string NodeLabel(const std::string& node);
/// Valid UTF-8 for ids and names written to JSON and glTF: invalid bytes (Latin-1 names some
/// IFC writers leave in STEP strings) become '?'.
std::string CleanUtf8(const std::string& s);
std::string NoSpaces(std::string s);

// --- what an IFC element becomes (bim_reading.cpp; ComponentClass in bim_components.cpp) ---

enum class Role { kSpace, kWall, kSlab, kColumn, kDoor, kWindow, kComponent, kFurniture, kOther };

/// Catalogue class of a component from its IFC class, its type object's class and, where those
/// are generic (IfcFlowTerminal, IfcBuildingElementProxy, IfcSensor, IfcLightFixture, ...), the
/// words of its name and its type object's name (`names`, English or German: "Steckdose",
/// "Smoke detector", "Raumthermostat"); `other:<IfcClass>` when none says a catalogue class.
/// Sizes pick sockets.
std::string ComponentClass(const std::string& ifc, const std::string& type_class,
                           const Eigen::Vector3d& size, const std::string& names = "");
bool IsComponentIfc(const std::string& ifc);
Role RoleOf(const std::string& ifc, ElementClass cls);

// --- convex polygon clipping in 3D (ClipHalfSpace, common/polygon.h): the pieces stay exactly
// on their original plane (bim_surfaces.cpp) ---

struct HalfSpace {
  Vector3d n;  // inside: n . x <= c
  double c;
};

/// Area (m^2) of a planar polygon, any winding; 0 for fewer than 3 vertices.
double Area(const Poly3& p);
/// A piece worth keeping: not a float-noise sliver (area or width under ~1 um).
bool Solid(const Poly3& p);
/// poly = inside + sum(outside): inside = poly within all half-spaces (empty if a sliver).
void Split(const Poly3& poly, const std::vector<HalfSpace>& region, Poly3* inside,
           std::vector<Poly3>* outside);
/// Unit normal by the right-hand rule, zero for a degenerate polygon.
Vector3d NormalOf(const Poly3& p);
/// The plan prism of the CCW triangle `ear` of `poly`: left of each of its edges.
std::vector<HalfSpace> EarRegion(const std::vector<Vector2d>& poly, const Eigen::Vector3i& ear);

// --- the output: buckets of pieces, one MeshPart each, in order of creation (bim_import.cpp) ---

struct Bucket {
  std::string name, id, subclass, room;
  ElementClass cls = ElementClass::kOther;
  int material = -1;
  std::vector<Poly3> pieces;
};

class Output {
 public:
  /// The bucket of (id, cls, subclass, room, material), made on first use; its part is named
  /// `<name or id>/<bucket index>`.
  Bucket& Get(const std::string& id, ElementClass cls, const std::string& subclass,
              const std::string& room, int material, const std::string& name = "");
  std::vector<Bucket>& buckets() { return buckets_; }
  /// One MeshPart per non-empty bucket, vertices shared where their float positions agree.
  std::vector<MeshPart> Parts() const;

 private:
  std::vector<Bucket> buckets_;
  std::map<std::string, std::size_t> index_;
};

// --- the model's elements, rooms and room wall faces ---

struct Element {
  std::string node;  // node name = id of its leftovers
  std::string ifc;   // IFC class
  std::vector<std::size_t> parts;
  Eigen::AlignedBox3d box;
  bool in_storey = false;
  bool merged = false;
  Role role = Role::kOther;
};

struct RoomData {
  Room room;
  std::string node;
  Polygon2 poly;
  std::vector<Eigen::Vector3i> ears;
};

/// One plane of a room's sloped ceiling (a roof's underside over an attic) and the slab faces
/// on it inside the room.
struct CeilingFaces {
  CeilingPlane plane;          // n unit, facing down into the room
  std::string id;              // truth element id, "ceiling_<room>_<k>"
  std::vector<Vector2d> plan;  // the plan vertices of its pieces
  double plan_area = 0.0;      // m^2, of its pieces seen from below
};

struct Face {
  int room = -1;
  int edge = -1;
  std::string id;
  Vector3d a, dir, n;  // edge start at the room's floor, unit direction, unit inward normal
  double length = 0.0, z0 = 0.0, z1 = 0.0;
  std::vector<std::pair<std::size_t, Poly3>> pieces;  // (element, piece)
  std::vector<int> materials;                         // per piece
  double umin = 0.0, umax = 0.0, vmin = 0.0, vmax = 0.0, area = 0.0;
  double w = 0.0;  // m, the wall plane's offset from the room edge along n (wall_search)
  bool kept = false;
  double U(const Vector3d& p) const { return (p - a).dot(dir); }
  double W(const Vector3d& p) const { return (p - a).dot(n); }
  std::vector<HalfSpace> Region() const {
    return {{-dir, -dir.dot(a)},
            {dir, dir.dot(a) + length},
            {-Vector3d::UnitZ(), -z0},
            {Vector3d::UnitZ(), z1}};
  }
};

/// Coverage of the face's pieces along the line v = const (horizontal, vertical = false) or
/// u = const (vertical): merged intervals of the other coordinate (bim_openings.cpp).
std::vector<std::pair<double, double>> Coverage(const Face& f, bool vertical, double at);
/// The uncovered interval around `x` within [lo, hi]; false if x is covered.
bool GapAround(const std::vector<std::pair<double, double>>& cov, double x, double lo, double hi,
               double* g0, double* g1);
/// The outline of a space's bottom face (triangles facing down at its lowest z), CCW from
/// above (bim_rooms.cpp).
bool Footprint(const std::vector<Poly3>& tris, double z_min, double tol, Polygon2* out,
               std::string* why);

/// One import: Run() takes the steps in order, each reading what the earlier ones made.
class Importer {
 public:
  Importer(const std::string& path, const BimImportParams& params) : path_(path), p_(params) {}

  BimImport Run();

 private:
  struct Hole {
    std::size_t face;
    double u0, u1, v0, v1;  // in the face's edge frame (u from f.a, v = z)
    double dist;
  };
  /// Where a generated door leaf hangs: hinge on face `f` at a jamb of hole `h`, opening from
  /// `dd` (hinge -> latch) towards `n` (into the swing room); `lw` the leaf width, m.
  struct Swing {
    const Face* f;
    const Hole* h;
    bool left;
    Vector3d n, dd, hinge;
    double lw;
  };

  // --- loading (bim_reading.cpp) ---
  void Load();
  // Names, type objects and storey spaces from an IFC file's STEP text (GlobalId keyed).
  void ReadStepInfo(const std::string& path);
  std::string NiceName(const std::string& node) const;
  std::string NiceNameOnly(const std::string& node) const;

  // --- storey and rooms (bim_rooms.cpp) ---
  // Storey node segments of a part's node path (assimp: "a/b/IfcBuildingStorey_x_guid/...").
  static std::string StoreyOf(const std::string& node_path);
  void SelectStorey();
  std::string StoreyName(const std::string& node) const;
  std::vector<Poly3> Triangles(const Element& e) const;
  void MakeRooms();
  // Share of room r's footprint covered by slab faces facing up (down) at height z.
  double SlabCover(std::size_t r, double z, bool up) const;
  void ResolveHeights();
  void Shift();

  // --- wall faces, floors, ceilings, columns (bim_surfaces.cpp) ---
  void MakeFaces();
  void Leftover(std::size_t e, int material, Poly3 piece);
  void FindWallPlanes();
  void DistributeStructure();
  void FinishFaces();
  void FloorsAndCeilings();
  int RepairMaterial(bool floor);
  int RoomAt(const Vector3d& p) const;

  // --- sloped ceilings, roofs over attics (bim_sloped_ceilings.cpp) ---
  // The parts of a slab's down-facing tilted `pieces` under a room's top: that room's ceiling
  // on their plane (bucketed, counted in ceiling_area_ seen from below). Returns the rest.
  std::vector<Poly3> SlopedCeilingPieces(int material, const Vector3d& n,
                                         std::vector<Poly3> pieces);
  // Each ceiling plane of a room with a sloped one, cut to where it is the lowest; the room's
  // wall faces topped by them.
  void SlopedCeilings();
  void Columns();
  void AllToLeftover(std::size_t ei, std::size_t pi);

  // --- doors, windows, open passages (bim_openings.cpp) ---
  // Faces with a hole around the element's centre, nearest first.
  std::vector<Hole> HolesAround(const Element& e) const;
  const StructuralElement& WallOf(const Face& f) const;
  void FillRect(Opening* o, const Hole& h) const;
  double DoorAngleDeg(const std::string& id, const Element& e) const;
  int LeafMaterial();
  void Openings();
  void ReportHoleShape(const Element& e, const Hole& h);
  void AddWindow(const Element& e, const Face& f0, Opening* o);
  void AddDoor(const Element& e, const std::vector<Hole>& holes, Opening* o);
  Swing MakeSwing(const std::vector<Hole>& holes, std::size_t k, bool left) const;
  bool SwingFits(const Swing& sw) const;
  Swing ChooseSwing(const Element& e, const std::vector<Hole>& holes, std::size_t hole_b);
  void AddLeaf(const Opening& o, const Swing& sw, double lambda, const std::string& swing_room);
  // Holes through a wall between two rooms that no door or window fills: leafless doorways.
  void Doorways();
  // A hole the reader cut larger than the IfcOpeningElement it belongs to: the wall restored
  // around the opening's body, the holes shrunk to it (a repair).
  void ReconcileHole(const Element& e, bool door, std::vector<Hole>* holes);
  struct Sides {
    bool left, right, below, above;  // along the first hole's face: u down, u up, z down, z up
  };
  void RestoreAroundBody(const std::vector<Vector3d>& body, const Sides& sides,
                         std::vector<Hole>* holes);
  // Area of e's own triangles in the plane of the convex polygon `piece` and inside it, m^2.
  double OwnCover(const Element& e, const Poly3& piece) const;
  // Wall inside an opening's rectangle (a round window, a sill): the opening's frame.
  void FillHole(const Opening& o, const Hole& h, bool door);
  // Rooms sharing a boundary stretch without a wall (open-plan spaces): open passages.
  void Passages();

  // --- service components and furniture (bim_components.cpp) ---
  void Components();
  // Smallest-area yaw of the element's plan extent, from its horizontal edge directions.
  void Yawed(const Element& e, FurnitureItem* fi) const;
  bool HostComponent(std::size_t ei, std::map<std::string, int>* counts);

  // --- the result (bim_import.cpp) ---
  // One repair: listed when `allowed`, else kept for the refusal naming `option`.
  void Repair(const std::string& what, const std::string& where, const std::string& from,
              const std::string& to, bool allowed, const std::string& option);
  void Finish();

  const std::string path_;
  const BimImportParams p_;
  Scene scene_;
  std::map<std::string, std::string> names_;       // GlobalId -> IFC Name
  std::map<std::string, std::string> type_class_;  // GlobalId -> "ifcoutlet" (its type object)
  std::map<std::string, std::string> type_guid_;   // GlobalId -> its type object's GlobalId
  std::map<std::string, std::vector<std::string>> storey_spaces_;  // storey -> space GlobalIds
  std::vector<OpeningBody> opening_bodies_;  // of the model's IfcOpeningElements
  // storey GlobalId -> (element GlobalId, ENTITY) of IfcRelContainedInSpatialStructure
  std::map<std::string, std::vector<std::pair<std::string, std::string>>> storey_contained_;
  std::set<std::size_t> merged_parts_, storey_parts_;
  std::vector<Element> elements_;
  std::string storey_;
  double next_storey_low_ = 1e300;
  double z0_ = 0.0, top_ = -1e300;
  std::vector<RoomData> rooms_;
  std::vector<Face> faces_;
  std::vector<Hole> holes_;                 // of every opening, on every face it was found in
  std::set<std::size_t> walls_with_faces_;  // elements
  std::map<std::size_t, double> floor_area_, ceiling_area_;
  std::map<int, int> columns_in_;
  std::vector<StructuralElement> walls_, floors_, ceilings_, columns_;
  std::map<std::size_t, std::vector<CeilingFaces>> slopes_;  // room -> its sloped ceiling planes
  std::vector<StructuralElement> sloped_ceilings_;
  std::set<std::string> other_ids_;
  mutable std::set<std::string> used_door_keys_;
  std::vector<std::pair<std::string, std::string>> needed_;  // (repair line, option)
  int doors_ = 0;                                            // D<k> ids given so far
  Output out_bucket_;
  BimImport out_;
};

}  // namespace mopad::scenes::bim
