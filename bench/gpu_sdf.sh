#!/usr/bin/env bash
# The SDF's rays on a GPU (rays/gpu_ray_caster.h): the GPU caster's tests
# and bench/sdf_gpu_bench, on a machine with a GPU that has none of this
# project's build (the device machines lent to some sessions: Ubuntu, an
# NVIDIA driver reached through glvnd's libEGL, no network).
#
# Here, after building (sdf_gpu_bench, sdf_bench, rays_test, sdf_test):
#   bench/gpu_sdf.sh pack
# packs build/gpu_sdf.tar.xz: the four binaries, the Debian libraries
# they link or open when first needed (Embree and glvnd's libEGL among them;
# not glibc, which the machine has), and the sample meshes.
# There, from the repository root with build/gpu_sdf.tar.xz carried:
#   bench/gpu_sdf.sh run [sdf_gpu_bench options for the big mesh]
# runs the GPU caster's tests, the bench on three sample meshes (CGAL
# measured beside), sdf_fast at 10% against the full sdf, with its steps'
# times, on the ten sample meshes of 20k faces or more (on the machine's
# cores, the rays where the automatic choice puts them, then on Embree
# alone: a lab server of as many cores without a GPU), then on the
# 1.42M-triangle mesh with CGAL's
# time given, and last sdf_fast against the full sdf on it, both ways
# (--cgal-seconds big=461.0 by default: measured on this project's 2-core
# build machine, docs/BENCHMARKS.md; CGAL alone would take most of a short
# lease).  NVIDIA's EGL vendor file is the device machines'; set
# __EGL_VENDOR_LIBRARY_FILENAMES to another where it lives elsewhere.
set -euo pipefail
cd "$(dirname "$0")/.."
# The sample meshes of 20k faces or more, where sdf_fast is measured.
fast_meshes="polygon_mesh mannequin-devil bear bear_bis fandisk_large man diplodocus armadillo bunny00 refined_elephant"
case "${1:-}" in
  pack)
    out=build/gpu_sdf
    rm -rf "$out"
    mkdir -p "$out/bin" "$out/lib" "$out/samples"
    bins="build/bin/sdf_gpu_bench build/bin/sdf_bench build/bin/rays_test build/bin/sdf_test"
    for b in $bins; do
      cp "$b" "$out/bin/"
      strip "$out/bin/$(basename "$b")"
    done
    # The libraries the binaries open when first needed (Embree, libEGL),
    # named in them as sonames, which ldd does not list, with their own.
    opened=""
    for soname in $(strings $bins | grep -E '^lib(embree|EGL)[^ /]*\.so(\.[0-9]+)*$' | sort -u); do
      opened="$opened $(ldconfig -p | awk -v s="$soname" '$1 == s && /x86-64/ {print $NF; exit}')"
    done
    # Without them the run on the device machine fails after its start:
    # said here instead, where it costs nothing.
    for want in libembree libEGL; do
      case "$opened" in
        *"/$want"*) ;;
        *) echo "gpu_sdf.sh: no $want soname found in $bins (core/shared_library.h)" >&2; exit 1 ;;
      esac
    done
    for lib in $( (ldd $bins $opened | awk '/=> \//{print $3}'; printf '%s\n' $opened) | sort -u); do
      case "$(basename "$lib")" in
        libc.so* | libm.so* | libdl.so* | libpthread.so* | librt.so* | ld-linux*) continue ;;
      esac
      cp -L "$lib" "$out/lib/"
    done
    for m in elephant $fast_meshes; do cp "build/samples/$m.off" "$out/samples/"; done
    tar -C build -cJf build/gpu_sdf.tar.xz gpu_sdf
    rm -rf "$out"
    ls -l build/gpu_sdf.tar.xz
    ;;
  run)
    shift
    big_options=("$@")
    [ ${#big_options[@]} -eq 0 ] && big_options=(--cgal-seconds big=461.0)
    dir=$(mktemp -d)
    tar -C "$dir" -xJf build/gpu_sdf.tar.xz
    g=$dir/gpu_sdf
    export LD_LIBRARY_PATH="$g/lib:/usr/local/nvidia/lib64:/usr/local/nvidia/lib:${LD_LIBRARY_PATH:-}"
    export __EGL_VENDOR_LIBRARY_FILENAMES="${__EGL_VENDOR_LIBRARY_FILENAMES:-/usr/local/nvidia/share/glvnd/egl_vendor.d/10_nvidia.json}"
    export CGVIEW_SAMPLES="$g/samples"
    nvidia-smi -L || true
    echo "cores: $(nproc)"
    "$g/bin/rays_test"
    "$g/bin/sdf_test" --gtest_filter='SdfRaysGpu.*'
    "$g/bin/sdf_gpu_bench" --repeat 3 --only elephant,armadillo,refined_elephant
    "$g/bin/sdf_bench" --fast-only --steps --repeat 3 --only "$(echo $fast_meshes | tr ' ' ,)"
    CGVIEW_SDF_RAYS=cpu "$g/bin/sdf_bench" --fast-only --steps --repeat 3 --only "$(echo $fast_meshes | tr ' ' ,)"
    "$g/bin/sdf_gpu_bench" --repeat 1 --only big "${big_options[@]}"
    # The 1.42M-face mesh is one of 20k faces or more too: sdf_fast on it,
    # both ways, last (the measurements above matter more if time runs out).
    "$g/bin/sdf_bench" --fast-only --steps --repeat 1 --only big
    CGVIEW_SDF_RAYS=cpu "$g/bin/sdf_bench" --fast-only --steps --repeat 1 --only big
    ;;
  *)
    echo "usage: $0 pack | run [sdf_gpu_bench options for the big mesh]" >&2
    exit 2
    ;;
esac
