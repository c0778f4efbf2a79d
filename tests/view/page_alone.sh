#!/bin/sh
# The viewer's page alone, in Debian's chromium, on tests/view/fake_stream.js's made-up world (every shape,
# a body at 1e12, two workers, a handoff): drawn, and body 100 drawn where it is after "go to body".
# usage: page_alone.sh SOURCE_DIR SCREENSHOT
set -eu
src="$1"
shot="$2"
# 77: skipped (ctest's SKIP_RETURN_CODE), when the npm test tools could not be installed.
if [ ! -f "$src/tests/node/node_modules/puppeteer-core/package.json" ]; then
    echo "skipped: npm's puppeteer-core is not installed in tests/node (deploy/setup.sh could not reach the npm registry)"
    exit 77
fi
log="$(mktemp)"
node "$src/tests/view/fake_stream.js" --port 0 >"$log" 2>&1 &
fake=$!
trap 'kill $fake 2>/dev/null; rm -f "$log"' EXIT
for _ in $(seq 100); do grep -q "http://" "$log" && break; sleep 0.1; done
url="$(grep -o 'http://[^ ]*' "$log" | head -n 1)"
node "$src/tests/view/check_page.js" --url "$url" --screenshot "$shot" --goto 100 \
    --expect-at 1000000000000.375,2.5,-3.25 --tolerance 1e-3 --min-frames 5 --timeout-s 60
