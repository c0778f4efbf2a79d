#!/usr/bin/env bash
# The main job: installs what is missing, builds, and runs the example scene with lpss-sim, printing
# what happened. usage: deploy/run-example.sh [SCENE] [extra lpss-sim options]
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
"$root/deploy/setup.sh" "$root/build"
scene="${1:-$root/deploy/scenes/far_stacks.textproto}"
shift || true
exec "$root/build/server/lpss-sim" "$scene" --frames 600 "$@"
