// The BIM import on small IFC 2x3 files written here (docs/scene-import.md): one 4 x 3 m room
// with 0.2 m walls, floor and ceiling slabs, a 0.9 x 2.0 m door in the south wall, a window in
// the east wall and an outlet 2 mm off the north wall. Variants: feet units, the whole building
// turned by 45 deg, a second space without representation, malformed files. Every answer is
// analytic (from the numbers below), never taken from the importer itself.
#include "scenes/bim_import.h"
#include "scenes/bim_import_internal.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "common/error.h"
#include "common/frames.h"
#include "scenes/door_angles.h"
#include "scenes/geometry.h"
#include "scenes/gltf_writer.h"
#include "scenes/ground_truth.h"
#include "scenes/scene_check.h"
#include "scenes/scene_loader.h"

namespace mopad::scenes {
namespace {

namespace fs = std::filesystem;
using Eigen::Vector2d;
using Eigen::Vector3d;

struct Box {  // plan polygon (metres, before rotation) extruded from z0 by h
  std::vector<Vector2d> poly;
  double z0 = 0.0, h = 0.0;
};

Box Rect(double x0, double y0, double x1, double y1, double z0, double h) {
  return {{{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}}, z0, h};
}

struct FixtureOptions {
  double angle_deg = 0.0;  // the whole building turned about z
  bool feet = false;       // write lengths in feet with a FOOT unit
  bool extra_space_without_representation = false;
  bool floor_slab = true;
  bool ceiling_slab = true;
  std::string schema = "IFC2X3";
  bool broken_foot_unit = false;
  bool outlet = true;
  bool extra_door_without_geometry = false;
  bool split_space = false;   // two 2 x 3 m spaces side by side, no wall between them
  double space_inset = 0.0;   // m, the space drawn this much inside the walls
  double space_height = 2.5;  // m (the ceiling slab's underside is at 2.5)
  double space_base = 0.0;    // m, the space's bottom (its top stays at space_height)
  bool west_lining = false;   // the west wall 18 cm, its room face a 2 cm IfcCovering
  bool far = false;           // georeferenced: the building at (500 km, 5400 km)
  bool brep_space = false;    // the space a faceted BRep whose bottom has a T-junction
  bool foundation = false;    // a lower storey "Foundation" with a footing and no space
};

// Writes a small IFC 2x3 STEP file; returns its path.
class IfcWriter {
 public:
  explicit IfcWriter(const FixtureOptions& o) : o_(o) {}

  std::string Write(const fs::path& path) {
    Header();
    const int wall_s = Element("IFCWALLSTANDARDCASE", "South", Rect(-0.2, -0.2, 4.2, 0.0, 0, 2.5));
    Element("IFCWALLSTANDARDCASE", "North", Rect(-0.2, 3.0, 4.2, 3.2, 0, 2.5));
    if (o_.west_lining) {
      Element("IFCWALLSTANDARDCASE", "West", Rect(-0.2, 0.0, -0.02, 3.0, 0, 2.5));
      Element("IFCCOVERING", "Lining", Rect(-0.02, 0.0, 0.0, 3.0, 0, 2.5), ".CLADDING.");
    } else {
      Element("IFCWALLSTANDARDCASE", "West", Rect(-0.2, 0.0, 0.0, 3.0, 0, 2.5));
    }
    const int wall_e = Element("IFCWALLSTANDARDCASE", "East", Rect(4.0, 0.0, 4.2, 3.0, 0, 2.5));
    if (o_.floor_slab)
      Element("IFCSLAB", "Floor", Rect(-0.2, -0.2, 4.2, 3.2, -0.2, 0.2), ".FLOOR.");
    if (o_.ceiling_slab)
      Element("IFCSLAB", "Ceiling", Rect(-0.2, -0.2, 4.2, 3.2, 2.5, 0.2), ".FLOOR.");
    // Door: opening through the south wall, x [1, 1.9], z [0, 2]; the closed leaf in it.
    const int hole_d = Element("IFCOPENINGELEMENT", "", Rect(1.0, -0.3, 1.9, 0.1, 0.0, 2.0));
    const int door = Element("IFCDOOR", "Door-1", Rect(1.0, -0.12, 1.9, -0.08, 0.0, 2.0));
    Rel("IFCRELVOIDSELEMENT", wall_s, hole_d);
    Rel("IFCRELFILLSELEMENT", hole_d, door);
    // Window: east wall, y [1, 2], z [0.9, 2.1].
    const int hole_w = Element("IFCOPENINGELEMENT", "", Rect(3.9, 1.0, 4.3, 2.0, 0.9, 1.2));
    const int window = Element("IFCWINDOW", "Window-1", Rect(4.08, 1.0, 4.12, 2.0, 0.9, 1.2));
    Rel("IFCRELVOIDSELEMENT", wall_e, hole_w);
    Rel("IFCRELFILLSELEMENT", hole_w, window);
    // Outlet 80 x 80 x 40 mm, its back 2 mm off the north wall's room face (y = 3).
    if (o_.outlet) {
      const int outlet =
          Element("IFCFLOWTERMINAL", "Socket-1", Rect(2.0, 2.958, 2.08, 2.998, 0.3, 0.08));
      const int type = Add("IFCOUTLETTYPE('" + Guid() + "',#5,'Socket',$,$,$,$,$,$,.POWEROUTLET.)");
      Add("IFCRELDEFINESBYTYPE('" + Guid() + "',#5,$,$,(#" + std::to_string(outlet) + "),#" +
          std::to_string(type) + ")");
    }
    if (o_.extra_door_without_geometry)
      elements_.push_back(Add("IFCDOOR('" + Guid() + "',#5,'Door-2',$,$,#12,$,$,2.0,0.9)"));
    std::vector<int> spaces;
    if (o_.split_space) {
      spaces.push_back(Element("IFCSPACE", "1", Rect(0.0, 0.0, 2.0, 3.0, 0.0, 2.5)));
      spaces.push_back(Element("IFCSPACE", "2", Rect(2.0, 0.0, 4.0, 3.0, 0.0, 2.5)));
    } else if (o_.brep_space) {
      spaces.push_back(BrepSpace());
    } else {
      const double d = o_.space_inset;
      spaces.push_back(
          Element("IFCSPACE", "1",
                  Rect(d, d, 4.0 - d, 3.0 - d, o_.space_base, o_.space_height - o_.space_base)));
    }
    if (o_.extra_space_without_representation)
      spaces.push_back(Add("IFCSPACE('" + Guid() +
                           "',#5,'2',$,$,#12,$,'Store',.ELEMENT.,"
                           ".INTERNAL.,$)"));
    if (o_.foundation) {
      const int footing =
          Element("IFCFOOTING", "Footing", Rect(-0.2, -0.2, 4.2, 3.2, -1.0, 0.5), ".PAD_FOOTING.");
      elements_.pop_back();  // contained in the foundation storey, not the ground floor
      Add("IFCRELCONTAINEDINSPATIALSTRUCTURE('" + Guid() + "',#5,$,$,(#" + std::to_string(footing) +
          "),#" + std::to_string(foundation_) + ")");
    }
    std::string contained, agg;
    for (int e : elements_) contained += (contained.empty() ? "#" : ",#") + std::to_string(e);
    for (int s : spaces) agg += (agg.empty() ? "#" : ",#") + std::to_string(s);
    Add("IFCRELCONTAINEDINSPATIALSTRUCTURE('" + Guid() + "',#5,$,$,(" + contained + "),#15)");
    Add("IFCRELAGGREGATES('" + Guid() + "',#5,$,$,#15,(" + agg + "))");
    out_ << "ENDSEC;\nEND-ISO-10303-21;\n";
    std::ofstream f(path, std::ios::binary | std::ios::trunc);
    f << out_.str();
    return path.string();
  }

 private:
  std::string Guid() {
    std::string s = std::to_string(++guid_);
    return std::string(22 - s.size(), '0') + s;
  }
  int Add(const std::string& body) {
    out_ << "#" << ++id_ << "=" << body << ";\n";
    return id_;
  }
  std::string L(double metres) const {  // a length in the file's unit
    std::ostringstream s;
    s.precision(12);
    s << std::fixed << (o_.feet ? metres / 0.3048 : metres);
    return s.str();
  }
  Vector2d Turn(const Vector2d& p) const {
    const double a = DegToRad(o_.angle_deg);
    const Vector2d far = o_.far ? Vector2d(500000.0, 5400000.0) : Vector2d::Zero();
    return far + Vector2d(std::cos(a) * p.x() - std::sin(a) * p.y(),
                          std::sin(a) * p.x() + std::cos(a) * p.y());
  }
  void Header() {
    out_ << "ISO-10303-21;\nHEADER;\nFILE_DESCRIPTION(('ViewDefinition [CoordinationView]'),"
            "'2;1');\nFILE_NAME('t.ifc','2026-11-25T00:00:00',(''),(''),'','','');\n"
         << "FILE_SCHEMA(('" << o_.schema << "'));\nENDSEC;\nDATA;\n";
    Add("IFCPERSON($,$,'',$,$,$,$,$)");               // 1
    Add("IFCORGANIZATION($,'o',$,$,$)");              // 2
    Add("IFCPERSONANDORGANIZATION(#1,#2,$)");         // 3
    Add("IFCAPPLICATION(#2,'1','t','t')");            // 4
    Add("IFCOWNERHISTORY(#3,#4,$,.ADDED.,$,$,$,0)");  // 5
    if (o_.feet) {
      Add("IFCDIMENSIONALEXPONENTS(1,0,0,0,0,0,0)");  // 6
      Add("IFCSIUNIT(*,.LENGTHUNIT.,$,.METRE.)");     // 7
      Add(o_.broken_foot_unit ? "IFCMEASUREWITHUNIT(IFCLENGTHMEASURE(oops),#7)"
                              : "IFCMEASUREWITHUNIT(IFCLENGTHMEASURE(0.3048),#7)");  // 8
      Add("IFCCONVERSIONBASEDUNIT(#6,.LENGTHUNIT.,'FOOT',#8)");                      // 9
    } else {
      Add("IFCSIUNIT(*,.LENGTHUNIT.,$,.METRE.)");  // 6
      Add("IFCSIUNIT(*,.PLANEANGLEUNIT.,$,.RADIAN.)");
      Add("IFCSIUNIT(*,.AREAUNIT.,$,.SQUARE_METRE.)");
      Add("IFCSIUNIT(*,.VOLUMEUNIT.,$,.CUBIC_METRE.)");  // 9
    }
    Add(o_.feet ? "IFCUNITASSIGNMENT((#9))" : "IFCUNITASSIGNMENT((#6,#7,#8,#9))");          // 10
    Add("IFCCARTESIANPOINT((0.,0.,0.))");                                                   // 11
    Add("IFCLOCALPLACEMENT($,#13)");                                                        // 12
    Add("IFCAXIS2PLACEMENT3D(#11,$,$)");                                                    // 13
    Add("IFCGEOMETRICREPRESENTATIONCONTEXT($,'Model',3,1.E-05,#13,$)");                     // 14
    Add("IFCBUILDINGSTOREY('" + Guid() + "',#5,'Ground floor',$,$,#12,$,$,.ELEMENT.,0.)");  // 15
    const int project = Add("IFCPROJECT('" + Guid() + "',#5,'P',$,$,$,$,(#14),#10)");
    const int site = Add("IFCSITE('" + Guid() + "',#5,'Site',$,$,#12,$,$,.ELEMENT.,$,$,$,$,$)");
    const int building = Add("IFCBUILDING('" + Guid() + "',#5,'B',$,$,#12,$,$,.ELEMENT.,$,$,$)");
    Add("IFCRELAGGREGATES('" + Guid() + "',#5,$,$,#" + std::to_string(project) + ",(#" +
        std::to_string(site) + "))");
    Add("IFCRELAGGREGATES('" + Guid() + "',#5,$,$,#" + std::to_string(site) + ",(#" +
        std::to_string(building) + "))");
    if (o_.foundation)
      foundation_ =
          Add("IFCBUILDINGSTOREY('" + Guid() + "',#5,'Foundation',$,$,#12,$,$,.ELEMENT.,-1.)");
    Add("IFCRELAGGREGATES('" + Guid() + "',#5,$,$,#" + std::to_string(building) + ",(#15" +
        (o_.foundation ? ",#" + std::to_string(foundation_) : std::string()) + "))");
    up_ = Add("IFCDIRECTION((0.,0.,1.))");
  }
  int Element(const std::string& entity, const std::string& name, const Box& b,
              const std::string& predefined = "") {
    std::string pts;
    std::vector<int> ids;
    for (const Vector2d& p : b.poly) {
      const Vector2d q = Turn(p);
      ids.push_back(Add("IFCCARTESIANPOINT((" + L(q.x()) + "," + L(q.y()) + "))"));
    }
    ids.push_back(ids.front());
    for (int i : ids) pts += (pts.empty() ? "#" : ",#") + std::to_string(i);
    const int line = Add("IFCPOLYLINE((" + pts + "))");
    const int profile = Add("IFCARBITRARYCLOSEDPROFILEDEF(.AREA.,$,#" + std::to_string(line) + ")");
    const int origin = Add("IFCCARTESIANPOINT((0.,0.," + L(b.z0) + "))");
    const int place = Add("IFCAXIS2PLACEMENT3D(#" + std::to_string(origin) + ",$,$)");
    const int solid = Add("IFCEXTRUDEDAREASOLID(#" + std::to_string(profile) + ",#" +
                          std::to_string(place) + ",#" + std::to_string(up_) + "," + L(b.h) + ")");
    const int rep =
        Add("IFCSHAPEREPRESENTATION(#14,'Body','SweptSolid',(#" + std::to_string(solid) + "))");
    const int shape = Add("IFCPRODUCTDEFINITIONSHAPE($,$,(#" + std::to_string(rep) + "))");
    const std::string head = entity + "('" + Guid() + "',#5," +
                             (name.empty() ? std::string("$") : "'" + name + "'") + ",$,$,#12,#" +
                             std::to_string(shape) + ",$";
    int id = 0;
    if (entity == "IFCSPACE")
      id = Add(head + ",.ELEMENT.,.INTERNAL.,$)");
    else if (entity == "IFCDOOR" || entity == "IFCWINDOW")
      id = Add(head + "," + L(b.h) + "," + L(0.9) + ")");
    else if (!predefined.empty())
      id = Add(head + "," + predefined + ")");
    else
      id = Add(head + ")");
    if (entity != "IFCSPACE" && entity != "IFCOPENINGELEMENT") elements_.push_back(id);
    return id;
  }
  // The 4 x 3 x 2.5 m room as an IfcFacetedBrep; its bottom is two faces, the second with a
  // vertex at (2, 1.5) on the first one's edge x = 2 (a T-junction).
  int BrepSpace() {
    auto pt = [&](double x, double y, double z) {
      const Vector2d q = Turn({x, y});
      return "#" + std::to_string(
                       Add("IFCCARTESIANPOINT((" + L(q.x()) + "," + L(q.y()) + "," + L(z) + "))"));
    };
    auto face = [&](const std::vector<std::string>& loop) {
      std::string refs;
      for (const auto& r : loop) refs += (refs.empty() ? "" : ",") + r;
      const int l = Add("IFCPOLYLOOP((" + refs + "))");
      const int b = Add("IFCFACEOUTERBOUND(#" + std::to_string(l) + ",.T.)");
      return "#" + std::to_string(Add("IFCFACE((#" + std::to_string(b) + "))"));
    };
    const double h = 2.5;
    std::vector<std::string> faces{
        face({pt(0, 0, 0), pt(0, 3, 0), pt(2, 3, 0), pt(2, 0, 0)}),
        face({pt(2, 0, 0), pt(2, 1.5, 0), pt(2, 3, 0), pt(4, 3, 0), pt(4, 0, 0)}),
        face({pt(0, 0, h), pt(4, 0, h), pt(4, 3, h), pt(0, 3, h)}),
        face({pt(0, 0, 0), pt(4, 0, 0), pt(4, 0, h), pt(0, 0, h)}),
        face({pt(4, 0, 0), pt(4, 3, 0), pt(4, 3, h), pt(4, 0, h)}),
        face({pt(4, 3, 0), pt(0, 3, 0), pt(0, 3, h), pt(4, 3, h)}),
        face({pt(0, 3, 0), pt(0, 0, 0), pt(0, 0, h), pt(0, 3, h)})};
    std::string refs;
    for (const auto& f : faces) refs += (refs.empty() ? "" : ",") + f;
    const int shell = Add("IFCCLOSEDSHELL((" + refs + "))");
    const int brep = Add("IFCFACETEDBREP(#" + std::to_string(shell) + ")");
    const int rep =
        Add("IFCSHAPEREPRESENTATION(#14,'Body','Brep',(#" + std::to_string(brep) + "))");
    const int shape = Add("IFCPRODUCTDEFINITIONSHAPE($,$,(#" + std::to_string(rep) + "))");
    return Add("IFCSPACE('" + Guid() + "',#5,'1',$,$,#12,#" + std::to_string(shape) +
               ",$,.ELEMENT.,.INTERNAL.,$)");
  }

  void Rel(const std::string& entity, int a, int b) {
    Add(entity + "('" + Guid() + "',#5,$,$,#" + std::to_string(a) + ",#" + std::to_string(b) + ")");
  }

  FixtureOptions o_;
  std::ostringstream out_;
  int id_ = 0, guid_ = 0, up_ = 0, foundation_ = 0;
  std::vector<int> elements_;
};

// Each malformed variant: one line, `path: error: ...`.
void ExpectOneLineError(const std::function<void()>& f, const std::string& prefix,
                        const std::string& contains) {
  try {
    f();
    ADD_FAILURE() << "no error for " << contains;
  } catch (const InputError& e) {
    const std::string m = e.what();
    EXPECT_EQ(m.rfind(prefix, 0), 0u) << m;
    EXPECT_NE(m.find(contains), std::string::npos) << m;
    EXPECT_EQ(m.find('\n'), std::string::npos) << m;
  }
}

class BimImportTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("mopad_bim_" +
            std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()));
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string Fixture(const FixtureOptions& o, const std::string& name = "t.ifc") {
    return IfcWriter(o).Write(dir_ / name);
  }
  fs::path dir_;
};

Vector3d Turned(const Vector3d& p, double deg) {
  const double a = DegToRad(deg);
  return {std::cos(a) * p.x() - std::sin(a) * p.y(), std::sin(a) * p.x() + std::cos(a) * p.y(),
          p.z()};
}

// The analytic truth of the fixture, turned by `deg`.
void ExpectFixtureTruth(const BimImport& imp, double deg, double door_deg) {
  const GroundTruth& t = imp.truth;
  ASSERT_EQ(t.rooms.size(), 1u);
  const Room& r = t.rooms[0];
  EXPECT_NEAR(r.floor_z, 0.0, 1e-4);
  EXPECT_NEAR(r.ceiling_z, 2.5, 1e-4);
  ASSERT_EQ(r.polygon.size(), 4u);
  EXPECT_NEAR(std::abs(SignedArea(r.polygon)), 12.0, 1e-3);
  // Every corner of the room is one of the turned corners.
  for (const Vector3d& c :
       {Vector3d(0, 0, 0), Vector3d(4, 0, 0), Vector3d(4, 3, 0), Vector3d(0, 3, 0)}) {
    const Vector3d q = Turned(c, deg);
    double best = 1e9;
    for (const auto& v : r.polygon) best = std::min(best, (v - q.head<2>()).norm());
    EXPECT_LT(best, 1e-4) << q.transpose();
  }
  int walls = 0, floors = 0, ceilings = 0;
  for (const auto& e : t.elements) {
    walls += e.element_class == ElementClass::kWall;
    floors += e.element_class == ElementClass::kFloor;
    ceilings += e.element_class == ElementClass::kCeiling;
    if (e.element_class != ElementClass::kWall) continue;
    EXPECT_NEAR(e.height, 2.5, 1e-4) << e.id;
    EXPECT_TRUE(std::abs(e.length - 4.0) < 1e-4 || std::abs(e.length - 3.0) < 1e-4) << e.id;
    // The normal points into the room: towards the room's centre.
    const Vector3d centre = Turned(Vector3d(2, 1.5, 0), deg);
    EXPECT_GT((centre - e.origin).dot(e.normal), 1.0) << e.id;
  }
  EXPECT_EQ(walls, 4);
  EXPECT_EQ(floors, 1);
  EXPECT_EQ(ceilings, 1);
  // The door: 0.9 x 2.0 in the south wall, hinge 3 mm inside the jamb at x = 1.9.
  ASSERT_EQ(t.openings.size(), 2u);
  const Opening* d = nullptr;
  const Opening* w = nullptr;
  for (const auto& o : t.openings) (o.type == OpeningType::kDoor ? d : w) = &o;
  ASSERT_TRUE(d && w);
  EXPECT_NEAR(d->u1 - d->u0, 0.9, 1e-4);
  EXPECT_NEAR(d->v1 - d->v0, 2.0, 1e-4);
  EXPECT_NEAR(d->v0, 0.0, 1e-4);
  EXPECT_NEAR(d->opening_angle, DegToRad(door_deg), 1e-9);
  EXPECT_EQ(d->state, DoorStateFromAngle(DegToRad(door_deg)));
  EXPECT_LT((d->hinge_point - Turned(Vector3d(1.897, 0.001, 0.0), deg)).norm(), 1e-4);
  EXPECT_NEAR(d->hinge_axis.z(), -1.0, 1e-9);
  // The window: 1 x 1.2 m, sill 0.9 m, in the east wall.
  EXPECT_NEAR(w->u1 - w->u0, 1.0, 1e-4);
  EXPECT_NEAR(w->v1 - w->v0, 1.2, 1e-4);
  EXPECT_NEAR(w->sill_height, 0.9, 1e-4);
  // The outlet: a socket on the north wall, moved the 2 mm onto it, centre on the face.
  ASSERT_EQ(t.service_components.size(), 1u);
  const ServiceComponent& s = t.service_components[0];
  EXPECT_EQ(s.bsc_class, "socket_x1");
  EXPECT_LT((s.centre - Turned(Vector3d(2.04, 3.0, 0.34), deg)).norm(), 1e-4);
  EXPECT_LT((s.normal - Turned(Vector3d(0, -1, 0), deg)).norm(), 1e-6);
  EXPECT_NEAR(s.size.z(), 0.04, 1e-4);
  const StructuralElement* host = t.FindElement(s.host);
  ASSERT_NE(host, nullptr);
  EXPECT_EQ(host->element_class, ElementClass::kWall);
  // And the scene agrees with its truth.
  const CheckReport rep = CheckScene(imp.scene, imp.truth);
  EXPECT_TRUE(rep.ok()) << rep.Summary();
}

TEST_F(BimImportTest, OneRoomGivesItsAnalyticTruthAndValidates) {
  const BimImport imp = ImportBim(Fixture({}));
  ExpectFixtureTruth(imp, 0.0, 90.0);
}

TEST_F(BimImportTest, FeetUnitFileGivesTheSameTruthInMetres) {
  FixtureOptions o;
  o.feet = true;
  const BimImport imp = ImportBim(Fixture(o));
  ExpectFixtureTruth(imp, 0.0, 90.0);
}

TEST_F(BimImportTest, WallsAt45DegreesGiveTheTurnedTruth) {
  FixtureOptions o;
  o.angle_deg = 45.0;
  const BimImport imp = ImportBim(Fixture(o));
  ExpectFixtureTruth(imp, 45.0, 90.0);
  // A wall's u axis is along a 45 deg direction.
  const StructuralElement& w = imp.truth.elements[0];
  EXPECT_NEAR(std::abs(w.u_axis.x()), std::sqrt(0.5), 1e-6);
  EXPECT_NEAR(std::abs(w.u_axis.y()), std::sqrt(0.5), 1e-6);
}

TEST_F(BimImportTest, DoorHingedOpenTo30DegreesHasItsLeafThere) {
  BimImportParams p;
  p.door_angles_deg = ParseDoorAngles({"D1=30"}, "--doors");
  const BimImport imp = ImportBim(Fixture({}), p);
  ExpectFixtureTruth(imp, 0.0, 30.0);
  EXPECT_EQ(imp.truth.openings[0].state, DoorState::kSemiOpen);
  // The leaf's farthest point from the hinge: hinge + 0.894 m (width - 2 x 3 mm) along
  // cos30 (-x) + sin30 (+y), the latch direction turned into the room.
  Vector3d far = Vector3d::Zero();
  const Vector3d hinge(1.897, 0.001, 0.0);
  double best = 0;
  for (const auto& part : imp.scene.parts) {
    if (part.element_class != ElementClass::kDoorLeaf) continue;
    for (const auto& v : part.positions) {
      const Vector3d q(v.x(), v.y(), 0.0);
      if ((q - hinge).norm() > best) {
        best = (q - hinge).norm();
        far = q;
      }
    }
  }
  const double a = DegToRad(30.0);
  const Vector3d dir(-std::cos(a), std::sin(a), 0.0);
  // The far corner is at the latch edge, on the leaf's back face (thickness 0.04 m).
  const Vector3d expected_front = hinge + 0.894 * dir;
  const Vector3d back_offset = 0.04 * Vector3d(-std::sin(a), -std::cos(a), 0.0);
  EXPECT_LT(std::min((far - expected_front).norm(), (far - expected_front - back_offset).norm()),
            1e-4)
      << far.transpose();
}

// An IfcOpeningElement's body as ArchiCAD writes it: a rectangle profile on its own 2D
// position (x turned to -x), an extrusion position whose axes are turned (extruding along the
// wall's y), under the wall's placement (turned 90 deg about z) under the storey's (z = 3 m).
// Worked by hand: in the wall's frame x [6.5, 8.5], y [-0.3, 0], z [0.8, 2.0]; in the world x
// [2.0, 2.3], y [7.5, 9.5], z [3.8, 5.0]. An opening whose body is a boolean result is only its
// placement's origin; the filling is named by its GlobalId.
TEST(OpeningBodies, ReadTheBodyThroughEveryPlacementAndProfilePosition) {
  const std::string text = R"(ISO-10303-21;
HEADER;
FILE_SCHEMA(('IFC2X3'));
ENDSEC;
DATA;
#1=IFCCARTESIANPOINT((0.,0.,0.));
#2=IFCDIRECTION((0.,0.,1.));
#3=IFCDIRECTION((1.,0.,0.));
#4=IFCDIRECTION((0.,1.,0.));
#5=IFCDIRECTION((-1.,0.,0.));
#6=IFCDIRECTION((-1.,0.));
#10=IFCCARTESIANPOINT((0.,0.,3.));
#11=IFCAXIS2PLACEMENT3D(#10,$,$);
#12=IFCLOCALPLACEMENT($,#11);
#20=IFCCARTESIANPOINT((2.,1.,0.));
#21=IFCAXIS2PLACEMENT3D(#20,#2,#4);
#22=IFCLOCALPLACEMENT(#12,#21);
#30=IFCCARTESIANPOINT((7.5,-0.3,0.8));
#31=IFCAXIS2PLACEMENT3D(#30,#2,#3);
#32=IFCLOCALPLACEMENT(#22,#31);
#40=IFCCARTESIANPOINT((0.,0.6));
#41=IFCAXIS2PLACEMENT2D(#40,#6);
#42=IFCRECTANGLEPROFILEDEF(.AREA.,'',#41,2.,1.2);
#43=IFCAXIS2PLACEMENT3D(#1,#4,#5);
#44=IFCEXTRUDEDAREASOLID(#42,#43,#2,0.3);
#45=IFCSHAPEREPRESENTATION($,'Body','SweptSolid',(#44));
#46=IFCPRODUCTDEFINITIONSHAPE($,$,(#45));
#47=IFCOPENINGELEMENT('0000000000000000000047',$,$,$,'Opening',#32,#46,$);
#48=IFCWINDOW('0000000000000000000048',$,'W',$,$,#32,$,$,1.2,2.);
#49=IFCRELFILLSELEMENT('0000000000000000000049',$,$,$,#47,#48);
#50=IFCBOOLEANCLIPPINGRESULT(.DIFFERENCE.,#44,#44);
#51=IFCSHAPEREPRESENTATION($,'Body','Clipping',(#50));
#52=IFCPRODUCTDEFINITIONSHAPE($,$,(#51));
#53=IFCOPENINGELEMENT('0000000000000000000053',$,$,$,'Opening',#22,#52,$);
ENDSEC;
END-ISO-10303-21;
)";
  const std::vector<bim::OpeningBody> bodies = bim::OpeningBodies(bim::IndexStep(text), 1.0);
  ASSERT_EQ(bodies.size(), 2u);
  const bim::OpeningBody& w = bodies[0];
  EXPECT_EQ(w.filling, "0000000000000000000048");
  EXPECT_TRUE(w.complete);
  ASSERT_EQ(w.corners.size(), 8u);
  Eigen::AlignedBox3d box;
  for (const Vector3d& c : w.corners) box.extend(c);
  EXPECT_LT((box.min() - Vector3d(2.0, 7.5, 3.8)).norm(), 1e-9) << box.min().transpose();
  EXPECT_LT((box.max() - Vector3d(2.3, 9.5, 5.0)).norm(), 1e-9) << box.max().transpose();
  const bim::OpeningBody& b = bodies[1];
  EXPECT_EQ(b.filling, "");
  EXPECT_FALSE(b.complete);
  ASSERT_EQ(b.corners.size(), 1u);
  EXPECT_LT((b.corners[0] - Vector3d(2.0, 1.0, 3.0)).norm(), 1e-9);
  // Millimetre files: the scale applies to every corner.
  const std::vector<bim::OpeningBody> mm = bim::OpeningBodies(bim::IndexStep(text), 0.001);
  EXPECT_LT((mm[0].corners[0] - 0.001 * w.corners[0]).norm(), 1e-12);
}

// The fixture's own openings (polyline profiles, feet, the building turned 45 deg): each door
// and window body holds the element filling it, in metres.
TEST_F(BimImportTest, OpeningBodiesOfTheFixtureHoldTheirFillingsInMetres) {
  FixtureOptions o;
  o.feet = true;
  o.angle_deg = 45.0;
  const std::string path = Fixture(o);
  const std::string text = bim::ReadText(path);
  const bim::StepIndex step = bim::IndexStep(text);
  const auto bodies = bim::OpeningBodies(step, bim::FullLengthScale(text, step, path));
  ASSERT_EQ(bodies.size(), 2u);
  const double a = DegToRad(45.0);
  // The door's: x [1, 1.9], y [-0.3, 0.1], z [0, 2]; the window's: x [3.9, 4.3], y [1, 2],
  // z [0.9, 2.1] (before the turn).
  const std::vector<std::pair<Vector2d, Vector2d>> plan{{{1.0, -0.3}, {1.9, 0.1}},
                                                        {{3.9, 1.0}, {4.3, 2.0}}};
  const std::vector<std::pair<double, double>> heights{{0.0, 2.0}, {0.9, 2.1}};
  for (std::size_t k = 0; k < 2; ++k) {
    EXPECT_FALSE(bodies[k].filling.empty());
    ASSERT_EQ(bodies[k].corners.size(), 10u);  // a closed polyline of 5 points, twice
    for (const Vector3d& c : bodies[k].corners) {
      const Vector2d back(std::cos(-a) * c.x() - std::sin(-a) * c.y(),
                          std::sin(-a) * c.x() + std::cos(-a) * c.y());
      EXPECT_GT(back.x(), plan[k].first.x() - 1e-6);
      EXPECT_LT(back.x(), plan[k].second.x() + 1e-6);
      EXPECT_GT(back.y(), plan[k].first.y() - 1e-6);
      EXPECT_LT(back.y(), plan[k].second.y() + 1e-6);
      EXPECT_TRUE(std::abs(c.z() - heights[k].first) < 1e-6 ||
                  std::abs(c.z() - heights[k].second) < 1e-6)
          << c.z();
    }
  }
}

TEST_F(BimImportTest, SpaceWithoutRepresentationIsReportedInOneLine) {
  FixtureOptions o;
  o.extra_space_without_representation = true;
  const BimImport imp = ImportBim(Fixture(o));
  EXPECT_EQ(imp.truth.rooms.size(), 1u);
  int lines = 0;
  for (const auto& l : imp.report) {
    EXPECT_EQ(l.find('\n'), std::string::npos);
    lines += l.find("space without representation") != std::string::npos;
  }
  EXPECT_EQ(lines, 1);
}

TEST_F(BimImportTest, ElementWithoutGeometryIsReportedInOneLine) {
  FixtureOptions o;
  o.extra_door_without_geometry = true;
  const BimImport imp = ImportBim(Fixture(o));
  int lines = 0;
  for (const auto& l : imp.report)
    lines += l.rfind("IFCDOOR 'Door-2'", 0) == 0 && l.find("no geometry") != std::string::npos;
  EXPECT_EQ(lines, 1);
  ExpectFixtureTruth(imp, 0.0, 90.0);  // the rest is the plain fixture's truth
}

TEST_F(BimImportTest, SpacesWithoutAWallBetweenThemGetAnOpenPassage) {
  FixtureOptions o;
  o.split_space = true;
  BimImport imp = ImportBim(Fixture(o));
  ASSERT_EQ(imp.truth.rooms.size(), 2u);
  EXPECT_EQ(imp.truth.format_version, kTruthFormatVersionPassages);
  int passages = 0;
  for (const auto& c : imp.truth.connections)
    if (c.door.empty()) {
      ++passages;
      EXPECT_EQ(c.room_a, "R1");
      EXPECT_EQ(c.room_b, "R2");
    }
  EXPECT_EQ(passages, 1);
  // 3 walls each (the shared edge has none), a door in R1, the window in R2.
  int walls = 0;
  for (const auto& e : imp.truth.elements) walls += e.element_class == ElementClass::kWall;
  EXPECT_EQ(walls, 6);
  const CheckReport ok = CheckScene(imp.scene, imp.truth);
  EXPECT_TRUE(ok.ok()) << ok.Summary();
  // Written and read back as version 2; as version 1 the passage is a dangling door and the
  // touching rooms an overlap.
  WriteBimImport(imp, (dir_ / "v2").string());
  EXPECT_EQ(ReadGroundTruth((dir_ / "v2" / "scene.truth.json").string()).connections.size(),
            imp.truth.connections.size());
  imp.truth.format_version = kTruthFormatVersion;
  const CheckReport v1 = CheckScene(imp.scene, imp.truth);
  bool overlap = false;
  for (const auto& e : v1.errors) overlap = overlap || e.find("overlap") != std::string::npos;
  EXPECT_TRUE(overlap) << v1.Summary();
  WriteGroundTruth(imp.truth, (dir_ / "v1.json").string());
  try {
    ReadGroundTruth((dir_ / "v1.json").string());
    ADD_FAILURE() << "version 1 with an open passage was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("dangling door id ''"), std::string::npos) << e.what();
  }
}

TEST_F(BimImportTest, GltfConvertedWithItsSpacesGivesTheSameTruth) {
  // A glTF whose node names carry the IFC classes and paths and which kept the space volumes
  // (here: the IFC as assimp loads it, written by our glTF writer) imports to the very same
  // truth as the IFC. (No outlet: its class comes from an IFC type object glTF cannot carry.)
  FixtureOptions o;
  o.outlet = false;
  const std::string ifc = Fixture(o, "t.ifc");
  LoadOptions spaces;
  spaces.import_ifc_spaces = true;
  WriteGlb(LoadScene(ifc, spaces), (dir_ / "t.glb").string());
  WriteGroundTruth(ImportBim(ifc).truth, (dir_ / "ifc.json").string());
  WriteGroundTruth(ImportBim((dir_ / "t.glb").string()).truth, (dir_ / "glb.json").string());
  std::ifstream a(dir_ / "ifc.json"), b(dir_ / "glb.json");
  const std::string sa((std::istreambuf_iterator<char>(a)), {});
  const std::string sb((std::istreambuf_iterator<char>(b)), {});
  EXPECT_GT(sa.size(), 1000u);
  EXPECT_EQ(sa, sb);
}

TEST_F(BimImportTest, SpaceDrawnInsideItsWallsNeedsAPlaneToleranceAndGetsTheWallPlanes) {
  FixtureOptions o;
  o.space_inset = 0.02;
  const std::string path = Fixture(o);
  // 2 cm is beyond the default 3 mm: no wall is the room's, each edge says so in one line.
  const BimImport strict = ImportBim(path);
  int lines = 0;
  for (const auto& l : strict.report) lines += l.find("no wall face on it") != std::string::npos;
  EXPECT_EQ(lines, 4);
  // With 3 cm the walls are found, and the truth takes their own planes (x = 0, 4; y = 0, 3),
  // not the space's edges 2 cm inside them.
  BimImportParams p;
  p.plane_tolerance = 0.03;
  const BimImport imp = ImportBim(path, p);
  int walls = 0;
  for (const auto& e : imp.truth.elements) {
    if (e.element_class != ElementClass::kWall) continue;
    ++walls;
    const double plane = e.origin.dot(e.normal);  // -(distance of the plane from the origin)
    const bool on_wall = std::abs(e.origin.x()) < 1e-4 || std::abs(e.origin.x() - 4.0) < 1e-4 ||
                         std::abs(e.origin.y()) < 1e-4 || std::abs(e.origin.y() - 3.0) < 1e-4;
    EXPECT_TRUE(on_wall) << e.id << " origin " << e.origin.transpose() << " plane " << plane;
    EXPECT_NEAR(e.height, 2.5, 1e-4);
  }
  EXPECT_EQ(walls, 4);
  EXPECT_EQ(imp.truth.openings.size(), 2u);
}

TEST_F(BimImportTest, SpaceDrawnIntoOrShortOfTheSlabGetsTheSlabsCeiling) {
  // Some tools draw a room's volume up to the next level (into the slab), others short of the
  // ceiling: the ceiling is the slab face at 2.5 m either way, said in one line.
  for (const double h : {2.8, 2.3}) {
    FixtureOptions o;
    o.space_height = h;
    std::string name = "h";
    name += std::to_string(h);
    name += ".ifc";
    const BimImport imp = ImportBim(Fixture(o, name));
    ExpectFixtureTruth(imp, 0.0, 90.0);
    int lines = 0;
    for (const auto& l : imp.repairs)
      lines += l.find("repair: ceiling height R1 (IfcSpace '1')") == 0 &&
               l.find("-> 2.500 m (the slab face over it)") != std::string::npos;
    EXPECT_EQ(lines, 1) << h;
  }
}

TEST_F(BimImportTest, WallSurfaceMadeByACoveringIsTheRoomsWall) {
  // The west wall's room face is a 2 cm lining (IfcCovering), not the wall itself: it is still
  // the room's wall, and the analytic truth is unchanged.
  FixtureOptions o;
  o.west_lining = true;
  const BimImport imp = ImportBim(Fixture(o));
  ExpectFixtureTruth(imp, 0.0, 90.0);
  EXPECT_EQ(imp.walls_with_room_faces, 3);  // IFC walls; the fourth face is the covering's
}

TEST_F(BimImportTest, GeoreferencedModelIsImportedWithAWarning) {
  // 5400 km from the origin: assimp 5.2.5 recentres IFC geometry but loses precision on the
  // way (measured: centimetres, up to 0.24 m in z). The import says so in one line rather than
  // presenting the result as exact.
  FixtureOptions o;
  o.far = true;
  const BimImport imp = ImportBim(Fixture(o));
  EXPECT_EQ(imp.truth.rooms.size(), 1u);
  int lines = 0;
  for (const auto& l : imp.report)
    lines +=
        l.find("coordinates reach 5400.0 km from the origin (georeferenced)") != std::string::npos;
  EXPECT_EQ(lines, 1);
}

TEST_F(BimImportTest, BrepSpaceWithATJunctionGivesItsRoom) {
  FixtureOptions o;
  o.brep_space = true;
  ExpectFixtureTruth(ImportBim(Fixture(o)), 0.0, 90.0);
}

TEST_F(BimImportTest, DefaultStoreyIsTheLowestWithSpaces) {
  // The lowest storey, "Foundation", holds only a footing: the default is the ground floor.
  FixtureOptions o;
  o.foundation = true;
  const std::string path = Fixture(o);
  ExpectFixtureTruth(ImportBim(path), 0.0, 90.0);
  EXPECT_EQ(ListIfcStoreys(path).size(), 2u);
  BimImportParams p;
  p.storey = "Foundation";
  ExpectOneLineError([&] { ImportBim(path, p); },
                     path + ": error: no room can be made on storey 'Foundation'",
                     "none with a usable volume");
}

TEST_F(BimImportTest, SameInputGivesTheSameBytes) {
  const std::string path = Fixture({});
  WriteBimImport(ImportBim(path), (dir_ / "a").string());
  WriteBimImport(ImportBim(path), (dir_ / "b").string());
  for (const char* f : {"scene.glb", "scene.truth.json"}) {
    std::ifstream a(dir_ / "a" / f, std::ios::binary), b(dir_ / "b" / f, std::ios::binary);
    const std::string sa((std::istreambuf_iterator<char>(a)), {});
    const std::string sb((std::istreambuf_iterator<char>(b)), {});
    EXPECT_FALSE(sa.empty());
    EXPECT_EQ(sa, sb) << f;
  }
  // And what was written reads back and validates.
  const GroundTruth back = ReadGroundTruth((dir_ / "a" / "scene.truth.json").string());
  EXPECT_EQ(back.rooms.size(), 1u);
}

TEST_F(BimImportTest, MissingFloorIsRefusedOrMadeFromTheSpace) {
  FixtureOptions o;
  o.floor_slab = false;
  const std::string path = Fixture(o);
  try {
    ImportBim(path);
    FAIL() << "no error";
  } catch (const BimRepairsNeeded& e) {
    const std::string m = e.what();
    EXPECT_EQ(m.rfind(path + ": error: the file needs 1 repair(s); the first: floor R1", 0), 0u)
        << m;
    EXPECT_NE(m.find("0.0 % floor"), std::string::npos) << m;
    EXPECT_NE(m.find("--floor-from-spaces or --repair"), std::string::npos) << m;
    EXPECT_EQ(m.find('\n'), std::string::npos);
    ASSERT_EQ(e.repairs.size(), 1u);
    EXPECT_EQ(e.repairs[0].rfind("repair: floor R1 (IfcSpace '1'): 0.0 % floor geometry at z = "
                                 "0.000 m -> the space footprint (--floor-from-spaces)",
                                 0),
              0u)
        << e.repairs[0];
  }
  for (const bool all : {false, true}) {
    BimImportParams p;
    (all ? p.repair : p.floor_from_spaces) = true;
    const BimImport imp = ImportBim(path, p);
    ExpectFixtureTruth(imp, 0.0, 90.0);
    ASSERT_EQ(imp.repairs.size(), 1u);
    EXPECT_EQ(imp.repairs[0].rfind("repair: floor R1", 0), 0u) << imp.repairs[0];
  }
}

TEST_F(BimImportTest, EveryRepairTheFileNeedsIsListedInOneRun) {
  // No floor slab and no ceiling slab: two repairs, both named by the one refusal (the outlet,
  // with no ceiling above it, stays on its wall).
  FixtureOptions o;
  o.floor_slab = false;
  o.ceiling_slab = false;
  const std::string path = Fixture(o);
  std::vector<std::string> needed;
  try {
    ImportBim(path);
    ADD_FAILURE() << "no error";
  } catch (const BimRepairsNeeded& e) {
    needed = e.repairs;
    EXPECT_NE(std::string(e.what()).find("needs " + std::to_string(needed.size()) + " repair"),
              std::string::npos)
        << e.what();
  }
  ASSERT_GE(needed.size(), 2u);
  EXPECT_EQ(needed[0].rfind("repair: floor R1", 0), 0u) << needed[0];
  EXPECT_EQ(needed[1].rfind("repair: ceiling R1", 0), 0u) << needed[1];
  BimImportParams p;
  p.repair = true;
  const BimImport imp = ImportBim(path, p);
  ASSERT_EQ(imp.repairs.size(), needed.size());
  for (std::size_t k = 0; k < needed.size(); ++k)  // the same lines, now applied
    EXPECT_EQ(needed[k].rfind(imp.repairs[k], 0), 0u) << needed[k] << " vs " << imp.repairs[k];
  EXPECT_TRUE(CheckScene(imp.scene, imp.truth).ok());
}

TEST_F(BimImportTest, SpaceFloatingAboveTheSlabGetsTheSlabsFloor) {
  // A space drawn from 1.22 m while its walls, door and slab start at 0: the floor is the slab's
  // top (the building elements are the truth; the space's box an annotation), in one repair line.
  FixtureOptions o;
  o.space_base = 1.22;
  const BimImport imp = ImportBim(Fixture(o));
  ExpectFixtureTruth(imp, 0.0, 90.0);
  int lines = 0;
  for (const auto& l : imp.repairs)
    lines += l.rfind("repair: floor height R1 (IfcSpace '1'): 1.220 m (the space's bottom) -> "
                     "0.000 m (the slab face under it)",
                     0) == 0;
  EXPECT_EQ(lines, 1);
}

TEST_F(BimImportTest, MalformedInputsGiveOneClearLine) {
  FixtureOptions ifc5;
  ifc5.schema = "IFC5";
  const std::string p5 = Fixture(ifc5, "ifc5.ifc");
  ExpectOneLineError([&] { ImportBim(p5); }, p5 + ": error: unsupported IFC schema", "IFC5");
  ExpectOneLineError([&] { ListIfcStoreys(p5); }, p5 + ": error: unsupported IFC schema", "IFC5");

  FixtureOptions foot;
  foot.feet = true;
  foot.broken_foot_unit = true;
  const std::string pf = Fixture(foot, "foot.ifc");
  ExpectOneLineError([&] { ImportBim(pf); }, pf + ": error:", "length conversion factor");

  const std::string ok = Fixture({}, "ok.ifc");
  BimImportParams storey;
  storey.storey = "Roof";
  ExpectOneLineError([&] { ImportBim(ok, storey); }, ok + ": error: no such storey",
                     "'Ground floor'");
  BimImportParams door;
  door.door_angles_deg = {{"D7", 45.0}};
  ExpectOneLineError([&] { ImportBim(ok, door); }, ok + ": error: --doors names no door", "D7");
  BimImportParams angle;
  angle.door_angle_deg = -5;
  ExpectOneLineError([&] { ImportBim(ok, angle); }, "error: import parameter door_angle_deg",
                     "[0.000, 180.000]");

  const fs::path none = dir_ / "missing.ifc";
  ExpectOneLineError([&] { ImportBim(none.string()); }, none.string() + ": error:", "cannot open");

  // A file whose only space has no representation: no room can be made.
  const fs::path empty = dir_ / "nospace.ifc";
  {
    std::ifstream in(ok);
    std::string text((std::istreambuf_iterator<char>(in)), {});
    // Drop the space's representation (its shape is the last #n before ",$,.ELEMENT.,.INT").
    const std::size_t at = text.find("IFCSPACE(");
    const std::size_t shape = text.find(",#12,#", at);
    const std::size_t end = text.find(',', shape + 6);
    text.replace(shape + 5, end - shape - 5, "$");
    std::ofstream(empty) << text;
  }
  ExpectOneLineError([&] { ImportBim(empty.string()); },
                     empty.string() + ": error: no room can be made", "none with a usable volume");
}

TEST_F(BimImportTest, StoreysAreListedWithElevationsInMetres) {
  FixtureOptions o;
  o.feet = true;
  const std::vector<BimStorey> s = ListIfcStoreys(Fixture(o));
  ASSERT_EQ(s.size(), 1u);
  EXPECT_EQ(s[0].name, "Ground floor");
  EXPECT_TRUE(s[0].has_elevation);
  EXPECT_NEAR(s[0].elevation, 0.0, 1e-12);
}

TEST_F(BimImportTest, MergedModelAddsItsComponentsInTheSameFrame) {
  // The architectural model has no outlet; the "electrical model" of the same building has it.
  // Merged, the outlet is hosted on the architectural model's wall exactly as if it were its own.
  FixtureOptions arch_options;
  arch_options.outlet = false;
  const std::string arch = Fixture(arch_options, "arch.ifc");
  const std::string elec = Fixture({}, "elec.ifc");
  EXPECT_TRUE(ImportBim(arch).truth.service_components.empty());
  BimImportParams p;
  p.merge = {elec};
  const BimImport imp = ImportBim(arch, p);
  ExpectFixtureTruth(imp, 0.0, 90.0);
  // Merging the model with itself adds nothing: same GlobalIds are the same elements.
  BimImportParams self;
  self.merge = {elec};
  EXPECT_EQ(ImportBim(elec, self).truth.service_components.size(), 1u);
}

TEST_F(BimImportTest, MergedModelsComponentsOfOtherClassesGetUniqueIds) {
  // Two components that are no catalogue class, of two IFC classes, one from each model: both
  // `other`, numbered by one counter (they once were both `other_1`, and validate refused it).
  const std::string plain = Fixture({}, "plain.ifc");
  auto untyped = [&](const std::string& name, const std::string& entity, const std::string& guid) {
    std::ifstream in(plain);
    std::string text((std::istreambuf_iterator<char>(in)), {});
    const std::size_t rel = text.find("IFCRELDEFINESBYTYPE");
    const std::size_t line = text.rfind('#', rel);
    text.erase(line, text.find('\n', rel) + 1 - line);  // no type object
    const std::size_t at = text.find("IFCFLOWTERMINAL('");
    text.replace(at + 17, 22, guid);
    text.replace(at, 15, entity);
    const std::size_t label = text.find("'Socket-1'");
    text.replace(label, 10, "'Box-1'");
    const fs::path out = dir_ / name;
    std::ofstream(out) << text;
    return out.string();
  };
  const std::string arch = untyped("arch.ifc", "IFCFLOWCONTROLLER", "ARCH00000000000000000A");
  const std::string elec = untyped("elec.ifc", "IFCFLOWTERMINAL", "ELEC00000000000000000E");
  BimImportParams p;
  p.merge = {elec};
  const BimImport imp = ImportBim(arch, p);
  std::set<std::string> ids, classes;
  for (const ServiceComponent& c : imp.truth.service_components) {
    EXPECT_TRUE(ids.insert(c.id).second) << c.id;
    classes.insert(c.bsc_class);
  }
  EXPECT_EQ(ids, (std::set<std::string>{"other_1", "other_2"}));
  EXPECT_EQ(classes, (std::set<std::string>{"other:IfcFlowController", "other:IfcFlowTerminal"}));
  const CheckReport rep = CheckScene(imp.scene, imp.truth);
  EXPECT_TRUE(rep.ok()) << rep.Summary();
  // Written and read back: the truth reader accepts it.
  WriteBimImport(imp, (dir_ / "merged").string());
  EXPECT_EQ(ReadGroundTruth((dir_ / "merged" / "scene.truth.json").string())
                .service_components.size(),
            2u);
}

TEST(BimComponentClass, GenericClassesTakeTheirClassFromTheirNames) {
  const Vector3d small(0.08, 0.04, 0.08), double_socket(0.15, 0.04, 0.08);
  using bim::ComponentClass;
  EXPECT_EQ(ComponentClass("IfcFlowTerminal", "", double_socket, "Steckdose 2-fach"),
            "socket_x2");
  EXPECT_EQ(ComponentClass("IfcFlowTerminal", "", small, "Duplex Receptacle"), "socket_x1");
  EXPECT_EQ(ComponentClass("IfcFlowController", "", small, "Lichtschalter"), "switch");
  EXPECT_EQ(ComponentClass("IfcBuildingElementProxy", "", small, "Rauchmelder"), "smoke_detector");
  // A thermostat is no switch and no smoke detector, though an IfcSensor.
  EXPECT_EQ(ComponentClass("IfcSensor", "", small, "Raumthermostat"), "other:IfcSensor");
  EXPECT_EQ(ComponentClass("IfcFlowController", "", small, "Thermostat | Temperaturschalter"),
            "other:IfcFlowController");
  // Lights are not in the catalogue, exit lights are.
  EXPECT_EQ(ComponentClass("IfcFlowTerminal", "", small, "Deckenleuchte"),
            "other:IfcFlowTerminal");
  EXPECT_EQ(ComponentClass("IfcFlowTerminal", "", small, "Exit sign light"), "exit_light");
  EXPECT_EQ(ComponentClass("IfcFlowTerminal", "", small, "Box-1"), "other:IfcFlowTerminal");
  // The type object's class is said first; a sensor without words is a smoke detector.
  EXPECT_EQ(ComponentClass("IfcFlowTerminal", "ifcoutlet", small, "Lamp"), "socket_x1");
  EXPECT_EQ(ComponentClass("IfcSensor", "", small, ""), "smoke_detector");
}

}  // namespace
}  // namespace mopad::scenes
