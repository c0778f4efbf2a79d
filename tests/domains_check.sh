#!/bin/sh
# Every test takes a DDS domain of its own: two tests on one domain, run at once by ctest -j, read each
# other's samples (seen: Wire.LateJoinerAndRegionFilter and an own-partition test on 171 both failed), and
# network namespaces do not part them (the built-in profile also talks over shared memory, which they do
# not separate). This lists the domain ids the tests write as literals, in the forms they use, and fails
# on any id used twice. The benches (tests/bench) run one at a time and are left out.
# usage: domains_check.sh TESTS_DIR
set -u
dir=$1
found=$(find "$dir" -path "$dir/bench" -prune -o \( -name '*.cpp' -o -name '*.hpp' \) -print | sort |
    xargs grep -noE '([Dd]omain[A-Za-z_]* = [0-9]+|DomainCleanup [a-z_]+\([0-9]+\)|compare_with_sim\([0-9]+, [0-9]+\))' |
    sed -E 's/^([^:]+:[0-9]+):.*[^0-9]([0-9]+)\)?$/\2 \1/')
test -n "$found" || { echo "no domain id found under $dir: the patterns no longer match the tests"; exit 1; }
count=$(echo "$found" | wc -l)
dups=$(echo "$found" | awk '{print $1}' | sort | uniq -d)
if [ -n "$dups" ]; then
    for id in $dups; do
        echo "domain $id is used by more than one test:"
        echo "$found" | awk -v id="$id" '$1 == id {print "  " $2}'
    done
    exit 1
fi
echo "$count domain ids, each used once"
