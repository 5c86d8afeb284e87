#include "report/report_walls.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <opencv2/imgproc.hpp>
#include <sstream>
#include <vector>

#include "common/error.h"
#include "common/format.h"
#include "io/image_codec.h"
#include "modelling/model_io.h"
#include "modelling/orthoimage.h"
#include "modelling/sm5_io.h"
#include "report/report.h"
#include "runfolder/layout.h"

namespace mopad::report {
namespace {

namespace fs = std::filesystem;

std::string Base64(const std::string& bytes) {
  const auto* in = reinterpret_cast<const unsigned char*>(bytes.data());
  const std::size_t n = bytes.size();
  static const char* k = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  out.reserve((n + 2) / 3 * 4);
  for (std::size_t i = 0; i < n; i += 3) {
    const std::uint32_t b = (std::uint32_t{in[i]} << 16) |
                            (i + 1 < n ? std::uint32_t{in[i + 1]} << 8 : 0) |
                            (i + 2 < n ? std::uint32_t{in[i + 2]} : 0);
    out += k[(b >> 18) & 63];
    out += k[(b >> 12) & 63];
    out += i + 1 < n ? k[(b >> 6) & 63] : '=';
    out += i + 2 < n ? k[b & 63] : '=';
  }
  return out;
}

// The plan view's door colours (report/report.cpp), by SM4 state; windows blue.
const char* OpeningColour(const modelling::DetectedOpening& o) {
  if (o.type == modelling::OpeningType::kWindow) return "#1e88e5";
  switch (o.state) {
    case modelling::DoorState::kOpen:
      return "#2e9d3a";
    case modelling::DoorState::kSemiOpen:
      return "#e69500";
    case modelling::DoorState::kClosed:
      return "#c62828";
  }
  return "#000";
}

// The pixel size (m) of an image of cols x rows pixels over a patch of width x height (m):
// the whole millimetre that gives exactly that many pixels, else the larger ratio.
double PixelOf(double width, double height, int cols, int rows) {
  for (int mm = 1; mm <= 500; ++mm) {
    const double p = mm / 1000.0;
    if (std::ceil(width / p - 1e-9) == cols && std::ceil(height / p - 1e-9) == rows) return p;
  }
  return std::max(width / std::max(cols, 1), height / std::max(rows, 1));
}

// One wall's figure; "" when it has no readable colour image.
std::string WallFigure(const std::string& room, const modelling::StructuralPatch& wall,
                       const fs::path& png, const modelling::Sm4Model& sm4,
                       const modelling::Sm5Model& sm5, std::size_t& bytes) {
  std::error_code ec;
  if (!fs::is_regular_file(png, ec)) return "";  // a wall imaged by no scan
  io::Image8 decoded = io::ReadImage8(png.string(), 3);
  if (decoded.empty()) return "";
  const cv::Mat image(decoded.height, decoded.width, CV_8UC3, decoded.pixels.data());
  const modelling::PatchFrame frame = modelling::PatchFrame::Of(wall);
  const double pixel = PixelOf(frame.width, frame.height, image.cols, image.rows);
  const int rows = std::min(kWallImageRows, image.rows);
  const int cols =
      std::max(1, static_cast<int>(std::lround(image.cols * double(rows) / image.rows)));
  cv::Mat small;
  cv::resize(image, small, cv::Size(cols, rows), 0, 0, cv::INTER_AREA);
  const std::string jpeg =
      io::EncodeJpeg({small.data, small.cols, small.rows, 3, 8, small.step}, kWallImageJpegQuality);
  bytes += jpeg.size();
  // SVG pixels per metre; v up in the wall, y down in the SVG.
  const double s = rows / (image.rows * pixel);
  const double top = image.rows * pixel;
  auto X = [&](double u) { return FormatFixed(u * s, 1); };
  auto Y = [&](double v) { return FormatFixed((top - v) * s, 1); };
  auto L = [&](double len) { return FormatFixed(len * s, 1); };
  std::ostringstream f;
  int openings = 0, components = 0;
  std::ostringstream over;
  for (const auto& o : sm4.openings) {
    if (o.host != wall.id) continue;
    ++openings;
    double u0 = 1e300, u1 = -1e300, v0 = 1e300, v1 = -1e300;
    for (const Vec3& c : o.corners) {
      const Vec2 uv = frame.ToUv(c);
      u0 = std::min(u0, uv.x()), u1 = std::max(u1, uv.x());
      v0 = std::min(v0, uv.y()), v1 = std::max(v1, uv.y());
    }
    const bool door = o.type == modelling::OpeningType::kDoor;
    const std::string label =
        o.id + (door ? std::string(" door, ") + ToString(o.state) : std::string(" window"));
    over << "<rect class='opening " << (door ? "door" : "window") << "' fill='none' stroke='"
         << OpeningColour(o) << "' stroke-width='2' x='" << X(u0) << "' y='" << Y(v1) << "' width='"
         << L(u1 - u0) << "' height='" << L(v1 - v0) << "'><title>" << HtmlEscape(label)
         << "</title></rect><text fill='" << OpeningColour(o) << "' x='"
         << FormatFixed(u0 * s + 2, 1) << "' y='" << FormatFixed((top - v1) * s + 11, 1) << "'>"
         << HtmlEscape(label) << "</text>\n";
  }
  for (const auto& c : sm5.components) {
    if (c.host != wall.id) continue;
    ++components;
    const Vec2 uv = frame.ToUv(c.centre);
    const double hw = 0.5 * c.size.x(), hh = 0.5 * c.size.y();
    over << "<rect class='component' fill='none' stroke='#ff00ff' stroke-width='1.5' x='"
         << X(uv.x() - hw) << "' y='" << Y(uv.y() + hh) << "' width='" << L(2 * hw) << "' height='"
         << L(2 * hh) << "'><title>" << HtmlEscape(c.id + " " + c.class_name)
         << FormatNumbers(", alpha %.2f", c.alpha) << "</title></rect><text fill='#ff00ff' x='"
         << X(uv.x() + hw + 0.02) << "' y='" << Y(uv.y()) << "'>" << HtmlEscape(c.class_name)
         << "</text>\n";
  }
  f << "<figure class='wall' data-room='" << HtmlEscape(room) << "' data-wall='"
    << HtmlEscape(wall.id) << "'><svg xmlns='http://www.w3.org/2000/svg' width='" << cols
    << "' height='" << rows << "' viewBox='0 0 " << cols << " " << rows
    << "' font-family='sans-serif' font-size='10'><image width='" << cols << "' height='" << rows
    << "' preserveAspectRatio='none' href='data:image/jpeg;base64," << Base64(jpeg) << "'/>\n"
    << over.str() << "</svg><figcaption>" << HtmlEscape(room + " " + wall.id) << ": "
    << FormatFixed(frame.width, 2) << " m x " << FormatFixed(frame.height, 2) << " m, " << openings
    << (openings == 1 ? " opening, " : " openings, ") << components
    << (components == 1 ? " component" : " components") << "</figcaption></figure>\n";
  return f.str();
}

}  // namespace

std::string WallImagesHtml(const std::string& run_dir) {
  std::ostringstream body;
  std::size_t bytes = 0, walls = 0;
  for (const fs::path dir :
       runfolder::RoomFolders(run_dir.empty() ? "." : run_dir, runfolder::kSm3)) {
    const std::string name = dir.filename().string();
    try {
      const modelling::StructuralModel sm3 = modelling::ReadSm3((dir / runfolder::kSm3).string());
      std::error_code ec;
      const modelling::Sm4Model sm4 = fs::exists(dir / runfolder::kSm4, ec)
                                          ? modelling::ReadSm4((dir / runfolder::kSm4).string())
                                          : modelling::Sm4Model{};
      const modelling::Sm5Model sm5 = fs::exists(dir / runfolder::kSm5, ec)
                                          ? modelling::ReadSm5((dir / runfolder::kSm5).string())
                                          : modelling::Sm5Model{};
      // The folder's name (the truth room in a main-job run) and the robot's name when it differs.
      const std::string label =
          sm3.room.empty() || sm3.room == name ? name : name + " (" + sm3.room + ")";
      for (const auto& p : sm3.patches) {
        if (p.patch_class != modelling::PatchClass::kWall) continue;
        const std::string fig = WallFigure(
            label, p, dir / runfolder::kOrthoimages / (p.id + "_colour.png"), sm4, sm5, bytes);
        if (!fig.empty()) ++walls;
        body << fig;
      }
    } catch (const InputError& e) {
      body << "<p>No wall images of " << HtmlEscape(name) << ": " << HtmlEscape(e.what())
           << "</p>\n";
    }
  }
  const std::string figures = body.str();
  if (figures.empty()) return "";
  return "<h2>Wall orthoimages</h2>\n<p class='legend'>The robot's colour orthoimage of each "
         "wall (" +
         std::to_string(walls) + " walls, " + std::to_string((bytes + 512) / 1024) +
         " KB of JPEG at " + std::to_string(kWallImageRows) +
         " px high) with its SM4 openings <span style='color:#2e9d3a'>&#9633; open</span> <span "
         "style='color:#e69500'>&#9633; semi-open</span> <span style='color:#c62828'>&#9633; "
         "closed door</span> <span style='color:#1e88e5'>&#9633; window</span> and SM5 "
         "components <span style='color:#ff00ff'>&#9633; class</span>; black: not seen.</p>\n"
         "<div class='walls'>\n" +
         figures + "</div>\n";
}

}  // namespace mopad::report
