#!/usr/bin/env bash
# The exports' acceptance on a run folder (docs/exports.md): writes RUN_DIR/export/ with
# `mopad export all`, then checks each file with an independent reader against the model files:
#   IFC   npm web-ifc opens model.ifc with no error; its counts per class equal those of the
#         sm3/sm4/sm5 files; every wall, slab, covering, column, door, window and component has a
#         mesh
#   glTF  the Khronos validator reports 0 errors on model.glb
#   LAS   npm copc reads sm1.las: point count, bounds, classification histogram (folded back to
#         the SM1 labels) and colour sums equal those of the rooms' sm1.ply
# With a second run folder of the same seed, also compares the three files byte for byte.
# Needs node and the npm oracles in build/_npm (scripts/install-deps.sh --test).
#   scripts/exports-acceptance.sh RUN_DIR [SECOND_RUN_DIR]
set -euo pipefail
cd "$(dirname "$0")/.."
run="${1:?usage: scripts/exports-acceptance.sh RUN_DIR [SECOND_RUN_DIR]}"
modules="$PWD/build/_npm/node_modules"
./build/tools/mopad export all "$run"
if [[ -n "${2:-}" ]]; then ./build/tools/mopad export all "$2" >/dev/null; fi
node tools/validators/check_ifc.js "$run/export/model.ifc" "$modules" > /tmp/mopad_ifc_$$.json
node tools/validators/validate_gltf.js "$run/export/model.glb" "$modules"
node tools/validators/check_las.js "$run/export/sm1.las" "$modules" > /tmp/mopad_las_$$.json
/usr/bin/python3 - "$run" /tmp/mopad_ifc_$$.json /tmp/mopad_las_$$.json "${2:-}" <<'EOF'
import glob, json, os, struct, sys
run, ifc_json, las_json, second = sys.argv[1:5]
ifc, las = json.load(open(ifc_json)), json.load(open(las_json))
rooms = sorted(glob.glob(os.path.join(run, "rooms", "*", "sm3.json")))
ok = True
def check(name, got, want):
    global ok
    same = got == want
    ok &= same
    print(f"{'PASS' if same else 'FAIL'} {name}: export {got}, model files {want}")

def component_entity(c):
    if c.startswith("socket") or c == "built_in_socket": return "IFCOUTLET"
    return {"switch": "IFCSWITCHINGDEVICE", "smoke_detector": "IFCSENSOR",
            "fire_alarm_switch": "IFCALARM", "fire_extinguisher": "IFCFIRESUPPRESSIONTERMINAL",
            "exit_light": "IFCLIGHTFIXTURE", "emergency_light": "IFCLIGHTFIXTURE",
            "radiator": "IFCSPACEHEATER",
            "electrical_panel": "IFCELECTRICDISTRIBUTIONBOARD"}.get(c, "IFCBUILDINGELEMENTPROXY")

# Counts from the model files (the floor model when there is one).
src = [os.path.join(run, "floor")] if os.path.exists(os.path.join(run, "floor", "sm3.json")) \
    else [os.path.dirname(p) for p in rooms]
want = {k: 0 for k in ["IFCWALL", "IFCSLAB", "IFCCOVERING", "IFCCOLUMN", "IFCOPENINGELEMENT",
                       "IFCDOOR", "IFCWINDOW"]}
want["IFCSPACE"] = sum(any(p["class"] == "floor" for p in json.load(open(r))["patches"])
                       for r in rooms)
for d in src:
    sm3 = json.load(open(os.path.join(d, "sm3.json")))
    cls = {"wall": "IFCWALL", "floor": "IFCSLAB", "ceiling": "IFCCOVERING"}
    for p in sm3["patches"]:
        if p["class"] in cls: want[cls[p["class"]]] += 1
    want["IFCCOLUMN"] += len({p["id"].split("_face_")[0] for p in sm3["patches"]
                              if p["class"] == "column"})
    if os.path.exists(os.path.join(d, "sm4.json")):
        for o in json.load(open(os.path.join(d, "sm4.json")))["openings"]:
            want["IFCOPENINGELEMENT"] += 1
            want["IFCDOOR" if o["type"] == "door" else "IFCWINDOW"] += 1
# Components: floor/sm5.json when the floor model has one, else the rooms'.
floor_sm5 = os.path.join(run, "floor", "sm5.json")
comp_dirs = [os.path.dirname(floor_sm5)] if os.path.exists(floor_sm5) else \
    [os.path.dirname(p) for p in rooms]
for d in comp_dirs:
    if os.path.exists(os.path.join(d, "sm5.json")):
        for c in json.load(open(os.path.join(d, "sm5.json")))["components"]:
            e = component_entity(c["class"])
            want[e] = want.get(e, 0) + 1
check("web-ifc errors", ifc["errors"], 0)
for k, v in sorted(want.items()):
    check(f"IFC count {k}", ifc["counts"].get(k, 0), v)
    if k not in ("IFCOPENINGELEMENT", "IFCSPACE"):
        check(f"IFC meshed {k}", ifc["meshed"].get(k, 0), v)

# The rooms' sm1.ply, mapped into the export frame as the exports do (X_WM of the first room).
def pose(d):
    p = os.path.join(d, "run.json")
    return json.load(open(p)).get("X_WM") if os.path.exists(p) else None
def mul(a, b): return [[sum(a[i][k] * b[k][j] for k in range(4)) for j in range(4)] for i in range(4)]
def inv(t):
    r = [[t[j][i] for j in range(3)] for i in range(3)]
    p = [-sum(r[i][k] * t[k][3] for k in range(3)) for i in range(3)]
    return [r[0] + [p[0]], r[1] + [p[1]], r[2] + [p[2]], [0, 0, 0, 1]]
first = next((pose(os.path.dirname(r)) for r in rooms if pose(os.path.dirname(r))), None)
n, lo, hi = 0, [1e300] * 3, [-1e300] * 3
labels, rgb = [0, 0, 0, 0], [0, 0, 0]
for r in rooms:
    d = os.path.dirname(r)
    ply = os.path.join(d, "sm1.ply")
    if not os.path.exists(ply): continue
    X = mul(inv(first), pose(d)) if first and pose(d) else [[1,0,0,0],[0,1,0,0],[0,0,1,0],[0,0,0,1]]
    data = open(ply, "rb").read()
    head = data[:data.index(b"end_header\n") + 11].decode()
    props = [l.split()[1:] for l in head.splitlines() if l.startswith("property")]
    fmt = "<" + "".join({"float": "f", "uchar": "B", "ushort": "H", "double": "d", "int": "i",
                         "uint": "I", "char": "b", "short": "h"}[t] for t, _ in props)
    names = [nm for _, nm in props]
    ix, iy, iz = names.index("x"), names.index("y"), names.index("z")
    ir, ig, ib, il = names.index("red"), names.index("green"), names.index("blue"), \
        names.index("scalar_label")
    for rec in struct.iter_unpack(fmt, data[len(head):]):
        x, y, z = rec[ix], rec[iy], rec[iz]
        q = [X[i][0] * x + X[i][1] * y + X[i][2] * z + X[i][3] for i in range(3)]
        for a in range(3):
            if q[a] < lo[a]: lo[a] = q[a]
            if q[a] > hi[a]: hi[a] = q[a]
        labels[rec[il]] += 1
        rgb[0] += rec[ir]; rgb[1] += rec[ig]; rgb[2] += rec[ib]
        n += 1
check("LAS version/format", (las["version"], las["format"]), ("1.4", 7))
check("LAS point count", las["points"], n)
check("LAS header count", las["header_count"], n)
def near(name, got, want, tol):
    global ok
    same = abs(got - want) <= tol
    ok &= same
    print(f"{'PASS' if same else 'FAIL'} {name}: export {got:.6f}, model files {want:.6f}")
for a, axis in enumerate("xyz"):  # stored on a 0.1 mm grid: within half a step
    near(f"LAS min {axis}", las["min"][a], lo[a], 0.5e-4 + 1e-9)
    near(f"LAS max {axis}", las["max"][a], hi[a], 0.5e-4 + 1e-9)
c = {int(k): v for k, v in las["classification"].items()}
folded = [c.get(64, 0), sum(c.get(k, 0) for k in range(67, 72)), c.get(65, 0), c.get(66, 0)]
check("LAS classes folded to SM1 labels [none, inlier, outlier, clutter]", folded, labels)
check("LAS colour sums (16-bit = 257 x 8-bit)", las["rgb_sum"], [257 * v for v in rgb])
if second:
    for f in ["model.ifc", "model.glb", "sm1.las"]:
        a = open(os.path.join(run, "export", f), "rb").read()
        b = open(os.path.join(second, "export", f), "rb").read()
        check(f"same bytes {f} ({len(a)} bytes)", a == b, True)
print("exports acceptance:", "PASS" if ok else "FAIL")
sys.exit(0 if ok else 1)
EOF
