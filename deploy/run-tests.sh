#!/usr/bin/env bash
# The test suite: installs what is missing, builds, and runs every test that is not labelled long.
# usage: deploy/run-tests.sh [extra ctest options]
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
"$root/deploy/setup.sh" "$root/build"
cd "$root/build"
exec ctest --output-on-failure -j "$(nproc 2>/dev/null || echo 2)" --timeout 600 -LE long "$@"
