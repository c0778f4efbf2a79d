#!/usr/bin/env bash
# Runs lpss-bench sub-commands into docs/results/ and assembles docs/results.md from
# docs/results.template.md (deploy/assemble-results.sh), where {{NAME}} stands for the markdown NAME's run
# produced.
# usage: deploy/run-bench.sh [SUBCOMMAND ...]   (default: all; --assemble: only rebuild docs/results.md).
# Takes a quiet machine and about an hour (cluster-scale alone, up to a million bodies: about 25 minutes).
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
"$root/deploy/setup.sh" "$root/build"
out="$root/docs/results"
subs=("$@")
if [[ "${1:-}" == "--assemble" ]]; then subs=(); elif ((${#subs[@]} == 0)); then subs=(precision pareto instances overhead stacks scaling stability accuracy cluster cluster-security cluster-scale late-join dis); fi
for sub in "${subs[@]}"; do
    echo "lpss: lpss-bench $sub"
    # cluster-security is the cluster sub-command run with --security (its output goes to cluster-security/).
    if [[ "$sub" == cluster-security ]]; then args=(cluster --security); else args=("$sub"); fi
    (cd "$root" && build/lpss-bench --out docs/results "${args[@]}" >/dev/null)
done
"$root/deploy/assemble-results.sh"
echo "lpss: docs/results.md assembled"
