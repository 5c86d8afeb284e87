#include "report/report_viewer.h"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "common/error.h"
#include "exports/building_model.h"
#include "exports/gltf_export.h"
#include "runfolder/layout.h"

namespace mopad::report {
namespace {

using Json = nlohmann::ordered_json;

// The script: a three.js view (WebGL, orbit controls) when the library is inlined and the
// browser gives a WebGL context, else the canvas 2D view (painter's algorithm, flat shading).
// Both read the same data and share the class and truth toggles.
const char* kViewerScript = R"JS(
(function () {
  const M = JSON.parse(document.getElementById('mopad3d-data').textContent);
  const cv = document.getElementById('mopad3d');
  const note = document.getElementById('mopad3d-note');
  const W = cv.width, H = cv.height;
  const hidden = new Set(['ceiling']);
  const lo = [Infinity, Infinity, Infinity], hi = [-Infinity, -Infinity, -Infinity];
  for (const m of M.meshes)
    for (let k = 0; k < m.p.length; k += 3)
      for (let a = 0; a < 3; ++a) { lo[a] = Math.min(lo[a], m.p[k + a]); hi[a] = Math.max(hi[a], m.p[k + a]); }
  const c = [0, 1, 2].map((a) => 0.5 * (lo[a] + hi[a]));
  const radius = Math.max(0.5 * Math.hypot(hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]), 1e-3);

  function threeView() {
    const T = window.THREE;
    const renderer = new T.WebGLRenderer({canvas: cv, antialias: true, preserveDrawingBuffer: true});
    renderer.setSize(W, H);
    const scene = new T.Scene();
    scene.background = new T.Color(1, 1, 1);
    const camera = new T.PerspectiveCamera(40, W / H, radius / 100, radius * 50);
    camera.up.set(0, 0, 1);
    const d = 3.0 * radius;  // the bounding sphere fits the 40 deg field of view
    camera.position.set(c[0] - 0.45 * d, c[1] - 0.65 * d, c[2] + 0.65 * d);
    scene.add(camera);
    scene.add(new T.AmbientLight(0xffffff, 0.6));
    // Sunlight from above and one side: walls of different orientations shade differently.
    const sun = new T.DirectionalLight(0xffffff, 0.5);
    sun.position.set(c[0] + 0.5 * radius, c[1] - 0.8 * radius, c[2] + radius);
    sun.target.position.set(c[0], c[1], c[2]);
    scene.add(sun, sun.target);
    const materials = M.materials.map((mat) => new T.MeshLambertMaterial(
        {color: new T.Color(mat.rgb[0], mat.rgb[1], mat.rgb[2]), side: T.DoubleSide}));
    const groups = {};
    M.materials.forEach((mat) => { groups[mat.name] = new T.Group(); scene.add(groups[mat.name]); });
    for (const m of M.meshes) {
      const g = new T.BufferGeometry();
      g.setAttribute('position', new T.Float32BufferAttribute(m.p, 3));
      g.setIndex(m.t);
      const flat = g.toNonIndexed();  // one normal per triangle: flat shading
      flat.computeVertexNormals();
      groups[M.materials[m.m].name].add(new T.Mesh(flat, materials[m.m]));
    }
    const truth = new T.Group();
    const black = new T.LineBasicMaterial({color: 0x000000});
    for (const loop of M.truth) {
      const g = new T.BufferGeometry();
      g.setAttribute('position', new T.Float32BufferAttribute(loop, 3));
      truth.add(new T.LineLoop(g, black));
    }
    truth.visible = false;
    scene.add(truth);
    const render = () => renderer.render(scene, camera);
    const controls = new T.OrbitControls(camera, cv);
    controls.target.set(c[0], c[1], c[2]);
    controls.update();
    controls.addEventListener('change', render);
    const apply = () => { for (const name in groups) groups[name].visible = !hidden.has(name); };
    return {
      name: 'three.js r' + T.REVISION,
      redraw: () => { apply(); render(); },
      setTruth: (on) => { truth.visible = on; render(); },
    };
  }

  function canvasView() {
    const g = cv.getContext('2d');
    const tris = [];
    for (const m of M.meshes) {
      const p = m.p;
      for (let k = 0; k < m.t.length; k += 3) {
        const v = [m.t[k], m.t[k + 1], m.t[k + 2]].map((i) => [p[3 * i], p[3 * i + 1], p[3 * i + 2]]);
        const e1 = [0, 1, 2].map((a) => v[1][a] - v[0][a]), e2 = [0, 1, 2].map((a) => v[2][a] - v[0][a]);
        const n = [e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0]];
        const l = Math.hypot(n[0], n[1], n[2]) || 1;
        tris.push({v: v, n: n.map((x) => x / l), m: m.m});
      }
    }
    let yaw = -0.7, pitch = 0.9, zoom = 1.0, showTruth = false;
    function draw() {
      g.fillStyle = '#ffffff';
      g.fillRect(0, 0, W, H);
      const cy = Math.cos(yaw), sy = Math.sin(yaw), cp = Math.cos(pitch), sp = Math.sin(pitch);
      const s = zoom * Math.min(W, H) / (2.1 * radius);
      const P = (p) => {
        const x = p[0] - c[0], y = p[1] - c[1], z = p[2] - c[2];
        const x1 = cy * x - sy * y, y1 = sy * x + cy * y;
        return [W / 2 + s * x1, H / 2 - s * (sp * y1 + cp * z), cp * y1 - sp * z];
      };
      const list = [];
      for (const t of tris) {
        if (hidden.has(M.materials[t.m].name)) continue;
        const q = t.v.map(P);
        // Light from the viewer: |n . d| with d the view direction in the model frame.
        const d = [sy * cp, cy * cp, -sp];
        const shade = 0.45 + 0.55 * Math.abs(t.n[0] * d[0] + t.n[1] * d[1] + t.n[2] * d[2]);
        list.push({q: q, depth: (q[0][2] + q[1][2] + q[2][2]) / 3, shade: shade, m: t.m});
      }
      list.sort((a, b) => b.depth - a.depth);
      for (const t of list) {
        const col = M.materials[t.m].rgb.map((x) => Math.round(255 * Math.min(1, x * t.shade)));
        g.fillStyle = g.strokeStyle = 'rgb(' + col.join(',') + ')';
        g.beginPath();
        g.moveTo(t.q[0][0], t.q[0][1]);
        g.lineTo(t.q[1][0], t.q[1][1]);
        g.lineTo(t.q[2][0], t.q[2][1]);
        g.closePath();
        g.fill();
        g.stroke();
      }
      if (!showTruth) return;
      g.strokeStyle = '#000000';
      for (const loop of M.truth) {
        g.beginPath();
        for (let k = 0; k < loop.length; k += 3) {
          const q = P([loop[k], loop[k + 1], loop[k + 2]]);
          if (k === 0) g.moveTo(q[0], q[1]); else g.lineTo(q[0], q[1]);
        }
        g.closePath();
        g.stroke();
      }
    }
    let drag = null;
    cv.addEventListener('mousedown', (e) => { drag = [e.clientX, e.clientY]; });
    window.addEventListener('mouseup', () => { drag = null; });
    window.addEventListener('mousemove', (e) => {
      if (!drag) return;
      yaw += 0.01 * (e.clientX - drag[0]);
      pitch = Math.max(-1.5, Math.min(1.5, pitch + 0.01 * (e.clientY - drag[1])));
      drag = [e.clientX, e.clientY];
      draw();
    });
    cv.addEventListener('wheel', (e) => {
      e.preventDefault();
      zoom = Math.max(0.2, Math.min(20, zoom * Math.exp(-0.001 * e.deltaY)));
      draw();
    }, {passive: false});
    return {name: 'canvas-2d', redraw: draw, setTruth: (on) => { showTruth = on; draw(); }};
  }

  let view = null;
  if (window.THREE && window.THREE.OrbitControls) {
    // Probe on a spare canvas: a failed WebGL request must not claim the view's canvas.
    const probe = document.createElement('canvas');
    if (probe.getContext('webgl') || probe.getContext('experimental-webgl')) view = threeView();
    else note.textContent = 'This browser gives no WebGL context: a flat 2D-canvas view instead.';
  }
  if (!view) view = canvasView();
  cv.dataset.renderer = view.name;
  const legend = document.getElementById('mopad3d-classes');
  M.materials.forEach((mat) => {
    const label = document.createElement('label');
    const box = document.createElement('input');
    box.type = 'checkbox';
    box.checked = !hidden.has(mat.name);
    box.addEventListener('change', () => {
      if (box.checked) hidden.delete(mat.name); else hidden.add(mat.name);
      view.redraw();
    });
    const swatch = document.createElement('span');
    swatch.style.color = 'rgb(' + mat.rgb.map((x) => Math.round(255 * x)).join(',') + ')';
    swatch.textContent = ' \u25A0 ';
    label.append(box, swatch, mat.name + '  ');
    legend.append(label);
  });
  if (M.truth.length > 0) {
    const label = document.createElement('label');
    const box = document.createElement('input');
    box.type = 'checkbox';
    box.addEventListener('change', () => view.setTruth(box.checked));
    label.append(box, ' truth (black outlines)');
    legend.append(label);
  }
  view.redraw();
})();
)JS";

// `text` safe inside a <script> element: "</script" cannot end it early.
std::string ScriptSafe(std::string text) {
  for (std::size_t at = text.find("</"); at != std::string::npos; at = text.find("</", at + 3))
    text.replace(at, 2, "<\\/");
  return text;
}

// The library files under `three_dir`, inlined as two <script> elements; "" when either is
// missing or unreadable.
std::string InlineThreeJs(const std::string& three_dir) {
  namespace fs = std::filesystem;
  std::string out;
  for (const char* file : {kThreeJsFile, kOrbitControlsFile}) {
    std::ifstream in(fs::path(three_dir) / file, std::ios::binary);
    if (!in) return "";
    std::ostringstream text;
    text << in.rdbuf();
    if (!in.good() && !in.eof()) return "";
    out += "<script>" + ScriptSafe(text.str()) + "</script>\n";
  }
  return out;
}

double Mm(double v) {
  const double r = std::round(v * 1000.0) / 1000.0;
  return r == 0.0 ? 0.0 : r;
}

// A run folder, a room folder or a floor model: what exports::ReadRunFolder reads.
bool HasModel(const std::filesystem::path& dir) {
  std::error_code ec;
  return !runfolder::RoomFolders(dir.string(), runfolder::kSm3).empty() ||
         std::filesystem::exists(dir / runfolder::kFloorDir / runfolder::kSm3, ec);
}

// The truth's outlines in the export frame E: structural faces (no ceilings: they would hide
// the rooms' outlines from above), openings, components' visible faces.
Json TruthLoops(const scenes::GroundTruth& truth, const Eigen::Isometry3d& X_EW) {
  Json loops = Json::array();
  auto add = [&](const std::vector<Eigen::Vector3d>& loop) {
    Json flat = Json::array();
    for (const auto& p_W : loop) {
      const Eigen::Vector3d p_E = X_EW * p_W;
      for (int a = 0; a < 3; ++a) flat.push_back(Mm(p_E[a]));
    }
    loops.push_back(std::move(flat));
  };
  for (const auto& e : truth.elements)
    if (e.element_class != scenes::ElementClass::kCeiling)
      for (const auto& poly : e.polygons) add(poly);
  for (const auto& o : truth.openings) add(o.corners);
  for (const auto& c : truth.service_components) {
    const Eigen::Vector3d n = c.normal.normalized();
    const Eigen::Vector3d x0 = Eigen::Vector3d::UnitZ().cross(n);
    const Eigen::Vector3d x = x0.norm() > 1e-6 ? x0.normalized() : Eigen::Vector3d::UnitX();
    const Eigen::Vector3d y = n.cross(x), hx = 0.5 * c.size.x() * x, hy = 0.5 * c.size.y() * y;
    add({c.centre - hx - hy, c.centre + hx - hy, c.centre + hx + hy, c.centre - hx + hy});
  }
  return loops;
}

}  // namespace

std::string ModelViewerHtml(const std::string& run_dir, const scenes::GroundTruth* truth,
                            const std::string& three_dir) {
  if (!HasModel(run_dir.empty() ? "." : run_dir)) return "";
  io::GlbScene scene;
  Json truth_loops = Json::array();
  try {
    const exports::RunFolder run = exports::ReadRunFolder(run_dir);
    scene = exports::SemanticScene(exports::BuildBuildingModel(run));
    if (truth && run.X_WE) truth_loops = TruthLoops(*truth, run.X_WE->inverse());
  } catch (const InputError& e) {
    return "<h2>3D model</h2>\n<p>No 3D view: " + std::string(e.what()) + "</p>\n";
  }
  if (scene.meshes.empty()) return "";
  Json data;
  data["materials"] = Json::array();
  for (const auto& m : scene.materials)
    data["materials"].push_back(
        {{"name", m.name}, {"rgb", {m.base_color[0], m.base_color[1], m.base_color[2]}}});
  data["meshes"] = Json::array();
  for (const auto& mesh : scene.meshes) {
    Json p = Json::array(), t = Json::array();
    for (const auto& q : mesh.positions)
      for (int a = 0; a < 3; ++a) p.push_back(Mm(q[a]));
    for (const auto& tri : mesh.triangles)
      for (std::uint32_t i : tri) t.push_back(i);
    data["meshes"].push_back({{"id", mesh.name}, {"m", mesh.material}, {"p", p}, {"t", t}});
  }
  data["truth"] = std::move(truth_loops);
  // JSON allows "<\/" for "</".
  const std::string text = ScriptSafe(data.dump());
  const std::string library = InlineThreeJs(three_dir);
  const std::string note = library.empty()
                               ? "three.js was not found in " + three_dir +
                                     " (Debian package libjs-three): a flat 2D-canvas view instead."
                               : "";
  return "<h2>3D model</h2>\n<p class='legend'>The robot's model (as export/model.glb), coloured "
         "by class: drag to turn, wheel to zoom, right-drag to pan. "
         "<span id='mopad3d-classes'></span></p>\n<p id='mopad3d-note'>" +
         note +
         "</p>\n<canvas id='mopad3d' width='960' height='600' "
         "style='border:1px solid #ccc;cursor:grab'></canvas>\n"
         "<script type='application/json' id='mopad3d-data'>" +
         text + "</script>\n" + library + "<script>" + kViewerScript + "</script>\n";
}

}  // namespace mopad::report
