#!/usr/bin/env bash
# The main job: installs what is missing, builds, and runs the example scene on a localhost cluster (a
# coordinator and two workers, in real time for 10 s), printing a live summary.
# usage: deploy/run-example.sh [SCENE] [extra lpss-cluster options]
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
"$root/deploy/setup.sh" "$root/build"
scene="${1:-$root/deploy/scenes/far_stacks.textproto}"
shift || true
exec "$root/build/server/lpss-cluster" "$scene" --workers 2 --frames 600 --realtime "$@"
