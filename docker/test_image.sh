#!/usr/bin/env bash
# Builds the CGView image with podman and checks it: the server starts from the
# image's own entry point as its non-root user, answers the health route, takes
# an upload, runs a job and renders.  Needs root; installs podman and
# debootstrap when they are missing.  No Docker engine is needed: the base image
# is made locally with debootstrap, the build runs with chroot isolation, and
# the server runs by chroot in the mounted image (where `podman run` cannot).
#
#   docker/test_image.sh            build (ccache in ~/.cache/cgview-ccache) and test
#   CGVIEW_IMAGE=cgview:dev docker/test_image.sh
#
# Takes long the first time: debootstrap, apt, npm and the whole C++ build.
set -euo pipefail
cd "$(dirname "$0")/.."

IMAGE=${CGVIEW_IMAGE:-localhost/cgview:test}
BASE=docker.io/library/debian:bookworm
MIRROR=${CGVIEW_DEBIAN_MIRROR:-http://deb.debian.org/debian}
CCACHE=${CGVIEW_CCACHE:-$HOME/.cache/cgview-ccache}

say() { printf '==> %s\n' "$*"; }
die() { printf 'test_image.sh: error: %s\n' "$*" >&2; exit 1; }
[ "$(id -u)" -eq 0 ] || die "run as root (debootstrap, podman image mount and chroot need it)"

missing=()
for t in podman debootstrap curl; do command -v "$t" >/dev/null || missing+=("$t"); done
if [ ${#missing[@]} -gt 0 ]; then
  say "Installing ${missing[*]}"
  DEBIAN_FRONTEND=noninteractive apt-get update -q
  DEBIAN_FRONTEND=noninteractive apt-get install -y -q --no-install-recommends "${missing[@]}"
fi

work=$(mktemp -d /tmp/cgview-image-XXXXXX)
server_pid=
cleanup() {
  if [ -n "$server_pid" ]; then kill "$server_pid" 2>/dev/null || true; wait "$server_pid" 2>/dev/null || true; fi
  podman image unmount "$IMAGE" >/dev/null 2>&1 || true
  rm -rf "$work"
}
trap cleanup EXIT

if ! podman image exists "$BASE"; then
  say "Making the base image $BASE with debootstrap ($MIRROR)"
  debootstrap --variant=minbase bookworm "$work/rootfs" "$MIRROR" >"$work/debootstrap.log" 2>&1 \
    || { tail -20 "$work/debootstrap.log"; die "debootstrap failed"; }
  tar -C "$work/rootfs" -c . | podman import - "$BASE" >/dev/null
  rm -rf "$work/rootfs"
fi

say "Building $IMAGE (docker/Dockerfile)"
mkdir -p "$CCACHE"
start=$SECONDS
volumes=(-v "$CCACHE:/ccache")
# This machine's own certificate authorities (a proxy's), for apt and npm in the build.
cas=/usr/local/share/ca-certificates
compgen -G "$cas/*.crt" >/dev/null && volumes+=(-v "$cas:$cas:ro")
podman build --isolation=chroot --format docker "${volumes[@]}" -f docker/Dockerfile -t "$IMAGE" .
say "Built in $((SECONDS - start)) s"

inspect() { podman image inspect --format "$1" "$IMAGE"; }
[ "$(inspect '{{.Config.User}}')" = cgview ] || die "the image does not run as the user cgview"
inspect '{{json .Config.Volumes}}' | grep -q '"/var/lib/cgview"' || die "/var/lib/cgview is not a volume"
inspect '{{json .Config.Healthcheck}}' | grep -q '/api/v1/health' || die "the image has no health check"

root=$(podman image mount "$IMAGE")
uid=$(awk -F: '$1 == "cgview" {print $3}' "$root/etc/passwd")
[ -n "$uid" ] && [ "$uid" -ne 0 ] || die "no non-root user cgview in the image"
mkdir -p "$work/data"
chown "$uid:$uid" "$work/data"
# A user and its token, made by the image's own program in the data volume:
# the server listens on every address in the image, so it wants a token.
token=$(unshare --mount --propagation private sh -c '
  root=$1 data=$2 uid=$3; shift 3
  mount --bind "$data" "$root/var/lib/cgview" && exec chroot --userspec="$uid:$uid" "$root" "$@"' \
  sh "$root" "$work/data" "$uid" "$(inspect '{{index .Config.Entrypoint 0}}')" --data-dir /var/lib/cgview user add tester) \
  || die "cgview-server user add failed in the image"
auth=(-H "Authorization: Bearer $token")
port=$(python3 -c 'import socket; s = socket.socket(); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1])')
# The image's own entry point (a later --port wins), as its user, in a mount
# namespace of its own: /proc, /dev, a /tmp and the data volume over the
# read-only image, gone when the server stops.
mapfile -t entry < <(inspect '{{range .Config.Entrypoint}}{{println .}}{{end}}' | sed '/^$/d')
say "Starting ${entry[*]} --port $port in the image, as uid $uid"
unshare --mount --propagation private sh -c '
  root=$1 data=$2 uid=$3; shift 3
  mount -t proc proc "$root/proc" && mount --rbind /dev "$root/dev" && mount -t tmpfs tmpfs "$root/tmp" \
    && mount --bind "$data" "$root/var/lib/cgview" \
    && exec chroot --userspec="$uid:$uid" "$root" "$@"' \
  sh "$root" "$work/data" "$uid" "${entry[@]}" --port "$port" --samples none >"$work/server.log" 2>&1 &
server_pid=$!

url=http://127.0.0.1:$port/api/v1
for _ in $(seq 300); do
  curl -fsS "${auth[@]}" "$url/health" >/dev/null 2>&1 && break
  kill -0 "$server_pid" 2>/dev/null || { cat "$work/server.log"; die "the server exited"; }
  sleep 0.2
done
[ "$(curl -sS -o /dev/null -w '%{http_code}' "$url/meshes")" = 401 ] || die "a request without a token was not refused"
health=$(curl -fsS "${auth[@]}" "$url/health") || { cat "$work/server.log"; die "no answer from $url/health"; }
echo "$health" | grep -q '"status":"ok"' || die "health: $health"
say "health: $health"
# The health check's command, run in the image (its curl) against this port.
chroot "$root" curl -sS -o /dev/null "$url/health" || die "the image's curl cannot reach the health route"
# unshare, sh and chroot each exec the next: $server_pid is the server.
grep -q "^Uid:[[:space:]]*$uid[[:space:]]" "/proc/$server_pid/status" || die "the server does not run as uid $uid"

mesh=$(curl -fsS "${auth[@]}" -X POST --data-binary @"$root/opt/cgview/samples/elephant.off" "$url/meshes?name=elephant.off") \
  || die "the upload failed"
id=$(echo "$mesh" | python3 -c 'import json, sys; print(json.load(sys.stdin)["id"])')
say "uploaded elephant.off as $id"
curl -fsS "${auth[@]}" "$url/meshes" | grep -q "\"$id\"" || die "the mesh is not listed"
ls "$work/data" | grep -q . || die "nothing was written to the data volume"
job=$(curl -fsS "${auth[@]}" -X POST -d "{\"algorithm\":\"centroid_distance\",\"inputs\":{\"mesh\":\"$id\"}}" "$url/jobs" \
  | python3 -c 'import json, sys; print(json.load(sys.stdin)["id"])') || die "the job was refused"
state=
for _ in $(seq 300); do
  state=$(curl -fsS "${auth[@]}" "$url/jobs/$job" | python3 -c 'import json, sys; print(json.load(sys.stdin)["state"])')
  case $state in done|failed|cancelled|interrupted) break ;; esac
  sleep 0.2
done
[ "$state" = done ] || { cat "$work/server.log"; die "the job ended $state"; }
say "job $job done (cgview-worker runs in the image)"
curl -fsS "${auth[@]}" -o "$work/render.png" "$url/meshes/$id/render.png?width=64&height=48&field=distance" \
  || { cat "$work/server.log"; die "render.png failed"; }
[ "$(head -c 8 "$work/render.png" | od -An -tx1 | tr -d ' ')" = 89504e470d0a1a0a ] || die "render.png is not a PNG"
say "render.png: $(stat -c %s "$work/render.png") bytes"
say "image $IMAGE: $(inspect '{{.Size}}' | awk '{printf "%.0f MB", $1 / 1e6}'); all checks passed"
