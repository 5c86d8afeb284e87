// Reading a BIM model: the IFC STEP text (entity index, attributes, strings, length units),
// the `<IfcClass>_<Name>_<GlobalId>` node names, the role each IFC class plays, and the load of
// the model and its merged companions through assimp (scenes/bim_import_internal.h).
#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

#include "common/error.h"
#include "scenes/assimp_loader.h"
#include "scenes/bim_import_internal.h"
#include "scenes/scene_loader.h"

namespace mopad::scenes::bim {
namespace {

void AppendUtf8(unsigned cp, std::string* out) {
  if (cp < 0x80) {
    *out += static_cast<char>(cp);
  } else if (cp < 0x800) {
    *out += static_cast<char>(0xC0 | (cp >> 6));
    *out += static_cast<char>(0x80 | (cp & 0x3F));
  } else {
    *out += static_cast<char>(0xE0 | (cp >> 12));
    *out += static_cast<char>(0x80 | ((cp >> 6) & 0x3F));
    *out += static_cast<char>(0x80 | (cp & 0x3F));
  }
}

}  // namespace

StepIndex IndexStep(const std::string& text) {
  StepIndex index;
  std::size_t i = text.find("DATA;");
  if (i == std::string::npos) return index;
  while ((i = text.find('#', i)) != std::string::npos) {
    std::size_t j = i + 1;
    while (j < text.size() && std::isdigit(static_cast<unsigned char>(text[j]))) ++j;
    if (j == i + 1) {
      ++i;
      continue;
    }
    const unsigned long id = std::stoul(text.substr(i + 1, j - i - 1));
    std::size_t k = j;
    while (k < text.size() && std::isspace(static_cast<unsigned char>(text[k]))) ++k;
    if (k >= text.size() || text[k] != '=') {
      i = j;
      continue;
    }
    ++k;
    while (k < text.size() && std::isspace(static_cast<unsigned char>(text[k]))) ++k;
    bool quoted = false;
    std::size_t e = k;
    for (; e < text.size(); ++e) {
      if (text[e] == '\'')
        quoted = !quoted;
      else if (text[e] == ';' && !quoted)
        break;
    }
    index.bodies[id] = text.substr(k, e - k);
    i = e;
  }
  return index;
}

std::string EntityOf(const std::string& body) {
  std::size_t n = 0;
  while (n < body.size() && (std::isalnum(static_cast<unsigned char>(body[n])) || body[n] == '_'))
    ++n;
  std::string s = body.substr(0, n);
  for (char& c : s) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  return s;
}

std::vector<std::string> Attributes(const std::string& body) {
  std::vector<std::string> out;
  const std::size_t open = body.find('(');
  if (open == std::string::npos) return out;
  int depth = 0;
  bool quoted = false;
  std::string cur;
  for (std::size_t i = open + 1; i < body.size(); ++i) {
    const char c = body[i];
    if (c == '\'') quoted = !quoted;
    if (!quoted) {
      if (c == '(') ++depth;
      if (c == ')') {
        if (depth == 0) break;
        --depth;
      }
      if (c == ',' && depth == 0) {
        out.push_back(cur);
        cur.clear();
        continue;
      }
    }
    cur += c;
  }
  out.push_back(cur);
  for (auto& a : out) {
    while (!a.empty() && std::isspace(static_cast<unsigned char>(a.front()))) a.erase(a.begin());
    while (!a.empty() && std::isspace(static_cast<unsigned char>(a.back()))) a.pop_back();
  }
  return out;
}

std::string StepString(const std::string& attr) {
  if (attr.size() < 2 || attr.front() != '\'' || attr.back() != '\'') return "";
  const std::string s = attr.substr(1, attr.size() - 2);
  std::string out;
  for (std::size_t i = 0; i < s.size(); ++i) {
    if (s[i] == '\'' && i + 1 < s.size() && s[i + 1] == '\'') {
      out += '\'';
      ++i;
    } else if (s.compare(i, 3, "\\S\\") == 0 && i + 3 < s.size()) {
      AppendUtf8(static_cast<unsigned char>(s[i + 3]) + 0x80u, &out);
      i += 3;
    } else if (s.compare(i, 4, "\\X2\\") == 0) {
      std::size_t j = i + 4;
      while (j + 4 <= s.size() && s.compare(j, 4, "\\X0\\") != 0) {
        AppendUtf8(static_cast<unsigned>(std::strtoul(s.substr(j, 4).c_str(), nullptr, 16)), &out);
        j += 4;
      }
      i = j + 3;
    } else {
      out += s[i];
    }
  }
  return out;
}

double FullLengthScale(const std::string& text, const StepIndex& index, const std::string& where) {
  const double unapplied = IfcUnappliedLengthScale(text, where);
  for (const auto& [id, body] : index.bodies) {
    if (EntityOf(body) != "IFCUNITASSIGNMENT") continue;
    for (std::size_t p = body.find('#'); p != std::string::npos; p = body.find('#', p + 1)) {
      const auto it = index.bodies.find(std::strtoul(body.c_str() + p + 1, nullptr, 10));
      if (it == index.bodies.end() || it->second.find(".LENGTHUNIT.") == std::string::npos)
        continue;
      if (EntityOf(it->second) != "IFCSIUNIT") return unapplied;
      static const std::pair<const char*, double> kPrefixes[] = {
          {".KILO.", 1e3},   {".HECTO.", 1e2},  {".DECA.", 1e1},  {".DECI.", 1e-1},
          {".CENTI.", 1e-2}, {".MILLI.", 1e-3}, {".MICRO.", 1e-6}};
      for (const auto& [name, s] : kPrefixes)
        if (it->second.find(name) != std::string::npos) return s;
      return 1.0;
    }
    break;
  }
  return unapplied;
}

std::string ReadText(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  if (!f) throw InputError(path, "cannot open file", "unreadable", "a readable file");
  std::ostringstream ss;
  ss << f.rdbuf();
  return ss.str();
}

std::string ReadIfcStepText(const std::string& path) {
  std::string text = ReadText(path);
  const std::string schema = IfcSchemaOf(text);
  if (schema.rfind("IFC2X", 0) != 0 && schema.rfind("IFC4", 0) != 0)
    throw InputError(path, "unsupported IFC schema", schema.empty() ? "no FILE_SCHEMA" : schema,
                     "IFC2X3 or IFC4");
  return text;
}

std::vector<unsigned long> StepRefs(const std::string& attr) {
  std::vector<unsigned long> out;
  for (std::size_t q = attr.find('#'); q != std::string::npos; q = attr.find('#', q + 1))
    out.push_back(std::strtoul(attr.c_str() + q + 1, nullptr, 10));
  return out;
}

std::string NodeGuid(const std::string& node) {
  if (node.size() < kGuidLength + 2 || node[node.size() - kGuidLength - 1] != '_') return "";
  return node.substr(node.size() - kGuidLength);
}

std::string NodeLabel(const std::string& node) {
  const std::size_t first = node.find('_');
  if (first == std::string::npos) return node;
  const std::string guid = NodeGuid(node);
  const std::size_t end = guid.empty() ? node.size() : node.size() - kGuidLength - 1;
  return end > first ? node.substr(first + 1, end - first - 1) : "";
}

std::string CleanUtf8(const std::string& s) {
  std::string out;
  for (std::size_t i = 0; i < s.size();) {
    const unsigned char c = static_cast<unsigned char>(s[i]);
    const int n = c < 0x80 ? 1 : (c >> 5) == 6 ? 2 : (c >> 4) == 14 ? 3 : (c >> 3) == 30 ? 4 : 0;
    bool ok = n > 0 && i + n <= s.size() && !(n == 1 && c < 0x20);
    for (int k = 1; ok && k < n; ++k) ok = (static_cast<unsigned char>(s[i + k]) >> 6) == 2;
    if (ok) {
      out.append(s, i, static_cast<std::size_t>(n));
      i += static_cast<std::size_t>(n);
    } else {
      out += '?';
      ++i;
    }
  }
  return out;
}

std::string NoSpaces(std::string s) {
  s.erase(std::remove_if(s.begin(), s.end(), [](unsigned char c) { return std::isspace(c) != 0; }),
          s.end());
  return s;
}

bool IsComponentIfc(const std::string& ifc) {
  const std::string c = Lower(ifc);
  static const std::set<std::string> kNames = {"ifcoutlet",
                                               "ifcswitchingdevice",
                                               "ifcalarm",
                                               "ifcsensor",
                                               "ifcactuator",
                                               "ifcfiresuppressionterminal",
                                               "ifclightfixture",
                                               "ifclamp",
                                               "ifcflowterminal",
                                               "ifcelectricdistributionpoint",
                                               "ifcelectricdistributionboard",
                                               "ifcspaceheater",
                                               "ifcairterminal",
                                               "ifcsanitaryterminal",
                                               "ifcstackterminal",
                                               "ifcwasteterminal",
                                               "ifccommunicationsappliance",
                                               "ifcaudiovisualappliance",
                                               "ifcprotectivedevice",
                                               "ifcunitaryequipment",
                                               "ifcflowcontroller",
                                               "ifcdistributioncontrolelement",
                                               "ifcbuildingelementproxy",
                                               "ifcdiscreteaccessory",
                                               "ifcsignal"};
  return kNames.count(c) > 0;
}

Role RoleOf(const std::string& ifc, ElementClass cls) {
  const std::string c = Lower(ifc);
  // Air: space volumes, and opening volumes when a converter kept them (assimp does not).
  if (cls == ElementClass::kSpace || c == "ifcopeningelement" || c == "ifcvirtualelement")
    return Role::kSpace;
  if (cls == ElementClass::kWall) return Role::kWall;
  if (cls == ElementClass::kSlab || cls == ElementClass::kCeiling || cls == ElementClass::kRoof ||
      cls == ElementClass::kFloor)
    return Role::kSlab;
  if (cls == ElementClass::kColumn) return Role::kColumn;
  if (c == "ifcdoor" || c == "ifcdoorstandardcase") return Role::kDoor;
  if (c == "ifcwindow" || c == "ifcwindowstandardcase") return Role::kWindow;
  if (cls == ElementClass::kFurniture) return Role::kFurniture;
  if (IsComponentIfc(ifc)) return Role::kComponent;
  return Role::kOther;
}

void Importer::Load() {
  LoadOptions lo;
  lo.import_ifc_spaces = true;
  scene_ = LoadScene(path_, lo);
  const std::string ext = Lower(std::filesystem::path(path_).extension().string());
  if (ext == ".ifc") ReadStepInfo(path_);
  std::set<std::string> own_ids;
  for (const MeshPart& part : scene_.parts) own_ids.insert(part.element_id);
  for (const std::string& m : p_.merge) {
    const Scene other = LoadScene(m, lo);
    if (Lower(std::filesystem::path(m).extension().string()) == ".ifc") ReadStepInfo(m);
    const int offset = static_cast<int>(scene_.materials.size());
    for (const Material& mat : other.materials) scene_.materials.push_back(mat);
    const int tex_offset = static_cast<int>(scene_.textures.size());
    for (const Texture& t : other.textures) scene_.textures.push_back(t);
    for (std::size_t k = offset; k < scene_.materials.size(); ++k)
      if (scene_.materials[k].base_color_texture >= 0)
        scene_.materials[k].base_color_texture += tex_offset;
    std::size_t taken = 0, known = 0;
    for (MeshPart part : other.parts) {
      const Role r = RoleOf(part.subclass, part.element_class);
      if (r != Role::kComponent && r != Role::kFurniture) continue;
      if (own_ids.count(part.element_id)) {  // the same GlobalId: the same element
        ++known;
        continue;
      }
      if (part.material >= 0) part.material += offset;
      merged_parts_.insert(scene_.parts.size());
      scene_.parts.push_back(std::move(part));
      ++taken;
    }
    out_.report.push_back("merge " + m + ": " + std::to_string(taken) +
                          " component/furniture part(s) taken, " + std::to_string(known) +
                          " already in the model, the rest of that model ignored");
  }
  // Elements in order of first appearance.
  std::map<std::string, std::size_t> index;
  for (std::size_t i = 0; i < scene_.parts.size(); ++i) {
    const MeshPart& part = scene_.parts[i];
    const std::string id = part.element_id.empty() ? "unlabelled" : CleanUtf8(part.element_id);
    auto [it, fresh] = index.emplace(id, elements_.size());
    if (fresh) {
      Element e;
      e.node = id;
      e.ifc = part.subclass;
      e.role = RoleOf(part.subclass, part.element_class);
      elements_.push_back(e);
    }
    Element& e = elements_[it->second];
    e.parts.push_back(i);
    e.merged = e.merged || merged_parts_.count(i) > 0;
    for (const auto& v : part.positions) e.box.extend(v.cast<double>());
  }
}

// Names, type objects and storey spaces from an IFC file's STEP text (GlobalId keyed).
void Importer::ReadStepInfo(const std::string& path) {
  const std::string text = ReadText(path);
  const StepIndex step = IndexStep(text);
  std::map<unsigned long, std::string> guid_of;
  for (const auto& [id, body] : step.bodies) {
    const std::vector<std::string> a = Attributes(body);
    if (a.size() < 3) continue;
    const std::string guid = StepString(a[0]);
    if (guid.size() != kGuidLength) continue;
    guid_of[id] = guid;
    names_[guid] = StepString(a[2]);
  }
  const auto refs = StepRefs;
  // Georeferenced coordinates: assimp 5.2.5 computes IFC geometry partly in float.
  double far = 0.0;
  for (const auto& [id, body] : step.bodies) {
    if (body.compare(0, 17, "IFCCARTESIANPOINT") != 0) continue;
    const std::size_t open = body.find("((");
    if (open == std::string::npos) continue;
    const char* c = body.c_str() + open + 2;
    for (int k = 0; k < 3; ++k) {
      char* end = nullptr;
      const double v = std::strtod(c, &end);
      if (end == c) break;
      if (std::isfinite(v)) far = std::max(far, std::abs(v));
      c = end;
      while (*c == ',' || *c == ' ') ++c;
    }
  }
  const double scale = FullLengthScale(text, step, path);
  far *= scale;
  if (path == path_) opening_bodies_ = OpeningBodies(step, scale);
  if (far > kFarFromOrigin)
    out_.report.push_back(path + ": coordinates reach " + Fmt(far / 1000.0, 1) +
                          " km from the origin (georeferenced); assimp 5.2.5 computes IFC "
                          "geometry partly in float: expect errors of " +
                          Fmt(far * 1.2e-7 * 1000.0, 0) + " mm or more");
  for (const auto& [id, body] : step.bodies) {
    const std::string entity = EntityOf(body);
    const std::vector<std::string> a = Attributes(body);
    if (entity == "IFCRELDEFINESBYTYPE" && a.size() >= 6) {
      // (guid, owner, name, description, (#objects), #type)
      const auto type = step.bodies.find(refs(a[5]).empty() ? 0 : refs(a[5])[0]);
      if (type == step.bodies.end()) continue;
      std::string cls = Lower(EntityOf(type->second));
      if (cls.size() > 4 && cls.compare(cls.size() - 4, 4, "type") == 0) cls.resize(cls.size() - 4);
      for (unsigned long o : refs(a[4]))
        if (guid_of.count(o)) {
          type_class_[guid_of[o]] = cls;
          if (guid_of.count(type->first)) type_guid_[guid_of[o]] = guid_of[type->first];
        }
    } else if (entity == "IFCRELCONTAINEDINSPATIALSTRUCTURE" && a.size() >= 6) {
      // (guid, owner, name, description, (#elements), #structure)
      const std::vector<unsigned long> where = refs(a[5]);
      if (where.empty() || !guid_of.count(where[0])) continue;
      for (unsigned long o : refs(a[4]))
        if (guid_of.count(o) && step.bodies.count(o))
          storey_contained_[guid_of[where[0]]].emplace_back(guid_of[o],
                                                            EntityOf(step.bodies.at(o)));
    } else if (entity == "IFCRELAGGREGATES" && a.size() >= 6) {
      // (guid, owner, name, description, #relating, (#related)): spaces of a storey.
      const std::vector<unsigned long> whole = refs(a[4]);
      if (whole.empty() || !step.bodies.count(whole[0]) ||
          EntityOf(step.bodies.at(whole[0])) != "IFCBUILDINGSTOREY")
        continue;
      for (unsigned long o : refs(a[5]))
        if (step.bodies.count(o) && EntityOf(step.bodies.at(o)) == "IFCSPACE" && guid_of.count(o) &&
            guid_of.count(whole[0]))
          storey_spaces_[guid_of[whole[0]]].push_back(guid_of[o]);
    }
  }
}

std::string Importer::NiceName(const std::string& node) const {
  const auto it = names_.find(NodeGuid(node));
  const std::string n = it != names_.end() && !it->second.empty() ? it->second : NodeLabel(node);
  return IfcClassFromNodeName(node) + " '" + n + "'";
}

std::string Importer::NiceNameOnly(const std::string& node) const {
  const auto it = names_.find(NodeGuid(node));
  return it != names_.end() ? it->second : "";
}

}  // namespace mopad::scenes::bim

namespace mopad::scenes {

namespace {

// "IFCLABEL('open')" -> "open", "IFCPLANEANGLEMEASURE(1.5707)" -> "1.5707", "'x'" -> "x", "$" -> "".
std::string NominalValue(const std::string& attr) {
  std::string v = attr;
  const std::size_t open = v.find('(');
  if (open != std::string::npos && v.back() == ')' && v.front() != '\'')
    v = v.substr(open + 1, v.size() - open - 2);
  if (v.size() >= 2 && v.front() == '\'') return bim::StepString(v);
  return v == "$" ? "" : v;
}

}  // namespace

IfcProperties ReadIfcProperties(const std::string& path) {
  const bim::StepIndex index = bim::IndexStep(bim::ReadIfcStepText(path));
  const auto refs = bim::StepRefs;
  auto body = [&](unsigned long id) -> const std::string* {
    const auto it = index.bodies.find(id);
    return it == index.bodies.end() ? nullptr : &it->second;
  };
  IfcProperties out;
  for (const auto& [id, rel] : index.bodies) {
    if (bim::EntityOf(rel) != "IFCRELDEFINESBYPROPERTIES") continue;
    // (guid, owner, name, description, (#objects), #definition)
    const std::vector<std::string> a = bim::Attributes(rel);
    if (a.size() < 6) continue;
    const std::vector<unsigned long> def = refs(a[5]);
    const std::string* set = def.empty() ? nullptr : body(def[0]);
    if (!set || bim::EntityOf(*set) != "IFCPROPERTYSET") continue;
    // (guid, owner, name, description, (#properties))
    const std::vector<std::string> sa = bim::Attributes(*set);
    if (sa.size() < 5) continue;
    const std::string set_name = bim::StepString(sa[2]);
    std::vector<std::pair<std::string, std::string>> values;
    for (unsigned long pid : refs(sa[4])) {
      const std::string* prop = body(pid);
      if (!prop || bim::EntityOf(*prop) != "IFCPROPERTYSINGLEVALUE") continue;
      // (name, description, nominal value, unit)
      const std::vector<std::string> pa = bim::Attributes(*prop);
      if (pa.size() < 3) continue;
      values.emplace_back(set_name + "." + bim::StepString(pa[0]), NominalValue(pa[2]));
    }
    for (unsigned long object : refs(a[4])) {
      const std::string* product = body(object);
      if (!product) continue;
      const std::vector<std::string> pa = bim::Attributes(*product);
      if (pa.empty()) continue;
      const std::string guid = bim::StepString(pa[0]);
      if (guid.empty()) continue;
      for (const auto& [key, value] : values) out[guid][key] = value;
    }
  }
  return out;
}

std::vector<BimStorey> ListIfcStoreys(const std::string& path) {
  const std::string text = bim::ReadIfcStepText(path);
  const bim::StepIndex index = bim::IndexStep(text);
  const double scale = bim::FullLengthScale(text, index, path);
  std::vector<BimStorey> out;
  for (const auto& [id, body] : index.bodies) {
    if (bim::EntityOf(body) != "IFCBUILDINGSTOREY") continue;
    const std::vector<std::string> a = bim::Attributes(body);
    BimStorey s;
    if (!a.empty()) s.global_id = bim::StepString(a[0]);
    if (a.size() > 2) s.name = bim::StepString(a[2]);
    if (a.size() > 9 && a[9] != "$") {
      char* end = nullptr;
      const double v = std::strtod(a[9].c_str(), &end);
      if (end != a[9].c_str() && std::isfinite(v)) {
        s.elevation = v * scale;
        s.has_elevation = true;
      }
    }
    out.push_back(s);
  }
  return out;
}

}  // namespace mopad::scenes
