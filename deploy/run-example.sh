#!/usr/bin/env bash
# The main job: installs what is missing, builds, and runs the example scene on a localhost cluster (a
# coordinator and two workers, in real time for 10 s), printing a live summary. lpss-view shows it in a
# browser meanwhile, on this machine only: the address is printed first.
# usage: deploy/run-example.sh [SCENE] [extra lpss-cluster options; --workers and --frames replace 2 and 600,
#        --domain, --profile and --security are the viewer's too]
#        LPSS_VIEW_PORT=P picks the viewer's port (default 8090); LPSS_VIEW=0 runs without it.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
"$root/deploy/setup.sh" "$root/build"
# The scene, if the first argument is not an option (deploy/run-example.sh --domain 5 runs the example scene).
scene="$root/deploy/scenes/far_stacks.textproto"
if [[ $# -gt 0 && "$1" != -* ]]; then
    scene=$1
    shift
fi
# The viewer reads the cluster's domain, with its profile, and under DDS Security as its observer: as given
# among the extra options, if they are.
view_options=()
previous=""
for arg in "$@"; do
    case "$previous" in
    --domain | --profile) view_options+=("$previous" "$arg") ;;
    --security) view_options+=(--security "$arg/observer") ;;
    esac
    case "$arg" in
    --domain=* | --profile=*) view_options+=("$arg") ;;
    --security=*) view_options+=(--security "${arg#--security=}/observer") ;;
    esac
    previous=$arg
done
if [[ "${LPSS_VIEW:-1}" != 0 ]]; then
    view_log="$root/build/lpss-view.log"
    "$root/build/client/lpss-view" --port "${LPSS_VIEW_PORT:-8090}" "${view_options[@]}" >"$view_log" 2>&1 &
    view=$!
    trap 'kill "$view" 2>/dev/null || true; wait "$view" 2>/dev/null || true' EXIT
    for _ in $(seq 50); do
        grep -q "http://" "$view_log" 2>/dev/null && break
        kill -0 "$view" 2>/dev/null || break
        sleep 0.1
    done
    if address="$(grep -o 'http://[^ ]*' "$view_log")"; then
        echo "lpss: watch the world at $address (lpss-view; open it in a browser on this machine)"
    else
        echo "lpss: lpss-view did not start (see $view_log); the cluster runs without it" >&2
    fi
fi
# The example's settings, unless given among the extra options (lpss-cluster refuses an option twice),
# as "--workers 3" or "--workers=3".
given() {
    local option=$1 arg
    shift
    for arg in "$@"; do [[ "$arg" == "$option" || "$arg" == "$option="* ]] && return 0; done
    return 1
}
defaults=()
given --workers "$@" || defaults+=(--workers 2)
given --frames "$@" || defaults+=(--frames 600)
given --realtime "$@" || defaults+=(--realtime)
"$root/build/server/lpss-cluster" "$scene" "${defaults[@]}" "$@"
