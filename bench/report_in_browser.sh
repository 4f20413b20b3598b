#!/bin/sh
# Optional check that a report opens in a browser and shows its figures:
# loads report.html in headless Chromium, counts the figures (inline SVG)
# in the page the browser built, and saves a screenshot to look at.
# Chromium is not a build or test dependency; install it with
#   apt-get install -y chromium
#   usage: sh bench/report_in_browser.sh reports/demo/report.html [shot.png] [WIDTHxHEIGHT]
set -eu
HTML=${1:?usage: report_in_browser.sh REPORT.html [SHOT.png] [WIDTHxHEIGHT]}
SHOT=${2:-${HTML%.html}.png}
SIZE=${3:-1200x2400}
BROWSER=$(command -v chromium || command -v chromium-browser || true)
if [ -z "$BROWSER" ]; then
    echo "report_in_browser: chromium is not installed (apt-get install -y chromium)" >&2
    exit 2
fi
case $HTML in /*) ;; *) HTML=$(pwd)/$HTML ;; esac
PROFILE=$(mktemp -d /tmp/cascade-chromium.XXXXXX)
trap 'rm -rf "$PROFILE"' EXIT
run() {
    "$BROWSER" --headless --no-sandbox --disable-gpu --disable-quic --no-first-run \
        --disable-background-networking --disable-component-update --disable-sync \
        --user-data-dir="$PROFILE" "$@" 2>/dev/null
}
expected=$(grep -c '<figure>' "$HTML" || true)
shown=$(run --dump-dom "file://$HTML" | grep -o '<svg' | wc -l)
missing=$(run --dump-dom "file://$HTML" | grep -c 'figure missing' || true)
run --screenshot="$SHOT" --window-size="$(echo "$SIZE" | tr x ,)" "file://$HTML" >/dev/null
echo "report_in_browser: $HTML: $shown inline figures in the page Chromium built ($expected expected, $missing missing); screenshot $SHOT"
[ "$shown" -ge "$expected" ] && [ "$missing" -eq 0 ] && [ -s "$SHOT" ]
