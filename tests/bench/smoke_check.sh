#!/bin/sh
# The lpss-bench smoke test: a quick precision run, and what its outputs must show. Not a timing check:
# lpss (float and double) keeps every distance's error within the paper's bound for the largest sector
# size run (3e-2 for L = 1024) and always collides; plain float Bullet fails far out (the comparison is real);
# the markdown and the plot are written.  usage: smoke_check.sh LPSS_BENCH
set -u
bench=$1
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
"$bench" --quick --out "$out" precision >"$out/log" 2>&1 || { cat "$out/log"; echo "lpss-bench failed"; exit 1; }
csv=$out/precision/precision.csv
head -1 "$csv" | grep -q '^scene,direction,distance,config,sector_size,error,ms_per_frame,collided' ||
    { echo "unexpected header: $(head -1 "$csv")"; exit 1; }
test -s "$out/precision/precision.md" || { echo "no markdown"; exit 1; }
test -s "$out/precision/precision.png" || { echo "no plot"; exit 1; }
awk -F, 'NR > 1 {
    if ($4 ~ /^lpss-/) {
        lpss[$4]++
        if ($8 != 1 || $6 > 3e-2) { print "lpss off at " $0; bad = 1 }
    }
    if ($4 == "bullet-float" && $3 >= 1e12 && ($8 == 1 && $6 < 1)) { print "plain float Bullet did not fail at " $0; bad = 1 }
    if ($4 == "bullet-float" && $3 >= 1e12) far_plain++
}
END {
    if (lpss["lpss-float"] < 10 || lpss["lpss-double"] < 10) { print "too few lpss rows (float " lpss["lpss-float"] ", double " lpss["lpss-double"] ")"; bad = 1 }
    if (far_plain < 2) { print "no plain float Bullet rows far out"; bad = 1 }
    exit bad
}' "$csv"
