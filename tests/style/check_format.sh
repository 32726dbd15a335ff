#!/bin/sh
# Every C++ file in the tree is laid out as .clang-format says: a file
# written by hand and never formatted fails here, with the lines it would
# change.  Fix with: clang-format -i FILE (or the loop below with -i).
# The web client's files are laid out as web-client/.prettierrc.json says,
# checked by the prettier of its package-lock.json.  Fix with:
# (cd web-client && npm run format).
set -eu
root=$(cd "$(dirname "$0")/../.." && pwd)
cd "$root"
command -v clang-format >/dev/null || { echo "clang-format is missing (./setup.sh test installs it)" >&2; exit 1; }
files=$(find algorithms bench clients protocol server tests -name node_modules -prune -o \
  \( -name '*.cpp' -o -name '*.h' \) -type f -print | sort)
[ -n "$files" ] || { echo "no C++ files found under $root" >&2; exit 1; }
# shellcheck disable=SC2086
clang-format --dry-run --Werror $files
echo "$(echo "$files" | wc -l) C++ files formatted as .clang-format says"

# The paths of web-client/package.json's format:check script.
[ -x web-client/node_modules/.bin/prettier ] || {
  echo "prettier is missing from web-client/node_modules: run ./setup.sh (its npm ci installs it from web-client/package-lock.json)" >&2
  exit 1
}
(cd web-client && npx --no-install prettier --check src tests index.html ./*.ts ./*.json)
