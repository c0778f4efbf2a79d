#!/usr/bin/env bash
# Makes docs/images/lpss-view.png, the README's picture of lpss-view: the example scene (far_stacks) on a
# two-worker cluster in real time, the page opened in headless chromium and sent to the stack 1e9 units out.
# usage: deploy/view-screenshot.sh [OUT.png]   (after deploy/setup.sh; uses DDS domain 160)
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
out="${1:-$root/docs/images/lpss-view.png}"
logs="$(mktemp -d)"
"$root/build/server/lpss-cluster" "$root/deploy/scenes/far_stacks.textproto" --workers 2 --frames 1200 --realtime \
    --domain 160 --quiet --await-clients 1 --log-dir "$logs" >"$logs/cluster.out" 2>&1 &
cluster=$!
"$root/build/client/lpss-view" --domain 160 --port 0 >"$logs/view.out" 2>&1 &
view=$!
trap 'kill "$view" "$cluster" 2>/dev/null || true; wait 2>/dev/null || true; rm -rf "$logs"' EXIT
for _ in $(seq 100); do grep -q "http://" "$logs/view.out" && break; sleep 0.1; done
url="$(grep -o 'http://[^ ]*' "$logs/view.out")"
node "$root/tests/view/check_page.js" --url "$url" --goto "1e9 box 3" --min-frames 30 --timeout-s 60 \
    --screenshot "$out"
echo "written: $out"
