#!/usr/bin/env bash
# Builds OpenMoPAD with GCC's sanitizers and runs tests under them (docs/reliability.md,
# "Sanitizers"):
#   scripts/sanitize.sh [asan|tsan|all]          (default: all, asan then tsan)
#   asan  build-asan/, -DMOPAD_SANITIZE=address: AddressSanitizer with LeakSanitizer and
#         UndefinedBehaviorSanitizer (cmake/Sanitizers.cmake); runs the whole default suite
#         (ctest -LE long).
#   tsan  build-tsan/, -DMOPAD_SANITIZE=thread: ThreadSanitizer; runs the tests labelled
#         `threaded` (ctest -L threaded): the TLS simulation (mopad_sim_tests), the TBB loops of
#         perception, modelling, autonomy and evaluation, and the suite runner.
# Both are built at -O1 -g -DNDEBUG (RelWithDebInfo with -O1): the code paths of the Release
# binary (NDEBUG, Eigen's own asserts off), optimised enough to run the suite in minutes, and
# -O1 keeps the stack traces of the reports exact (no inlining across most calls). Each
# sanitizer writes its reports to BUILD/sanitizer-logs/ (log_path), from every process a test
# starts as well (the `mopad` a CLI test runs, forked children); one line per mode sums up:
# tests run, passed, failed, and reports. Exit status 1 when any test fails or any report was
# written. Suppressions (each justified there): scripts/lsan.supp, scripts/tsan.supp.
# Not part of the default build or of scripts/test.sh. Run it niced on a shared machine:
#   nice -n 10 scripts/sanitize.sh asan
# MOPAD_SANITIZE_JOBS=N builds and tests with N jobs (default: nproc).
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
mode="${1:-all}"
case "$mode" in
  asan) modes=(asan) ;;
  tsan) modes=(tsan) ;;
  all) modes=(asan tsan) ;;
  *)
    echo "usage: scripts/sanitize.sh [asan|tsan|all]; got '$mode'" >&2
    exit 2
    ;;
esac
jobs="${MOPAD_SANITIZE_JOBS:-$(nproc)}"
# A test runs 2-5x slower under ASan and 5-15x under TSan than in Release, where the longest
# takes about a minute: every test gets 25 minutes.
timeout=1500
generator=()
command -v ninja >/dev/null && generator=(-G Ninja)

# BuildTsanTbb BUILD: oneTBB instrumented with ThreadSanitizer in BUILD/_tbb. Debian's libtbb is
# not instrumented: TSan sees neither the hand-over of a task to a worker thread nor its
# completion, and reports every TBB loop as a race on its own data (and the scheduler's task
# objects as races with themselves). Suppressing those would hide a real race in any TBB loop
# body too, since every such report passes through TBB's frames. So the tsan build links the
# same oneTBB, Debian's own source of the installed libtbb-dev version (apt-get source, with a
# deb-src list of its own in BUILD/_apt; nothing on the system changes), built with the
# project's TBB_SANITIZE=thread option.
BuildTsanTbb() {
  local bf="$1" pkg ver apt src
  [[ -f "$bf/_tbb/done" ]] && return 0
  pkg=$(dpkg-query -W -f='${source:Package}' libtbb-dev)
  ver=$(dpkg-query -W -f='${source:Version}' libtbb-dev)
  apt="$bf/_apt"
  rm -rf "$apt" "$bf/_tbb" "$bf/_tbb-build"
  mkdir -p "$apt/parts" "$apt/lists/partial" "$apt/cache/archives/partial" "$apt/src"
  local suites="bookworm bookworm-updates"
  cat >"$apt/parts/src.sources" <<EOS
Types: deb-src
URIs: http://deb.debian.org/debian
Suites: $suites
Components: main
Signed-By: /usr/share/keyrings/debian-archive-keyring.gpg

Types: deb-src
URIs: http://deb.debian.org/debian-security
Suites: bookworm-security
Components: main
Signed-By: /usr/share/keyrings/debian-archive-keyring.gpg
EOS
  local o=(-o Dir::Etc::SourceParts="$apt/parts" -o Dir::Etc::SourceList=/dev/null
           -o Dir::State::Lists="$apt/lists" -o Dir::Cache="$apt/cache")
  # Each step writes to BUILD/_tbb.log; a failure names the step and shows the log's end.
  local log="$bf/_tbb.log"
  : >"$log"
  Step() {
    local what="$1"
    shift
    if ! "$@" >>"$log" 2>&1; then
      echo "sanitize.sh: tsan: $what failed ($*); the end of $log:" >&2
      tail -n 20 "$log" >&2
      return 1
    fi
  }
  Step "apt-get update of the deb-src list (deb.debian.org)" apt-get "${o[@]}" update
  (cd "$apt/src" &&
    Step "apt-get source $pkg=$ver" apt-get "${o[@]}" source --download-only "$pkg=$ver")
  src="$apt/src/tbb"
  # apt has checked the files against the signed Release file; dpkg-source's warning that it
  # cannot verify the .dsc's own signature (no Debian developer keyring here) is expected.
  Step "unpacking the source" dpkg-source -x "$apt/src/${pkg}_${ver#*:}.dsc" "$src"
  Step "configuring oneTBB" cmake -S "$src" -B "$bf/_tbb-build" "${generator[@]}" \
    -DCMAKE_BUILD_TYPE=RelWithDebInfo -DTBB_SANITIZE=thread -DTBB_TEST=OFF -DTBB_STRICT=OFF \
    -DTBBMALLOC_BUILD=OFF -DCMAKE_INSTALL_PREFIX="$bf/_tbb" -DCMAKE_INSTALL_LIBDIR=lib
  Step "building oneTBB" cmake --build "$bf/_tbb-build" -j"$jobs"
  Step "installing oneTBB" cmake --install "$bf/_tbb-build"
  touch "$bf/_tbb/done"
}

summaries=()
status=0
for m in "${modes[@]}"; do
  start=$(date +%s)
  bf="$root/build-$m"
  logs="$bf/sanitizer-logs"
  if [[ $m == asan ]]; then
    sanitize=address
    selection=(-LE long)
    # halt_on_error: the first report ends the process with a failure (ASan always does; UBSan
    # does because of -fno-sanitize-recover). detect_leaks: LeakSanitizer at every exit.
    export ASAN_OPTIONS="detect_leaks=1:halt_on_error=1:check_initialization_order=1:strict_init_order=1:log_path=$logs/asan"
    export LSAN_OPTIONS="suppressions=$root/scripts/lsan.supp:print_suppressions=0"
    # UBSan linked with ASan (GCC 12) writes its reports to stderr whatever log_path says; with
    # -fno-sanitize-recover each one ends its process with a failure, so its test fails and
    # ctest prints the report: the summary counts the "runtime error:" lines of the ctest log.
    export UBSAN_OPTIONS="halt_on_error=1:print_stacktrace=1:log_path=$logs/ubsan"
  else
    sanitize=thread
    selection=(-L threaded)
    # Every report, not only the first: a process goes on and exits 66 at its end, so the test
    # fails and one run lists all the races. ignore_noninstrumented_modules: the interceptors
    # (malloc, free, mutexes) called from a library that is not instrumented (Debian's Embree,
    # OpenCV, GDAL) do not count as accesses: TSan cannot see those libraries' own
    # synchronisation, so their allocations and locks would only give false reports; every access
    # of our code and of the instrumented oneTBB still counts (scripts/tsan.supp).
    export TSAN_OPTIONS="halt_on_error=0:exitcode=66:second_deadlock_stack=1:ignore_noninstrumented_modules=1:suppressions=$root/scripts/tsan.supp:print_suppressions=0:log_path=$logs/tsan"
  fi
  rm -rf "$logs"
  mkdir -p "$logs"
  extra=()
  if [[ $m == tsan ]]; then
    BuildTsanTbb "$bf"
    extra=(-DTBB_DIR="$bf/_tbb/lib/cmake/TBB")
    # Embree and OpenCV load libtbb.so.12 too: the instrumented one, so that one scheduler runs.
    export LD_LIBRARY_PATH="$bf/_tbb/lib${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}"
  fi
  if [[ ! -f "$bf/CMakeCache.txt" ]]; then
    cmake -S "$root" -B "$bf" "${generator[@]}" -DCMAKE_BUILD_TYPE=RelWithDebInfo \
      -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -g -DNDEBUG" -DMOPAD_SANITIZE=$sanitize \
      -DMOPAD_TEST_TIMEOUT=$timeout "${extra[@]}" >/dev/null
  fi
  # The build runs each test binary once to list its tests (gtest_discover_tests), under the
  # sanitizer options above: a report there counts as well.
  if [[ $m == asan ]]; then
    cmake --build "$bf" -j"$jobs"
  else
    cmake --build "$bf" -j"$jobs" --target mopad_threaded_tests
  fi
  # The npm oracles (glTF validator, web-ifc, copc) of the Release build, so the tests that use
  # them run here too instead of skipping.
  if [[ -d "$root/build/_npm" && ! -e "$bf/_npm" ]]; then
    ln -s "$root/build/_npm" "$bf/_npm"
  fi
  ctest_log="$bf/sanitize-ctest.log"
  set +e
  ctest --test-dir "$bf" "${selection[@]}" -j"$jobs" --timeout "$timeout" --output-on-failure \
    >"$ctest_log" 2>&1
  set -e
  tail -n 40 "$ctest_log" | sed -n '/tests passed/,$p'
  total=$(sed -nE 's/.*tests passed, ([0-9]+) tests? failed out of ([0-9]+).*/\2/p' "$ctest_log")
  failed=$(sed -nE 's/.*tests passed, ([0-9]+) tests? failed out of ([0-9]+).*/\1/p' "$ctest_log")
  total=${total:-0} failed=${failed:-0}
  shopt -s nullglob
  reports=("$logs"/*)
  shopt -u nullglob
  for r in "${reports[@]}"; do
    echo "--- $r"
    head -n 40 "$r"
  done
  ub_lines=$(grep -c ': runtime error: ' "$ctest_log" || true)
  if (( ub_lines > 0 )); then
    echo "--- UBSan reports in $ctest_log:"
    grep -A 3 ': runtime error: ' "$ctest_log" | head -n 40
  fi
  minutes=$(( ($(date +%s) - start + 30) / 60 ))
  summaries+=("sanitize.sh: $m: $total tests run, $((total - failed)) passed, $failed failed; $(( ${#reports[@]} + ub_lines )) sanitizer reports ($logs, $ctest_log); $minutes min")
  if (( total == 0 || failed > 0 || ${#reports[@]} + ub_lines > 0 )); then
    status=1
  fi
done
printf '%s\n' "${summaries[@]}"
exit $status
