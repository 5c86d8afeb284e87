#include "sim/sensor_jobs.h"

#include "sim/realism.h"

// The sensor simulator on the command line: `mopad scan`, `mopad lrf`, `mopad bench raycast`
// (sim/sensor_jobs.h).
#include <sys/resource.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <sstream>

#include "common/atomic_file.h"
#include "common/error.h"
#include "common/params.h"
#include "common/polygon.h"
#include "scenes/door_angles.h"
#include "scenes/ground_truth.h"
#include "scenes/scene_paths.h"
#include "sim/embree_world.h"
#include "sim/lrf.h"
#include "sim/raycast_bench.h"
#include "sim/scan_writer.h"
#include "sim/sensor_jobs.h"
#include "sim/threads.h"
#include "sim/tls_scanner.h"

namespace mopad::sim {
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

double Since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

/// Peak resident memory of this process so far (getrusage ru_maxrss), MiB.
double PeakRssMiB() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return static_cast<double>(u.ru_maxrss) / 1024.0;
}

/// The default office scene spec, looked up beside the sources (cwd or the build tree).
std::optional<std::string> DefaultOfficeSpec() {
  std::vector<fs::path> candidates = {fs::current_path() / "scenes/office_5rooms.yaml"};
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  if (!ec) {
    for (fs::path p = exe.parent_path(); !p.empty() && p != p.root_path(); p = p.parent_path())
      candidates.push_back(p / "scenes/office_5rooms.yaml");
  }
  for (const auto& c : candidates)
    if (fs::is_regular_file(c, ec)) return c.string();
  return std::nullopt;
}

Pose3 ParsePose(const std::string& s) {
  std::vector<double> v;
  std::stringstream ss(s);
  for (std::string item; std::getline(ss, item, ',');) {
    try {
      std::size_t used = 0;
      v.push_back(std::stod(item, &used));
      if (used != item.size()) throw std::invalid_argument(item);
    } catch (const std::exception&) {
      throw InputError("--pose", "not a number", "'" + item + "'", "x,y,z,yaw_deg");
    }
  }
  if (v.size() != 4)
    throw InputError("--pose", "wrong number of values", std::to_string(v.size()),
                     "4: x,y,z,yaw_deg");
  Pose2 p2{v[0], v[1], DegToRad(v[3])};
  return p2.To3d(v[2]);
}

void ApplyDoors(EmbreeWorld& world, const std::vector<std::string>& doors) {
  for (const auto& [id, deg] : scenes::ParseDoorAngles(doors, "--door"))
    world.SetDoorAngle(id, DegToRad(deg));
}

/// A progress bar on stderr, only when stderr is a terminal and the work lasts over a second.
class Progress {
 public:
  explicit Progress(std::string label)
      : label_(std::move(label)), tty_(isatty(fileno(stderr))), t0_(Clock::now()) {}
  void Update(double fraction) {
    if (!tty_) return;
    const double t = Since(t0_);
    if (t < 1.0 || t - last_ < 0.1) return;
    last_ = t;
    shown_ = true;
    const int width = 40, filled = static_cast<int>(fraction * width);
    std::fprintf(stderr, "\r%s [%s%s] %3d%% %.1fs", label_.c_str(),
                 std::string(filled, '#').c_str(), std::string(width - filled, '.').c_str(),
                 static_cast<int>(100 * fraction), t);
    std::fflush(stderr);
  }
  void Done() {
    if (shown_) std::fprintf(stderr, "\n");
  }

 private:
  std::string label_;
  bool tty_;
  Clock::time_point t0_;
  double last_ = 0;
  bool shown_ = false;
};

TlsParams TlsParamsFromOptions(const std::string& profile, const std::string& profile_file,
                               std::optional<double> step_deg, std::optional<int> footprint_rays) {
  TlsParams p =
      profile_file.empty() ? TlsProfile(profile) : LoadParamsFile<TlsParams>(profile_file);
  if (step_deg) p.step_deg = *step_deg;
  if (footprint_rays) p.footprint_rays = *footprint_rays;
  p.Validate();
  return p;
}

}  // namespace

// ---------------------------------------------------------------- mopad scan

void RunScan(const ScanOptions& o) {
  const auto t0 = Clock::now();
  if (fs::path(o.output).extension() != ".ply")
    throw InputError(o.output, "output must be a .ply file");
  if (!o.truth.empty() && fs::path(o.truth).extension() != ".ply") {
    throw InputError(o.truth, "truth sidecar must be a .ply file", "", "e.g. scan.truth.ply");
  }
  const TlsParams params =
      RealisticTls(TlsParamsFromOptions(o.profile, o.profile_file, o.step_deg, o.footprint_rays),
                   RealismProfile(o.realism).scanner, o.seed);
  ScanRequest req;
  req.seed = o.seed;
  req.scan_id = o.scan_id;
  req.X_WB = ParsePose(o.pose);
  double t_load = 0, t_build = 0, t_scan = 0;
  std::uint64_t pulses = 0, points = 0;
  RunWithThreads(o.threads, [&] {
    scenes::LoadedScene loaded = scenes::LoadSceneArg(o.scene);
    t_load = Since(t0);
    const auto t1 = Clock::now();
    EmbreeWorld world(std::move(loaded.scene), loaded.truth ? &*loaded.truth : nullptr);
    ApplyDoors(world, o.doors);
    TlsScanner scanner(world, params);
    t_build = Since(t1);
    const auto t2 = Clock::now();
    pulses = scanner.pulses();
    ScanFileSink sink({o.output, o.ptx, o.truth}, scanner.MakeHeader(req),
                      scanner.MakeTruthHeader(req), pulses);
    Progress progress("scan");
    sink.on_progress = [&](std::uint64_t cols) {
      progress.Update(static_cast<double>(cols) / scanner.columns());
    };
    scanner.ScanStreamed(req, sink);
    sink.Close();
    progress.Done();
    points = sink.points_written();
    t_scan = Since(t2);
    // The effective configuration beside the result (reproducibility).
    fs::path cfg = fs::path(o.output);
    cfg.replace_extension(".tls.yaml");
    YAML::Node node;
    node["scene"] = o.scene;
    node["pose"] = o.pose;
    node["seed"] = o.seed;
    node["scan_id"] = o.scan_id;
    node["doors"] = o.doors;
    node["tls"] = SaveParams(params);
    std::ostringstream cfg_text;
    cfg_text << node << "\n";
    WriteWholeFile(cfg.string(), cfg_text.str());
    std::printf("scene    %s: %zu triangles, %zu doors (load %.2f s, BVH %.2f s)\n",
                loaded.description.c_str(), world.scene().TriangleCount(), world.DoorIds().size(),
                t_load, t_build);
    std::printf("scan     %u rows x %u columns = %llu pulses, %d ray(s)/pulse, step %.4g deg\n",
                scanner.rows(), scanner.columns(), static_cast<unsigned long long>(pulses),
                params.footprint_rays, params.step_deg);
  });
  std::printf("wrote    %s: %llu points%s%s\n", o.output.c_str(),
              static_cast<unsigned long long>(points), o.ptx.empty() ? "" : (", " + o.ptx).c_str(),
              o.truth.empty() ? "" : (", " + o.truth).c_str());
  std::printf(
      "time     scan+write %.2f s (%.1f M pulses/s), total %.2f s; peak memory %.0f MiB; threads "
      "%d\n",
      t_scan, pulses / t_scan / 1e6, Since(t0), PeakRssMiB(),
      o.threads > 0 ? o.threads : AvailableThreads());
}

// ---------------------------------------------------------------- mopad lrf

void RunLrf(const LrfOptions& o) {
  const std::string ext = fs::path(o.output).extension().string();
  if (ext != ".csv" && ext != ".json") throw InputError(o.output, "output must be .csv or .json");
  std::vector<LrfParams> rig;
  const LrfParams base =
      o.profile_file.empty() ? LrfProfile(o.profile) : LoadParamsFile<LrfParams>(o.profile_file);
  if (o.paper_rig) {
    rig = PaperLrfRig(o.profile);
    if (!o.profile_file.empty())
      for (auto& r : rig) {
        const auto frame = r.frame;
        const auto mount = r.mount_xyz;
        r = base;
        r.frame = frame;
        r.mount_xyz = mount;
      }
  } else if (o.heights.empty()) {
    rig = {base};
  } else {
    for (std::size_t i = 0; i < o.heights.size(); ++i) {
      LrfParams p = base;
      p.frame = "lrf_" + std::to_string(i);
      p.mount_xyz[2] = o.heights[i];
      rig.push_back(p);
    }
  }
  scenes::LoadedScene loaded = scenes::LoadSceneArg(o.scene);
  EmbreeWorld world(std::move(loaded.scene), loaded.truth ? &*loaded.truth : nullptr);
  ApplyDoors(world, o.doors);
  const Pose3 X_WB = ParsePose(o.pose);
  std::vector<interfaces::LrfScan> scans;
  for (const auto& p : rig)
    scans.push_back(LrfSimulator(world, p).Scan(X_WB, o.seed, o.seq, o.time));
  std::ostringstream out;
  if (ext == ".csv") {
    out << "frame,seq,timestamp,beam,angle_rad,range_m,intensity,mount_z_m\n";
    char line[256];
    for (const auto& s : scans)
      for (std::size_t i = 0; i < s.ranges.size(); ++i) {
        std::snprintf(line, sizeof(line), "%s,%llu,%.6f,%zu,%.7f,%.5f,%.4f,%.4f\n", s.frame.c_str(),
                      static_cast<unsigned long long>(s.seq), s.timestamp, i,
                      s.angle_min + i * s.angle_increment, s.ranges[i],
                      s.intensities.empty() ? 0.0f : s.intensities[i], s.X_BL.translation().z());
        out << line;
      }
  } else {
    nlohmann::json j = nlohmann::json::array();
    for (const auto& s : scans) {
      nlohmann::json m = nlohmann::json::array();
      for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 4; ++c) m.push_back(s.X_BL.matrix()(r, c));
      j.push_back({{"frame", s.frame},
                   {"seq", s.seq},
                   {"timestamp", s.timestamp},
                   {"angle_min", s.angle_min},
                   {"angle_increment", s.angle_increment},
                   {"range_min", s.range_min},
                   {"range_max", s.range_max},
                   {"X_BL_3x4", m},
                   {"ranges", s.ranges},
                   {"intensities", s.intensities}});
    }
    out << j.dump(1) << "\n";
  }
  WriteWholeFile(o.output, out.str());
  for (const auto& s : scans) {
    std::size_t returns = 0;
    for (float r : s.ranges) returns += r < s.range_max;
    std::printf("%s: %zu beams, %zu returns, mount z %.2f m\n", s.frame.c_str(), s.ranges.size(),
                returns, s.X_BL.translation().z());
  }
  std::printf("wrote %s\n", o.output.c_str());
}

// ---------------------------------------------------------------- mopad bench raycast

/// Default bench pose: the vertex centroid of the largest room whose centroid lies inside it (on
/// its floor), or the centre of the scene's bounding box without a truth sidecar.
Pose3 DefaultBenchPose(const scenes::LoadedScene& loaded) {
  Pose3 X = Pose3::Identity();
  const auto box = loaded.scene.Bounds();
  X.translation() = Eigen::Vector3d(box.center().x(), box.center().y(), box.min().z());
  if (!loaded.truth) return X;
  double best_area = 0.0;
  for (const auto& room : loaded.truth->rooms) {
    const auto& poly = room.polygon;
    if (poly.size() < 3) continue;
    Eigen::Vector2d c = Eigen::Vector2d::Zero();
    double area = 0.0;
    for (std::size_t i = 0; i < poly.size(); ++i) {
      const auto& a = poly[i];
      const auto& b = poly[(i + 1) % poly.size()];
      c += a;
      area += 0.5 * (a.x() * b.y() - b.x() * a.y());
    }
    c /= static_cast<double>(poly.size());
    const bool inside = PointInPolygon(c, poly);
    if (inside && std::abs(area) > best_area) {
      best_area = std::abs(area);
      X.translation() = Eigen::Vector3d(c.x(), c.y(), room.floor_z);
    }
  }
  return X;
}

class CountingSink final : public ScanSink {
 public:
  void Consume(ScanBlock& b) override {
    for (const auto& p : b.points) points += p.valid();
  }
  std::uint64_t points = 0;
};

void RunBench(const BenchOptions& o) {
  std::string scene_arg = o.scene;
  if (scene_arg.empty()) {
    const auto spec = DefaultOfficeSpec();
    if (!spec) {
      throw InputError("--scene", "no scene given and scenes/office_5rooms.yaml not found", "",
                       "a scene folder, file or spec");
    }
    scene_arg = *spec;
  }
  const int threads = o.threads > 0 ? o.threads : AvailableThreads();
  RunWithThreads(threads, [&] {
    const auto t0 = Clock::now();
    scenes::LoadedScene loaded = scenes::LoadSceneArg(scene_arg);
    const double t_load = Since(t0);
    const Pose3 X_WB = o.pose.empty() ? DefaultBenchPose(loaded) : ParsePose(o.pose);
    const auto t1 = Clock::now();
    EmbreeWorld world(std::move(loaded.scene), loaded.truth ? &*loaded.truth : nullptr);
    const double t_build = Since(t1);
    TlsParams p1 = TlsProfile(o.profile);
    p1.step_deg = o.step_deg;
    p1.footprint_rays = 1;
    TlsParams pk = p1;
    pk.footprint_rays = o.footprint_rays;
    const TlsScanner s1(world, p1), sk(world, pk);
    ScanRequest req;
    req.seed = o.seed;
    req.X_WB = X_WB;
    const double pulses = static_cast<double>(s1.pulses());
    std::printf(
        "scene      %s\n           %zu triangles, %zu doors; load %.2f s, BVH build %.3f s\n",
        loaded.description.c_str(), world.scene().TriangleCount(), world.DoorIds().size(), t_load,
        t_build);
    std::printf("pose       scanner at (%.2f, %.2f, %.2f) m\n",
                (X_WB * s1.X_BS()).translation().x(), (X_WB * s1.X_BS()).translation().y(),
                (X_WB * s1.X_BS()).translation().z());
    std::printf(
        "ray set    %u x %u = %.0f pulses (360 x 100 deg at %.4g deg), %d threads, best of %d "
        "runs\n",
        s1.rows(), s1.columns(), pulses, o.step_deg, threads, std::max(1, o.repeat));
    // Each measurement is the best of --repeat runs (the machine may be shared).
    double ta = 1e300, tb = 1e300, tc = 1e300;
    std::uint64_t hits = 0;
    CountingSink cb, cc;
    for (int rep = 0; rep < std::max(1, o.repeat); ++rep) {
      // (a) bare Embree packet loop, distances only.
      std::vector<float> distances(s1.pulses(), 0.0f);
      auto t = Clock::now();
      hits = BareRaycast(world, s1, req, distances);
      ta = std::min(ta, Since(t));
      distances = std::vector<float>();
      // (b) full model, one ray per pulse; (c) the K-ray footprint.
      cb.points = cc.points = 0;
      t = Clock::now();
      s1.ScanStreamed(req, cb);
      tb = std::min(tb, Since(t));
      t = Clock::now();
      sk.ScanStreamed(req, cc);
      tc = std::min(tc, Since(t));
    }
    const double ra = pulses / ta, rb = pulses / tb, rc = pulses * o.footprint_rays / tc;
    std::printf(
        "(a) bare Embree rtcIntersect16 loop   %6.3f s  %7.1f M rays/s  %7.1f M points/s (hits)\n",
        ta, ra / 1e6, hits / ta / 1e6);
    std::printf("(b) full TLS model, 1 ray/pulse       %6.3f s  %7.1f M rays/s  %7.1f M points/s\n",
                tb, rb / 1e6, cb.points / tb / 1e6);
    std::printf(
        "(c) full TLS model, %2d rays/pulse      %6.3f s  %7.1f M rays/s  %7.1f M points/s\n",
        o.footprint_rays, tc, rc / 1e6, cc.points / tc / 1e6);
    std::printf("ratios     (b)/(a) = %.2f (pulses/s)   (c)/(a) = %.2f (pulses/s), %.2f (rays/s)\n",
                ta / tb, ta / tc, rc / ra);
    std::printf(
        "vs HELIOS++ reference (0.45 M pts/s 1-ray, 0.1 M pts/s 19-ray): (b) %.0fx, (c) %.0fx\n",
        cb.points / tb / 0.45e6, cc.points / tc / 0.1e6);
    std::printf("peak mem   %.0f MiB (getrusage ru_maxrss)\n", PeakRssMiB());
  });
}

}  // namespace mopad::sim
