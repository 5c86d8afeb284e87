// Every .gltf/.glb of the external corpora either loads into a sane scene or is rejected with
// one InputError line starting with its path; nothing crashes, hangs or reads out of bounds
// (run this binary under AddressSanitizer to check the last part).
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <string>
#include <vector>

#include "common/error.h"
#include "scenes/scene_loader.h"

namespace mopad::scenes {
namespace {

namespace fs = std::filesystem;

const fs::path kExternal = fs::path(MOPAD_SOURCE_DIR) / ".." / "shared" / "testdata" / "external";

struct Outcome {
  std::string path;
  bool accepted = false;
  std::string message;  // the error line when rejected
  double seconds = 0.0;
};

std::vector<std::string> GltfFiles(const fs::path& root) {
  std::vector<std::string> files;
  for (const auto& e : fs::recursive_directory_iterator(root)) {
    const std::string ext = e.path().extension().string();
    if (e.is_regular_file() && (ext == ".gltf" || ext == ".glb"))
      files.push_back(e.path().string());
  }
  std::sort(files.begin(), files.end());  // deterministic order
  return files;
}

// Loads one file and checks the contract of either outcome.
Outcome LoadOne(const std::string& path) {
  Outcome o;
  o.path = path;
  const auto t0 = std::chrono::steady_clock::now();
  try {
    const Scene s = LoadScene(path);
    o.accepted = true;
    EXPECT_GT(s.TriangleCount(), 0u) << path;
    for (const MeshPart& p : s.parts) {
      for (const auto& v : p.positions) EXPECT_TRUE(v.allFinite()) << path;
      for (const auto& t : p.triangles)
        for (int k = 0; k < 3; ++k) {
          EXPECT_GE(t[k], 0) << path;
          EXPECT_LT(t[k], static_cast<int>(p.positions.size())) << path;
        }
    }
  } catch (const InputError& e) {
    o.message = e.what();
    EXPECT_EQ(o.message.rfind(path + ": error: ", 0), 0u) << o.message;
    EXPECT_EQ(o.message.find('\n'), std::string::npos) << o.message;
    EXPECT_EQ(o.message.find('\r'), std::string::npos) << o.message;
  } catch (const std::exception& e) {
    ADD_FAILURE() << path << ": not an InputError: " << e.what();
  }
  o.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  // A hang guard, not a benchmark: the largest file loads in well under a second.
  EXPECT_LT(o.seconds, 10.0) << path;
  return o;
}

std::string Relative(const std::string& path) { return fs::relative(path, kExternal).string(); }

TEST(Corpus, LoaderPackLoadsOrIsRejectedWithOneLine) {
  const fs::path root = kExternal / "gltf_loader_pack";
  if (!fs::is_directory(root)) GTEST_SKIP() << "no fixtures at " << root;
  int accepted = 0, rejected = 0;
  for (const std::string& f : GltfFiles(root)) {
    const Outcome o = LoadOne(f);
    (o.accepted ? accepted : rejected)++;
    std::printf("  %-8s %-70s %s\n", o.accepted ? "loaded" : "rejected", Relative(f).c_str(),
                o.accepted ? "" : o.message.substr(f.size() + 2).c_str());
  }
  std::printf("gltf_loader_pack: %d loaded, %d rejected\n", accepted, rejected);
  EXPECT_GT(accepted, 10);
}

// Validator codes about data our loader reads (geometry, hierarchy, buffers): a file reported
// with any of them must not be accepted.
const std::set<std::string> kGeometryErrors = {
    "ACCESSOR_TOO_LONG",
    "BUFFER_VIEW_TOO_LONG",
    "ACCESSOR_SPARSE_COUNT_OUT_OF_RANGE",
    "NODE_LOOP",
    "NODE_PARENT_OVERRIDE",
    "SCENE_NON_ROOT_NODE",
    "UNRESOLVED_REFERENCE",
    "MESH_PRIMITIVE_ATTRIBUTES_ACCESSOR_INVALID_FORMAT",
    "MESH_PRIMITIVE_INDICES_ACCESSOR_INVALID_FORMAT",
    "MESH_PRIMITIVE_UNEQUAL_ACCESSOR_COUNT",
    "MESH_INVALID_WEIGHTS_COUNT",
    "VALUE_NOT_IN_RANGE",
    "ROTATION_NON_UNIT",
    "NODE_MATRIX_TRS",
    "INVALID_JSON",
    "BUFFER_BYTE_LENGTH_MISMATCH",
    "BUFFER_MISSING_GLB_DATA",
    "IO_ERROR",
};

TEST(Corpus, ValidatorCorpusAgreesWithTheValidatorOnGeometryErrors) {
  const fs::path root = kExternal / "gltf_validator_corpus";
  if (!fs::is_directory(root)) GTEST_SKIP() << "no corpus at " << root;
  int err_rejected = 0, err_accepted = 0, ok_accepted = 0, ok_rejected = 0;
  std::map<std::string, int> rejected_ok_reasons;
  for (const std::string& f : GltfFiles(root)) {
    std::ifstream report_file(f + ".report.json");
    ASSERT_TRUE(report_file) << "no report for " << f;
    const nlohmann::json report = nlohmann::json::parse(report_file);
    const int num_errors = report["issues"]["numErrors"].get<int>();
    std::set<std::string> codes;
    for (const auto& m : report["issues"]["messages"])
      if (m["severity"].get<int>() == 0) codes.insert(m["code"].get<std::string>());
    const Outcome o = LoadOne(f);
    std::string code_list;
    for (const auto& c : codes) code_list += (code_list.empty() ? "" : ",") + c;
    if (num_errors > 0) {
      (o.accepted ? err_accepted : err_rejected)++;
      if (o.accepted)
        std::printf("  accepted despite validator errors: %s [%s]\n", Relative(f).c_str(),
                    code_list.c_str());
      for (const auto& c : codes)
        EXPECT_FALSE(o.accepted && kGeometryErrors.count(c))
            << Relative(f) << " accepted despite " << c;
    } else {
      (o.accepted ? ok_accepted : ok_rejected)++;
      if (!o.accepted) {
        // Group the reasons: the part of the message after "error: " up to ';'.
        std::string why = o.message.substr(o.message.find("error: ") + 7);
        why = why.substr(0, why.find(';'));
        rejected_ok_reasons[why]++;
        std::printf("  error-free but rejected: %s: %s\n", Relative(f).c_str(), why.c_str());
      }
    }
  }
  std::printf("\nglTF-Validator corpus (%d files)\n",
              err_rejected + err_accepted + ok_accepted + ok_rejected);
  std::printf("  %-28s %9s %9s\n", "validator verdict", "accepted", "rejected");
  std::printf("  %-28s %9d %9d\n", "numErrors > 0", err_accepted, err_rejected);
  std::printf("  %-28s %9d %9d\n", "numErrors = 0", ok_accepted, ok_rejected);
  std::printf("  error-free files rejected, by reason:\n");
  for (const auto& [why, n] : rejected_ok_reasons) std::printf("    %3d  %s\n", n, why.c_str());
  EXPECT_GT(err_rejected + err_accepted, 0);
}

}  // namespace
}  // namespace mopad::scenes
