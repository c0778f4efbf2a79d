#!/usr/bin/env bash
# docs/results.md must be what deploy/assemble-results.sh makes of docs/results.template.md and the benches'
# markdown: prose written into results.md alone is lost at the next assembly (the template had fallen some 280
# lines behind results.md before this check).
# usage: results_assembly_check.sh SOURCE_DIR
set -euo pipefail
src=$1
assembled=$(mktemp)
trap 'rm -f "$assembled"' EXIT
"$src/deploy/assemble-results.sh" "$assembled"
if ! cmp -s "$assembled" "$src/docs/results.md"; then
    echo "docs/results.md is not what deploy/assemble-results.sh makes: edit docs/results.template.md (or"
    echo "rerun the bench), then run deploy/assemble-results.sh. The difference (assembled, then results.md):"
    diff "$assembled" "$src/docs/results.md" | head -40
    exit 1
fi
echo "docs/results.md is its template assembled"
