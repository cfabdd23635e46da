#!/usr/bin/env bash
# The suite report's page on a small suite (two scenes, their base runs):
# the verdict box comes right after the title, every link of the contents
# reaches an anchor, the provenance block names the BLAS, the one-pass role
# switch's load drop at 0.138 mm is flagged, the axisymmetric scene's mesh
# figure has r and z axes, figures are files (--single-file embeds them),
# and the page at 1400 px does not overflow horizontally (Debian's chromium:
# scripts/setup --tests; without it the check fails unless RPFEM_ALLOW_SKIP=1).
set -u
rpfem=$1; src=$2
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
. "$(dirname "$0")/lib/check.bash"
. "$(dirname "$0")/lib/skip.bash"
o=$tmp/o
"$rpfem" suite --cases "$src/cases" --scene upsetting_frictionless_axisym --scene role_switch_flat_punch \
  --no-studies --no-variants --jobs 2 --out "$o" > "$tmp/log" 2>&1
check "suite wrote the report" '[ -s "$o/report.html" ]' || { cat "$tmp/log"; exit 1; }
/usr/bin/python3 - "$o/report.html" > "$tmp/page" <<'PY'
import re, sys
from html.parser import HTMLParser
s = open(sys.argv[1]).read()
class First(HTMLParser):
    # The body's top-level elements in order (tag, class).
    def __init__(self):
        super().__init__(); self.depth = None; self.top = []
    def handle_starttag(self, tag, attrs):
        if tag == "body": self.depth = 0; return
        if self.depth == 0: self.top.append((tag, dict(attrs).get("class", "")))
        if self.depth is not None and tag not in ("img", "meta", "br"): self.depth += 1
    def handle_endtag(self, tag):
        if self.depth is not None and tag != "body": self.depth -= 1
p = First(); p.feed(s)
print("first:", " ".join("%s.%s" % t for t in p.top[:2]))
ids = set(re.findall(r"id='([^']+)'", s))
print("missing anchors:", sorted(set(re.findall(r"href='#([^']+)'", s)) - ids) or "none")
print("scene anchors:", " ".join(sorted(i for i in ids if i.startswith("scene-"))))
PY
check "verdict box right after the title" 'grep -q "^first: h1. div.verdict" "$tmp/page"'
check "contents links reach anchors" 'grep -q "^missing anchors: none" "$tmp/page"'
check "contents link every scene" \
  'grep -q "scene-role_switch_flat_punch scene-upsetting_frictionless_axisym" "$tmp/page" && grep -q "href=.#scene-role_switch_flat_punch" "$o/report.html"'
check "provenance block with the BLAS" 'grep -q "<h2 id=.provenance.>Provenance</h2>" "$o/report.html" && grep -q "<td>BLAS loaded</td><td>/" "$o/report.html"'
check "role switch drop flagged" 'grep -q "<li>penalty: the load drops [0-9.]* % in one step, from [0-9.]* kN at 0.125 mm" "$o/report.html"'
check "flags counted in the verdict" 'grep -q "Load flags: [1-9][0-9]* in 1 scene: <a href=.#scene-role_switch_flat_punch.>" "$o/report.html"'
# The mesh figure's axes, read off the figure the report draws.
(cd "$src/reports" && /usr/bin/python3 - "$o" > "$tmp/axes" <<'PY'
import json, sys
import field_figures
from results import load_run
out = sys.argv[1]
runs = [load_run(out, r) for r in json.load(open(out + "/suite.json"))["runs"]]
# The mesh panels' axis names (the colour bar's axis has no x label).
field_figures.png_bytes = lambda fig: ({a.get_xlabel() for a in fig.axes} - {""},
                                       {a.get_ylabel() for a in fig.axes if a.get_xlabel()} - {""})
for sc in ("upsetting_frictionless_axisym",):
    print(sc, *(sorted(n) for n in field_figures.strain_rate_png(out, [r for r in runs if r["case"] == sc], sc)))
PY
)
check "r and z axes in axisymmetry" 'grep -qx "upsetting_frictionless_axisym \[.r (mm).\] \[.z (mm).\]" "$tmp/axes"'
check "figures are files" '! grep -q "data:image" "$o/report.html" && grep -q "src=.report_files/role_switch_flat_punch_load.png." "$o/report.html"'
/usr/bin/python3 "$src/reports/make_report.py" "$o" --single-file > /dev/null 2>&1
check "--single-file embeds the figures" 'grep -q "src=.data:image/png;base64," "$o/report.html" && ! grep -q "src=.report_files/" "$o/report.html"'
/usr/bin/python3 "$src/reports/make_report.py" "$o" > /dev/null 2>&1
if command -v chromium > /dev/null; then
  # A copy of the page that writes whether it overflows into its title.
  sed 's#</body>#<script>window.addEventListener("load", function () { var d = document.documentElement; document.title = "overflow " + (d.scrollWidth > window.innerWidth ? "yes" : "no") + " " + d.scrollWidth; });</script></body>#' \
    "$o/report.html" > "$o/probe.html"
  timeout 120 chromium --headless --disable-gpu --no-sandbox --window-size=1400,1000 --virtual-time-budget=10000 \
    --run-all-compositor-stages-before-draw --dump-dom "file://$o/probe.html" 2> /dev/null | grep -o "<title>[^<]*" > "$tmp/title"
  check "no horizontal overflow at 1400 px ($(cat "$tmp/title"))" 'grep -q "overflow no" "$tmp/title"'
else
  cannot_check "no horizontal overflow at 1400 px (chromium is not installed)"
fi
exit $fail
