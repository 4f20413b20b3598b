#!/bin/sh
# make test-browser: the nightly dashboard rendered by a real browser.
#
# Three nights of `cascade regress` with the stand-in solver (two pass, the
# third compares with a baseline moved beyond a tolerance), then `cascade
# report --nightly`; headless Chromium loads the page, --dump-dom gives the
# document it parsed and --screenshot what it drew.  Checks: every figure
# of the page has its inline SVG in the parsed document, nothing is
# reported missing, and the screenshot shows the pixels of the figures (the
# blue tolerance bands, the red column of the regressed night) -- a page
# whose SVG did not render has neither.  The screenshot is kept in OUT.
#
#   usage: sh tests/browser/nightly_page.sh BINDIR OUT
set -eu
bindir=$1
out=$2
mkdir -p "$out"
out=$(cd "$out" && pwd)
work=$(mktemp -d /tmp/cascade-browser.XXXXXX)
trap 'rm -rf "$work"' EXIT
fail() { echo "test-browser: FAIL: $*" >&2; exit 1; }

cd "$work"
cat > night.yaml <<'YAML'
name: browsernight
description: the nightly dashboard in a browser (stand-in solver)
base: {type: fake, fake: {x: 0.1, y: 1.0}}
sweep:
  grid:
    fake.y: [1.0, 2.0]
    fake.x: [0.1, 0.2, 0.4, 0.8]
metrics: [x_squared, sum]
report:
  resolution: fake.x
regress:
  tolerances:
    default: {abs: 0, rel: 1.0e-9}
    sum: {abs: 1.0e-6, rel: 0}
  order: 0.01
YAML
run() { "$bindir/cascade" "$@" --solver "$bindir/fake-solver" --quiet > /dev/null; }
run regress night.yaml --update-baseline
run regress night.yaml
run regress night.yaml
# night 3: the baseline of sum at x = 0.1, y = 1 moved by 5e-6 (5 tolerances)
sed 's/^\(.*"metric":"sum","params":{"fake.x":0.1,"fake.y":1.0}.*"value":\)1.1}/\11.100005}/' \
    baselines/browsernight.json > moved.json
cmp -s moved.json baselines/browsernight.json && fail "could not move a baseline value"
if run regress night.yaml --baseline moved.json; then fail "night 3 should have regressed"; fi
"$bindir/cascade" report --nightly --out page/nightly.html > report.log
cat report.log

page=page/nightly.html
figures=$(grep -c '<figure class="trend"' "$page")
[ "$figures" -ge 1 ] || fail "no figure in the page"

browser() {
    # --no-sandbox: the tests run as root in CI containers
    timeout 120 chromium --headless --no-sandbox --disable-gpu --hide-scrollbars \
        --no-first-run --user-data-dir="$work/profile" "$@" 2> "$work/chromium.log"
}
browser --dump-dom "file://$work/$page" > dom.html || fail "chromium --dump-dom failed: $(tail -3 chromium.log)"
svgs=$(grep -o '<svg' dom.html | wc -l)
figs=$(grep -o '<figure class="trend"' dom.html | wc -l)
echo "test-browser: $figures figures in the page; the browser parsed $figs figures and $svgs inline SVGs"
[ "$figs" -eq "$figures" ] || fail "the browser found $figs of $figures figures"
[ "$svgs" -eq "$figures" ] || fail "$svgs inline SVGs for $figures figures"
if grep -qi 'missing' dom.html; then fail "the page reports something missing: $(grep -io '.\{60\}missing.\{60\}' dom.html | head -3)"; fi

browser --window-size=1100,3000 --screenshot="$out/nightly.png" "file://$work/$page" \
    || fail "chromium --screenshot failed: $(tail -3 chromium.log)"
[ -s "$out/nightly.png" ] || fail "no screenshot"
# the drawn figures: pixels of the tolerance band (#cfe3f7 at 80 % over
# white) in every figure, and of the regressed night's column (#f8d0d0)
python3 - "$out/nightly.png" "$figures" <<'PY'
import struct, sys, zlib
path, figures = sys.argv[1], int(sys.argv[2])
data = open(path, 'rb').read()
assert data[:8] == b'\x89PNG\r\n\x1a\n', 'not a PNG'
pos, idat, w = 8, b'', 0
while pos < len(data):
    n, kind = struct.unpack('>I4s', data[pos:pos + 8])
    body = data[pos + 8:pos + 8 + n]
    if kind == b'IHDR':
        w, h, depth, color, _, _, interlace = struct.unpack('>IIBBBBB', body)
        assert depth == 8 and color in (2, 6) and interlace == 0, 'unexpected PNG layout'
        bpp = 3 if color == 2 else 4
    elif kind == b'IDAT':
        idat += body
    pos += 12 + n
raw, stride = zlib.decompress(idat), w * bpp
prev, rows, i = bytearray(stride), [], 0
for y in range(h):
    f, line = raw[i], bytearray(raw[i + 1:i + 1 + stride])
    i += 1 + stride
    for x in range(stride):
        a = line[x - bpp] if x >= bpp else 0
        b, c = prev[x], (prev[x - bpp] if x >= bpp else 0)
        if f == 1: line[x] = (line[x] + a) & 255
        elif f == 2: line[x] = (line[x] + b) & 255
        elif f == 3: line[x] = (line[x] + (a + b) // 2) & 255
        elif f == 4:
            p = a + b - c
            pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
            line[x] = (line[x] + (a if pa <= pb and pa <= pc else b if pb <= pc else c)) & 255
    rows.append(bytes(line))
    prev = line
def near(px, rgb): return all(abs(px[k] - rgb[k]) <= 6 for k in range(3))
band_rows = red = 0
for r in rows:
    hit = 0
    for x in range(0, stride, bpp):
        px = r[x:x + 3]
        if near(px, (217, 233, 249)): hit += 1
        elif near(px, (248, 208, 208)): red += 1
    band_rows += hit > 200   # a row across a band
print('test-browser: screenshot %dx%d: %d rows across tolerance bands, %d pixels of regressed nights'
      % (w, h, band_rows, red))
assert band_rows >= 10 * figures, 'the tolerance bands were not drawn'
assert red > 500, 'the regressed night was not drawn'
PY
echo "test-browser: passed; screenshot in $out/nightly.png"
