#!/usr/bin/env bash
# `mopad run` killed with SIGKILL at KILLS seeded random moments, each in a fresh run: after each
# kill, does every JSON of the run folder parse (a temporary `*.tmp` of a write in progress may
# remain: no reader opens it), does `mopad run --resume DIR` finish the run, and are the resumed
# run's files those of an uninterrupted run of the same seed (scripts/compare-runs.py: model
# files byte for byte, every other file too or, for timings, with its wall-clock keys removed).
# Long (KILLS x ~1.5 runs): not part of ctest.
#
#   scripts/kill-resume.sh [BUILD_DIR] [OUT_DIR]             (OUT_DIR: out/kill-resume)
#   KILLS=20 KILL_SEED=52 RUN_SEED=1 SPEC=scenes/two_rooms_door.yaml STEP_DEG=0.5 ...
#   (STEP_DEG= : the config's TLS step)
#   SPEC=office scripts/kill-resume.sh ...                   (the default scene, office_5rooms)
#
# The kill moments are drawn from bash's $RANDOM seeded with KILL_SEED: uniform over the
# uninterrupted run's wall time, in steps of 1 %. The same moments every time the script runs on
# the same machine; what state each kill meets depends on the machine's speed.
# The binary is copied to OUT_DIR first: a rebuild cannot change the binary a resume must match.
# A kill before the run recorded itself (checkpoint `none`: no folder yet, or no manifest) has
# nothing to resume: --resume must refuse it (exit 2, "nothing to resume") and the same command
# run again must give the uninterrupted run's files ("refused; rerun exit 0").
# Exit code 0 when every kill ends with every JSON parsing, a finished resume (or refusal and
# rerun) and no differing file; 1 otherwise; 2 when the binary is missing.
set -uo pipefail
here="$(cd "$(dirname "$0")/.." && pwd)"
build="${1:-$here/build}"
out="${2:-$here/out/kill-resume}"
kills="${KILLS:-20}"
RANDOM="${KILL_SEED:-52}"
spec="${SPEC:-scenes/two_rooms_door.yaml}"
[ -x "$build/tools/mopad" ] || { echo "kill-resume: $build/tools/mopad not built" >&2; exit 2; }
rm -rf "$out"
mkdir -p "$out"
cp "$build/tools/mopad" "$out/mopad"
mopad="$out/mopad"
args=(run -q --seed "${RUN_SEED:-1}")
if [ "$spec" = office ]; then
  scene=office_5rooms
else
  scene="$(basename "$spec" .yaml)"
  args+=(--spec "$here/$spec")
fi
step="${STEP_DEG-0.5}"
[ -n "$step" ] && args+=(--step-deg "$step")

now() { date +%s.%N; }
elapsed() { awk -v a="$1" -v b="$2" 'BEGIN { printf "%.1f", b - a }'; }

# jsons DIR -> "N/M" (N of the M JSON files parse) and the temporary files left, e.g. "12/12 0"
jsons() {
  python3 - "$1" <<'PY'
import json, os, sys
n = ok = tmp = 0
for root, _, names in os.walk(sys.argv[1]):
    for f in names:
        tmp += f.endswith(".tmp")
        if f.endswith(".json"):
            n += 1
            try:
                json.load(open(os.path.join(root, f)))
                ok += 1
            except Exception:
                print("unparsable:", os.path.join(root, f), file=sys.stderr)
print("%d/%d %d" % (ok, n, tmp))
PY
}

state_of() {
  python3 -c 'import json,sys; m=json.load(open(sys.argv[1])); print(m["state"]+":"+str(len(m["boundaries"]))+"rooms")' \
    "$1/checkpoint/manifest.json" 2>/dev/null || echo "none"
}

# Every run writes to the same path (eval/evaluation.json names its run folder).
run="$out/run"
t0=$(now)
"$mopad" "${args[@]}" -o "$run" > "$out/uninterrupted.log" 2>&1
rc=$?
whole=$(elapsed "$t0" "$(now)")
[ $rc -eq 0 ] || { echo "kill-resume: the uninterrupted run failed (exit $rc, $out/uninterrupted.log)" >&2; exit 1; }
mv "$run" "$out/uninterrupted"

echo "kill-resume: $scene, run seed ${RUN_SEED:-1}, ${step:+step $step deg, }uninterrupted run ${whole} s; $kills SIGKILLs (KILL_SEED=${KILL_SEED:-52})"
printf '%-4s %9s %-16s %-10s %-5s %-24s %s\n' kill "at (s)" "checkpoint" "JSON ok" ".tmp" "resume" "vs uninterrupted (files: cmp= / timing-only / differ; models cmp=)"
fail=0
for k in $(seq 1 "$kills"); do
  pct=$((1 + RANDOM % 99))
  delay=$(awk -v w="$whole" -v p="$pct" 'BEGIN { printf "%.2f", w * p / 100 }')
  "$mopad" "${args[@]}" -o "$run" > "$out/kill$k.log" 2>&1 &
  pid=$!
  sleep "$delay"
  kill -KILL "$pid" 2>/dev/null || delay="${delay}(ended)"
  wait "$pid" 2>/dev/null
  state=$(state_of "$run")
  read -r parsed tmp <<< "$(jsons "$run" 2> "$out/kill$k.unparsable")"
  t1=$(now)
  "$mopad" run -q --resume "$run" > "$out/kill$k.resume.log" 2>&1
  rrc=$?
  resume="exit $rrc, $(elapsed "$t1" "$(now)") s"
  if [ "$state" = none ]; then
    # Killed before the run recorded itself (no checkpoint/manifest.json): there is nothing to
    # resume, and --resume must refuse in one line with exit 2. What a user then does, the same
    # command again, must start the run afresh whatever the kill left, and give the same files.
    if [ $rrc -eq 2 ] && grep -q "error: nothing to resume" "$out/kill$k.resume.log"; then
      "$mopad" "${args[@]}" -o "$run" >> "$out/kill$k.resume.log" 2>&1
      rrc=$?
      resume="refused; rerun exit $rrc, $(elapsed "$t1" "$(now)") s"
    else
      rrc=1
    fi
  fi
  read -r nref ncmp nloose nbad nmod nmodcmp <<< "$(python3 "$here/scripts/compare-runs.py" "$out/uninterrupted" "$run")"
  mv "$run.cmp" "$out/kill$k.cmp"
  read -r after _ <<< "$(jsons "$run" 2>> "$out/kill$k.unparsable")"
  verdict=ok
  if [ "${parsed%/*}" != "${parsed#*/}" ] || [ "${after%/*}" != "${after#*/}" ] || [ $rrc -ne 0 ] ||
     [ "${nbad:-1}" != 0 ] || [ "${nmod:-0}" != "${nmodcmp:-x}" ]; then
    verdict=FAIL
    fail=1
  fi
  printf '%-4s %9s %-16s %-10s %-5s %-24s %s\n' "$k" "$delay" "$state" "$parsed" "$tmp" "$resume" \
    "$nref files: $ncmp / $nloose / $nbad; models $nmodcmp/$nmod  $verdict"
  rm -rf "$run"
done
[ $fail -eq 0 ] && echo "PASS" || echo "FAIL (differences: $out/kill*.cmp, unparsable files: $out/kill*.unparsable)"
exit $fail
