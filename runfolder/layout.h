#pragma once
// The layout of a run folder (`mopad run -o DIR`, `mopad room -o DIR`; docs/models.md): the
// one place that names its files and finds its rooms. Every writer and reader of a run folder
// (mission, evaluation, exports, the report) asks this module; none spells a file name or walks
// rooms/ itself.
//
//   DIR/rooms/<ID>/   one room's files (kRoom*); a `mopad room` run is one such folder as DIR
//   DIR/floor/        the floor model (sm3.json, sm4.json) of a floor mission
//   DIR/eval/         the evaluator's files (`mopad eval`)
//   DIR/export/       the deliverables (`mopad export all`)
//   DIR/checkpoint/   what `mopad run --resume` needs
//   DIR/dtt.json, trajectory_*.tum, summary.json, room.effective.yaml, report.html, report.md
//
// Truth-free: it names files and reads folders; it knows nothing of scenes or the simulator.

#include <string>
#include <string_view>
#include <vector>

namespace mopad::runfolder {

// A room's files (docs/models.md).
inline constexpr std::string_view kRunJson = "run.json";          ///< run record (run_record.h)
inline constexpr std::string_view kSm1 = "sm1.ply";               ///< SM1 labelled cloud
inline constexpr std::string_view kSm2 = "sm2.json";              ///< SM2 RoI B-rep
inline constexpr std::string_view kSm3 = "sm3.json";              ///< SM3 structural model
inline constexpr std::string_view kSm4 = "sm4.json";              ///< SM4 openings
inline constexpr std::string_view kSm5 = "sm5.json";              ///< SM5 service components
inline constexpr std::string_view kDsm3 = "dsm3.ply";             ///< DSM3 labelled voxels
inline constexpr std::string_view kModelsGlb = "models.glb";      ///< SM3-SM5 as glTF
inline constexpr std::string_view kOrthoimages = "orthoimages";   ///< folder: wall images (PNG)
inline constexpr std::string_view kModelFigures = "model.json";   ///< the room model's figures
inline constexpr std::string_view kScansLog = "scans.json";       ///< per-scan log
inline constexpr std::string_view kScanPoses = "scan_poses.tum";  ///< scanner poses, map frame
inline constexpr std::string_view kMapYaml = "map.yaml";          ///< obstacle map (+ map.png)
inline constexpr std::string_view kRoomEvaluation = "evaluation.json";  ///< truth side's scores
// Files of a room folder and of the run folder alike.
inline constexpr std::string_view kSummary = "summary.json";
inline constexpr std::string_view kEffectiveConfig = "room.effective.yaml";
inline constexpr std::string_view kTrajectoryEstimated = "trajectory_estimated.tum";
inline constexpr std::string_view kTrajectoryTrue = "trajectory_true.tum";
// The run folder's own files and folders.
inline constexpr std::string_view kRoomsDir = "rooms";
inline constexpr std::string_view kFloorDir = "floor";
inline constexpr std::string_view kEvalDir = "eval";
inline constexpr std::string_view kExportDir = "export";
inline constexpr std::string_view kCheckpointDir = "checkpoint";
inline constexpr std::string_view kDtt = "dtt.json";
inline constexpr std::string_view kReportHtml = "report.html";
inline constexpr std::string_view kReportMarkdown = "report.md";

/// `dir`/`name` as a string (a path join that takes the names above).
std::string Join(const std::string& dir, std::string_view name);

/// DIR/rooms/<id>.
std::string RoomDir(const std::string& run_dir, const std::string& id);

/// The room folders of a run folder, each holding the file `marker` (kRunJson for a run the
/// evaluator can line up with the truth, kSm3 for a room with a model): `run_dir` itself when
/// it holds `marker` (a `mopad room` run), else every DIR/rooms/<ID>/ that does, in name order.
/// Empty when there is none (or `run_dir` is not a folder); callers say what they expected.
std::vector<std::string> RoomFolders(const std::string& run_dir, std::string_view marker);

}  // namespace mopad::runfolder
