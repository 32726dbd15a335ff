#!/usr/bin/env bash
# CGView set-up on Debian bookworm.  Each command is idempotent: it installs
# what is missing (Debian and npm packages), builds in Release into build/,
# then does its job.
#
#   ./setup.sh start   install, build the programs alone, and serve the viewer with the sample meshes
#                      (http://127.0.0.1:8080/; CGVIEW_PORT, CGVIEW_DATA change port and data dir)
#   ./setup.sh test    install, build, and run every test
#   ./setup.sh build   install and build only
#   ./setup.sh install install only (Debian and npm packages)
#
# CGVIEW_TESTS=0 leaves out the test tools, the tests and the benchmarks: the
# programs alone (the container image's build, docker/Dockerfile); `start`
# leaves them out unless CGVIEW_TESTS=1.
# Run as root, or as a user who may sudo (for apt-get).
set -euo pipefail

cd "$(dirname "$0")"
ROOT=$(pwd)
BUILD_DIR=${CGVIEW_BUILD_DIR:-$ROOT/build}
JOBS=${CGVIEW_JOBS:-$(nproc)}
# `start` serves: it installs and configures no test tools (a later `test` adds them).
if [ "${1:-}" = start ]; then TESTS=${CGVIEW_TESTS:-0}; else TESTS=${CGVIEW_TESTS:-1}; fi

say() { if [ -t 1 ]; then printf '\033[1m==> %s\033[0m\n' "$*"; else printf '==> %s\n' "$*"; fi; }
die() { printf 'setup.sh: error: %s\n' "$*" >&2; exit 1; }

# Debian packages: build tools, libraries, sample data; then test tools.
APT_PACKAGES=(
  build-essential cmake ninja-build ccache pkg-config git
  libboost-dev libboost-system-dev nlohmann-json3-dev libcgal-dev libeigen3-dev libgmp-dev libmpfr-dev
  libdraco-dev libtinygltf-dev
  libegl-dev libopengl-dev libgles-dev libegl-mesa0 libgl1-mesa-dri libpng-dev
  libopenvdb-dev libembree-dev
  libsqlite3-dev libssl-dev zlib1g-dev libzip-dev prometheus-cpp-dev
  libcgal-demo
  # Each job's worker and each upload's reader starts in a sandbox
  # (server/sandbox.h): bubblewrap, with util-linux's setpriv (a root
  # server's per-job user) and prlimit (its limits on Slurm nodes).
  bubblewrap util-linux
  nodejs npm
)
TEST_APT_PACKAGES=(
  draco libgtest-dev libgmock-dev
  assimp-testmodels assimp-utils
  chromium wrk
  # The fuzz targets (tests/fuzz): clang's sanitizer and libFuzzer runtimes are
  # in libclang-rt-14-dev, which clang only recommends.
  clang libfuzzer-14-dev libclang-rt-14-dev
  # A campaign's CPU time, fork mode's children included (tests/fuzz/run.sh).
  time
  python3 python3-websocket python3-prometheus-client
  openssl
  # The layout check of the C++ files (tests/style).
  clang-format
  # A real Slurm cluster for the tests (tests/slurm): munged, slurmctld and
  # slurmd run from a temporary directory, not as the system's services.
  slurm-wlm slurmctld slurmd slurm-client munge
  # The Slurm executor's batch script on a node without the data directory.
  curl
  # The Python client's arrays, Open3D and meshio interop, and its package
  # installed offline in a venv (clients/python; its build backend is the
  # standard library, no setuptools or wheel needed).
  python3-numpy python3-open3d python3-meshio python3-venv
  # The paper's figures as notebooks, run headless by the tests (clients/python/notebooks).
  python3-nbclient python3-ipykernel python3-matplotlib
)
[ "$TESTS" = 0 ] || APT_PACKAGES+=("${TEST_APT_PACKAGES[@]}")

as_root() {
  if [ "$(id -u)" -eq 0 ]; then "$@"
  elif command -v sudo >/dev/null; then sudo "$@"
  else die "installing packages needs root: run as root or install sudo"; fi
}

install_debian_packages() {
  local missing=()
  for p in "${APT_PACKAGES[@]}"; do
    # nodejs and npm may come from elsewhere (a newer Node): keep that one.
    if [ "$p" = nodejs ] && command -v node >/dev/null; then continue; fi
    if [ "$p" = npm ] && command -v npm >/dev/null; then continue; fi
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q 'install ok installed' || missing+=("$p")
  done
  if [ ${#missing[@]} -eq 0 ]; then
    say "Debian packages: all ${#APT_PACKAGES[@]} present"
    return
  fi
  say "Debian packages: installing ${missing[*]}"
  as_root env DEBIAN_FRONTEND=noninteractive apt-get update -q || die "apt-get update failed"
  as_root env DEBIAN_FRONTEND=noninteractive apt-get install -y -q --no-install-recommends "${missing[@]}" \
    || die "apt-get could not install: ${missing[*]}"
}

# Vite 8 needs Node 20.19 or newer; bookworm's nodejs is 18.  Then Node 20's
# own binary comes from the npm registry (the package node-linux-ARCH, with
# Debian's npm), into npm's global prefix, ahead of /usr/bin on the PATH.
ensure_node() {
  local version
  version=$(node -p 'const [a, b] = process.versions.node.split(".").map(Number); a * 1000 + b' 2>/dev/null || echo 0)
  [ "$version" -ge 20019 ] && return
  local arch
  case "$(dpkg --print-architecture)" in amd64) arch=x64 ;; arm64) arch=arm64 ;; *) die "no Node 20 binary for $(dpkg --print-architecture)" ;; esac
  say "Node.js $(node --version 2>/dev/null || echo 'is missing;') is too old for Vite 8: Node 20 from the npm registry"
  as_root npm install -g --no-audit --no-fund "node-linux-$arch@20" || die "npm could not install Node 20"
  as_root ln -sf "$(npm root -g)/node-linux-$arch/bin/node" "$(npm prefix -g)/bin/node"
  hash -r
}

check_tools() {
  local t
  local tools=(cmake ninja g++ ccache node npm bwrap setpriv prlimit)
  [ "$TESTS" = 0 ] || tools+=(draco_decoder assimp python3 clang++ sbatch slurmctld slurmd munged)
  for t in "${tools[@]}"; do
    # slurmctld, slurmd and munged are in /usr/sbin, which a user's PATH may lack.
    PATH="$PATH:/usr/sbin:/sbin" command -v "$t" >/dev/null || die "'$t' is missing after the install (see the apt-get output above)"
  done
  local node_major
  node_major=$(node -p 'process.versions.node.split(".")[0]')
  [ "$node_major" -ge 20 ] || die "Node.js $(node --version) is too old: Vite 8 needs Node 20.19 or newer (is $(npm prefix -g)/bin on the PATH?)"
  [ -f /usr/share/doc/libcgal-dev/data.tar.gz ] || die "CGAL's sample data is missing: the Debian package libcgal-demo did not install it"
}

install_npm_packages() {
  if [ -d "$ROOT/web-client/node_modules" ] && [ "$ROOT/web-client/node_modules/.package-lock.json" -nt "$ROOT/web-client/package-lock.json" ]; then
    say "npm packages for web-client/: present"
    return
  fi
  say "npm packages for web-client/ (npm ci)"
  (cd "$ROOT/web-client" && npm ci --no-audit --no-fund --loglevel=error) || die "npm could not install web-client's packages"
}

build_web_client() {
  # Built again only when a source of it is newer than the last build (a second start serves at once).
  local stamp="$ROOT/web-client/dist/.built"
  if [ -f "$stamp" ] && [ -z "$(find "$ROOT/web-client" \( -path "$ROOT/web-client/node_modules" -o -path "$ROOT/web-client/dist" -o -path "$ROOT/web-client/tests" \) -prune -o -type f -newer "$stamp" -print -quit)" ]; then
    say "The web client in web-client/dist: up to date"
    return
  fi
  say "Building the web client (TypeScript, Vite) into web-client/dist"
  (cd "$ROOT/web-client" && npm run --silent build) || die "the web client's build failed"
  touch "$stamp"
}

# build [TARGET]: configure, then build TARGET (all when none is given).
build() {
  local target=${1:-all}
  say "Building (Release) $target into $BUILD_DIR with $JOBS jobs"
  # Said each time: a build directory configured with CGVIEW_TESTS=0 gets its tests back.
  local tests=ON
  [ "$TESTS" != 0 ] || tests=OFF
  cmake -S "$ROOT" -B "$BUILD_DIR" -G Ninja -DCMAKE_BUILD_TYPE=Release -DCGVIEW_BUILD_TESTS=$tests -DCGVIEW_BUILD_BENCH=$tests \
    || die "cmake configure failed"
  cmake --build "$BUILD_DIR" -j "$JOBS" --target "$target" || die "the build failed"
}

install_packages() {
  install_debian_packages
  ensure_node
  check_tools
  install_npm_packages
}

# setup [TARGET]: install, then build the web client and TARGET (all when none is given).
setup() {
  install_packages
  build_web_client
  build "$@"
}

start() {
  local port=${CGVIEW_PORT:-8080} data=${CGVIEW_DATA:-$ROOT/cgview-data}
  say "Starting cgview-server with the sample meshes: open http://127.0.0.1:$port/ (Ctrl-C stops it)"
  exec "$BUILD_DIR/bin/cgview-server" --host 127.0.0.1 --port "$port" --data-dir "$data" \
    --static-dir "$ROOT/web-client/dist" --samples default
}

run_tests() {
  say "Running every test (ctest)"
  local out="$BUILD_DIR/ctest-output.txt" rc=0
  # Twice as many tests as cores: most tests wait (on a server, a cluster, a
  # browser) more than they compute; the few that keep a core busy (chromium,
  # the fuzzers) count as two (their PROCESSORS).  --timeout: what a test
  # without a limit of its own may take before it fails.
  ctest --test-dir "$BUILD_DIR" --output-on-failure --timeout 300 -j "$((JOBS * 2))" | tee "$out" || rc=$?
  # Where the suite's time goes, passed or not: the 15 slowest tests of this run.
  say "The 15 slowest tests (seconds)"
  grep -E 'Test +#[0-9]+: ' "$out" | sed -E 's/.*Test +#[0-9]+: ([^ ]+) .* ([0-9.]+) sec$/\2 \1/' |
    sort -gr | head -15 | awk '{ printf "%8.1f  %s\n", $1, $2 }' || true
  return "$rc"
}

case "${1:-}" in
  start) setup cgview_programs; start ;;
  test) setup; run_tests ;;
  build) setup ;;
  install) install_packages ;;
  -h|--help|"") sed -n '2,15p' "$0" | sed 's/^# \{0,1\}//'; [ -n "${1:-}" ] ;;
  *) die "unknown command '$1' (start, test, build or install)" ;;
esac
