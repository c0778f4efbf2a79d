#!/bin/bash
# Reproduces a defect now fixed (docs/operations.md, "Fixed: a worker that joined after a standby took over
# never ran a frame"): a 2-worker --realtime cluster of the example scene, both workers killed
# (no --restart-workers, so the coordinator holds the world), the coordinator killed 2 s later, a worker
# started by hand under id 1 2 s after that. Seen on 2026-12-03: the standby took over, waited out the
# last worker's 5 s silence, admitted the new worker 1 at once, and that worker never ran a frame: every
# 5 s it was taken as gone and admitted again, and lpss-watch stopped at the frame of the kill. Since the
# standby writes the planes' descriptions again when it takes over, the joiner runs to the last frame.
# LOG_LEVEL=debug sets the hand-started worker's --log-level.
#   unshare -rn bash -c 'ip link set lo up; tests/tools/takeover_during_hold.sh build'
set -u
build=$(cd "$1" && pwd); domain=175
here=$(cd "$(dirname "$0")/../.." && pwd)
logs=$(mktemp -d /tmp/lpss_takeover_hold_XXXX)
"$build/server/lpss-cluster" "$here/deploy/scenes/far_stacks.textproto" --workers 2 --realtime --frames 1500 \
  --domain $domain --log-dir "$logs/cluster" > "$logs/cluster.out" 2>&1 &
cluster=$!
"$build/client/lpss-watch" --domain $domain --frames 1500 --wait-s 30 > "$logs/watch.out" 2>&1 &
watch=$!
sleep 6
pkill -KILL -f "[l]pss-worker --domain $domain "
sleep 2
pkill -KILL -f "[l]pss-coordinator --domain $domain .*--await-standby"
sleep 2
"$build/server/lpss-worker" --domain $domain --id 1 --log-level ${LOG_LEVEL:-info} > "$logs/worker-1-by-hand.out" 2>&1 &
worker=$!
sleep 12
kill -INT $cluster 2>/dev/null; sleep 3; kill $worker $watch 2>/dev/null; wait
echo "standby (the coordinator after the takeover):"
grep -E "taking over|gone|joined|goes on" "$logs/cluster/standby.log"
echo "the worker started by hand:"
cat "$logs/worker-1-by-hand.out"
tail -1 "$logs/watch.out"
echo "logs: $logs"
