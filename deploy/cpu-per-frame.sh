#!/usr/bin/env bash
# CPU time and wakes per frame of each process of a localhost cluster: runs lpss-cluster on a scene in a
# loopback-only network namespace of its own, reads each process's user+system time and voluntary context
# switches (all its threads, and its main thread) from /proc and the frame from the live line twice, FROM
# and TO seconds after the start, and prints the difference per frame.
# usage: deploy/cpu-per-frame.sh SCENE WORKERS [FROM TO [DOMAIN]]   (defaults: 6 s, 10 s, domain 230)
# THREADS=1 also prints each process's threads that were woken at least once a frame: CPU and wakes a frame,
# and what the thread was waiting in at the second reading (the kernel's wchan, '-' if it was running then:
# futex_do_wait for a thread woken by another, such as Fast DDS's event thread; __skb_wait_for_more_packets
# for a receiving thread).
# Uses build/server/lpss-cluster (deploy/setup.sh builds it). Long scenes: make FROM later than the load.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
scene="$1" workers="$2" from="${3:-6}" to="${4:-10}" domain="${5:-230}"
out="$(mktemp -d)"
unshare -rn sh -c "ip link set lo up; exec '$root/build/server/lpss-cluster' '$scene' --workers $workers \
    --frames 100000000 --domain $domain" >"$out/cluster.out" 2>&1 &
cluster=$!
trap 'kill $cluster 2>/dev/null; wait $cluster 2>/dev/null; rm -rf "$out"' EXIT
ticks=$(getconf CLK_TCK)
# One line per process: pid, user+system ticks, voluntary context switches of all its threads and of its
# main thread (each a wait that ended: a wake), and what it is (worker N, coordinator, standby).
sample() {
    for pid in $(pgrep -f "lpss-(worker|coordinator) --domain $domain "); do
        local times wakes main
        times=$(awk '{ print $14 + $15 }' "/proc/$pid/stat" 2>/dev/null) || continue
        wakes=$(cat /proc/"$pid"/task/*/status 2>/dev/null | awk '/^voluntary_ctxt_switches/ { n += $2 } END { print n + 0 }')
        main=$(awk '/^voluntary_ctxt_switches/ { print $2 }' "/proc/$pid/status" 2>/dev/null) || continue
        echo "$pid $times $wakes $main $(tr '\0' ' ' <"/proc/$pid/cmdline" | awk '{ print ($1 ~ /worker$/) ? "worker_" $5 : (/--standby/ ? "standby" : "coordinator") }')"
    done
}
# One line per thread of each process: pid, tid, user+system ticks, voluntary context switches, wchan.
threads() {
    for pid in $(pgrep -f "lpss-(worker|coordinator) --domain $domain "); do
        for task in /proc/"$pid"/task/*; do
            local tid times wakes
            tid=${task##*/}
            times=$(awk '{ print $14 + $15 }' "$task/stat" 2>/dev/null) || continue
            wakes=$(awk '/^voluntary_ctxt_switches/ { print $2 }' "$task/status" 2>/dev/null) || continue
            echo "$pid $tid $times $wakes $(cat "$task/wchan" 2>/dev/null || echo -)"
        done
    done
}
maybe_threads() { if [[ "${THREADS:-}" == 1 ]]; then threads; fi; }
frame() { grep -a '^frame' "$out/cluster.out" | tail -n 1 | awk '{ print $2 }'; }
sleep "$from"
f1=$(frame) s1=$(sample) t1=$(maybe_threads)
sleep "$((to - from))"
f2=$(frame) s2=$(sample) t2=$(maybe_threads)
if [[ -z "$f1" || -z "$f2" || "$f2" -le "$f1" ]]; then
    echo "no frames between ${from} s and ${to} s; lpss-cluster said:" >&2
    tail -n 5 "$out/cluster.out" >&2
    exit 1
fi
echo "frames $f1 to $f2 ($scene, $workers worker(s)); per frame: CPU ms, wakes of all threads, of the main thread:"
awk -v frames=$((f2 - f1)) -v ticks="$ticks" '
    NR == FNR { before[$1] = $2; wakes[$1] = $3; main[$1] = $4; next }
    ($1 in before) { ms = 1000 * ($2 - before[$1]) / ticks / frames; total += ms
                     printf "%8.2f %6.1f %6.1f  %s (pid %s)\n", ms, ($3 - wakes[$1]) / frames,
                            ($4 - main[$1]) / frames, $5, $1 }
    END { printf "%8.2f  all\n", total }' <(echo "$s1") <(echo "$s2" | sort -n)
if [[ "${THREADS:-}" == 1 ]]; then
    echo "threads woken at least once a frame: CPU ms and wakes a frame, waiting in (main: the process's own)"
    awk -v frames=$((f2 - f1)) -v ticks="$ticks" '
        NR == FNR { before[$2] = $3; wakes[$2] = $4; next }
        ($2 in before) { w = ($4 - wakes[$2]) / frames
                         if (w >= 1) printf "%8.3f %6.1f  pid %s tid %s %s\n", 1000 * ($3 - before[$2]) / ticks / frames, w,
                                            $1, $2, ($1 == $2 ? "main" : ($5 == "0" ? "-" : $5)) }' \
        <(echo "$t1") <(echo "$t2" | sort -n)
fi
