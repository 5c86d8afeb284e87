#!/usr/bin/env bash
# Issue 15 acceptance: SM4 (openings and door states) of the main job, one table.
#   office_5rooms: `mopad run --seed N` for each seed (default 1..5);
#   random floors: `mopad scene random --seed K` then `mopad run --scene` (RANDOM="1 2 ..." to set,
#   default none). Long (minutes): not part of ctest.
#
#   scripts/openings-acceptance.sh [BUILD_DIR] [OUT_DIR] [SEEDS...]
#   RANDOM_FLOORS="1 2 3" scripts/openings-acceptance.sh ...
# A run whose folder already holds summary.json is not run again, so two instances with disjoint
# seeds can share OUT_DIR and a last call with every seed prints the pooled table.
set -euo pipefail
here="$(cd "$(dirname "$0")/.." && pwd)"
build="${1:-$here/build}"
out="${2:-$here/out/openings-acceptance}"
shift $(( $# > 2 ? 2 : $# )) || true
seeds=("$@")
[ ${#seeds[@]} -eq 0 ] && seeds=(1 2 3 4 5)
read -r -a floors <<< "${RANDOM_FLOORS:-}"
mopad="$build/tools/mopad"
[ -x "$mopad" ] || { echo "openings-acceptance: $mopad not built" >&2; exit 2; }
mkdir -p "$out"
runs=()
for s in "${seeds[@]}"; do
  runs+=("office_s$s")
  [ -f "$out/office_s$s/summary.json" ] && continue
  "$mopad" run --seed "$s" -o "$out/office_s$s" > "$out/office_s$s.log" 2>&1 || echo "run seed $s failed (see $out/office_s$s.log)"
  rm -f "$out"/office_s"$s"/rooms/*/sm1.ply
done
for k in "${floors[@]}"; do
  runs+=("random$k/run")
  [ -f "$out/random$k/run/summary.json" ] && continue
  "$mopad" scene random --seed "$k" -o "$out/random$k/scene" > /dev/null
  "$mopad" run --scene "$out/random$k/scene" -o "$out/random$k/run" > "$out/random$k.log" 2>&1 || echo "random floor $k failed (see $out/random$k.log)"
  rm -f "$out"/random"$k"/run/rooms/*/sm1.ply
done
/usr/bin/env python3 - "$out" "${runs[@]}" <<'PY'
import json, os, sys
out, runs = sys.argv[1], sys.argv[2:]
print(f"{'run':<16} {'rooms':>5} {'truth':>5} {'found':>5} {'false':>5} {'prec':>6} {'recall':>6} "
      f"{'e_abs':>6} {'e_r':>6} {'states':>7} {'ang_med':>7} {'ang_max':>7} {'sm4_s':>6}")
def tot(o): return o["matched"] + o["missed"]
pooled = {"truth": 0, "found": 0, "false": 0, "tp": 0.0, "fp": 0.0, "fn": 0.0, "right": 0, "doors": 0}
for r in runs:
    try:
        e = json.load(open(os.path.join(out, r, "eval", "evaluation.json")))
    except Exception as ex:
        print(f"{r:<16} missing ({ex})"); continue
    o = e["summary"].get("openings")
    if not o:
        print(f"{r:<16} no openings scored"); continue
    rooms = len(e["rooms"])
    st = o["door_states"]
    # The slowest room's SM4 wall time (summary.json; the wall clock of this run, which shares
    # the machine when two instances run).
    try:
        secs = [x.get("sm4_seconds", 0.0) for x in json.load(open(os.path.join(out, r, "summary.json")))["rooms"]]
        sm4 = f"{max(secs):6.2f}" if secs else f"{'':>6}"
    except Exception:
        sm4 = f"{'':>6}"
    print(f"{r:<16} {rooms:>5} {tot(o):>5} {o['matched']:>5} {o['false_openings']:>5} {o['precision']:6.3f} "
          f"{o['recall']:6.3f} {o['e_abs_m2']['mean']:6.3f} {o['e_r']['mean']:6.3f} {st['right']:>3}/{st['doors']:<3} "
          f"{o['angle_error_deg']['median'] or 0:7.2f} {o['angle_error_deg']['max'] or 0:7.2f} {sm4}")
    pooled["truth"] += tot(o); pooled["found"] += o["matched"]; pooled["false"] += o["false_openings"]
    pooled["tp"] += o.get("tp_m2", 0.0); pooled["fp"] += o["fp_m2"]; pooled["fn"] += o["fn_m2"]
    pooled["right"] += st["right"]; pooled["doors"] += st["doors"]
p = pooled
prec = p["tp"] / (p["tp"] + p["fp"]) if p["tp"] + p["fp"] > 0 else float("nan")
rec = p["tp"] / (p["tp"] + p["fn"]) if p["tp"] + p["fn"] > 0 else float("nan")
print(f"pooled: openings {p['found']}/{p['truth']} found, {p['false']} false; area precision {prec:.3f}, "
      f"recall {rec:.3f}; door states right {p['right']}/{p['doors']}")
PY
