#include "io/step_writer.h"

#include <gtest/gtest.h>

#include <cstdlib>
#include <set>
#include <stdexcept>
#include <string>

namespace mopad::io {
namespace {

TEST(StepWriter, InstancesAreNumberedInOrderAndTheFileHasHeaderAndData) {
  StepWriter w;
  EXPECT_EQ(w.Add("IFCCARTESIANPOINT", "(0.,0.,0.)"), 1);
  EXPECT_EQ(w.Add("IFCDIRECTION", "(0.,0.,1.)"), 2);
  EXPECT_EQ(w.Add("IFCAXIS2PLACEMENT3D", StepRef(1) + ",#2,$"), 3);
  EXPECT_EQ(w.Count(), 3);
  StepHeader h;
  h.file_name = "model.ifc";
  const std::string t = w.Text(h);
  EXPECT_EQ(t.rfind("ISO-10303-21;\nHEADER;\nFILE_DESCRIPTION(('ViewDefinition [ReferenceView]'),"
                    "'2;1');\n",
                    0),
            0u)
      << t;
  EXPECT_NE(t.find("FILE_NAME('model.ifc','1970-01-01T00:00:00',(''),(''),"), std::string::npos);
  EXPECT_NE(t.find("FILE_SCHEMA(('IFC4'));\nENDSEC;\nDATA;\n#1=IFCCARTESIANPOINT((0.,0.,0.));\n"
                   "#2=IFCDIRECTION((0.,0.,1.));\n#3=IFCAXIS2PLACEMENT3D(#1,#2,$);\nENDSEC;\n"
                   "END-ISO-10303-21;\n"),
            std::string::npos)
      << t;
  EXPECT_THROW(w.Add("IfcWall", "$"), std::invalid_argument);  // keywords are upper case
  EXPECT_THROW(w.Add("", "$"), std::invalid_argument);
}

TEST(StepWriter, StringsEscapeQuotesBackslashesAndNonAscii) {
  EXPECT_EQ(StepString("wall_1"), "'wall_1'");
  EXPECT_EQ(StepString("it's"), "'it''s'");
  EXPECT_EQ(StepString("a\\b"), "'a\\\\b'");
  EXPECT_EQ(StepString(""), "''");
  // U+00E9 (2-byte UTF-8) and U+00B2 in one \X2\ run; back to ASCII closes it.
  EXPECT_EQ(StepString("caf\xC3\xA9\xC2\xB2 m"), "'caf\\X2\\00E900B2\\X0\\ m'");
  // A newline is not printable: encoded, never written raw.
  EXPECT_EQ(StepString("a\nb"), "'a\\X2\\000A\\X0\\b'");
  // U+1F600 as a UTF-16 surrogate pair.
  EXPECT_EQ(StepString("\xF0\x9F\x98\x80"), "'\\X2\\D83DDE00\\X0\\'");
  // A lone continuation byte and a truncated sequence are U+FFFD, not copied through.
  EXPECT_EQ(StepString("\x80"), "'\\X2\\FFFD\\X0\\'");
  EXPECT_EQ(StepString("x\xE2\x82"), "'x\\X2\\FFFD\\X0\\'");
}

TEST(StepWriter, RealsHaveADotAndReadBackExactly) {
  EXPECT_EQ(StepReal(0.0), "0.");
  EXPECT_EQ(StepReal(-0.0), "0.");
  EXPECT_EQ(StepReal(1.0), "1.");
  EXPECT_EQ(StepReal(-0.25), "-0.25");
  EXPECT_EQ(StepReal(1.5e-7), "1.5E-07");
  EXPECT_EQ(StepReal(1e22), "1.E22");
  for (double v : {0.1, 1.0 / 3.0, -2.8015000000000003, 11.0503, 6.02214076e23, 5e-324}) {
    const std::string s = StepReal(v);
    EXPECT_NE(s.find('.'), std::string::npos) << s;
    EXPECT_EQ(std::strtod(s.c_str(), nullptr), v) << s;
  }
  EXPECT_THROW(StepReal(std::numeric_limits<double>::quiet_NaN()), std::invalid_argument);
  EXPECT_THROW(StepReal(std::numeric_limits<double>::infinity()), std::invalid_argument);
}

TEST(StepWriter, ListsReferencesAndEnumerations) {
  EXPECT_EQ(StepList({}), "()");
  EXPECT_EQ(StepList({"1.", "'a'"}), "(1.,'a')");
  EXPECT_EQ(StepRefList({4, 17}), "(#4,#17)");
  EXPECT_EQ(StepEnum("CEILING"), ".CEILING.");
}

TEST(StepWriter, GlobalIdsAre22IfcBase64CharactersDeterministicAndDistinct) {
  const std::string alphabet = "0123456789ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz_$";
  std::set<std::string> seen;
  for (int k = 0; k < 2000; ++k) {
    const std::string key = "run-content-hash/R1/wall_" + std::to_string(k);
    const std::string id = IfcGlobalId(key);
    ASSERT_EQ(id.size(), 22u);
    EXPECT_LE(id[0], '3') << id;  // the first character holds 2 bits
    for (char c : id) EXPECT_NE(alphabet.find(c), std::string::npos) << id;
    EXPECT_EQ(IfcGlobalId(key), id);  // a pure function of the key
    seen.insert(id);
  }
  EXPECT_EQ(seen.size(), 2000u);
  EXPECT_NE(IfcGlobalId("a"), IfcGlobalId("b"));
  EXPECT_NE(IfcGlobalId("ab"), IfcGlobalId("ba"));
}

}  // namespace
}  // namespace mopad::io
