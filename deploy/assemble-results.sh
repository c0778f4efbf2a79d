#!/usr/bin/env bash
# Assembles docs/results.md from docs/results.template.md, where {{NAME}} on a line of its own stands for
# docs/results/NAME/NAME.md (the markdown lpss-bench NAME wrote), its pictures re-pointed. Prose goes in the
# template: results.md is rewritten whole at every assembly (the test Docs.ResultsMdIsItsTemplateAssembled
# fails when the two part).
# usage: deploy/assemble-results.sh [OUTPUT]   (default: docs/results.md)
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
out="$root/docs/results"
target="${1:-$root/docs/results.md}"
template="$root/docs/results.template.md"
{
    while IFS= read -r line; do
        if [[ "$line" =~ ^\{\{([a-z_-]+)\}\}$ ]]; then
            name="${BASH_REMATCH[1]}"
            md="$out/$name/$name.md"
            if [[ -f "$md" ]]; then
                sed -E "s#\]\(($name[A-Za-z0-9_-]*\.png)\)#](results/$name/\1)#g" "$md"
            else
                echo "(not measured yet: run deploy/run-bench.sh $name)"
            fi
        else
            printf '%s\n' "$line"
        fi
    done <"$template"
} >"$target"
