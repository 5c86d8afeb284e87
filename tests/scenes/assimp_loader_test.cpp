// Formats through assimp: OBJ axes, error messages, IFC schema refusal and unit scaling.
#include "scenes/assimp_loader.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "common/error.h"
#include "scenes/scene_loader.h"
#include "tests/process_temp_dir.h"

namespace mopad::scenes {
namespace {

namespace fs = std::filesystem;

std::string WriteFile(const std::string& name, const std::string& text) {
  const fs::path dir = test_support::ProcessTempDir("mopad_assimp_test_", "", false);
  const std::string path = (dir / name).string();
  std::ofstream(path, std::ios::binary) << text;
  return path;
}

// Expects `fn` to throw InputError with one line starting with `path: error: ` and containing
// `fragment`; returns the message.
template <typename Fn>
std::string ExpectInputError(Fn fn, const std::string& path, const std::string& fragment) {
  try {
    fn();
  } catch (const InputError& e) {
    const std::string m = e.what();
    EXPECT_EQ(m.rfind(path + ": error: ", 0), 0u) << m;
    EXPECT_EQ(m.find('\n'), std::string::npos) << m;
    EXPECT_NE(m.find(fragment), std::string::npos) << m;
    return m;
  }
  ADD_FAILURE() << "no InputError for " << path;
  return "";
}

const char kQuadObj[] =
    "o wall_quad\n"
    "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n"
    "f 1 2 3 4\n";

TEST(AssimpLoader, ObjIsTriangulatedAndTakenAsYupByDefault) {
  const std::string path = WriteFile("quad.obj", kQuadObj);
  const Scene s = LoadScene(path);
  EXPECT_EQ(s.TriangleCount(), 2u);
  const Eigen::AlignedBox3d box = s.Bounds();
  // OBJ (x, y, z) with y up -> world (x, -z, y): the quad stands in the world xz plane.
  EXPECT_NEAR(box.min().y(), 0.0, 1e-9);
  EXPECT_NEAR(box.max().y(), 0.0, 1e-9);
  EXPECT_NEAR(box.max().z(), 1.0, 1e-6);
  EXPECT_NE(s.parts[0].name.find("wall_quad"), std::string::npos) << s.parts[0].name;

  LoadOptions zup;
  zup.up_axis = UpAxis::kZ;
  const Eigen::AlignedBox3d zbox = LoadScene(path, zup).Bounds();
  EXPECT_NEAR(zbox.max().y(), 1.0, 1e-6);
  EXPECT_NEAR(zbox.max().z(), 0.0, 1e-9);
}

TEST(AssimpLoader, MissingFileIsOneLineError) {
  const std::string path = "/nonexistent/dir/house.obj";
  const std::string m = ExpectInputError([&] { LoadScene(path); }, path, "cannot open file");
  EXPECT_EQ(m,
            path + ": error: cannot open file; got no such file, expected an existing scene file");
  ExpectInputError([&] { LoadWithAssimp(path); }, path, "cannot open file");
}

TEST(AssimpLoader, UnknownExtensionIsOneLineError) {
  const std::string path = WriteFile("scene.xyz", "hello");
  ExpectInputError([&] { LoadScene(path); }, path, "unsupported file extension; got '.xyz'");
}

TEST(AssimpLoader, GarbageObjIsOneLineError) {
  const std::string path = WriteFile("garbage.ply", "ply\nformat nonsense\n");
  ExpectInputError([&] { LoadScene(path); }, path, "assimp cannot read the file");
}

const char kIfc4Header[] =
    "ISO-10303-21;\nHEADER;\nFILE_DESCRIPTION(('ViewDefinition [ReferenceView]'),'2;1');\n"
    "FILE_NAME('x.ifc','2024-01-01T00:00:00',(''),(''),'','','');\n"
    "FILE_SCHEMA(('IFC4'));\nENDSEC;\nDATA;\n#1=IFCPROJECT('0001',$,$,$,$,$,$,$,$);\nENDSEC;\n"
    "END-ISO-10303-21;\n";

TEST(AssimpLoader, Ifc4GoesToIfcPlusPlusBeforeAssimpSeesIt) {
  const std::string path = WriteFile("model4.ifc", kIfc4Header);
  ExpectInputError([&] { LoadScene(path); }, path, "the IFC4 reader (IfcPlusPlus)");
  std::string v4 = kIfc4Header;
  v4.replace(v4.find("'IFC4'"), 6, "'IFC3'");
  const std::string path3 = WriteFile("model3.ifc", v4);
  const std::string m =
      ExpectInputError([&] { LoadScene(path3); }, path3, "unsupported IFC schema");
  EXPECT_NE(m.find("got IFC3, expected IFC2X3 or IFC4"), std::string::npos) << m;
  EXPECT_EQ(IfcSchemaOf(kIfc4Header), "IFC4");
  EXPECT_EQ(IfcSchemaOf("ISO-10303-21;\nHEADER;\nFILE_SCHEMA (('ifc4x3_add2'));\nENDSEC;"),
            "IFC4X3_ADD2");
  EXPECT_EQ(IfcSchemaOf("no header at all"), "");
  const std::string not_ifc = WriteFile("notifc.ifc", "solid cube\nendsolid\n");
  ExpectInputError([&] { LoadScene(not_ifc); }, not_ifc, "not an IFC STEP file");
}

// A minimal IFC 2x3 file: one 4 x 0.2 x 3 wall extruded in a site, with a length unit of
// `unit_entities` (which must define #21 as the IFCUNITASSIGNMENT).
std::string TinyIfc(const std::string& unit_entities) {
  return "ISO-10303-21;\nHEADER;\n"
         "FILE_DESCRIPTION(('ViewDefinition [CoordinationView]'),'2;1');\n"
         "FILE_NAME('tiny.ifc','2024-01-01T00:00:00',(''),(''),'','','');\n"
         "FILE_SCHEMA(('IFC2X3'));\nENDSEC;\nDATA;\n"
         "#1=IFCPERSON($,$,'',$,$,$,$,$);\n"
         "#2=IFCORGANIZATION($,'org',$,$,$);\n"
         "#3=IFCPERSONANDORGANIZATION(#1,#2,$);\n"
         "#4=IFCAPPLICATION(#2,'1','app','app');\n"
         "#5=IFCOWNERHISTORY(#3,#4,$,.ADDED.,$,$,$,0);\n"
         "#10=IFCCARTESIANPOINT((0.,0.,0.));\n"
         "#11=IFCDIRECTION((0.,0.,1.));\n"
         "#12=IFCDIRECTION((1.,0.,0.));\n"
         "#13=IFCAXIS2PLACEMENT3D(#10,#11,#12);\n"
         "#14=IFCGEOMETRICREPRESENTATIONCONTEXT($,'Model',3,1.E-05,#13,$);\n" +
         unit_entities +
         "#30=IFCPROJECT('0YvctVUKr0kugbFTf53O9L',#5,'P',$,$,$,$,(#14),#21);\n"
         "#40=IFCLOCALPLACEMENT($,#13);\n"
         "#41=IFCSITE('1YvctVUKr0kugbFTf53O9L',#5,'Site',$,$,#40,$,$,.ELEMENT.,$,$,$,$,$);\n"
         "#42=IFCRELAGGREGATES('2YvctVUKr0kugbFTf53O9L',#5,$,$,#30,(#41));\n"
         "#50=IFCLOCALPLACEMENT(#40,#13);\n"
         "#52=IFCCARTESIANPOINT((2.,0.1));\n"
         "#51=IFCAXIS2PLACEMENT2D(#52,$);\n"
         "#53=IFCRECTANGLEPROFILEDEF(.AREA.,$,#51,4.,0.2);\n"
         "#54=IFCEXTRUDEDAREASOLID(#53,#13,#11,3.);\n"
         "#55=IFCSHAPEREPRESENTATION(#14,'Body','SweptSolid',(#54));\n"
         "#56=IFCPRODUCTDEFINITIONSHAPE($,$,(#55));\n"
         "#57=IFCWALLSTANDARDCASE('3YvctVUKr0kugbFTf53O9L',#5,'W1',$,$,#50,#56,$);\n"
         "#58=IFCRELCONTAINEDINSPATIALSTRUCTURE('4YvctVUKr0kugbFTf53O9L',#5,$,$,(#57),#41);\n"
         "ENDSEC;\nEND-ISO-10303-21;\n";
}

const char kMetre[] =
    "#20=IFCSIUNIT(*,.LENGTHUNIT.,$,.METRE.);\n"
    "#21=IFCUNITASSIGNMENT((#20));\n";
const char kFoot[] =
    "#19=IFCDIMENSIONALEXPONENTS(1,0,0,0,0,0,0);\n"
    "#20=IFCSIUNIT(*,.LENGTHUNIT.,$,.METRE.);\n"
    "#22=IFCMEASUREWITHUNIT(IFCLENGTHMEASURE(0.3048),#20);\n"
    "#23=IFCCONVERSIONBASEDUNIT(#19,.LENGTHUNIT.,'FOOT',#22);\n"
    "#21=IFCUNITASSIGNMENT((#23));\n";

TEST(AssimpLoader, IfcUnitSniffing) {
  EXPECT_DOUBLE_EQ(IfcUnappliedLengthScale(TinyIfc(kMetre)), 1.0);
  EXPECT_DOUBLE_EQ(IfcUnappliedLengthScale(TinyIfc(kFoot)), 0.3048);
  // Millimetres: assimp applies SI prefixes itself, nothing left for us.
  EXPECT_DOUBLE_EQ(IfcUnappliedLengthScale("#7 = IFCSIUNIT(*, .LENGTHUNIT., .MILLI., .METRE.);\n"
                                           "#8 = IFCUNITASSIGNMENT((#7));\n"),
                   1.0);
  // Inch given as 25.4 mm: the measure's own unit prefix counts.
  EXPECT_DOUBLE_EQ(
      IfcUnappliedLengthScale("#140=IFCSIUNIT(*,.LENGTHUNIT.,.MILLI.,.METRE.);\n"
                              "#14=IFCMEASUREWITHUNIT(IFCLENGTHMEASURE(25.4),#140);\n"
                              "#15=IFCCONVERSIONBASEDUNIT(#1,.LENGTHUNIT.,'INCH',#14);\n"
                              "#16=IFCUNITASSIGNMENT((#15));\n"),
      0.0254);
  EXPECT_DOUBLE_EQ(IfcUnappliedLengthScale("#1=IFCPROJECT($);"), 1.0);
  EXPECT_THROW(IfcUnappliedLengthScale("#15=IFCCONVERSIONBASEDUNIT(#1,.LENGTHUNIT.,'FOOT',#99);\n"
                                       "#16=IFCUNITASSIGNMENT((#15));\n",
                                       "x.ifc"),
               InputError);
}

TEST(AssimpLoader, IfcFootUnitsAreScaledToMetres) {
  LoadOptions keep;
  keep.drop_degenerate_triangles = false;
  const Scene metre = LoadScene(WriteFile("wall_m.ifc", TinyIfc(kMetre)), keep);
  const Scene foot = LoadScene(WriteFile("wall_ft.ifc", TinyIfc(kFoot)), keep);
  ASSERT_GT(metre.TriangleCount(), 0u);
  EXPECT_EQ(metre.TriangleCount(), foot.TriangleCount());
  const Eigen::Vector3d m = metre.Bounds().sizes();
  const Eigen::Vector3d f = foot.Bounds().sizes();
  // Wall 4 x 0.2 x 3 units, IFC z up -> world z up.
  EXPECT_NEAR(m.x(), 4.0, 1e-5);
  EXPECT_NEAR(m.y(), 0.2, 1e-5);
  EXPECT_NEAR(m.z(), 3.0, 1e-5);
  EXPECT_TRUE(f.isApprox(0.3048 * m, 1e-5)) << f.transpose() << " vs " << m.transpose();
  for (const MeshPart& p : metre.parts) {
    EXPECT_EQ(p.element_class, ElementClass::kWall) << p.name;
    EXPECT_EQ(p.subclass, "IfcWallStandardCase");
    EXPECT_EQ(p.element_id.rfind("IfcWallStandardCase_W1_", 0), 0u) << p.element_id;
  }
}

TEST(AssimpLoader, IfcNodeNames) {
  EXPECT_EQ(IfcClassFromNodeName("IfcWallStandardCase_Wand-Ext-ERDG-1_3rPX_Juz59peXXY6wDJl18"),
            "IfcWallStandardCase");
  EXPECT_EQ(IfcClassFromNodeName("IfcMappedItem"), "IfcMappedItem");
  EXPECT_EQ(IfcClassFromNodeName("$RelAggregates"), "");
  EXPECT_EQ(IfcClassFromNodeName("Ifc"), "");
  EXPECT_EQ(IfcClassFromNodeName("Ifcwall_x"), "");
  EXPECT_EQ(IfcClassFromNodeName("wall_R1_2"), "");
}

}  // namespace
}  // namespace mopad::scenes
