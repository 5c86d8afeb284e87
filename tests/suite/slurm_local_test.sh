#!/usr/bin/env bash
# `mopad suite slurm ... --submit` on a real single-node Slurm (scripts/slurm-local.sh), ctest
# label `slurm`. Exit 77 (ctest skip) when Slurm is not installed or cannot start here.
#   1. mechanics: submit.sh with a stand-in mopad that records each shard's and the merge's
#      arguments: every array task ran its own shard, and the merge ran after all of them;
#   2. a real two-case suite (one_room.yaml, seeds 1 and 2, two shards): the merge job leaves
#      DIR/suite.json with both cases. Skipped (with a note) by a mopad without `suite run`.
# Usage: slurm_local_test.sh MOPAD_BINARY SOURCE_DIR
set -euo pipefail
mopad="$(readlink -f "$1")"
src="$(readlink -f "$2")"
readonly kWaitS=840  # s: the longest wait for a merge job (ctest's TIMEOUT is 900 s)

work="$(mktemp -d "${TMPDIR:-/tmp}/mopad-slurm-test.XXXXXX")"
chmod 755 "$work"  # munged (user munge) reaches its socket folder below
cleanup() {
  "$src/scripts/slurm-local.sh" stop "$work/slurm" 2>/dev/null || true
  rm -rf "$work"
}
trap cleanup EXIT

rc=0
conf="$("$src/scripts/slurm-local.sh" start "$work/slurm")" || rc=$?
if ((rc == 4)); then
  echo "SKIP: no local Slurm here (scripts/slurm-local.sh start exit 4)"
  exit 77
fi
((rc == 0)) || { echo "FAIL: scripts/slurm-local.sh start exit $rc"; exit 1; }
eval "$conf"  # export SLURM_CONF=...

# The merge job id in `mopad suite slurm --submit`'s output; waits until it has ended and prints
# its state (COMPLETED, FAILED, CANCELLED, ...).
wait_for_merge() {
  local out="$1" id state="" i
  id="$(sed -n 's/^merge job \([0-9]*\).*/\1/p' <<< "$out")"
  [[ -n "$id" ]] || { echo "FAIL: no merge job id in: $out" >&2; return 1; }
  for ((i = 0; i < kWaitS * 2; ++i)); do
    state="$(scontrol show job -o "$id" 2>/dev/null | sed -n 's/.*JobState=\([A-Z_]*\).*/\1/p')"
    case "$state" in
      PENDING | RUNNING | CONFIGURING | COMPLETING | "") sleep 0.5 ;;
      *) break ;;
    esac
  done
  echo "$state"
}

# 1. Mechanics, with a stand-in mopad.
fake="$work/fake-mopad"
cat > "$fake" <<'EOF'
#!/usr/bin/env bash
# `suite run SUITE -o DIR --shard I/N ...` and `suite merge DIRS... -o OUT`, recorded.
log="$(dirname "$0")/calls.log"
case "$2" in
  run) mkdir -p "$5"; echo "$(date +%s.%N) run $7 $5" >> "$log" ;;
  merge) echo "$(date +%s.%N) merge ${*:3}" >> "$log" ;;
esac
EOF
chmod +x "$fake"
echo "suite: mechanics" > "$work/mechanics.yaml"
out="$("$mopad" suite slurm "$work/mechanics.yaml" -o "$work/M" --shards 4 --throttle 2 \
  --mopad "$fake" --submit)"
echo "$out"
state="$(wait_for_merge "$out")"
echo "merge job: $state"
cat "$work/calls.log"
[[ "$state" == COMPLETED ]] || { echo "FAIL: merge job $state"; exit 1; }
runs="$(grep -c ' run ' "$work/calls.log")"
[[ "$runs" == 4 ]] || { echo "FAIL: $runs shard tasks ran, expected 4"; exit 1; }
for i in 0 1 2 3; do
  grep -q " run $((i + 1))/4 $work/M/shards/$i\$" "$work/calls.log" ||
    { echo "FAIL: shard $((i + 1))/4 did not run into shards/$i"; exit 1; }
  ls "$work/M/logs/"*_"$i".out > /dev/null || { echo "FAIL: no log of task $i"; exit 1; }
done
shards="$work/M/shards/0 $work/M/shards/1 $work/M/shards/2 $work/M/shards/3"
tail -n 1 "$work/calls.log" | grep -q " merge $shards -o $work/M\$" ||
  { echo "FAIL: the merge did not run last over all shards"; exit 1; }
echo "PASS: mechanics (4 shards, throttle 2, merge after them)"
echo "jobcomp.log (Slurm's record of the finished jobs):"
cat "$work/slurm/jobcomp.log"

# 2. A real two-case suite.
if ! "$mopad" suite --help 2>&1 | grep -qE '^ +run( |$)'; then
  echo "NOTE: this mopad has no \`suite run\`; the real two-case suite is left out"
  exit 0
fi
cat > "$work/two.yaml" <<EOF
suite: slurm-two
scenes:
  - spec: $src/scenes/one_room.yaml
seeds: [1, 2]
limits: {wall_s: 600}
keep: summary
EOF
out="$("$mopad" suite slurm "$work/two.yaml" -o "$work/B" --shards 2 --submit)"
echo "$out"
state="$(wait_for_merge "$out")"
echo "merge job: $state"
squeue
cat "$work/B/logs/"*.out || true
[[ "$state" == COMPLETED ]] || { echo "FAIL: merge job $state"; exit 1; }
[[ -f "$work/B/suite.json" ]] || { echo "FAIL: no $work/B/suite.json"; exit 1; }
cases="$(grep -o '"id": *"[^"]*seed-[0-9]*"' "$work/B/suite.json" | sort -u | wc -l)"
[[ "$cases" == 2 ]] || { echo "FAIL: suite.json holds $cases cases, expected 2"; exit 1; }
echo "PASS: two-case suite through Slurm"
