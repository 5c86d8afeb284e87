#include "exports/ifc_export.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <map>
#include <numbers>

#include "io/step_writer.h"

namespace mopad::exports {
namespace {

using io::StepEnum;
using io::StepList;
using io::StepReal;
using io::StepRef;
using io::StepRefList;
using io::StepString;
using Vec3 = Eigen::Vector3d;

std::string Upper(std::string s) {
  for (char& c : s) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  return s;
}

// A right-handed frame: origin, extrusion axis z, profile axes x and y = z x x.
struct Frame {
  Vec3 origin, x, z;
  Vec3 Y() const { return z.cross(x); }
};

// x: horizontal when z is not vertical (so a wall profile's y is up), else the map x axis.
Vec3 HorizontalX(const Vec3& z) {
  const Vec3 x = Vec3::UnitZ().cross(z);
  return x.norm() > 1e-6 ? x.normalized() : Vec3::UnitX();
}

class IfcBuilder {
 public:
  IfcBuilder(const BuildingModel& model, const IfcExportParams& params)
      : model_(model), params_(params) {}
  std::string Build(IfcCounts* counts);

 private:
  std::string Gid(const std::string& id) const {
    return StepString(io::IfcGlobalId(model_.content_key + "/" + id));
  }
  int Add(const std::string& type, const std::string& args) { return w_.Add(type, args); }
  int Point3(const Vec3& p) {
    return Add("IFCCARTESIANPOINT",
               StepList({StepReal(Clean(p.x())), StepReal(Clean(p.y())), StepReal(Clean(p.z()))}));
  }
  int Dir3(const Vec3& d) {
    return Add("IFCDIRECTION",
               StepList({StepReal(Clean(d.x())), StepReal(Clean(d.y())), StepReal(Clean(d.z()))}));
  }
  // Rounds to 1e-9 m so that -0 and 1e-17 noise do not reach the file.
  static double Clean(double v) {
    const double r = std::round(v * 1e9) / 1e9;
    return r == 0.0 ? 0.0 : r;
  }
  int Axis3(const Frame& f) {
    return Add("IFCAXIS2PLACEMENT3D",
               StepRef(Point3(f.origin)) + "," + StepRef(Dir3(f.z)) + "," + StepRef(Dir3(f.x)));
  }
  int Placement() {  // every product is placed at the storey's (identity) placement
    return Add("IFCLOCALPLACEMENT", StepRef(storey_placement_) + "," + StepRef(identity_axis_));
  }
  int Body(const std::vector<Vec3>& polygon, const Frame& f, double depth);
  void Header();
  int Product(const std::string& entity, const Element& e, int body, const std::string& tail);
  void Pset(int product, const std::string& name, const std::string& id,
            const std::vector<std::pair<std::string, std::string>>& values);
  void ElementPset(int product, const Element& e);
  /// Where a wall's body lies along its into-the-wall axis (-normal), from its polygon's plane.
  struct Span {
    double start = 0.0, depth = 0.0;  ///< m
  };
  Span WallSpan(const Element& wall) const;
  int Wall(const Element& e);
  int Opening(const Element& e, const Element& host, int host_product);
  int Component(const Element& e);
  void Relations();

  const BuildingModel& model_;
  const IfcExportParams& params_;
  io::StepWriter w_;
  int body_context_ = 0, identity_axis_ = 0, storey_placement_ = 0, storey_ = 0;
  std::vector<int> in_storey_;
  std::map<std::string, int> space_of_room_;
  std::map<int, std::vector<int>> in_space_;  // space product -> contained products
  std::vector<int> spaces_;
  IfcCounts counts_;
  std::map<std::string, int> component_counts_;
};

// IfcExtrudedAreaSolid of `polygon` (projected into the frame's x-y plane) along the frame's z,
// wrapped in a 'Body' IfcShapeRepresentation and an IfcProductDefinitionShape.
int IfcBuilder::Body(const std::vector<Vec3>& polygon, const Frame& f, double depth) {
  std::vector<int> points;
  const Vec3 y = f.Y();
  for (const auto& p : polygon) {
    const Vec3 d = p - f.origin;
    points.push_back(Add("IFCCARTESIANPOINT",
                         StepList({StepReal(Clean(d.dot(f.x))), StepReal(Clean(d.dot(y)))})));
  }
  points.push_back(points.front());  // IfcPolyline closes by repeating the first point
  const int curve = Add("IFCPOLYLINE", StepRefList(points));
  const int profile = Add("IFCARBITRARYCLOSEDPROFILEDEF", ".AREA.,$," + StepRef(curve));
  const int solid =
      Add("IFCEXTRUDEDAREASOLID", StepRef(profile) + "," + StepRef(Axis3(f)) + "," +
                                      StepRef(Dir3(Vec3::UnitZ())) + "," + StepReal(depth));
  const int rep = Add("IFCSHAPEREPRESENTATION",
                      StepRef(body_context_) + ",'Body','SweptSolid'," + StepRefList({solid}));
  return Add("IFCPRODUCTDEFINITIONSHAPE", "$,$," + StepRefList({rep}));
}

void IfcBuilder::Header() {
  const int units =
      Add("IFCUNITASSIGNMENT", StepRefList({Add("IFCSIUNIT", "*,.LENGTHUNIT.,$,.METRE."),
                                            Add("IFCSIUNIT", "*,.AREAUNIT.,$,.SQUARE_METRE."),
                                            Add("IFCSIUNIT", "*,.VOLUMEUNIT.,$,.CUBIC_METRE."),
                                            Add("IFCSIUNIT", "*,.PLANEANGLEUNIT.,$,.RADIAN.")}));
  identity_axis_ = Axis3({Vec3::Zero(), Vec3::UnitX(), Vec3::UnitZ()});
  const int context = Add("IFCGEOMETRICREPRESENTATIONCONTEXT",
                          "$,'Model',3,1.E-05," + StepRef(identity_axis_) + ",$");
  body_context_ = Add("IFCGEOMETRICREPRESENTATIONSUBCONTEXT",
                      "'Body','Model',*,*,*,*," + StepRef(context) + ",$,.MODEL_VIEW.,$");
  const int project =
      Add("IFCPROJECT", Gid("project") + ",$," + StepString(model_.name) + "," +
                            StepString("export frame: " + model_.frame_note) + ",$,$,$," +
                            StepRefList({context}) + "," + StepRef(units));
  const int site_placement = Add("IFCLOCALPLACEMENT", "$," + StepRef(identity_axis_));
  const int site = Add("IFCSITE", Gid("site") + ",$,'Site',$,$," + StepRef(site_placement) +
                                      ",$,$,.ELEMENT.,$,$,$,$,$");
  const int building_placement =
      Add("IFCLOCALPLACEMENT", StepRef(site_placement) + "," + StepRef(identity_axis_));
  const int building = Add("IFCBUILDING", Gid("building") + ",$,'Building',$,$," +
                                              StepRef(building_placement) + ",$,$,.ELEMENT.,$,$,$");
  storey_placement_ =
      Add("IFCLOCALPLACEMENT", StepRef(building_placement) + "," + StepRef(identity_axis_));
  storey_ = Add("IFCBUILDINGSTOREY", Gid("storey") + ",$,'Storey 0',$,$," +
                                         StepRef(storey_placement_) + ",$,$,.ELEMENT.,0.");
  Add("IFCRELAGGREGATES",
      Gid("rel/project") + ",$,$,$," + StepRef(project) + "," + StepRefList({site}));
  Add("IFCRELAGGREGATES",
      Gid("rel/site") + ",$,$,$," + StepRef(site) + "," + StepRefList({building}));
  Add("IFCRELAGGREGATES",
      Gid("rel/building") + ",$,$,$," + StepRef(building) + "," + StepRefList({storey_}));
}

// An IfcProduct subtype: GlobalId, OwnerHistory, Name, Description, ObjectType, ObjectPlacement,
// Representation, then `tail` (Tag, PredefinedType, ...).
int IfcBuilder::Product(const std::string& entity, const Element& e, int body,
                        const std::string& tail) {
  const int id =
      Add(Upper(entity), Gid(e.id) + ",$," + StepString(e.id) + ",$," + StepString(e.class_name) +
                             "," + StepRef(Placement()) + "," + StepRef(body) + "," + tail);
  ElementPset(id, e);
  return id;
}

void IfcBuilder::Pset(int product, const std::string& name, const std::string& id,
                      const std::vector<std::pair<std::string, std::string>>& values) {
  std::vector<int> props;
  for (const auto& [key, value] : values)
    props.push_back(Add("IFCPROPERTYSINGLEVALUE", StepString(key) + ",$," + value + ",$"));
  const int set = Add("IFCPROPERTYSET",
                      Gid(id + "/" + name) + ",$," + StepString(name) + ",$," + StepRefList(props));
  Add("IFCRELDEFINESBYPROPERTIES",
      Gid(id + "/" + name + "/rel") + ",$,$,$," + StepRefList({product}) + "," + StepRef(set));
}

void IfcBuilder::ElementPset(int product, const Element& e) {
  Pset(product, "MoPAD_Element", e.id,
       {{"Id", "IFCIDENTIFIER(" + StepString(e.id) + ")"},
        {"Room", "IFCLABEL(" + StepString(e.room) + ")"},
        {"Class", "IFCLABEL(" + StepString(e.class_name) + ")"}});
}

IfcBuilder::Span IfcBuilder::WallSpan(const Element& wall) const {
  const auto t = wall.properties.find("thickness_m");
  if (t != wall.properties.end() && t->is_number() && t->get<double>() > 0.0)
    return {-0.5 * t->get<double>(), t->get<double>()};  // polygon on the axis plane
  return {0.0, params_.wall_thickness};                  // polygon on the room's face
}

int IfcBuilder::Wall(const Element& e) {
  const Vec3 z = -e.normal;  // away from the room (or the axis plane's +n side), into the wall
  const Span span = WallSpan(e);
  const int body =
      Body(e.polygon, {e.polygon.front() + z * span.start, HorizontalX(z), z}, span.depth);
  ++counts_.walls;
  return Product("IfcWall", e, body, "$,.SOLIDWALL.");
}

// The void in the host wall and the door or window that fills it.
int IfcBuilder::Opening(const Element& e, const Element& host, int host_product) {
  const Vec3 z = -e.normal;
  const Vec3 x = HorizontalX(z);
  const double margin = params_.opening_margin;
  const Span span = WallSpan(host);
  const int void_body = Body(e.polygon, {e.polygon.front() + z * (span.start - margin), x, z},
                             span.depth + 2 * margin);
  Element hole = e;
  hole.id = e.id + "/void";
  hole.class_name = "opening";
  const int opening = Product("IfcOpeningElement", hole, void_body, "$,.OPENING.");
  ++counts_.openings;
  Add("IFCRELVOIDSELEMENT",
      Gid(e.id + "/voids") + ",$,$,$," + StepRef(host_product) + "," + StepRef(opening));
  const bool door = e.kind == ElementKind::kDoor;
  const double t = door ? params_.leaf_thickness : params_.pane_thickness;
  const double inset = span.start + 0.5 * (span.depth - t);  // the leaf in mid-wall
  const int body = Body(e.polygon, {e.polygon.front() + z * inset, x, z}, t);
  // OverallHeight, OverallWidth at 0.1 mm (the model files' resolution).
  const auto mm01 = [](double v) { return StepReal(std::round(v * 1e4) / 1e4); };
  const std::string size = "$," + mm01(e.height) + "," + mm01(e.width) + ",";
  const int filler = door ? Product("IfcDoor", e, body, size + ".DOOR.,.NOTDEFINED.,$")
                          : Product("IfcWindow", e, body, size + ".WINDOW.,.NOTDEFINED.,$");
  (door ? counts_.doors : counts_.windows) += 1;
  Add("IFCRELFILLSELEMENT",
      Gid(e.id + "/fills") + ",$,$,$," + StepRef(opening) + "," + StepRef(filler));
  std::vector<std::pair<std::string, std::string>> values;
  if (door) {
    values.push_back({"State", "IFCLABEL(" + StepString(e.properties.value("state", "")) + ")"});
    const auto angle = e.properties.value("opening_angle_deg", nlohmann::ordered_json());
    if (angle.is_number())  // radians: the file's plane angle unit
      values.push_back(
          {"OpeningAngle", "IFCPLANEANGLEMEASURE(" +
                               StepReal(angle.get<double>() * std::numbers::pi / 180.0) + ")"});
    values.push_back({"ClearWidth", "IFCLENGTHMEASURE(" +
                                        StepReal(e.properties.value("clear_width_m", 0.0)) + ")"});
  }
  values.push_back(
      {"Confidence", "IFCNORMALISEDRATIOMEASURE(" +
                         StepReal(std::clamp(e.properties.value("confidence", 0.0), 0.0, 1.0)) +
                         ")"});
  values.push_back({"Host", "IFCIDENTIFIER(" + StepString(e.properties.value("host", "")) + ")"});
  Pset(filler, "MoPAD_Opening", e.id, values);
  return filler;
}

int IfcBuilder::Component(const Element& e) {
  const double w = e.size.x() > 0 ? e.size.x() : params_.default_component_size;
  const double h = e.size.y() > 0 ? e.size.y() : params_.default_component_size;
  const double d = e.size.z() > 0 ? e.size.z() : params_.default_component_depth;
  const Vec3 z = e.normal;
  const Vec3 x = HorizontalX(z);
  const Vec3 y = z.cross(x);
  const Vec3 base = e.centre;  // the back face on the host plane, depth out along the normal
  const std::vector<Vec3> rect = {
      base - 0.5 * w * x - 0.5 * h * y, base + 0.5 * w * x - 0.5 * h * y,
      base + 0.5 * w * x + 0.5 * h * y, base - 0.5 * w * x + 0.5 * h * y};
  const int body = Body(rect, {base, x, z}, d);
  const IfcClassOf cls = ComponentIfcClass(e.class_name);
  const int product = Product(cls.entity, e, body, "$," + StepEnum(cls.predefined_type));
  ++component_counts_[cls.entity];
  Pset(product, "MoPAD_Component", e.id,
       {{"Class", "IFCLABEL(" + StepString(e.class_name) + ")"},
        {"Alpha", "IFCREAL(" + StepReal(e.properties.value("alpha", 0.0)) + ")"},
        {"FoundBy", "IFCLABEL(" + StepString(e.properties.value("found_by", "")) + ")"},
        {"Host", "IFCIDENTIFIER(" + StepString(e.properties.value("host", "")) + ")"}});
  return product;
}

void IfcBuilder::Relations() {
  if (!spaces_.empty())
    Add("IFCRELAGGREGATES",
        Gid("rel/storey") + ",$,$,$," + StepRef(storey_) + "," + StepRefList(spaces_));
  if (!in_storey_.empty())
    Add("IFCRELCONTAINEDINSPATIALSTRUCTURE",
        Gid("rel/storey/contains") + ",$,$,$," + StepRefList(in_storey_) + "," + StepRef(storey_));
  for (const auto& [space, products] : in_space_)
    Add("IFCRELCONTAINEDINSPATIALSTRUCTURE", Gid("rel/space/" + std::to_string(space)) + ",$,$,$," +
                                                 StepRefList(products) + "," + StepRef(space));
}

std::string IfcBuilder::Build(IfcCounts* counts) {
  Header();
  for (const Space& s : model_.spaces) {
    Element e;
    e.id = s.room + "/space";
    e.room = s.room;
    e.class_name = "space";
    const int body = Body(s.footprint, {Vec3(0, 0, s.z0), Vec3::UnitX(), Vec3::UnitZ()},
                          std::max(1e-3, s.z1 - s.z0));
    const int space =
        Add("IFCSPACE", Gid(e.id) + ",$," + StepString(s.room) + ",$,$," + StepRef(Placement()) +
                            "," + StepRef(body) + ",$,.ELEMENT.,.INTERNAL.,$");
    ElementPset(space, e);
    space_of_room_[s.room] = space;
    spaces_.push_back(space);
    ++counts_.spaces;
  }
  std::vector<int> product_of(model_.elements.size(), 0);
  for (std::size_t i = 0; i < model_.elements.size(); ++i) {
    const Element& e = model_.elements[i];
    const Vec3 up = Vec3::UnitZ();
    int p = 0;
    if (e.kind == ElementKind::kWall) {
      p = Wall(e);
    } else if (e.kind == ElementKind::kFloor) {
      const double z = e.polygon.front().z();
      p = Product("IfcSlab", e,
                  Body(e.polygon, {Vec3(0, 0, z - params_.slab_thickness), Vec3::UnitX(), up},
                       params_.slab_thickness),
                  "$,.FLOOR.");
      ++counts_.slabs;
    } else if (e.kind == ElementKind::kCeiling) {
      // A level ceiling is extruded up from its height; a sloped one (an attic's roof) away
      // from the room, across its own plane.
      const double z = e.polygon.front().z();
      const Vec3 away = -e.normal.normalized();
      const Frame f = away.z() > 0.999 || !away.allFinite()
                          ? Frame{Vec3(0, 0, z), Vec3::UnitX(), up}
                          : Frame{e.polygon.front(), HorizontalX(away), away};
      p = Product("IfcCovering", e, Body(e.polygon, f, params_.covering_thickness), "$,.CEILING.");
      ++counts_.coverings;
    } else if (e.kind == ElementKind::kColumn) {
      p = Product(
          "IfcColumn", e,
          Body(e.polygon, {Vec3(0, 0, e.z0), Vec3::UnitX(), up}, std::max(1e-3, e.z1 - e.z0)),
          "$,.COLUMN.");
      ++counts_.columns;
    } else if (e.kind == ElementKind::kDoor || e.kind == ElementKind::kWindow) {
      if (e.host < 0 || product_of[e.host] == 0) continue;  // no wall to void: left out
      p = Opening(e, model_.elements[static_cast<std::size_t>(e.host)], product_of[e.host]);
    } else {
      p = Component(e);
      const auto it = space_of_room_.find(e.room);
      if (it != space_of_room_.end()) {
        in_space_[it->second].push_back(p);
        product_of[i] = p;
        continue;
      }
    }
    product_of[i] = p;
    in_storey_.push_back(p);
  }
  Relations();
  counts_.components.assign(component_counts_.begin(), component_counts_.end());
  if (counts) *counts = counts_;
  io::StepHeader header;
  header.file_name = "model.ifc";
  return w_.Text(header);
}

}  // namespace

std::string IfcText(const BuildingModel& model, const IfcExportParams& params, IfcCounts* counts) {
  return IfcBuilder(model, params).Build(counts);
}

}  // namespace mopad::exports
