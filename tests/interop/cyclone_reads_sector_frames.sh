#!/bin/sh
# Another vendor keeps reading: a Cyclone DDS reader of lpss/sector_frames (tests/interop/
# cyclone_sector_reader.c, types from idl/lpss.idl by Cyclone's idlc) beside an lpss cluster of 2 workers.
# It must take samples from both workers up to the last frame, and the unregistrations the workers' writers
# send as they end (key only), with no warning from Cyclone (it warns on samples it cannot decode, such as
# a key hash it cannot turn into a key). Runs in a network namespace of its own when it can (root);
# both vendors are held to 127.0.0.1 either way.
# usage: cyclone_reads_sector_frames.sh READER LPSS_CLUSTER SCENE DOMAIN
set -eu
if [ "${LPSS_IN_NAMESPACE:-}" != 1 ] && unshare -n true 2>/dev/null; then
    LPSS_IN_NAMESPACE=1 exec unshare -n sh -c 'ip link set lo up && exec sh "$0" "$@"' "$0" "$@"
fi
reader=$1 cluster=$2 scene=$3 domain=$4
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cat >"$work/cyclone.xml" <<XML
<CycloneDDS>
  <Domain id="any">
    <General>
      <Interfaces><NetworkInterface address="127.0.0.1"/></Interfaces>
      <AllowMulticast>false</AllowMulticast>
    </General>
    <Discovery>
      <ParticipantIndex>auto</ParticipantIndex>
      <MaxAutoParticipantIndex>40</MaxAutoParticipantIndex>
      <Peers><Peer address="127.0.0.1"/></Peers>
      <SPDPInterval>0.2s</SPDPInterval>
    </Discovery>
    <Tracing><Category>warning</Category><OutputFile>$work/cyclone-warnings.log</OutputFile></Tracing>
  </Domain>
</CycloneDDS>
XML
CYCLONEDDS_URI="file://$work/cyclone.xml" "$reader" "$domain" 90 300 2 >"$work/reader.out" 2>&1 &
pid=$!
sleep 1
# Paced (5 s): Fast DDS and Cyclone find each other by unicast on 127.0.0.1, which takes a few of their
# announcements; an unpaced run ends before the last of them.
"$cluster" "$scene" --workers 2 --frames 300 --realtime --domain "$domain" --quiet --log-dir "$work/logs" >"$work/cluster.out" 2>&1 ||
    { cat "$work/cluster.out"; echo "lpss-cluster failed"; exit 1; }
wait "$pid" || { cat "$work/reader.out"; echo "the Cyclone reader failed"; exit 1; }
cat "$work/reader.out"
out=$(cat "$work/reader.out")
fail=0
case "$out" in *"newest frame 300,"*) ;; *) echo "the Cyclone reader did not see frame 300"; fail=1 ;; esac
echo "$out" | grep -Eq 'writers( 0)? 1 2' || { echo "the Cyclone reader did not hear both workers"; fail=1; }
case "$out" in *"without 0,"*) echo "no unregistration reached the Cyclone reader (the check would not see an undecodable one)"; fail=1 ;; esac
if [ -s "$work/cyclone-warnings.log" ]; then
    echo "Cyclone DDS warned:"; head -20 "$work/cyclone-warnings.log"; fail=1
fi
exit $fail
