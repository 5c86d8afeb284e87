#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "common/error.h"
#include "runfolder/keep.h"
#include "tests/process_temp_dir.h"

namespace mopad::runfolder {
namespace {

namespace fs = std::filesystem;

// A run folder in miniature: one file of each kind a run writes.
const std::vector<std::string> kFiles = {
    "summary.json", "report.html", "report.md", "room.effective.yaml", "trajectory_true.tum",
    "eval/evaluation.json", "eval/isprs_R1.svg", "eval/dsm3_truth_R1.ply", "export/model.ifc",
    "export/model.glb", "export/sm1.las", "rooms/R1/run.json", "rooms/R1/sm3.json",
    "rooms/R1/sm1.ply", "rooms/R1/models.glb", "rooms/R1/orthoimages/wall_1_colour.png",
    "suite.stdout.log"};

fs::path MakeRun(const std::string& name) {
  const fs::path d = test_support::ProcessTempDir(name);
  for (const auto& f : kFiles) {
    fs::create_directories((d / f).parent_path());
    std::ofstream(d / f) << "0123456789";
  }
  return d;
}

std::vector<std::string> Left(const fs::path& d) {
  std::vector<std::string> out;
  for (const auto& f : kFiles)
    if (fs::exists(d / f)) out.push_back(f);
  return out;
}

TEST(KeepLevel, SummaryKeepsRecordsAndReportsModelsAddsDeliverablesAllKeepsEverything) {
  const fs::path all = MakeRun("mopad_keep_all_");
  EXPECT_EQ(PruneRunFolder(all.string(), KeepLevel::kAll), 0u);
  EXPECT_EQ(Left(all), kFiles);

  const fs::path models = MakeRun("mopad_keep_models_");
  EXPECT_EQ(PruneRunFolder(models.string(), KeepLevel::kModels), 30u);  // three clouds
  for (const auto& f : Left(models)) EXPECT_FALSE(f.ends_with(".ply") || f.ends_with(".las")) << f;
  EXPECT_TRUE(fs::exists(models / "export/model.ifc"));

  const fs::path summary = MakeRun("mopad_keep_summary_");
  PruneRunFolder(summary.string(), KeepLevel::kSummary);
  EXPECT_EQ(Left(summary),
            (std::vector<std::string>{"summary.json", "report.html", "report.md",
                                      "room.effective.yaml", "eval/evaluation.json",
                                      "eval/isprs_R1.svg", "rooms/R1/run.json", "rooms/R1/sm3.json",
                                      "suite.stdout.log"}));
  EXPECT_FALSE(fs::exists(summary / "rooms/R1/orthoimages"));  // emptied, removed
  EXPECT_FALSE(fs::exists(summary / "export"));
  EXPECT_TRUE(fs::exists(summary / "rooms/R1"));
}

TEST(KeepLevel, ParsesTheThreeNamesOnly) {
  EXPECT_EQ(ParseKeepLevel("models"), KeepLevel::kModels);
  EXPECT_STREQ(ToString(ParseKeepLevel("summary")), "summary");
  EXPECT_THROW(ParseKeepLevel("some"), InputError);
}

}  // namespace
}  // namespace mopad::runfolder
