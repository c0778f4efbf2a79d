#!/usr/bin/env bash
# Installs the Debian packages lpss needs that are missing, then configures and builds (Release).
# usage: deploy/setup.sh [BUILD_DIR]   (default: build). Idempotent: a second run only rebuilds.
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
root="$(cd "$here/.." && pwd)"
# Absolute: the npm step below runs in another directory.
build="$(realpath -m "${1:-$root/build}")"

missing=()
while read -r pkg; do
    [[ -z "$pkg" || "$pkg" == \#* ]] && continue
    status="$(dpkg-query -W -f='${Status}' "$pkg" 2>/dev/null || true)"
    [[ "$status" == "install ok installed" ]] || missing+=("$pkg")
done <"$here/packages.txt"

if ((${#missing[@]})); then
    echo "lpss: installing missing Debian packages: ${missing[*]}"
    if [[ $(id -u) -ne 0 ]]; then
        echo "lpss: need root to install packages (run as root, or install them yourself)" >&2
        exit 1
    fi
    export DEBIAN_FRONTEND=noninteractive
    apt-get update -qq
    apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
fi

if ! command -v npm >/dev/null 2>&1; then
    echo "lpss: installing Debian's npm (for the pinned test tools in tests/node)"
    if [[ $(id -u) -ne 0 ]]; then
        echo "lpss: need root to install npm (run as root, or install it yourself)" >&2
        exit 1
    fi
    export DEBIAN_FRONTEND=noninteractive
    apt-get install -y -qq --no-install-recommends npm >/dev/null
fi
# Test tools, pinned by tests/node/package-lock.json; installed again only when the lockfile changes.
node_dir="$root/tests/node"
# Without them lpss builds and runs; the tests that need them say they are skipped and why.
if [[ ! -f "$node_dir/node_modules/.package-lock.json" ||
    "$node_dir/package-lock.json" -nt "$node_dir/node_modules/.package-lock.json" ]]; then
    echo "lpss: installing the test tools of tests/node (npm ci)"
    mkdir -p "$build"
    if ! (cd "$node_dir" && npm ci --no-audit --no-fund --loglevel=error >"$build/npm-ci.log" 2>&1); then
        echo "lpss: could not install the test tools of tests/node from the npm registry ($(grep -m1 -o 'reason: .*' "$build/npm-ci.log" || tail -n 1 "$build/npm-ci.log")); the tests that need them (open-dis, puppeteer-core) will be reported as skipped. Log: $build/npm-ci.log" >&2
    fi
fi

jobs="$(nproc 2>/dev/null || echo 2)"
mkdir -p "$build"
log="$build/build.log"
echo "lpss: building in $build (log: $log)"
if ! { [[ -f "$build/CMakeCache.txt" ]] || cmake -S "$root" -B "$build" -DCMAKE_BUILD_TYPE=Release; } >"$log" 2>&1 ||
    ! cmake --build "$build" -j "$jobs" >>"$log" 2>&1; then
    tail -n 40 "$log" >&2
    echo "lpss: build failed (full log: $log)" >&2
    exit 1
fi
