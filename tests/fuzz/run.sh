#!/usr/bin/env bash
# Builds the fuzz targets (clang, libFuzzer, ASan, UBSan) into BUILD/fuzz and
# runs them.
#
#   tests/fuzz/run.sh --ci [TARGET...]          each target 20 s on the committed corpus
#                                               (what ctest runs: a parser regression fails it)
#   tests/fuzz/run.sh --campaign S [TARGET...]  each target S seconds on CGVIEW_JOBS cores (default: all),
#                                               growing BUILD/fuzz/corpus/TARGET from the seeds
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
  --ci) SECONDS_EACH=${CGVIEW_FUZZ_SECONDS:-20}; shift ;;
  --campaign) SECONDS_EACH=${2:?--campaign needs seconds}; shift 2 ;;
  *) sed -n '2,14p' "$0" | sed 's/^# \{0,1\}//'; exit 2 ;;
esac
command -v clang++ >/dev/null || { echo "run.sh: clang++ is missing (Debian: clang, libfuzzer-14-dev)" >&2; exit 1; }
mkdir -p "$BUILD"
if [ ! -f "$BUILD/build.ninja" ]; then
  CXX=clang++ cmake -S "$HERE" -B "$BUILD" -G Ninja -DCMAKE_BUILD_TYPE=None -DCMAKE_CXX_COMPILER_LAUNCHER=ccache >/dev/null
fi
cmake --build "$BUILD" -j "${CGVIEW_JOBS:-$(nproc)}"
TARGETS=("$@")
[ ${#TARGETS[@]} -gt 0 ] || TARGETS=(off obj ply stl gltf glb drc mtl skeleton voxel zip frame json params config ws)
failed=()
for t in "${TARGETS[@]}"; do
  work="$BUILD/corpus/$t"
  mkdir -p "$work" "$BUILD/findings/$t"
  # The committed seeds stay as they are; what the fuzzer finds goes to work.
  args=(-max_total_time="$SECONDS_EACH" -timeout=10 -rss_limit_mb=2048 -malloc_limit_mb=2048 -max_len=65536
        -artifact_prefix="$BUILD/findings/$t/" -print_final_stats=1)
  [ -f "dict/$t.dict" ] && args+=(-dict="dict/$t.dict")
  # Fork mode counts out-of-memory inputs and timeouts without stopping; they are findings too.
  if [ "$MODE" = --campaign ]; then args+=(-fork="${CGVIEW_JOBS:-$(nproc)}" -ignore_crashes=0 -ignore_ooms=0 -ignore_timeouts=0); fi
  log="$BUILD/findings/$t.log"
  # /usr/bin/time counts the CPU of fork mode's children too: a campaign's
  # size is its CPU time, which the wall clock overstates on a busy machine.
  cpu="$BUILD/findings/$t.cpu"
  if /usr/bin/time -f '%U %S' -o "$cpu" "$BUILD/fuzz_$t" "${args[@]}" "$work" "corpus/$t" >"$log" 2>&1; then
    echo "fuzz_$t: $(grep -E '^#[0-9]+' "$log" | tail -1 | sed 's/^#/runs /'); $(awk '{printf "%.1f CPU-min", ($1+$2)/60}' "$cpu")"
  else
    echo "fuzz_$t: FINDING (log: $log)"; grep -E 'ERROR|SUMMARY|Test unit written' "$log" | head -5
    failed+=("$t")
  fi
done
if [ ${#failed[@]} -gt 0 ]; then echo "run.sh: findings in ${failed[*]}" >&2; exit 1; fi
