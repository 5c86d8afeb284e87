#include "mission/run_checkpoint.h"

#include <dlfcn.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <stdexcept>

#include "common/error.h"
#include "common/params.h"
#include "io/text_file.h"

namespace mopad::mission {
namespace {

namespace fs = std::filesystem;
constexpr const char* kFormat = "mopad-checkpoint";
constexpr int kVersion = 1;

std::string ReadFile(const fs::path& p) { return io::ReadTextFile(p.string()); }

std::string HashText(const std::string& s) { return Fingerprint().Add(s).Hex(); }

// The effective config, every field; yaml-cpp writes doubles with 17 significant digits, so
// loading it back gives the same bits (Open checks that it does).
std::string ConfigText(const FloorMissionParams& p) { return YAML::Dump(SaveParams(p)) + "\n"; }

// The file whose code runs the mission: the mopad binary, or, in Python, the module
// mopad._mopad (the interpreter is not what makes the bytes). A resumed run gives the bytes of
// an uninterrupted one only with the code that started it.
std::string MissionCodeFile() {
  Dl_info info{};
  if (dladdr(reinterpret_cast<const void*>(&MissionCodeFile), &info) != 0 && info.dli_fname &&
      info.dli_fname[0] == '/') {
    std::error_code ec;
    if (fs::is_regular_file(info.dli_fname, ec)) return info.dli_fname;
  }
  return "/proc/self/exe";
}

std::string BinaryHash() {
  std::ifstream f(MissionCodeFile(), std::ios::binary);
  if (!f) return "unknown";
  Fingerprint h;
  std::vector<char> buf(1 << 20);
  while (f) {
    f.read(buf.data(), static_cast<std::streamsize>(buf.size()));
    h.Bytes(buf.data(), static_cast<std::size_t>(f.gcount()));
  }
  return h.Hex();
}

// A double as the 16 hex digits of its bits: read back exactly, whatever the text formatting.
std::string BitsHex(double v) {
  std::uint64_t u;
  std::memcpy(&u, &v, sizeof u);
  char buf[17];
  std::snprintf(buf, sizeof buf, "%016llx", static_cast<unsigned long long>(u));
  return buf;
}

double DoubleOfHex(const std::string& s, const std::string& where) {
  if (s.size() != 16 || s.find_first_not_of("0123456789abcdef") != std::string::npos)
    throw InputError(where, "corrupt checkpoint: a double's bits", s, "16 hex digits");
  const std::uint64_t u = std::stoull(s, nullptr, 16);
  double v;
  std::memcpy(&v, &u, sizeof v);
  return v;
}

}  // namespace

Fingerprint& Fingerprint::Bytes(const void* data, std::size_t size) {
  const auto* p = static_cast<const unsigned char*>(data);
  for (std::size_t i = 0; i < size; ++i) h_ = (h_ ^ p[i]) * 0x100000001B3ull;
  return *this;
}
Fingerprint& Fingerprint::Add(const std::string& s) {
  Add(s.size());
  return Bytes(s.data(), s.size());
}
Fingerprint& Fingerprint::Add(double v) { return Bytes(&v, sizeof v); }
Fingerprint& Fingerprint::Add(std::int64_t v) { return Bytes(&v, sizeof v); }
std::string Fingerprint::Hex() const {
  char buf[17];
  std::snprintf(buf, sizeof buf, "%016llx", static_cast<unsigned long long>(h_));
  return buf;
}

std::string HashFolder(const std::string& dir) {
  std::error_code ec;
  std::vector<fs::path> files;
  for (fs::recursive_directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec))
    if (it->is_regular_file()) files.push_back(it->path());
  if (ec) throw InputError(dir, "cannot read the scene folder; " + ec.message());
  std::sort(files.begin(), files.end());
  Fingerprint h;
  for (const fs::path& p : files) {
    h.Add(fs::relative(p, dir).generic_string());
    h.Add(ReadFile(p));
  }
  return h.Hex();
}

RunCheckpoint RunCheckpoint::Create(const std::string& run_dir, const RunInputs& inputs) {
  RunCheckpoint ck;
  ck.dir_ = (fs::path(run_dir) / "checkpoint").string();
  ck.inputs_ = inputs;
  std::error_code ec;
  fs::create_directories(ck.dir_, ec);
  if (ec) throw InputError(ck.dir_, "cannot create the checkpoint folder; " + ec.message());
  // An older run's manifest goes first: killed while this one is written, the folder holds no
  // manifest (nothing to resume) rather than one naming the old run.
  fs::remove(fs::path(ck.dir_) / "manifest.json", ec);
  fs::remove(fs::path(ck.dir_) / "spec.yaml", ec);
  const std::string config = ConfigText(inputs.params);
  io::WriteFileAtomically((fs::path(ck.dir_) / "config.yaml").string(), config);
  ck.config_hash_ = HashText(config);
  if (!inputs.spec_text.empty()) {
    io::WriteFileAtomically((fs::path(ck.dir_) / "spec.yaml").string(), inputs.spec_text);
    ck.spec_hash_ = HashText(inputs.spec_text);
  }
  ck.binary_hash_ = BinaryHash();
  ck.WriteManifest();
  return ck;
}

RunCheckpoint RunCheckpoint::Open(const std::string& run_dir) {
  RunCheckpoint ck;
  ck.dir_ = (fs::path(run_dir) / "checkpoint").string();
  const std::string manifest_path = (fs::path(ck.dir_) / "manifest.json").string();
  if (!fs::is_directory(run_dir))
    throw InputError(run_dir, "nothing to resume: the folder does not exist");
  if (!fs::exists(manifest_path))
    throw InputError(run_dir,
                     "nothing to resume: no checkpoint/manifest.json (the run was started by "
                     "another version, or killed before it wrote its checkpoint)");
  nlohmann::json m;
  try {
    m = nlohmann::json::parse(ReadFile(manifest_path));
  } catch (const nlohmann::json::exception& e) {
    throw InputError(manifest_path, "corrupt checkpoint manifest; " + std::string(e.what()));
  }
  try {
    if (m.value("format", "") != kFormat || m.value("version", 0) != kVersion)
      throw InputError(manifest_path, "not a checkpoint this mopad reads",
                       m.value("format", "?") + " version " + std::to_string(m.value("version", 0)),
                       std::string(kFormat) + " version " + std::to_string(kVersion));
    ck.complete_ = m.at("state").get<std::string>() == "complete";
    ck.resumes_ = m.at("resumes").get<int>();
    ck.config_hash_ = m.at("config_hash").get<std::string>();
    ck.spec_hash_ = m.at("spec_hash").get<std::string>();
    ck.scene_hash_ = m.at("scene_hash").get<std::string>();
    ck.binary_hash_ = m.at("binary_hash").get<std::string>();
    const nlohmann::json& s = m.at("scene");
    ck.inputs_.scene_source = s.at("source").get<std::string>();
    ck.inputs_.scene_folder = s.at("folder").get<std::string>();
    ck.inputs_.spec_name = s.at("spec_name").get<std::string>();
    if (!m.at("start_W_bits").is_null()) {
      const auto bits = m.at("start_W_bits").get<std::vector<std::string>>();
      if (bits.size() != 3)
        throw InputError(manifest_path, "corrupt checkpoint: start_W_bits",
                         std::to_string(bits.size()) + " values", "3");
      ck.inputs_.start_W =
          Pose2{DoubleOfHex(bits[0], manifest_path), DoubleOfHex(bits[1], manifest_path),
                DoubleOfHex(bits[2], manifest_path)};
    }
    ck.inputs_.rooms = m.at("rooms").get<std::vector<std::string>>();
    for (const nlohmann::json& b : m.at("boundaries")) {
      RoomBoundary r;
      r.robot_room = b.at("robot_room").get<std::string>();
      r.room = b.at("room").get<std::string>();
      r.scans = b.at("scans").get<int>();
      r.sim_time = b.at("sim_time_s").get<double>();
      r.fingerprint = b.at("fingerprint").get<std::string>();
      ck.boundaries_.push_back(std::move(r));
    }
    if (ck.complete_) return ck;  // nothing to check: the run is done

    const std::string binary = BinaryHash();
    if (binary != ck.binary_hash_)
      throw InputError(manifest_path,
                       "the run was started by another mopad binary; only the binary that "
                       "started it resumes it to the same bytes (run it again without --resume)",
                       binary, ck.binary_hash_);
    const std::string config_path = (fs::path(ck.dir_) / "config.yaml").string();
    const std::string config = ReadFile(config_path);
    if (HashText(config) != ck.config_hash_)
      throw InputError(config_path, "the config differs from the one the run started with",
                       "hash " + HashText(config), "hash " + ck.config_hash_);
    ck.inputs_.params =
        LoadParams<FloorMissionParams>(LoadYamlString(config, config_path), config_path);
    ValidateParams(ck.inputs_.params, "room.");
    if (ConfigText(ck.inputs_.params) != config)
      throw InputError(config_path, "the config does not load back to the same values");
    if (ck.inputs_.params.room.drive.seed != m.at("seed").get<std::uint64_t>())
      throw InputError(manifest_path, "the config's seed differs from the manifest's",
                       std::to_string(ck.inputs_.params.room.drive.seed),
                       std::to_string(m.at("seed").get<std::uint64_t>()));
    if (!ck.spec_hash_.empty()) {
      const std::string spec_path = (fs::path(ck.dir_) / "spec.yaml").string();
      ck.inputs_.spec_text = ReadFile(spec_path);
      if (HashText(ck.inputs_.spec_text) != ck.spec_hash_)
        throw InputError(spec_path, "the scene spec differs from the one the run started with");
    } else if (ck.inputs_.scene_folder.empty()) {
      throw InputError(manifest_path, "corrupt checkpoint: neither a scene folder nor a spec");
    }
  } catch (const nlohmann::json::exception& e) {
    throw InputError(manifest_path, "corrupt checkpoint manifest; " + std::string(e.what()));
  }
  ++ck.resumes_;
  ck.WriteManifest();
  return ck;
}

void RunCheckpoint::SetScene(const std::string& scene_folder) {
  const std::string hash = HashFolder(scene_folder);
  if (scene_hash_.empty()) {
    scene_hash_ = hash;
    WriteManifest();
  } else if (hash != scene_hash_) {
    throw InputError(scene_folder, "the scene changed since the run started; resume refused",
                     "hash " + hash, "hash " + scene_hash_);
  }
}

void RunCheckpoint::RoomDone(const RoomBoundary& b) {
  const std::size_t k = next_room_++;
  if (k < boundaries_.size()) {
    const RoomBoundary& r = boundaries_[k];
    if (r.fingerprint != b.fingerprint || r.robot_room != b.robot_room)
      throw std::runtime_error(
          "resume: room " + std::to_string(k + 1) + " (" + b.robot_room + ", " + b.room +
          ") did not replay as the checkpoint recorded it (fingerprint " + b.fingerprint +
          ", recorded " + r.fingerprint + " for " + r.robot_room +
          "): the run is not deterministic here; run it again without --resume");
    return;
  }
  boundaries_.push_back(b);
  WriteManifest();
}

void RunCheckpoint::MarkComplete() {
  complete_ = true;
  WriteManifest();
}

void RunCheckpoint::MarkStopped() {
  stopped_ = true;
  WriteManifest();
}

void RunCheckpoint::WriteManifest() const {
  nlohmann::ordered_json m;
  m["format"] = kFormat;
  m["version"] = kVersion;
  m["state"] = complete_ ? "complete" : stopped_ ? "stopped" : "running";
  m["resume"] = "replay";  // a resumed run re-runs the job from these inputs (run_checkpoint.h)
  m["resumes"] = resumes_;
  m["seed"] = inputs_.params.room.drive.seed;
  m["config_hash"] = config_hash_;
  m["spec_hash"] = spec_hash_;
  m["scene_hash"] = scene_hash_;
  m["binary_hash"] = binary_hash_;
  m["scene"] = {{"source", inputs_.scene_source},
                {"folder", inputs_.scene_folder},
                {"spec_name", inputs_.spec_name}};
  if (inputs_.start_W) {
    const Pose2& s = *inputs_.start_W;
    m["start_W"] = {s.x, s.y, s.yaw};
    m["start_W_bits"] = {BitsHex(s.x), BitsHex(s.y), BitsHex(s.yaw)};
  } else {
    m["start_W"] = nullptr;
    m["start_W_bits"] = nullptr;
  }
  m["rooms"] = inputs_.rooms;
  nlohmann::ordered_json bs = nlohmann::json::array();
  for (std::size_t k = 0; k < boundaries_.size(); ++k) {
    const RoomBoundary& b = boundaries_[k];
    bs.push_back({{"index", k + 1},
                  {"robot_room", b.robot_room},
                  {"room", b.room},
                  {"scans", b.scans},
                  {"sim_time_s", b.sim_time},
                  {"fingerprint", b.fingerprint}});
  }
  m["boundaries"] = std::move(bs);
  io::WriteFileAtomically((fs::path(dir_) / "manifest.json").string(), m.dump(2) + "\n");
}

}  // namespace mopad::mission
