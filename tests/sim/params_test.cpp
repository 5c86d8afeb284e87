#include "common/params.h"

#include <gtest/gtest.h>

#include "common/error.h"
#include "sim/lrf.h"
#include "sim/robot_body.h"
#include "sim/tls_params.h"

namespace mopad::sim {
namespace {

const std::string kProfiles = std::string(MOPAD_SOURCE_DIR) + "/sim/profiles/";

template <class T>
std::string Dump(const T& p) {
  YAML::Emitter e;
  e << SaveParams(p);
  return e.c_str();
}

TEST(SimParams, TlsYamlRoundTrip) {
  TlsParams p = TlsProfile("riegl_vz400");
  p.step_deg = 0.04;
  p.footprint_rays = 7;
  p.camera_offset = {0.01, 0.02, 0.03};
  p.echo_mode = "first";
  YAML::Emitter e;
  e << SaveParams(p);
  const TlsParams back = LoadParams<TlsParams>(LoadYamlString(e.c_str(), "roundtrip"), "roundtrip");
  EXPECT_EQ(Dump(back), Dump(p));
}

// The YAML round trips above cannot see a field left out of Visit(); the coverage check can.
TEST(SimParams, EveryFieldIsInTheFieldList) {
  for (const auto& m : FieldsMissingFromVisit(TlsProfile("riegl_vz400"), "tls."))
    ADD_FAILURE() << m;
  for (const auto& m : FieldsMissingFromVisit(LrfProfile("sick_lms111"), "lrf."))
    ADD_FAILURE() << m;
  for (const auto& m : FieldsMissingFromVisit(RobotBodyParams{}, "body.")) ADD_FAILURE() << m;
}

TEST(SimParams, LrfYamlRoundTrip) {
  const LrfParams p = LrfProfile("sick_lms111");
  YAML::Emitter e;
  e << SaveParams(p);
  const LrfParams back = LoadParams<LrfParams>(LoadYamlString(e.c_str(), "roundtrip"), "roundtrip");
  EXPECT_EQ(Dump(back), Dump(p));
}

TEST(SimParams, ShippedProfileFilesEqualTheBuiltInProfiles) {
  for (const auto& name : TlsProfileNames()) {
    EXPECT_EQ(Dump(LoadParamsFile<TlsParams>(kProfiles + name + ".yaml")), Dump(TlsProfile(name)))
        << name;
  }
  for (const auto& name : LrfProfileNames()) {
    EXPECT_EQ(Dump(LoadParamsFile<LrfParams>(kProfiles + name + ".yaml")), Dump(LrfProfile(name)))
        << name;
  }
}

TEST(SimParams, UnknownKeysAndBadValuesAreRejected) {
  try {
    LoadParams<TlsParams>(LoadYamlString("step_deg: 0.1\nstep_degs: 0.2\n", "p.yaml"), "p.yaml");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("p.yaml:2: error: unknown key 'step_degs'"),
              std::string::npos)
        << e.what();
  }
  EXPECT_THROW(LoadParams<TlsParams>(LoadYamlString("step_deg: 0.001\n", "p.yaml"), "p.yaml"),
               InputError);
  TlsParams p;
  p.range_accuracy = 0.001;  // below precision: accuracy is the total error
  EXPECT_THROW(p.Validate(), InputError);
  p = TlsParams{};
  p.echo_mode = "loudest";
  EXPECT_THROW(p.Validate(), InputError);
  EXPECT_THROW(TlsProfile("faro_focus"), InputError);
  EXPECT_THROW(LrfProfile("velodyne"), InputError);
}

}  // namespace
}  // namespace mopad::sim
