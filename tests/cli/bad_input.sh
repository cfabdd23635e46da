#!/usr/bin/env bash
# Requirement: bad input gives a one-line error naming the file and key,
# and exit code 2.
set -u
rpfem=$1; src=$2
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
fail=0
expect() {  # expect NAME PATTERN -- command...
  local name=$1 pattern=$2; shift 3
  local err rc
  err=$("$@" 2>&1 >/dev/null); rc=$?
  local lines; lines=$(printf '%s\n' "$err" | grep -c .)
  if [ "$rc" -ne 2 ] || [ "$lines" -ne 1 ] || ! printf '%s' "$err" | grep -q -- "$pattern"; then
    echo "FAIL $name: exit $rc, $lines line(s): $err"; fail=1
  else
    echo "ok   $name: $err"
  fi
}
base=$src/cases/upsetting_frictionless_axisym.toml
expect missing-file "no such case file" -- "$rpfem" run "$tmp/nope.toml" --out "$tmp/o1"
printf '[run\ngeometry = "axisymmetric"\n' > "$tmp/bad.toml"
expect malformed "malformed TOML" -- "$rpfem" run "$tmp/bad.toml" --out "$tmp/o2"
sed 's/^nx = 20/nx = 20\nnxx = 3/' "$base" > "$tmp/unknown.toml"
expect unknown-key "unknown key 'bodies.billet.mesh.nxx'" -- "$rpfem" run "$tmp/unknown.toml" --out "$tmp/o3"
sed 's/^library = "AISI1035".*/K = -3.0\nn = 0.2/' "$base" > "$tmp/negk.toml"
expect negative-K "bodies.billet.material.K': expected a positive number" -- "$rpfem" run "$tmp/negk.toml" --out "$tmp/o4"
expect zero-height "bodies.billet.mesh.height': expected a positive number" -- "$rpfem" run "$base" --out "$tmp/o5" --set bodies.billet.mesh.height=0.0
expect bad-formulation "formulation 'nonsense' is unknown" -- "$rpfem" run "$base" --out "$tmp/o6" --formulation nonsense
expect bad-set "--set" -- "$rpfem" run "$base" --out "$tmp/o7" --set nonsense
# [expect] tables (docs/case-format.md) are validated as every other key.
ext=$src/cases/extremes/penalty_beta.toml
expect expect-outcome "expect.outcome': expected one of 'finished' 'stopped'" -- "$rpfem" run "$ext" --out "$tmp/o8" --set expect.outcome=maybe
expect expect-unknown "expect.outcom': unknown key" -- "$rpfem" run "$ext" --out "$tmp/o9" --set expect.outcom=finished
expect expect-bounds "expect.measure.0.min': min is above max" -- "$rpfem" run "$ext" --out "$tmp/o10" --set expect.measure.0.min=1.0
expect expect-reference "expect.measure.0.reference_case': no such file" -- "$rpfem" run "$ext" --out "$tmp/o11" --set expect.measure.0.reference_case=nope.toml
expect penetration-tolerance "run.penetration_tolerance': expected a positive number" -- "$rpfem" run "$base" --out "$tmp/o12" --set run.penetration_tolerance=0.0
# Output folders that cannot be: bad input naming --out, not an internal
# error (each command creates its folder before anything runs).
touch "$tmp/afile"
expect out-under-file "--out '$tmp/afile/sub': cannot create the output folder: Not a directory" -- \
  "$rpfem" run "$base" --out "$tmp/afile/sub"
expect out-is-file "--out '$tmp/afile': a file is there" -- "$rpfem" run "$base" --out "$tmp/afile"
expect out-empty "--out: expected a folder name, got an empty one" -- "$rpfem" run "$base" --out ""
expect out-too-long "cannot create the output folder: File name too long" -- \
  "$rpfem" run "$base" --out "$tmp/$(printf 'a%.0s' $(seq 300))"
expect out-unwritable "--out '/proc/rpfem': cannot create the output folder" -- "$rpfem" run "$base" --out /proc/rpfem
expect sweep-out-is-file "--out '$tmp/afile': a file is there" -- \
  "$rpfem" sweep "$src/cases/studies/step_convergence_test2.toml" --out "$tmp/afile"
expect suite-out-is-file "--out '$tmp/afile': a file is there" -- \
  "$rpfem" suite --out "$tmp/afile" --scene upsetting_dies_frictionless_axisym
expect calibrate-out-is-file "--out '$tmp/afile': a file is there" -- \
  "$rpfem" calibrate "$src/cases/upsetting_dies_frictionless_axisym.toml" --auto-beta 1e-3 --out "$tmp/afile"
# An array index in --set too large for any integer: no such entry.
expect set-huge-index "'99999999999999999999' does not name a table" -- \
  "$rpfem" run "$src/cases/upsetting_dies_frictionless_axisym.toml" --out "$tmp/o13" --set contact_pairs.99999999999999999999.body=x
# A die with two coincident vertices (a segment with no normal), and a
# flow stress whose scales are not finite in double precision.
expect die-zero-segment "key 'dies.top_die.vertex.1': coincides with vertex 0" -- \
  "$rpfem" run "$src/cases/upsetting_dies_frictionless_axisym.toml" --out "$tmp/o14" --formulation penalty \
  --set dies.top_die.vertex.1.x=-1.0 --set dies.top_die.vertex.1.y=10.0
sed 's/^library = "AISI1035".*/K = 1e308\nn = 0.2/' "$base" > "$tmp/bigk.toml"
expect infinite-scales "key 'bodies.billet.material': its initial flow stress gives a volumetric penalty alpha of inf" -- \
  "$rpfem" run "$tmp/bigk.toml" --out "$tmp/o15"
# Names that become columns, attributes and file names: letters, digits,
# '_', '-', '.' and '+' (a comma or a quote broke history.csv's header).
expect run-name "key 'run.name': expected a name of letters, digits" -- \
  "$rpfem" run "$base" --out "$tmp/o16" --set 'run.name=a;b'
sed 's/^\[bodies\.billet/[bodies."bil,let"/' "$base" > "$tmp/bodyname.toml"
expect body-name "key 'bodies.bil,let': the table's name: expected a name" -- "$rpfem" run "$tmp/bodyname.toml" --out "$tmp/o17"
expect monitor-name "key 'monitors.0.name': expected a name of letters, digits" -- \
  "$rpfem" run "$src/cases/upsetting_friction.toml" --out "$tmp/o18" --set 'monitors.0.name=bulge,radius'
expect case-is-folder "cases: a folder; expected a case file" -- "$rpfem" run "$src/cases" --out "$tmp/o19"
# Limits on the whole mesh and the step count, before anything that size
# is built (nx = ny = 1e5 ran out of memory after 8 GB).
expect max-elements "key 'bodies.billet.mesh': 1e+10 elements (nx 100000 x ny 100000 at run.mesh_factor 1), 1e+10 over all bodies; expected at most run.max_elements = 2000000" -- \
  "$rpfem" run "$base" --out "$tmp/o20" --set bodies.billet.mesh.nx=100000 --set bodies.billet.mesh.ny=100000
expect max-elements-factor "key 'bodies.billet.mesh': 6400 elements (nx 80 x ny 80 at run.mesh_factor 4), 6400 over all bodies; expected at most run.max_elements = 5000" -- \
  "$rpfem" run "$base" --out "$tmp/o21" --set run.mesh_factor=4.0 --set run.max_elements=5000
expect max-nodes "key 'bodies.billet.mesh': 1681 nodes, 1681 over all bodies; expected at most run.max_nodes = 1000" -- \
  "$rpfem" run "$base" --out "$tmp/o22" --set bodies.billet.mesh.nx=40 --set bodies.billet.mesh.ny=40 --set run.max_nodes=1000
expect max-steps "key 'stepping.stroke_increment': end_stroke / stroke_increment = 5e+12 steps; expected at most run.max_steps = 10000000" -- \
  "$rpfem" run "$base" --out "$tmp/o23" --set stepping.stroke_increment=1e-12
# The mesh generator's errors name the file and the key.
expect zero-size-element "upsetting_frictionless_axisym.toml: key 'bodies.billet.mesh': zero-size element" -- \
  "$rpfem" run "$base" --out "$tmp/o24" --set bodies.billet.mesh.x0=1e20
expect quadrilateral-corners "paper_test2_virtual_rigid.toml: key 'bodies.punch.mesh.corners': corner 3 (0.000000, 16.000000) turns clockwise" -- \
  "$rpfem" run "$src/cases/paper_test2_virtual_rigid.toml" --out "$tmp/o25" \
  --set 'bodies.punch.mesh.corners=[0.0, 10.0, 20.0, 13.52654, 0.0, 16.0, 20.0, 16.0]'
# A misspelt key is named as such, with the key it most likely meant (a
# required one was reported missing; an optional one as unknown only).
sed 's/^height = /heigth = /' "$base" > "$tmp/misspelt.toml"
expect misspelt-required "unknown key 'bodies.billet.mesh.heigth' (misspelt?); did you mean 'height'?" -- \
  "$rpfem" run "$tmp/misspelt.toml" --out "$tmp/o26"
# The step control's keys (stepping.tolerance).
expect bounds-without-tolerance "key 'stepping.tolerance': expected a tolerance where stepping.min_increment is given" -- \
  "$rpfem" run "$base" --out "$tmp/o27a" --set stepping.min_increment=0.001
expect tolerance-range "key 'stepping.tolerance': expected a number in (0, 1)" -- \
  "$rpfem" run "$base" --out "$tmp/o27b" --set stepping.tolerance=0.0
expect max-increment-range "key 'stepping.max_increment': expected a number in \[0.05, 5\]" -- \
  "$rpfem" run "$base" --out "$tmp/o27c" --set stepping.tolerance=1e-3 --set stepping.max_increment=0.01
expect misspelt-optional "unknown key 'stepping.output_evry' (misspelt, or not used by this scene and formulation); did you mean 'output_every'?" -- \
  "$rpfem" run "$base" --out "$tmp/o27" --set stepping.output_evry=2
# verify needs a suite's folder (every check failed as "no run", exit 1).
expect verify-missing "verify: '$tmp/nosuchdir': no such folder" -- "$rpfem" verify "$tmp/nosuchdir"
mkdir -p "$tmp/notasuite"
expect verify-not-a-suite "verify: '$tmp/notasuite' is not a suite's folder (no suite.json)" -- \
  "$rpfem" verify "$tmp/notasuite"
# A body far larger than its elements, or far from the origin: nodes
# double precision cannot merge (the merge grid's integer cells overflowed).
expect mesh-extent "upsetting_frictionless_axisym.toml: key 'bodies.billet.mesh': coordinates beyond double precision's range" -- \
  "$rpfem" run "$base" --out "$tmp/o28" --set bodies.billet.mesh.width=1e308
expect mesh-offset "upsetting_frictionless_plane.toml: key 'bodies.billet.mesh': coordinates up to 1e+13 mm" -- \
  "$rpfem" run "$src/cases/upsetting_frictionless_plane.toml" --out "$tmp/o29" --set bodies.billet.mesh.x0=1e13
expect mesh-overflow "paper_test1_double_action.toml: key 'bodies.upper.mesh': coordinates beyond double precision's range" -- \
  "$rpfem" run "$src/cases/paper_test1_double_action.toml" --out "$tmp/o30" --set bodies.upper.mesh.radius=1e308
# A search reach far below round-off (mortar's search samples overflowed
# an int), and a regularization whose viscosity is not finite (the run
# stopped at step 0 on a non-finite residual, exit 3).
expect capture-tiny "patch_two_blocks.toml: key 'contact.capture': expected a number in \\[1e-06, 1e+06\\]" -- \
  "$rpfem" run "$src/cases/patch_two_blocks.toml" --out "$tmp/o31" -d mortar --set contact.capture=1e-300
expect regularization-huge "key 'solver.regularization': with body 'billet' its viscosity is not finite" -- \
  "$rpfem" run "$base" --out "$tmp/o32" --set solver.alpha=1e-308 --set solver.regularization=1e308
# A symmetry plane through no node of the ring (0 to 10 mm high) held
# nothing and the run finished, its loads and volume doubled.
expect symmetry-off-body "ring_compression.toml: key 'symmetry.0.at': the plane y = 50.000000 mm holds no node .*a symmetry plane must hold nodes of a body" -- \
  "$rpfem" run "$src/cases/ring_compression.toml" --out "$tmp/o33" --set symmetry.0.at=50.0
# A case path with a name longer than the file system allows ended in
# "internal error: filesystem error ... File name too long" (exit 1).
long=$tmp/$(printf 'c%.0s' $(seq 295)).toml
expect case-name-too-long "$long: cannot read the case file: File name too long; expected the path of a readable TOML file" -- \
  "$rpfem" run "$long" --out "$tmp/o34"
# Fillets that do not fit between their segments: 1000 mm between two
# collinear segments (5 and 20 mm) and at an end of the profile were
# accepted without a word; 1000 mm at a right angle between them.
punch=$src/cases/indentation_fillet_punch.toml
expect fillet-straight "indentation_fillet_punch.toml: key 'dies.punch.vertex.1.fillet': a fillet of 1000.000000 mm where the profile runs straight on .*no corner to round" -- \
  "$rpfem" run "$punch" --out "$tmp/o35" --set dies.punch.vertex.1.fillet=1000.0 \
  --set dies.punch.vertex.2.x=24.0 --set dies.punch.vertex.2.y=10.0
expect fillet-at-end "key 'dies.punch.vertex.2.fillet': vertex 2 is an end of the profile; a fillet rounds the corner between two segments" -- \
  "$rpfem" run "$punch" --out "$tmp/o36" --set dies.punch.vertex.2.fillet=1000.0
expect fillet-too-large "key 'dies.punch.vertex.1.fillet': a fillet of 1000.000000 mm does not fit between its segments (5.000000 and 20.000000 mm long): its arc takes 1000.000000 mm of each; expected at most 5.000000 mm" -- \
  "$rpfem" run "$punch" --out "$tmp/o37" --set dies.punch.vertex.1.fillet=1000.0
# The remesher's size from the error: the target's range, and its bounds
# only with a target.
sticking=$src/cases/upsetting_sticking_remeshed.toml
expect remesh-target-error "upsetting_sticking_remeshed.toml: key 'remesh.target_error': expected a number in \[0, 1)" -- \
  "$rpfem" run "$sticking" --out "$tmp/o38" --set remesh.target_error=1.5
expect remesh-min-size-alone "key 'remesh.min_size': expected a remesh.target_error above 0 where remesh.min_size is given" -- \
  "$rpfem" run "$sticking" --out "$tmp/o39" --set remesh.min_size=0.1
expect remesh-max-size "key 'remesh.max_size': expected a number in \[0.2, 100\] (share of element_size" -- \
  "$rpfem" run "$sticking" --out "$tmp/o40" --set remesh.target_error=0.1 --set remesh.max_size=0.1
exit $fail
