#!/usr/bin/env bash
# Issue 17's scaling figures: wall time and peak memory of the floor mission (`mopad run
# --scene`) on random floors of 2, 5 and 10 rooms, one run at a time, each under
# `/usr/bin/time -v`. Benchmark figures, not a test: it prints a table and exits 0 (2 when the
# binary or /usr/bin/time is missing). Long (about 1 + 2.5 + 6 min per seed on 2 cores).
#
#   scripts/scaling-benchmark.sh [BUILD_DIR] [OUT_DIR]       (OUT_DIR: out/scaling-benchmark)
#   SEEDS="31 32" ROOMS="2 5 10" scripts/scaling-benchmark.sh ...
#
# SEEDS: `mopad scene random --seed` values (default 31 32, floors no acceptance uses);
# ROOMS: room counts (default 2 5 10). Every run is done again (timings of kept runs would mix
# machines). Per run: rooms visited / in the scene, TLS scans, the mission's platform seconds,
# wall seconds and peak RSS of the whole job (mission, SM1-SM5, evaluation, exports, report),
# and wall seconds per visited room; then the TLS scan and registration steps' seconds per scan
# in the first and the last room visited. Let nothing else run meanwhile: wall time is the figure.
set -uo pipefail
here="$(cd "$(dirname "$0")/.." && pwd)"
build="${1:-$here/build}"
out="${2:-$here/out/scaling-benchmark}"
mopad="$build/tools/mopad"
[ -x "$mopad" ] || { echo "scaling-benchmark: $mopad not built" >&2; exit 2; }
[ -x /usr/bin/time ] || { echo "scaling-benchmark: /usr/bin/time missing (apt install time)" >&2; exit 2; }
seeds="${SEEDS-31 32}"
rooms="${ROOMS-2 5 10}"
mkdir -p "$out"
for s in $seeds; do
  for r in $rooms; do
    echo "random floor seed $s, $r rooms" >&2
    scene="$out/scene_${s}_$r" dir="$out/run_${s}_$r"
    [ -f "$scene/scene.truth.json" ] ||
      "$mopad" scene random --seed "$s" --rooms "$r" -o "$scene" > "$scene.log" 2>&1 ||
      { echo "scaling-benchmark: scene generation failed, see $scene.log" >&2; continue; }
    rm -rf "$dir"
    /usr/bin/time -v "$mopad" run --scene "$scene" -o "$dir" -q > "$dir.log" 2>&1 || true
  done
done

python3 - "$out" "$seeds" "$rooms" <<'EOF'
import json, os, re, sys
out, seeds, rooms = sys.argv[1], sys.argv[2].split(), sys.argv[3].split()
print("| seed | rooms | visited | TLS scans | platform s | wall s | peak MB | wall s per visited room |")
print("|---|---|---|---|---|---|---|---|")
for s in seeds:
    for r in rooms:
        d = f"{out}/run_{s}_{r}"
        try:
            log = open(d + ".log").read()
            m = json.load(open(d + "/summary.json"))["mission"]
        except (OSError, ValueError, KeyError) as e:
            print(f"| {s} | {r} | run failed ({e}) | | | | | |")
            continue
        wall = re.search(r"Elapsed \(wall clock\) time \(h:mm:ss or m:ss\): (\S+)", log).group(1)
        secs = 0.0
        for part in wall.split(":"):
            secs = 60 * secs + float(part)
        peak = int(re.search(r"Maximum resident set size \(kbytes\): (\d+)", log).group(1)) / 1024
        v = m["rooms_visited"]
        print(f"| {s} | {r} | {v} | {m['scans']} | {m['sim_time_s']:.0f} | {secs:.1f} | "
              f"{peak:.0f} | {secs / max(v, 1):.1f} |")

# Per-scan cost against the scan's place in the mission: the room-scan steps of the first and
# the last room visited (rooms/*/scans.json, seconds), mean per scan, and their ratio.
import glob
print()
print("| seed | rooms | step | first room s/scan | last room s/scan | last / first |")
print("|---|---|---|---|---|---|")
for s in seeds:
    for r in rooms:
        rows = []
        for f in glob.glob(f"{out}/run_{s}_{r}/rooms/*/scans.json"):
            for sc in json.load(open(f)).get("scans", []):
                rows.append((sc["sim_time"], os.path.basename(os.path.dirname(f)), sc["seconds"]))
        if not rows:
            continue
        rows.sort(key=lambda x: x[0])
        order = list(dict.fromkeys(room for _, room, _ in rows))
        for step in ("scan", "registration"):
            def mean(room):
                v = [sec[step] for _, rm, sec in rows if rm == room]
                return sum(v) / len(v)
            a, b = mean(order[0]), mean(order[-1])
            print(f"| {s} | {r} | {step} | {a:.2f} | {b:.2f} | {b / a:.2f} |")
EOF
