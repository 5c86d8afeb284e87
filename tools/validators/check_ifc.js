// Opens an IFC file with npm `web-ifc` (an independent IFC reader) and prints one JSON line:
// {"schema", "counts": {IFCWALL: n, ...}, "meshed": {IFCWALL: n, ...}, "errors", "warnings",
//  "messages": [...]}: instances per class, how many of them web-ifc streamed a non-empty mesh
// for, and the log messages web-ifc printed. Exit 0 when it opened with no error message, 1 when
// web-ifc reported errors, 2 on usage or I/O problems.
// Usage: node check_ifc.js FILE.ifc [NODE_MODULES_DIR]
const fs = require('fs');
const path = require('path');
if (process.argv.length < 3) {
  console.error('usage: node check_ifc.js FILE.ifc [NODE_MODULES_DIR]');
  process.exit(2);
}
const file = process.argv[2];
const modules = process.argv[3];
const WebIFC = require(modules ? path.resolve(modules, 'web-ifc') : 'web-ifc');
const kClasses = ['IFCPROJECT', 'IFCSITE', 'IFCBUILDING', 'IFCBUILDINGSTOREY', 'IFCSPACE',
  'IFCWALL', 'IFCSLAB', 'IFCCOVERING', 'IFCCOLUMN', 'IFCOPENINGELEMENT', 'IFCDOOR', 'IFCWINDOW',
  'IFCOUTLET', 'IFCSWITCHINGDEVICE', 'IFCSENSOR', 'IFCALARM', 'IFCFIRESUPPRESSIONTERMINAL',
  'IFCLIGHTFIXTURE', 'IFCSPACEHEATER', 'IFCELECTRICDISTRIBUTIONBOARD', 'IFCBUILDINGELEMENTPROXY',
  'IFCRELVOIDSELEMENT', 'IFCRELFILLSELEMENT', 'IFCRELAGGREGATES',
  'IFCRELCONTAINEDINSPATIALSTRUCTURE', 'IFCPROPERTYSET'];

// Every message web-ifc (and its wasm module) prints goes through console.*.
const messages = {error: [], warn: []};
for (const level of ['error', 'warn']) {
  console[level] = (...args) => messages[level].push(args.join(' '));
}

async function main() {
  let bytes;
  try {
    bytes = new Uint8Array(fs.readFileSync(file));
  } catch (e) {
    process.stdout.write(`${file}: error: cannot read: ${e.message}\n`);
    process.exit(2);
  }
  const api = new WebIFC.IfcAPI();
  await api.Init();
  api.SetLogLevel(WebIFC.LogLevel.LOG_LEVEL_WARN);
  const model = api.OpenModel(bytes);
  const counts = {};
  const typeOf = new Map();
  for (const name of kClasses) {
    const ids = api.GetLineIDsWithType(model, WebIFC[name], false);
    counts[name] = ids.size();
    for (let i = 0; i < ids.size(); ++i) typeOf.set(ids.get(i), name);
  }
  const meshed = {};
  api.StreamAllMeshes(model, (mesh) => {
    let vertices = 0;
    for (let g = 0; g < mesh.geometries.size(); ++g) {
      const geometry = api.GetGeometry(model, mesh.geometries.get(g).geometryExpressID);
      vertices += geometry.GetVertexDataSize();
      geometry.delete();
    }
    const name = typeOf.get(mesh.expressID) || 'other';
    if (vertices > 0) meshed[name] = (meshed[name] || 0) + 1;
  });
  const schema = api.GetModelSchema(model);
  api.CloseModel(model);
  const out = {schema, counts, meshed, errors: messages.error.length,
    warnings: messages.warn.length, messages: messages.error.concat(messages.warn).slice(0, 10)};
  process.stdout.write(JSON.stringify(out) + '\n');
  process.exit(messages.error.length === 0 ? 0 : 1);
}
main().catch((e) => {
  process.stdout.write(`${file}: error: web-ifc failed: ${e && e.stack ? e.stack : e}\n`);
  process.exit(1);
});
