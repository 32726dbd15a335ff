#!/usr/bin/env bash
# Builds the fuzz targets (clang, libFuzzer, ASan, UBSan) into BUILD/fuzz and
# runs them.
#
#   tests/fuzz/run.sh --build                   builds the targets only (the build's cgview_fuzz_targets)
#   tests/fuzz/run.sh --ci [TARGET...]          each target 20 s on the committed corpus
#                                               (what ctest runs, fuzz.TARGET one a target, side by
#                                               side: a parser regression fails it)
#   tests/fuzz/run.sh --campaign S [TARGET...]  each target S seconds on CGVIEW_JOBS cores (default: all),
#                                               growing BUILD/fuzz/corpus/TARGET from the seeds
#   tests/fuzz/run.sh --campaign-cpu M [TARGET...]
#                                               each target until it has had M CPU-minutes, in runs
#                                               that go on from the corpus the last one grew
#
# A finding (crash, leak, sanitizer report, timeout over 10 s, more than
# 2 GB) is written to BUILD/fuzz/findings/TARGET/ and fails the run.  Keep it
# as a regression case: copy it into corpus/TARGET/ and a normal test.
# CGVIEW_BUILD_DIR as in setup.sh (default: build/).
set -euo pipefail
cd "$(dirname "$0")"
HERE=$(pwd)
BUILD=${CGVIEW_BUILD_DIR:-$HERE/../../build}/fuzz
MODE=${1:-}
case "$MODE" in
  --build) ;;
  --ci) SECONDS_EACH=${CGVIEW_FUZZ_SECONDS:-20}; shift ;;
  --campaign) SECONDS_EACH=${2:?--campaign needs seconds}; shift 2 ;;
  --campaign-cpu) CPU_MINUTES=${2:?--campaign-cpu needs minutes}; MODE=--campaign; shift 2 ;;
  *) sed -n '2,17p' "$0" | sed 's/^# \{0,1\}//'; exit 2 ;;
esac
command -v clang++ >/dev/null || { echo "run.sh: clang++ is missing (Debian: clang, libfuzzer-14-dev)" >&2; exit 1; }
mkdir -p "$BUILD"
if [ ! -f "$BUILD/build.ninja" ]; then
  CXX=clang++ cmake -S "$HERE" -B "$BUILD" -G Ninja -DCMAKE_BUILD_TYPE=None -DCMAKE_CXX_COMPILER_LAUNCHER=ccache >/dev/null
fi
JOBS=${CGVIEW_JOBS:-$(nproc)}
# ctest's fuzz.TARGET tests run side by side after the build (cgview_fuzz_targets), which built
# them once: CGVIEW_FUZZ_BUILT=1 keeps them from running ninja at the same time.
[ "${CGVIEW_FUZZ_BUILT:-0}" = 1 ] || cmake --build "$BUILD" -j "$JOBS"
[ "$MODE" != --build ] || exit 0
TARGETS=("$@")
[ ${#TARGETS[@]} -gt 0 ] || TARGETS=(off obj ply stl xyz gltf glb drc mtl skeleton voxel zip frame json params config ws)
failed=()
# One run of target $1 for $2 seconds: adds its CPU seconds to spent and its
# inputs to runs, and sets last (its final status line) and log; fails as the target did.
run_once() {
  local t=$1 work="$BUILD/corpus/$1"
  mkdir -p "$work" "$BUILD/findings/$t"
  # The committed seeds stay as they are; what the fuzzer finds goes to work.
  local args=(-max_total_time="$2" -timeout=10 -rss_limit_mb=2048 -malloc_limit_mb=2048 -max_len=65536
              -artifact_prefix="$BUILD/findings/$t/" -print_final_stats=1)
  [ -f "dict/$t.dict" ] && args+=(-dict="dict/$t.dict")
  # Fork mode counts out-of-memory inputs and timeouts without stopping; they are findings too.
  if [ "$MODE" = --campaign ]; then args+=(-fork="$JOBS" -ignore_crashes=0 -ignore_ooms=0 -ignore_timeouts=0); fi
  log="$BUILD/findings/$t.log"
  # /usr/bin/time counts the CPU of fork mode's children too: a campaign's
  # size is its CPU time, which the wall clock overstates on a busy machine.
  local cpu="$BUILD/findings/$t.cpu" rc=0
  /usr/bin/time -f '%U %S' -o "$cpu" "$BUILD/fuzz_$t" "${args[@]}" "$work" "corpus/$t" >"$log" 2>&1 || rc=$?
  # (After a failing run, time's file starts with a line of words, which add 0.)
  spent=$(awk -v s="$spent" '{s += $1 + $2} END {printf "%.0f", s}' "$cpu" 2>/dev/null || echo "$spent")
  # (-a: a log may hold bytes of an input.)
  local status n
  status=$(grep -aE '^#[0-9]+' "$log" | tail -1 || true)
  n=$(sed -nE 's/^#([0-9]+).*/\1/p' <<<"$status")
  runs=$((runs + ${n:-0}))
  last=$(sed -E 's/^#[0-9]+:?[[:space:]]*(DONE[[:space:]]*)?//' <<<"$status")
  return $rc
}
for t in "${TARGETS[@]}"; do
  spent=0 runs=0 chunks=0 found=0
  if [ -n "${CPU_MINUTES:-}" ]; then
    # A wall-clock time that gives what is left on an idle machine, and more
    # runs while other work took a share of the cores.
    while awk -v s="$spent" -v m="$CPU_MINUTES" 'BEGIN{exit !(s < m * 60)}'; do
      secs=$(awk -v s="$spent" -v m="$CPU_MINUTES" -v j="$JOBS" 'BEGIN{w = (m * 60 - s) / j * 1.05; printf "%d", w < 10 ? 10 : w}')
      chunks=$((chunks + 1))
      run_once "$t" "$secs" || { found=1; break; }
    done
  else
    chunks=1
    run_once "$t" "$SECONDS_EACH" || found=1
  fi
  if [ $found = 0 ]; then
    echo "fuzz_$t: $runs inputs in $chunks run(s), $(awk -v s="$spent" 'BEGIN{printf "%.1f", s/60}') CPU-min; at the end: $last"
  else
    echo "fuzz_$t: FINDING (log: $log)"; grep -E 'ERROR|SUMMARY|Test unit written' "$log" | head -5
    failed+=("$t")
  fi
done
if [ ${#failed[@]} -gt 0 ]; then echo "run.sh: findings in ${failed[*]}" >&2; exit 1; fi
