// Reads a LAS file with npm `copc` (an independent LAS reader: its Header and View) and prints
// one JSON line: {"version", "format", "points", "header_min", "header_max", "min", "max",
// "classification": {code: n}, "rgb_sum": [r, g, b], "gps_time": [min, max],
// "point_source_ids": [min, max]}. Exit 0 when it read, 1 when copc rejected the file, 2 on
// usage or I/O problems.  Usage: node check_las.js FILE.las [NODE_MODULES_DIR]
const fs = require('fs');
const path = require('path');
if (process.argv.length < 3) {
  console.error('usage: node check_las.js FILE.las [NODE_MODULES_DIR]');
  process.exit(2);
}
const file = process.argv[2];
const modules = process.argv[3];
const {Las} = require(modules ? path.resolve(modules, 'copc') : 'copc');
let bytes;
try {
  bytes = new Uint8Array(fs.readFileSync(file));
} catch (e) {
  process.stdout.write(`${file}: error: cannot read: ${e.message}\n`);
  process.exit(2);
}
try {
  const header = Las.Header.parse(bytes.subarray(0, 375));
  const n = Number(header.pointCount);
  const start = header.pointDataOffset;
  const view = Las.View.create(
      bytes.subarray(start, start + n * header.pointDataRecordLength), header);
  const get = (name) => view.getter(name);
  const [X, Y, Z, C, R, G, B, T, S] = ['X', 'Y', 'Z', 'Classification', 'Red', 'Green', 'Blue',
    'GpsTime', 'PointSourceId'].map(get);
  const min = [Infinity, Infinity, Infinity];
  const max = [-Infinity, -Infinity, -Infinity];
  const classification = {};
  const rgb = [0, 0, 0];
  const time = [Infinity, -Infinity];
  const source = [Infinity, -Infinity];
  for (let i = 0; i < view.pointCount; ++i) {
    const p = [X(i), Y(i), Z(i)];
    for (let a = 0; a < 3; ++a) {
      min[a] = Math.min(min[a], p[a]);
      max[a] = Math.max(max[a], p[a]);
    }
    const c = C(i);
    classification[c] = (classification[c] || 0) + 1;
    rgb[0] += R(i), rgb[1] += G(i), rgb[2] += B(i);
    const t = T(i), s = S(i);
    time[0] = Math.min(time[0], t), time[1] = Math.max(time[1], t);
    source[0] = Math.min(source[0], s), source[1] = Math.max(source[1], s);
  }
  process.stdout.write(JSON.stringify({
    version: `${header.majorVersion}.${header.minorVersion}`,
    format: header.pointDataRecordFormat, points: view.pointCount, header_count: n,
    header_min: header.min, header_max: header.max, min, max, classification, rgb_sum: rgb,
    gps_time: time, point_source_ids: source}) + '\n');
} catch (e) {
  process.stdout.write(`${file}: error: copc cannot read it: ${e.message}\n`);
  process.exit(1);
}
