#!/bin/bash
# Reproduces a defect now fixed (docs/operations.md, "Fixed: a restarted worker that never joined"):
# a 3-worker --realtime cluster, the coordinator killed before the third restart,
# a worker killed and started again under its id N times; says for each restart whether it joined, and
# prints the UDP ports each restarted worker bound (its participant id).
#   unshare -rn bash -c 'ip link set lo up; tests/tools/restart_after_takeover.sh build SCENE [N]'
# Seen with the soak test's scene (it writes /tmp/lpss_<pid>_soak.textproto): 2 to 5 of 9 restarts never
# joined, in 2 of 6 runs; since participants take fresh ports (dds::participant_id_with_fresh_ports), 18 of 18
# restarts in two runs joined.
set -u
build=$(cd "$1" && pwd); scene=$2; n=${3:-9}; domain=171
logs=$(mktemp -d /tmp/lpss_restart_XXXX)
"$build/server/lpss-cluster" "$scene" --workers 3 --domain $domain --frames 200000 --realtime --quiet \
  > "$logs/cluster.out" 2>&1 &
cluster=$!
sleep 6
for i in $(seq 1 "$n"); do
  w=$(( (i - 1) % 3 + 1 ))
  if [ "$i" = 3 ]; then
    kill -KILL $(pgrep -af "[l]pss-coordinator --domain $domain" | grep -v -- --standby | cut -d' ' -f1)
    sleep 3
  fi
  pkill -KILL -f "[l]pss-worker --domain $domain --id $w "
  sleep 3
  "$build/server/lpss-worker" --domain $domain --id $w --threads 1 > "$logs/w$i.log" 2>&1 &
  pid=$!
  sleep 7
  ports=$(ss -ulpn | grep "pid=$pid," | awk '{print $4}' | tr '\n' ' ')
  if grep -q "joins the cluster" "$logs/w$i.log"; then state=joined; else state="NOT joined"; fi
  echo "restart $i (worker $w): $state; ports $ports"
  # Shared-memory ports each lpss process still maps though they were removed (a stale port: what it
  # pushes there nobody reads).
  for p in $(pgrep -f "[l]pss-(coordinator|worker) --domain $domain"); do
    stale=$(grep -o 'fastrtps_port[0-9]* (deleted)' /proc/$p/maps 2>/dev/null | sort -u | tr '\n' ' ')
    [ -n "$stale" ] && echo "   pid $p ($(tr '\0' ' ' < /proc/$p/cmdline | cut -c1-60)): $stale"
  done
done
kill $cluster; sleep 3
pkill -KILL -f "[l]pss-.* --domain $domain"
wait 2>/dev/null
echo "logs: $logs"
