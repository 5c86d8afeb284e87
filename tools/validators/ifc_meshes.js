// Opens an IFC file with npm `web-ifc` (an independent IFC reader) and prints one line per
// product web-ifc meshes: GlobalId, IFC class, triangles, surface area (m^2) and the bounding
// box (min x y z, max x y z; m, IFC's Z-up world), tab-separated. web-ifc delivers Y-up
// (three.js) coordinates; they are turned back to Z-up here. Exit 0, or 2 on usage or I/O
// problems.
// Usage: node ifc_meshes.js FILE.ifc [NODE_MODULES_DIR]
const fs = require('fs');
const path = require('path');
if (process.argv.length < 3) {
  console.error('usage: node ifc_meshes.js FILE.ifc [NODE_MODULES_DIR]');
  process.exit(2);
}
const modules = process.argv[3];
const WebIFC = require(modules ? path.resolve(modules, 'web-ifc') : 'web-ifc');

async function main() {
  let bytes;
  try {
    bytes = new Uint8Array(fs.readFileSync(process.argv[2]));
  } catch (e) {
    console.error(`${process.argv[2]}: error: cannot read: ${e.message}`);
    process.exit(2);
  }
  const api = new WebIFC.IfcAPI();
  await api.Init();
  api.SetLogLevel(WebIFC.LogLevel.LOG_LEVEL_OFF);
  const model = api.OpenModel(bytes);
  const products = new Map();
  api.StreamAllMeshes(model, (mesh) => {
    const line = api.GetLine(model, mesh.expressID);
    const id = line.GlobalId ? line.GlobalId.value : `#${mesh.expressID}`;
    if (!products.has(id)) {
      products.set(id, {cls: line.constructor.name, tris: 0, area: 0,
                        lo: [Infinity, Infinity, Infinity], hi: [-Infinity, -Infinity, -Infinity]});
    }
    const p = products.get(id);
    for (let g = 0; g < mesh.geometries.size(); ++g) {
      const placed = mesh.geometries.get(g);
      const geometry = api.GetGeometry(model, placed.geometryExpressID);
      const v = api.GetVertexArray(geometry.GetVertexData(), geometry.GetVertexDataSize());
      const index = api.GetIndexArray(geometry.GetIndexData(), geometry.GetIndexDataSize());
      const m = placed.flatTransformation;  // column-major 4x4
      const points = [];
      for (let i = 0; i < v.length; i += 6) {  // x y z nx ny nz
        const x = v[i], y = v[i + 1], z = v[i + 2];
        const X = m[0] * x + m[4] * y + m[8] * z + m[12];
        const Y = m[1] * x + m[5] * y + m[9] * z + m[13];
        const Z = m[2] * x + m[6] * y + m[10] * z + m[14];
        const q = [X, -Z, Y];  // Y-up -> Z-up
        points.push(q);
        for (let k = 0; k < 3; ++k) {
          p.lo[k] = Math.min(p.lo[k], q[k]);
          p.hi[k] = Math.max(p.hi[k], q[k]);
        }
      }
      for (let i = 0; i + 2 < index.length; i += 3) {
        const a = points[index[i]], b = points[index[i + 1]], c = points[index[i + 2]];
        const u = [b[0] - a[0], b[1] - a[1], b[2] - a[2]];
        const w = [c[0] - a[0], c[1] - a[1], c[2] - a[2]];
        p.area += 0.5 * Math.hypot(u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2],
                                   u[0] * w[1] - u[1] * w[0]);
        ++p.tris;
      }
      geometry.delete();
    }
  });
  api.CloseModel(model);
  for (const [id, p] of products) {
    const f = (x) => x.toFixed(6);
    process.stdout.write([id, p.cls, p.tris, f(p.area), ...p.lo.map(f), ...p.hi.map(f)].join('\t') +
                         '\n');
  }
}
main().catch((e) => {
  console.error(`error: ${e.message}`);
  process.exit(2);
});
