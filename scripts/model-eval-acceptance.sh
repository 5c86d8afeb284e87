#!/usr/bin/env bash
# `mopad eval --model` on a main job's own export (docs/evaluation.md, "Scoring other tools'
# models"): scores RUN/export/model.ifc against the scene's truth, compares its figures with
# `mopad eval RUN` (the run folder's own scoring), then scores a damaged copy (a wall moved
# 10 cm, a door removed: scripts/damage-ifc.py) and prints the three side by side.
#   scripts/model-eval-acceptance.sh BUILD_DIR RUN_DIR [OUT_DIR]
# RUN_DIR is a finished `mopad run` folder (with export/model.ifc); the model's pose in the world
# is its first room's X_WM (the export frame, docs/exports.md).
set -euo pipefail
build=${1:?usage: model-eval-acceptance.sh BUILD_DIR RUN_DIR [OUT_DIR]}
run=${2:?usage: model-eval-acceptance.sh BUILD_DIR RUN_DIR [OUT_DIR]}
out=${3:-$run/model-eval}
mopad="$build/tools/mopad"
here=$(cd "$(dirname "$0")" && pwd)
[[ -f "$run/export/model.ifc" ]] || { echo "error: $run/export/model.ifc missing" >&2; exit 2; }
first=$(ls -d "$run"/rooms/*/ | head -1)
pose=$(python3 -c "
import json, math, sys
X = json.load(open(sys.argv[1]))['X_WM']
print('%.6f,%.6f,%.6f,%.6f' % (X[0][3], X[1][3], X[2][3], math.degrees(math.atan2(X[1][0], X[0][0]))))
" "$first/run.json")
scene=$(python3 -c "import json, sys; print(json.load(open(sys.argv[1]))['scene'])" "$first/run.json")
mkdir -p "$out"
echo "model pose (X_WM of $(basename "$first")): $pose"
"$mopad" eval "$run" -o "$out/run" > "$out/run.txt"
"$mopad" eval --model "$run/export/model.ifc" --scene "$scene" --pose "$pose" -o "$out/model" \
  > "$out/model.txt"
python3 "$here/damage-ifc.py" "$run/export/model.ifc" "$out/damaged.ifc" --move-wall 0.10 \
  --remove-door
"$mopad" eval --model "$out/damaged.ifc" --scene "$scene" --pose "$pose" -o "$out/damaged" \
  > "$out/damaged.txt"
python3 - "$out" <<'EOF'
import json, sys
out = sys.argv[1]
run = json.load(open(out + "/run/evaluation.json"))["summary"]
model = json.load(open(out + "/model/evaluation.json"))["summary"]
damaged = json.load(open(out + "/damaged/evaluation.json"))["summary"]

def det(s, c):
    d = s["detection"][c]
    return "%d/%d fp %d" % (d["tp"], d["n_truth"], d["fp"])

def f(v, k=4):
    return "-" if v is None else ("%." + str(k) + "f") % v

def comp(s):
    a = s["components"]["all"]
    return "%d/%d fp %d" % (a["tp"], a["n"], a["fp"])

def ends(s, k):
    if "wall_endpoints" not in s:
        return "-"
    e = s["wall_endpoints"]["endpoints"][k]
    return "%.3f/%.3f" % (e["precision"], e["recall"])

rows = [
    ("walls", lambda s: det(s, "wall")), ("floors", lambda s: det(s, "floor")),
    ("ceilings", lambda s: det(s, "ceiling")), ("columns", lambda s: det(s, "column")),
    ("d_v mean (cm)", lambda s: f(s["d_v"]["mean"] * 100, 3)),
    ("d_h mean (cm)", lambda s: f(s["d_h"]["mean"] * 100, 3)),
    ("phi mean (deg)", lambda s: f(s["phi_deg"]["mean"], 4)),
    ("ISPRS compl. @5cm", lambda s: f(s["isprs_completeness"])),
    ("ISPRS corr. @5cm", lambda s: f(s["isprs_correctness"])),
    ("room IoU mean", lambda s: f(s.get("room_iou_mean", s.get("floorplan_mean_iou")))),
    ("openings P", lambda s: f(s["openings"]["precision"])),
    ("openings R", lambda s: f(s["openings"]["recall"])),
    ("door states right", lambda s: "%d/%d" % (s["openings"]["door_states"]["right"],
                                              s["openings"]["door_states"]["doors"])),
    ("components", comp),
    ("wall endpoints P/R @5cm", lambda s: ends(s, 0)),
    ("wall endpoints P/R @10cm", lambda s: ends(s, 1)),
    ("wall endpoints P/R @20cm", lambda s: ends(s, 2)),
]
print("| figure | mopad eval RUN | eval --model model.ifc | damaged copy |")
print("|---|---|---|---|")
for name, get in rows:
    print("| %s | %s | %s | %s |" % (name, get(run), get(model), get(damaged)))
EOF
