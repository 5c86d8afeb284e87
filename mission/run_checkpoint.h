#pragma once
// The checkpoint of `mopad run` (docs/floor-mission.md, "Resume"): the folder DIR/checkpoint/
// that lets `mopad run --resume DIR` finish a run that was killed at any moment (SIGKILL, a
// power cut) with the same bytes an uninterrupted run writes.
//
// Resume is a verified replay: the run is deterministic (same scene + config + seed -> same
// bytes), so the checkpoint keeps what makes the run — the effective config, the scene (its spec
// text, or the folder given), the start pose, the rooms of the per-room mode — and, after every
// room, the fingerprint of the state the mission reached (RoomBoundary). `--resume` runs the job
// again from those inputs; the rooms the killed run finished are re-run, not read back, and each
// must reach its recorded fingerprint (else the replay stops with an internal error). No scan
// is lost: every scan is taken again, to the bit.
//
//   DIR/checkpoint/manifest.json  format, state ("running", "stopped" or "complete"), the
//                                 hashes (config,
//                                 spec, scene, binary), the seed, the start, the rooms done
//   DIR/checkpoint/config.yaml    the effective config (every field; doubles to 17 digits)
//   DIR/checkpoint/spec.yaml      the scene spec's text (generated scenes only)
// Every file is written atomically (io::WriteFileAtomically), the manifest last.
//
// World side (mission/): it names scenes and truth rooms. Not thread-safe.

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "mission/floor_job.h"

namespace mopad::mission {

/// FNV-1a (64 bit) over the bytes of what is added: fingerprints and file hashes that are the
/// same on every run, platform and compiler of one byte order.
class Fingerprint {
 public:
  Fingerprint& Bytes(const void* data, std::size_t size);
  Fingerprint& Add(const std::string& s);  ///< its size, then its bytes
  Fingerprint& Add(double v);              ///< its bits
  Fingerprint& Add(std::int64_t v);
  Fingerprint& Add(int v) { return Add(static_cast<std::int64_t>(v)); }
  Fingerprint& Add(std::size_t v) { return Add(static_cast<std::int64_t>(v)); }
  std::uint64_t Value() const { return h_; }
  std::string Hex() const;  ///< 16 lower-case hex digits

 private:
  std::uint64_t h_ = 0xCBF29CE484222325ull;
};

/// FNV-1a of a folder's regular files, in path order (each file's relative path, size and
/// bytes). InputError when the folder cannot be read.
std::string HashFolder(const std::string& dir);

/// What makes a run of `mopad run`: enough to run the same job again, bit for bit.
struct RunInputs {
  std::string scene_source;      ///< the spec's name or path, or the scene folder, as given
  std::string scene_folder;      ///< a scene folder given with --scene (absolute); empty: generated
  std::string spec_text;         ///< generated scenes: the scene spec's YAML text
  std::string spec_name;         ///< its name in error messages (the default's name, or the path)
  FloorMissionParams params;     ///< effective: defaults, --config, command-line overrides
  std::optional<Pose2> start_W;  ///< --start (world, yaw in rad)
  std::vector<std::string> rooms;  ///< per-room mode: these rooms; empty: the floor mission
};

class RunCheckpoint {
 public:
  /// A fresh run into `run_dir`: writes DIR/checkpoint/ (state "running"), replacing an older
  /// one. InputError when it cannot be written.
  static RunCheckpoint Create(const std::string& run_dir, const RunInputs& inputs);
  /// `--resume DIR`: reads DIR/checkpoint/. InputError with one line saying why when it is
  /// missing, unreadable or corrupt, of another format, written by another mopad binary, or
  /// when its config or spec no longer match the manifest's hashes.
  static RunCheckpoint Open(const std::string& run_dir);
  RunCheckpoint(const RunCheckpoint&) = default;
  RunCheckpoint& operator=(const RunCheckpoint&) = default;
  RunCheckpoint(RunCheckpoint&&) = default;
  RunCheckpoint& operator=(RunCheckpoint&&) = default;

  const RunInputs& Inputs() const { return inputs_; }
  const std::string& Dir() const { return dir_; }  ///< DIR/checkpoint
  bool Complete() const { return complete_; }
  /// Room boundaries recorded (by the killed runs, on a resume).
  int RecordedRooms() const { return static_cast<int>(boundaries_.size()); }
  int Resumes() const { return resumes_; }  ///< how often the run was resumed (this one counted)

  /// Records the hash of the scene folder the run uses, or checks it against the recorded one:
  /// InputError when the scene changed since the run started.
  void SetScene(const std::string& scene_folder);
  /// After each room: records the boundary, or, for a room the checkpoint already holds, checks
  /// that the replay reached it (std::runtime_error, an internal error, when it did not).
  void RoomDone(const RoomBoundary& b);
  /// The run's files are all written: state "complete" (the checkpoint is kept as the record of
  /// the run's inputs; `--resume` then says the run is complete).
  void MarkComplete();
  /// The run's files are written but the operator stopped it (SIGINT, SIGTERM) before all its
  /// rooms: state "stopped"; `--resume` runs it again to its end, as after a kill.
  void MarkStopped();

 private:
  RunCheckpoint() = default;
  void WriteManifest() const;

  std::string dir_;
  RunInputs inputs_;
  bool complete_ = false;
  bool stopped_ = false;
  int resumes_ = 0;
  std::string config_hash_, spec_hash_, scene_hash_, binary_hash_;
  std::vector<RoomBoundary> boundaries_;
  std::size_t next_room_ = 0;  // rooms this process finished
};

}  // namespace mopad::mission
