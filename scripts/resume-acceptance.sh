#!/usr/bin/env bash
# Issue 17, item 7 acceptance: `mopad run` killed with SIGKILL at three random moments and
# resumed (`mopad run --resume DIR`) each time writes the files of an uninterrupted run of the
# same seed (`cmp`), on office_5rooms (the default scene) and on two_rooms_door. The kill moments
# are drawn from bash's $RANDOM seeded with KILL_SEED (default 17): the same moments every time
# the script runs. Long (minutes): not part of ctest.
#
#   scripts/resume-acceptance.sh [BUILD_DIR] [OUT_DIR]      (OUT_DIR: out/resume-acceptance)
#   KILL_SEED=N RUN_SEED=S scripts/resume-acceptance.sh ...
#
# Files compared: every file of the uninterrupted run's folder, byte for byte, except
#   checkpoint/ (the checkpoint's own record: resumes counted);
#   the wall-clock timings of summary.json, rooms/*/summary.json, rooms/*/scans.json,
#   rooms/*/evaluation.json (keys seconds, wall_time, wall_time_s, tls_wall_time_s,
#   sm4_seconds, sm5_seconds): those files are compared with those keys removed;
#   report.md and report.html: compared without their "Timing" table (report.md) and with
#   the timing cells of report.html removed the same way.
# Exit code 0 when every scene passes, 1 otherwise, 2 when the binary is missing.
set -uo pipefail
here="$(cd "$(dirname "$0")/.." && pwd)"
build="${1:-$here/build}"
out="${2:-$here/out/resume-acceptance}"
mopad="$build/tools/mopad"
RANDOM="${KILL_SEED:-17}"
run_seed="${RUN_SEED:-1}"
[ -x "$mopad" ] || { echo "resume-acceptance: $mopad not built" >&2; exit 2; }
rm -rf "$out"
mkdir -p "$out"

now() { date +%s.%N; }
elapsed() { awk -v a="$1" -v b="$2" 'BEGIN { printf "%.1f", b - a }'; }

# compare REF DIR -> "FILES CMP TIMING DIFF ..." (scripts/compare-runs.py), the list in DIR.cmp
compare() { python3 "$here/scripts/compare-runs.py" "$1" "$2"; }

rows=()
fail=0
for scene in office_5rooms two_rooms_door; do
  args=(--seed "$run_seed" -q)
  [ "$scene" = two_rooms_door ] && args+=(--spec "$here/scenes/two_rooms_door.yaml")
  # Both runs write to the same path (eval/evaluation.json names its run folder): the
  # uninterrupted one is moved aside before the killed one starts.
  ref="$out/$scene/uninterrupted"
  got="$out/$scene/run"
  mkdir -p "$out/$scene"
  t0=$(now)
  "$mopad" run "${args[@]}" -o "$got" > "$ref.log" 2>&1
  rc=$?
  t1=$(now)
  mv "$got" "$ref"
  whole=$(elapsed "$t0" "$t1")
  if [ $rc -ne 0 ]; then
    rows+=("$(printf '%-15s uninterrupted run failed (exit %d, %s)' "$scene" $rc "$ref.log")")
    fail=1
    continue
  fi
  # Three kills at random moments of each process's life (5-95 % of the uninterrupted run's
  # duration), the first in the fresh run, the next two in resumed runs.
  kills=()
  resume_rcs=()
  for k in 1 2 3; do
    pct=$((5 + RANDOM % 91))
    delay=$(awk -v w="$whole" -v p="$pct" 'BEGIN { printf "%.2f", w * p / 100 }')
    if [ "$k" -eq 1 ]; then
      "$mopad" run "${args[@]}" -o "$got" > "$got.log.$k" 2>&1 &
    else
      "$mopad" run --resume "$got" -q > "$got.log.$k" 2>&1 &
    fi
    pid=$!
    sleep "$delay"
    if kill -9 "$pid" 2>/dev/null; then
      kills+=("${delay}s")
    else
      kills+=("${delay}s(ended)")
    fi
    wait "$pid" 2>/dev/null
    resume_rcs+=("$?")
  done
  t2=$(now)
  "$mopad" run --resume "$got" -q > "$got.log.final" 2>&1
  rc=$?
  t3=$(now)
  final=$(elapsed "$t2" "$t3")
  read -r nref nsame nloose nbad _ <<< "$(compare "$ref" "$got")"
  verdict=PASS
  if [ $rc -ne 0 ] || [ "${nbad:-1}" != 0 ] || [ "${nref:-0}" -lt 10 ]; then
    verdict=FAIL
    fail=1
  fi
  rows+=("$(printf '%-15s %7ss %-30s %-10s %8ss %5s %7s %7s %5s  %s' "$scene" "$whole" \
    "${kills[*]}" "${resume_rcs[*]}" "$final" "$nref" "$nsame" "$nloose" "$nbad" "$verdict")")
done

echo
echo "resume acceptance (KILL_SEED=${KILL_SEED:-17}, run seed $run_seed): SIGKILL three times, resume, compare"
printf '%-15s %8s %-30s %-10s %9s %5s %7s %7s %5s  %s\n' scene whole "kills (after start)" \
  "kill rcs" "last run" files "cmp=" "timing" diff result
for r in "${rows[@]}"; do echo "$r"; done
echo "(files: of the uninterrupted run's folder, checkpoint/ aside; cmp=: byte-identical;"
echo " timing: equal once wall-clock timing keys/tables are removed; diff: missing or different,"
echo " listed in $out/<scene>/run.cmp)"
[ $fail -eq 0 ] && echo "PASS" || echo "FAIL"
exit $fail
