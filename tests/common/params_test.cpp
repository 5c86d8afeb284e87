#include "common/params.h"

#include <gtest/gtest.h>

#include <fstream>
#include <map>
#include <string>
#include <vector>

namespace mopad {
namespace {

struct InnerParams {
  double gain = 2.0;  ///< -, [0, 10]
  template <class V>
  void Visit(V& v) {
    v("gain", gain, Bounds{0.0, 10.0});
  }
};

struct TestParams {
  double max_range = 30.0;  ///< m, (0, 1000]
  int rays = 7;             ///< count, [1, 64]
  bool enabled = true;
  std::string name = "default";
  std::vector<double> weights{1.0, 2.0};
  InnerParams inner;
  template <class V>
  void Visit(V& v) {
    v("max_range", max_range, Bounds{1e-9, 1000.0});
    v("rays", rays, Bounds{1, 64});
    v("enabled", enabled);
    v("name", name);
    v("weights", weights, Bounds{0.0, 100.0});
    v("inner", inner);
  }
};

TEST(Params, AbsentKeysKeepDefaults) {
  const auto p = LoadParams<TestParams>(LoadYamlString("rays: 3\n", "t.yaml"), "t.yaml");
  EXPECT_EQ(p.rays, 3);
  EXPECT_DOUBLE_EQ(p.max_range, 30.0);
  EXPECT_EQ(p.name, "default");
  EXPECT_DOUBLE_EQ(p.inner.gain, 2.0);
}

TEST(Params, UnknownKeyIsRejectedWithFileAndLine) {
  try {
    LoadParams<TestParams>(LoadYamlString("rays: 3\nmax_rnage: 5\n", "t.yaml"), "t.yaml");
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("t.yaml:2: error: unknown key 'max_rnage'"), std::string::npos) << m;
    EXPECT_NE(m.find("max_range"), std::string::npos) << m;  // lists the known keys
  }
}

// A key that is not a name (a sequence or a map as a key; the fuzz target of the scene spec
// found one, which escaped as a yaml-cpp exception: exit 3) is an input error with its line.
TEST(Params, AKeyThatIsASequenceOrAMapIsAnInputError) {
  for (const char* text : {"rays: 3\n? [a, b]\n: 5\n", "rays: 3\n? {a: 1}\n: 5\n"}) {
    try {
      LoadParams<TestParams>(LoadYamlString(text, "t.yaml"), "t.yaml");
      FAIL() << "expected InputError for " << text;
    } catch (const InputError& e) {
      const std::string m = e.what();
      EXPECT_EQ(m.rfind("t.yaml:2: error: a key is not a name; got a ", 0), 0u) << m;
      EXPECT_NE(m.find("expected one of: enabled, inner"), std::string::npos) << m;
    }
  }
}

TEST(Params, NestedUnknownKeyNamesItsPath) {
  try {
    LoadParams<TestParams>(LoadYamlString("inner:\n  gian: 1\n", "t.yaml"), "t.yaml");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("t.yaml:2: error: unknown key 'inner.gian'"),
              std::string::npos)
        << e.what();
  }
}

TEST(Params, WrongTypeAndOutOfRangeAreClear) {
  try {
    LoadParams<TestParams>(LoadYamlString("rays: many\n", "t.yaml"), "t.yaml");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("t.yaml:1: error: wrong type for 'rays'; got 'many', "
                                         "expected an integer"),
              std::string::npos)
        << e.what();
  }
  try {
    LoadParams<TestParams>(LoadYamlString("max_range: -1\n", "t.yaml"), "t.yaml");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("out of range"), std::string::npos) << e.what();
  }
  try {
    LoadParams<TestParams>(LoadYamlString("max_range: .nan\n", "t.yaml"), "t.yaml");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("'max_range' out of range"), std::string::npos);
  }
}

TEST(Params, SaveLoadRoundTrip) {
  TestParams p;
  p.max_range = 12.5;
  p.rays = 9;
  p.name = "x";
  p.weights = {0.5};
  p.inner.gain = 7.0;
  const YAML::Node saved = SaveParams(p);
  const auto q = LoadParams<TestParams>(LoadYamlString(YAML::Dump(saved), "s.yaml"), "s.yaml");
  EXPECT_EQ(YAML::Dump(SaveParams(q)), YAML::Dump(saved));
  EXPECT_EQ(q.rays, 9);
  EXPECT_EQ(q.weights, std::vector<double>{0.5});
  EXPECT_DOUBLE_EQ(q.inner.gain, 7.0);
}

TEST(Params, ValidateNamesTheField) {
  TestParams p;
  p.inner.gain = 11.0;
  try {
    ValidateParams(p, "test.");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("'test.inner.gain' out of range"), std::string::npos)
        << e.what();
  }
}

// A relation between fields that no single bound can state (lo below hi).
struct RangeParams {
  double lo = 1.0;  ///< m, [0, 100], below hi
  double hi = 2.0;  ///< m, [0, 100], above lo
  template <class V>
  void Visit(V& v) {
    v("lo", lo, Bounds{0.0, 100.0});
    v("hi", hi, Bounds{0.0, 100.0});
  }
  void Validate() const {
    if (!(lo < hi))
      throw InputError("", "parameter 'lo' must be below 'hi'", std::to_string(lo), "< hi");
  }
};

struct OuterParams {
  RangeParams range;
  template <class V>
  void Visit(V& v) {
    v("range", range);
  }
};

// ValidateParams runs a nested struct's own Validate() too, so that one call before any work
// refuses what the struct's user would refuse later; the message says which struct.
TEST(Params, ValidateRunsANestedStructsOwnChecksAndNamesItsPath) {
  OuterParams p;
  EXPECT_NO_THROW(ValidateParams(p, "cfg."));
  p.range.lo = 3.0;  // each value within its bounds, the pair not
  try {
    ValidateParams(p, "cfg.");
    FAIL() << "lo above hi accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()),
              "cfg.range: error: parameter 'lo' must be below 'hi'; got 3.000000, expected < hi");
  }
  // Bounds are still checked first, with the field's full path.
  p.range.lo = -1.0;
  try {
    ValidateParams(p, "cfg.");
    FAIL() << "lo below its bound accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("'cfg.range.lo' out of range"), std::string::npos)
        << e.what();
  }
}

TEST(Params, MissingFileAndBadYamlAreOneLineErrors) {
  try {
    LoadYamlFile("/nonexistent/p.yaml");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()).rfind("/nonexistent/p.yaml: error: cannot open file", 0), 0u)
        << e.what();
  }
  const std::string path = testing::TempDir() + "/bad.yaml";
  std::ofstream(path) << "a: [1, 2\nb: 3\n";
  try {
    LoadYamlFile(path);
    FAIL();
  } catch (const InputError& e) {
    const std::string m = e.what();
    EXPECT_EQ(m.find('\n'), std::string::npos);
    EXPECT_EQ(m.rfind(path + ":", 0), 0u) << m;
  }
}

// A field missing from Visit() keeps its default through a YAML round trip on both sides, so a
// round trip cannot catch it; the coverage check does (positive controls first).
struct ForgetfulParams {
  double a = 1.0;
  double forgotten = 2.0;  // not in Visit()
  int b = 3;
  InnerParams inner;
  template <class V>
  void Visit(V& v) {
    v("a", a);
    v("b", b);
    v("inner", inner);
  }
};

struct InnerForgetful {
  double kept = 0.0;
  std::string forgotten;
  template <class V>
  void Visit(V& v) {
    v("kept", kept);
  }
};

struct OuterOfForgetful {
  int n = 0;
  InnerForgetful inner;
  template <class V>
  void Visit(V& v) {
    v("n", n);
    v("inner", inner);
  }
};

TEST(Params, CoverageCheckFindsAFieldMissingFromVisit) {
  const auto missing = FieldsMissingFromVisit(ForgetfulParams{});
  ASSERT_EQ(missing.size(), 1u);
  EXPECT_NE(missing[0].find("between 'a' and 'b'"), std::string::npos) << missing[0];
  const auto nested = FieldsMissingFromVisit(OuterOfForgetful{}, "outer.");
  ASSERT_EQ(nested.size(), 1u);
  EXPECT_NE(nested[0].find("outer.inner."), std::string::npos) << nested[0];
  EXPECT_NE(nested[0].find("after 'kept'"), std::string::npos) << nested[0];
}

TEST(Params, CoverageCheckPassesACompleteFieldList) {
  EXPECT_TRUE(FieldsMissingFromVisit(TestParams{}).empty());
  EXPECT_TRUE(FieldsMissingFromVisit(InnerParams{}).empty());
}

// Lists of strings and maps from names to numbers (per-item settings such as a door's angle).
struct ListParams {
  std::vector<std::string> files;            ///< paths
  std::map<std::string, double> angles_deg;  ///< deg by id, [0, 180]
  template <class V>
  void Visit(V& v) {
    v("files", files);
    v("angles_deg", angles_deg, Bounds{0.0, 180.0});
  }
};

TEST(Params, StringListsAndNameMapsLoadSaveAndCheckEveryValue) {
  const auto p = LoadParams<ListParams>(
      LoadYamlString("files: [a.ifc, b.ifc]\nangles_deg: {D1: 45, D2: 0}\n", "l.yaml"), "l.yaml");
  EXPECT_EQ(p.files, (std::vector<std::string>{"a.ifc", "b.ifc"}));
  EXPECT_EQ(p.angles_deg, (std::map<std::string, double>{{"D1", 45.0}, {"D2", 0.0}}));
  const auto back = LoadParams<ListParams>(SaveParams(p), "saved");
  EXPECT_EQ(back.files, p.files);
  EXPECT_EQ(back.angles_deg, p.angles_deg);
  const auto empty = LoadParams<ListParams>(
      LoadYamlString(YAML::Dump(SaveParams(ListParams{})), "empty.yaml"), "empty.yaml");
  EXPECT_TRUE(empty.files.empty());
  EXPECT_TRUE(empty.angles_deg.empty());
  try {
    LoadParams<ListParams>(LoadYamlString("angles_deg: {D1: 45, D2: 200}\n", "l.yaml"), "l.yaml");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("'angles_deg.D2' out of range"), std::string::npos)
        << e.what();
  }
  EXPECT_THROW(LoadParams<ListParams>(LoadYamlString("files: a.ifc\n", "l.yaml"), "l.yaml"),
               InputError);
  EXPECT_THROW(LoadParams<ListParams>(LoadYamlString("angles_deg: [1]\n", "l.yaml"), "l.yaml"),
               InputError);
  EXPECT_TRUE(FieldsMissingFromVisit(ListParams{}).empty());
}

// A struct that holds another and lists its fields flat (`part.Visit(v)`): the keys of both at
// one level, every field still covered.
struct ComposedParams {
  InnerParams part{.gain = 3.0};
  int extra = 1;  ///< count, [0, 10]
  template <class V>
  void Visit(V& v) {
    part.Visit(v);
    v("extra", extra, Bounds{0, 10});
  }
};

TEST(Params, AMemberVisitedFlatKeepsItsKeysAtTheOwnersLevel) {
  EXPECT_EQ(YAML::Dump(SaveParams(ComposedParams{})), "gain: 3\nextra: 1");
  const auto p = LoadParams<ComposedParams>(LoadYamlString("extra: 2\n", "c.yaml"), "c.yaml");
  EXPECT_DOUBLE_EQ(p.part.gain, 3.0);  // the owner's default for its member
  EXPECT_EQ(p.extra, 2);
  EXPECT_TRUE(FieldsMissingFromVisit(ComposedParams{}).empty());
}

}  // namespace
}  // namespace mopad
