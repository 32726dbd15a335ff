#!/usr/bin/env bash
# REST throughput: wrk on loopback against GET /api/v1/health and one mesh's
# report, on the real cgview-server.  Prints a Markdown table.
#   bench/http_bench.sh [seconds] [connections]
set -euo pipefail
cd "$(dirname "$0")/.."
secs=${1:-10}
conns=${2:-32}
command -v wrk >/dev/null || { echo "http_bench: wrk is missing (Debian package wrk)" >&2; exit 1; }
data=$(mktemp -d)
out=$(mktemp)
build/bin/cgview-server --port 0 --data-dir "$data" --samples default > "$out" &
pid=$!
trap 'kill $pid 2>/dev/null; wait $pid 2>/dev/null; rm -rf "$data" "$out"' EXIT
for _ in $(seq 100); do grep -q serving "$out" && break; sleep 0.1; done
url=$(grep -o 'http://[0-9.:]*' "$out")
id=$(curl -s "$url/api/v1/meshes" | python3 -c 'import json,sys; print(json.load(sys.stdin)["meshes"][0]["id"])')
echo "| route | requests/s | p50 | p99 |"
echo "|---|---:|---:|---:|"
for path in /api/v1/health "/api/v1/meshes/$id"; do
  r=$(wrk -t2 -c"$conns" -d"${secs}s" --latency "$url$path")
  rps=$(echo "$r" | awk '/Requests\/sec/ {print $2}')
  p50=$(echo "$r" | awk '$1=="50%" {print $2}')
  p99=$(echo "$r" | awk '$1=="99%" {print $2}')
  label=$path
  [ "$path" = /api/v1/health ] || label="/api/v1/meshes/{id}"
  echo "| GET $label | $rps | $p50 | $p99 |"
done
