#!/usr/bin/env bash
# Smoke test of the topotet command-line tool: every command on a small generated mesh, the JSON
# reports, the exit codes (0 ok, 1 failed check, 2 bad usage/input with one error line), and no
# temporary file left behind.
#   usage: bash tests/cli_test.sh path/to/topotet
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)

topotet=$(realpath "${1:?usage: cli_test.sh path/to/topotet}")
work=$(mktemp -d "${TMPDIR:-/tmp}/topotet_cli_test.XXXXXX")
trap 'rm -rf "$work"' EXIT
cd "$work"

# pass, fail, expect, expect_error, contains and the counters.
source "$here/cli_harness.sh"

# expect_any_error NAME -- COMMAND...: exit 2 and exactly one line on stderr, 'topotet: error: ...'.
expect_any_error() {
  local name=$1
  shift
  expect 2 "$name" "$@"
  if [[ $(wc -l <"$name.err") == 1 ]] && grep -q '^topotet: error: ' "$name.err"; then
    pass "$name: one error line"
  else
    fail "$name: stderr is not one 'topotet: error:' line:"
    sed 's/^/        /' "$name.err" | head -n 10
  fi
}

json_ok() {  # json_ok FILE KEY: FILE parses as JSON and has top-level KEY
  if command -v python3 >/dev/null 2>&1; then
    python3 -c 'import json, sys; d = json.load(open(sys.argv[1])); sys.exit(0 if sys.argv[2] in d else 1)' "$1" "$2"
  else
    grep -q "\"$2\"" "$1"
  fi
}

check_json() {  # check_json FILE KEY
  if [[ -f $1 ]] && json_ok "$1" "$2"; then pass "$1 is JSON with '$2'"; else fail "$1 is not JSON with '$2'"; fi
}

# --- help and usage ---
expect 0 help -- "$topotet" --help
expect 0 version -- "$topotet" --version
if grep -Eq '^topotet [0-9]+\.[0-9]+\.[0-9]+$' version.out; then pass "--version prints the version"; else fail "--version: $(cat version.out)"; fi
for cmd in info generate convert simplify check demo extract; do
  expect 0 "help_$cmd" -- "$topotet" "$cmd" --help
done

# --- generate, info ---
expect 0 generate -- "$topotet" generate cube-sphere --tets 20000 --seed 3 -o in.mesh
expect 0 info -- "$topotet" info in.mesh --json info.json
check_json info.json input
if grep -q '^valid *yes' info.out; then pass "info says valid"; else fail "info does not say valid"; fi
# cube-sphere to a .mesh file streams (generate/README.md); its bytes must be what the in-memory
# writer gives the same mesh: rewrite it through convert (read + write_medit) and compare.
for n in 3000 50000; do
  expect 0 generate_stream_$n -- "$topotet" generate cube-sphere --tets $n --seed 3 -o stream$n.mesh
  expect 0 rewrite_stream_$n -- "$topotet" convert stream$n.mesh rewritten$n.mesh
  if cmp -s stream$n.mesh rewritten$n.mesh && cmp -s stream$n.sol rewritten$n.sol &&
     cmp -s stream$n.sol.fields.txt rewritten$n.sol.fields.txt; then
    pass "streamed cube-sphere $n: byte-identical to the in-memory writer"
  else
    fail "streamed cube-sphere $n differs from the in-memory writer"
  fi
done

# --- convert: .mesh -> .msh -> .vtu, and .msh -> .mesh (.vtu is write-only) ---
expect 0 convert_msh -- "$topotet" convert in.mesh in.msh
expect 0 convert_msh_binary -- "$topotet" convert in.mesh in_binary.msh --binary --validate
expect 0 convert_vtu -- "$topotet" convert in.msh in.vtu
expect 0 convert_back -- "$topotet" convert in_binary.msh back.mesh --validate
expect 0 check_roundtrip -- "$topotet" check in.mesh back.mesh
[[ -s in.vtu ]] && pass "in.vtu written" || fail "in.vtu missing"

# --- simplify: parallel (1 and 2 threads) and sequential, with JSON reports ---
expect 0 simplify_parallel -- "$topotet" simplify in.mesh -o out.mesh --ratio 0.3 --threads 2 --report report.json
check_json report.json levels
check_json report.json schema_version
if grep -q '^topology *PASS' simplify_parallel.out; then pass "simplify says PASS"; else fail "simplify does not say PASS"; fi
expect 0 simplify_one_thread -- "$topotet" simplify in.mesh -o out1.mesh --ratio 0.3 --threads 1 --quiet
if cmp -s out.mesh out1.mesh; then pass "same output for 1 and 2 threads"; else fail "output differs between 1 and 2 threads"; fi
expect 0 simplify_sequential -- "$topotet" simplify in.mesh -o seq.msh --ratio 0.3 --sequential --report seq.json
check_json seq.json levels
expect 0 check_parallel -- "$topotet" check in.mesh out.mesh --json check.json
check_json check.json topology
expect 0 check_sequential -- "$topotet" check in.mesh seq.msh
expect 0 simplify_levels -- "$topotet" simplify in.mesh -o lv.mesh --levels 0.5,0.2 --no-verify
# --vertex-map: every input vertex -> the output vertex it became (checked without topotet's readers).
expect 0 vertex_map -- "$topotet" simplify in.mesh -o vm.mesh --ratio 0.2 --optimize none --vertex-map vm.npy
contains vertex_map_report vertex_map.out "vertex map.*vm.npy"
expect 0 vertex_map_valid -- python3 "$here/vertex_map_check.py" vm.npy in.mesh vm.mesh
expect 0 vertex_map_txt -- "$topotet" simplify in.mesh -o vmt.mesh --ratio 0.2 --optimize none --vertex-map vm.txt -q --no-metrics
expect 0 vertex_map_txt_valid -- python3 "$here/vertex_map_check.py" vm.txt in.mesh vmt.mesh
expect_error vertex_map_extension "vm.csv.*npy.*txt" -- "$topotet" simplify in.mesh -o x.mesh --vertex-map vm.csv
expect_error vertex_map_levels "excludes" -- "$topotet" simplify in.mesh -o x.mesh --levels 0.5 --vertex-map vm.npy
[[ -s lv_0.5.mesh && -s lv_0.2.mesh ]] && pass "level files written" || fail "level files missing"
if grep -q '^measure *quality' simplify_parallel.out; then pass "simplify prints the measurement times"; else fail "no measure line"; fi
# The input is released during the simplification and read again for the measurements, unless the
# run writes over it: then it stays in memory, and the checks still compare with the original.
if grep -q '^measure .*input re-read' simplify_parallel.out &&
  python3 -c 'import json, sys; sys.exit(0 if json.load(open(sys.argv[1]))["reload_seconds"] > 0 else 1)' report.json; then
  pass "the input is read again for the measurements"
else
  fail "the input was not read again for the measurements"
fi
cp in.mesh self.mesh
[[ -f in.sol ]] && cp in.sol self.sol
expect 0 simplify_over_input -- "$topotet" simplify self.mesh -o self.mesh --ratio 0.3 --threads 2
if grep -q '^topology *PASS' simplify_over_input.out && ! grep -q 'input re-read' simplify_over_input.out &&
  cmp -s out.mesh self.mesh; then
  pass "simplify IN -o IN keeps the input for the checks"
else
  fail "simplify IN -o IN: wrong checks or output"
fi

# --- --no-metrics: the same output file, only counts, times and memory in the report ---
expect 0 simplify_no_metrics -- "$topotet" simplify in.mesh -o nm.mesh --ratio 0.3 --threads 2 --no-metrics --report nm.json
if cmp -s out.mesh nm.mesh; then pass "--no-metrics writes the same mesh"; else fail "--no-metrics output differs"; fi
if grep -q '^topology *not checked (--no-metrics' simplify_no_metrics.out &&
  ! grep -q '^\(quality\|fields\|distance\|measure\)' simplify_no_metrics.out; then
  pass "--no-metrics prints no measurement"
else
  fail "--no-metrics printed a measurement"
fi
if python3 -c '
import json, sys
r = json.load(open(sys.argv[1])); l = r["levels"][0]
ok = r["topology"] == "skipped" and r["input"]["quality"] is None and l["quality"] is None
ok = ok and l["surface_distance"] is None and l["field_error"] is None and l["vertices_after"] > 0
# The input is released during the run and not read again without metrics: its counts still show.
ok = ok and r["input"]["vertices"] == l["vertices_before"] > 0 and r["input"]["tets"] == l["tets_before"] > 0
sys.exit(0 if ok else 1)' nm.json; then
  pass "--no-metrics report has counts and no measurement"
else
  fail "--no-metrics report is wrong"
fi

# --- one JSON schema across commands (cli/json_report.h): the header, and a mesh described alike ---
if python3 -c '
import json, sys
info, simplify, check = (json.load(open(f)) for f in ("info.json", "report.json", "check.json"))
ok = all(list(r)[:3] == ["schema_version", "topotet_version", "command"] and r["schema_version"] == 2
         for r in (info, simplify, check))
ok = ok and (info["command"], simplify["command"], check["command"]) == ("info", "simplify", "check")
mesh_keys = ["file", "vertices", "tets", "read_seconds"]
meshes = (info["input"], simplify["input"], check["before"], check["after"])
ok = ok and all(list(m)[:4] == mesh_keys for m in meshes)
ok = ok and info["input"]["vertices"] == simplify["input"]["vertices"] == check["before"]["vertices"]
ok = ok and check["after"]["vertices"] == simplify["levels"][0]["vertices_after"]
ok = ok and set(check["after"]["quality"]) == set(simplify["input"]["quality"])
ok = ok and simplify["levels"][0]["topology"] == check["topology"] == "pass"
ok = ok and "topology_differences" in check and "topology_differences" in simplify["levels"][0]
sys.exit(0 if ok else 1)'; then
  pass "info, simplify and check reports share the header and the mesh keys"
else
  fail "the JSON reports of info, simplify and check differ in their common keys"
fi
expect 0 simplify_json_alias -- "$topotet" simplify in.mesh -o alias.mesh --ratio 0.3 --json alias.json -q
check_json alias.json levels

# --- verbosity: -q prints nothing, -v details and notes, -vv a timed log of the stages ---
[[ ! -s simplify_json_alias.out && ! -s simplify_json_alias.err ]] && pass "simplify -q prints nothing" ||
  fail "simplify -q printed: $(head -c 200 simplify_json_alias.out simplify_json_alias.err)"
expect 0 check_quiet -- "$topotet" check in.mesh out.mesh -q
expect 0 info_quiet -- "$topotet" info in.mesh -q
[[ ! -s check_quiet.out && ! -s info_quiet.out ]] && pass "check -q and info -q print nothing" || fail "check -q or info -q printed"
expect 0 simplify_verbose -- "$topotet" simplify in.mesh -o v.mesh --ratio 0.3 --threads 64 -v
if grep -q '^options *ratio 0.3' simplify_verbose.out && grep -q '^phases *evaluate' simplify_verbose.out &&
  grep -q '^ *interface ref' simplify_verbose.out && grep -q 'note: --threads 64: this process may use' simplify_verbose.err; then
  pass "simplify -v prints the options, phases, every surface label and the thread note"
else
  fail "simplify -v lacks details: $(cat simplify_verbose.out simplify_verbose.err | head -c 400)"
fi
cmp -s out.mesh v.mesh && pass "-v writes the same mesh" || fail "-v output differs"
expect 0 simplify_debug -- "$topotet" simplify in.mesh -o vv.mesh --ratio 0.3 -vv
if grep -q '^topotet: \[.*\] build in.mesh' simplify_debug.err && grep -q '^topotet: \[.*\] verify: done' simplify_debug.err &&
  grep -q '^rounds *round' simplify_debug.out; then
  pass "simplify -vv logs every stage with its time and prints the rounds"
else
  fail "simplify -vv log is missing: $(head -c 400 simplify_debug.err)"
fi
expect 0 info_verbose -- "$topotet" info in.mesh -v --json info_v.json
grep -q 'material 2 ' info_verbose.out && json_ok info_v.json input &&
  python3 -c 'import json; assert "topology_report" in json.load(open("info_v.json"))["input"]' &&
  pass "info -v prints every complex's Betti numbers" || fail "info -v has no topology table"
expect_any_error quiet_and_verbose -- "$topotet" info in.mesh -q -v

# --- the defaults of issue #12: sharp features and a tolerance; both can be turned off ---
if grep -q '^features .* sharp edges' info.out; then pass "info prints the sharp features"; else fail "info prints no features"; fi
if grep -q '^features .* sharp edges' simplify_parallel.out && grep -q '^tolerance .*% of the diagonal' simplify_parallel.out; then
  pass "simplify reports features and the default tolerance"
else
  fail "simplify does not report features and the default tolerance"
fi
expect 0 simplify_plain -- "$topotet" simplify in.mesh -o plain.mesh --ratio 0.3 --tolerance 0 --feature-angle 180 --report plain.json
if python3 -c '
import json, sys
l = json.load(open(sys.argv[1]))["levels"][0]
sys.exit(0 if l["tolerance"] == 0 and l["feature_edges"] == 0 else 1)' plain.json; then
  pass "--tolerance 0 --feature-angle 180 turn both off"
else
  fail "--tolerance 0 --feature-angle 180 did not turn both off"
fi
# --- limits that would stop a run short relax by default; given ones hold (issue #23) ---
# The default tolerance holds in.mesh at about 9% (its interfaces are staircases): the default run
# gets to 5% by relaxing it and says so; given on the command line (or --hard-limits), it holds.
expect 0 simplify_relaxed -- "$topotet" simplify in.mesh -o rx.mesh --ratio 0.05 --feature-angle 180 --report rx.json
expect 0 simplify_hard -- "$topotet" simplify in.mesh -o hard.mesh --ratio 0.05 --feature-angle 180 --tolerance-rel 0.004 --report hard.json
expect 0 simplify_hard_limits -- "$topotet" simplify in.mesh -o hl.mesh --ratio 0.05 --feature-angle 180 --hard-limits --report hl.json
if python3 -c '
import json, sys
rx, hard, hl = (json.load(open(f))["levels"][0] for f in sys.argv[1:4])
target = round(0.05 * rx["vertices_before"])
ok = rx["vertices_after"] == target and rx["relaxations"] and rx["tolerance"] > rx["tolerance_asked"]
ok = ok and rx["surface_distance"]["hausdorff"] <= rx["tolerance"]
for l in (hard, hl):  # the same H, held: stopped before the target, named
    ok = ok and l["vertices_after"] > target and l["tolerance"] == rx["tolerance_asked"]
    ok = ok and l["stopped"] is not None and l["stopped"]["dominant"] == "tolerance"
    ok = ok and all(s["limit"] != "tolerance" for s in l["relaxations"])
ok = ok and not hl["relaxations"] and hl["min_dihedral_used"] == 5
sys.exit(0 if ok else 1)' rx.json hard.json hl.json && grep -q '^relaxed   tolerance H .* -> ' simplify_relaxed.out &&
   ! grep -q '^relaxed' simplify_hard.out; then
  pass "default limits relax to the target (reported, Hausdorff within the last H); given ones and --hard-limits hold"
else
  fail "relaxing: the default run, a given tolerance or --hard-limits misbehaved"
fi
# --- field error bounds (issue #16): the limit holds and the measured error stays under the bound ---
expect 0 simplify_field_bounds -- "$topotet" simplify in.mesh -o fb.mesh --ratio 0.05 --max-field-error-rel 0.01 --no-verify --report fb.json
if python3 -c '
import json, sys
l = json.load(open(sys.argv[1]))["levels"][0]
b = l["field_bounds"]
ok = b["max_bound_rel"] <= 0.01 and b["measured_max_rel"] <= b["max_bound_rel"] and "field_error" in l["rejected"] \
    and b["check"] == "pass" and not b["check_failures"] and json.load(open(sys.argv[1]))["checks"] == "pass"
sys.exit(0 if ok else 1)' fb.json && grep -q '^bounds .*field error bound' simplify_field_bounds.out; then
  pass "--max-field-error-rel: bound <= E, measured <= bound, reported"
else
  fail "--max-field-error-rel: bound above E, measured above the bound, or not reported"
fi
expect_any_error field_bounds_with_levels -- "$topotet" simplify in.mesh -o lv.mesh --levels 0.5,0.3 --max-field-error 1
# --field-bound-mode everywhere: the bound holds at the dense samples between the vertices too.
expect 0 simplify_field_bounds_everywhere -- "$topotet" simplify in.mesh -o fe.mesh --ratio 0.05 --max-field-error-rel 0.01 \
  --field-bound-mode everywhere --no-verify --report fe.json
if python3 -c '
import json, sys
b = json.load(open(sys.argv[1]))["levels"][0]["field_bounds"]
ok = b["mode"] == "everywhere" and b["max_bound_rel"] <= 0.01 and b["check"] == "pass" and b["dense"]["points"] > 0 \
    and b["dense"]["above_bound"] == 0 and b["dense"]["max_error_rel"] <= 0.01 * (1 + 1e-9)
sys.exit(0 if ok else 1)' fe.json && grep -q '^bounds .*at every point the output covers.*none above' simplify_field_bounds_everywhere.out; then
  pass "--field-bound-mode everywhere: no dense sample above its tet's bound, reported"
else
  fail "--field-bound-mode everywhere: a dense sample above the bound, or not reported"
fi
expect_any_error everywhere_without_limit -- "$topotet" simplify in.mesh -o never.mesh --field-bound-mode everywhere --field-bounds
expect 0 simplify_feature_ref -- "$topotet" simplify in.mesh -o fr.mesh --ratio 0.3 --feature-ref 99
expect 0 convert_features -- "$topotet" convert in.mesh feat.mesh --features 99
if grep -q ' 99$' feat.mesh && grep -q ' 99$' fr.mesh; then pass "feature edges written with their ref"; else fail "no feature edges with ref 99"; fi
expect_any_error bad_feature_angle -- "$topotet" simplify in.mesh -o never.mesh --feature-angle 200

# --- bad input and usage: exit 2, one line ---
head -c 4000 in.mesh >truncated.mesh
expect_any_error truncated_info -- "$topotet" info truncated.mesh
expect_any_error truncated_simplify -- "$topotet" simplify truncated.mesh -o never.mesh
expect_any_error missing_file -- "$topotet" simplify no_such_file.mesh -o never.mesh
expect_any_error bad_option -- "$topotet" simplify in.mesh -o never.mesh --no-such-option
expect_any_error bad_ratio -- "$topotet" simplify in.mesh -o never.mesh --ratio 7
expect_any_error bad_field_weight_name -- "$topotet" simplify in.mesh -o never.mesh --field-weight no_such_field=2
expect_any_error bad_field_weight_syntax -- "$topotet" simplify in.mesh -o never.mesh --field-weight f
expect 0 simplify_field_weight -- "$topotet" simplify in.mesh -o fw.mesh --ratio 0.3 --no-verify --field-weight f=0.5 --report fw.json
if tr -d ' \n' <fw.json | grep -q '"field_weights":{"f":0.5}'; then pass "the report lists the field weights"; else fail "no field_weights in the report"; fi
expect_any_error bad_extension -- "$topotet" convert in.mesh never.xyz
expect_any_error bad_family -- "$topotet" generate no-such-family --tets 20000 -o never.mesh
expect_any_error no_command -- "$topotet"
[[ ! -e never.mesh ]] && pass "nothing written on error" || fail "never.mesh was written"

# --- a failed check: two different meshes ---
expect 0 generate_slab -- "$topotet" generate slab --tets 3000 -o slab.mesh
expect 1 check_fails -- "$topotet" check in.mesh slab.mesh

# --- progress for batch logs: plain lines on stderr, none by default without a terminal ---
expect 0 progress_lines -- "$topotet" simplify in.mesh -o pl.mesh --ratio 0.1 --threads 1 --no-metrics \
  --progress lines --progress-interval 0.001
if grep -Eq '^simplify: [0-9]+% after ' progress_lines.err && ! grep -q $'\r' progress_lines.err; then
  pass "progress lines: plain lines on stderr"
else
  fail "progress lines: no 'simplify: N% after' line, or a carriage return, on stderr"
fi
if ! grep -q '% after' progress_lines.out; then pass "progress lines: none on stdout"; else fail "progress lines on stdout"; fi
expect 0 progress_auto -- "$topotet" simplify in.mesh -o pa.mesh --ratio 0.1 --threads 1 --no-metrics
if ! grep -q '% after\|\[#' progress_auto.err; then pass "progress auto: silent without a terminal"; else fail "progress auto drew without a terminal"; fi
expect_any_error progress_bad -- "$topotet" simplify in.mesh -o pb.mesh --progress sometimes

# --- the collapse hierarchy (issue #16): one run, any level, checked against the original ---
expect 0 simplify_hierarchy -- "$topotet" simplify in.mesh -o hbase.mesh --ratio 0.1 --threads 2 --no-metrics --hierarchy h.tth
if grep -q '^hierarchy *h.tth: .* collapses' simplify_hierarchy.out; then pass "simplify reports the hierarchy"; else fail "no hierarchy line"; fi
expect 0 simplify_hierarchy_1 -- "$topotet" simplify in.mesh -o hbase1.mesh --ratio 0.1 --threads 1 --no-metrics --hierarchy h1.tth
if cmp -s h.tth h1.tth; then pass "hierarchy file identical for 1 and 2 threads"; else fail "hierarchy file differs between 1 and 2 threads"; fi
# With fields the hierarchy records each collapse's field error bound; --no-field-bounds records none.
expect 0 extract_bounded -- "$topotet" extract h.tth -o hb.mesh --levels-error 0.01
expect 0 simplify_hierarchy_nb -- "$topotet" simplify in.mesh -o hnb.mesh --ratio 0.1 --no-metrics --hierarchy hnb.tth --no-field-bounds
expect 0 extract_unbounded -- "$topotet" extract hnb.tth -o hnb_l.mesh --levels-error 1e-9
if awk '$1 == "0.01" {exit !($8 + 0 <= 0.01 && $7 + 0 <= $8 + 0)}' extract_bounded.out &&
  awk '$1 == "1e-09" {exit !($8 == "-")}' extract_unbounded.out; then
  pass "levels by bound: error at the original vertices <= bound <= E; --no-field-bounds records none"
else
  fail "hierarchy bounds: $(cat extract_bounded.out extract_unbounded.out | head -c 600)"
fi
expect 0 extract_vertices -- "$topotet" extract h.tth -o hv.mesh --vertices 2000
if grep -q '^output *hv.mesh: 2,000 vertices' extract_vertices.out && grep -q '^topology *PASS' extract_vertices.out; then
  pass "extract --vertices: the count asked for, topology PASS"
else
  fail "extract --vertices: $(cat extract_vertices.out)"
fi
expect 0 extract_voi -- "$topotet" extract h.tth -o hvoi.msh --voi sphere:0.5,0.5,0.5,0.2 --inside-error 0
expect 0 extract_voi_check -- "$topotet" check in.mesh hvoi.msh
expect 0 extract_levels -- "$topotet" extract h.tth -o hl.mesh --levels-error 1e-6,1e-4
if [[ -s hl_1e-06.mesh && -s hl_0.0001.mesh ]] && [[ $(grep -c PASS extract_levels.out) == 2 ]]; then
  pass "extract --levels-error: two levels written, both PASS"
else
  fail "extract --levels-error: $(ls hl_* 2>&1) $(cat extract_levels.out)"
fi
# The table as JSON: from extract, and from simplify --levels-error (after its own report).
expect 0 extract_levels_json -- "$topotet" extract h.tth -o hj.mesh --levels-error 1e-6,1e-4 --json hj.json
expect 0 simplify_levels_json -- "$topotet" simplify in.mesh -o hs.mesh --ratio 0.1 --no-metrics --hierarchy hs.tth --levels-error 1e-4 --json hs.json
if python3 - hj.json hs.json <<'PY'
import json, sys
e, s = (json.load(open(p)) for p in sys.argv[1:])
rows = e["error_levels"]
assert e["command"] == "extract" and e["checks"] == "pass" and [r["error"] for r in rows] == [1e-6, 1e-4], e
for r in rows + s["error_levels"]:
    assert r["topology"] == "pass" and r["vertices"] > 0 and r["tets"] > 0, r
    assert r["bound"] is not None and r["field_max_rel_at_original"] <= r["bound"] + 1e-12, r
assert rows[0]["vertices"] >= rows[1]["vertices"], rows
assert s["command"] == "simplify" and len(s["error_levels"]) == 1 and s["error_levels"][0]["path"] == "hs_0.0001.mesh", s
PY
then
  pass "--levels-error --json: the table's rows in extract's and simplify's JSON reports"
else
  fail "--levels-error --json: $(head -c 600 hj.json) $(head -c 600 hs.json)"
fi
expect_any_error extract_json_alone -- "$topotet" extract h.tth -o x.mesh --vertices 10 --json x.json
expect_any_error extract_no_level -- "$topotet" extract h.tth -o x.mesh
expect_any_error extract_bad_voi -- "$topotet" extract h.tth -o x.mesh --voi cube:1,2,3
head -c 100 h.tth > short.tth
expect_any_error extract_truncated -- "$topotet" extract short.tth -o x.mesh --vertices 10
if grep -q 'short.tth: byte [0-9]*: truncated' extract_truncated.err; then pass "truncated .tth: file and offset named"; else fail "truncated .tth: $(cat extract_truncated.err)"; fi
expect_any_error extract_not_tth -- "$topotet" extract in.mesh -o x.mesh --vertices 10

# --- no temporary file left behind ---
leftovers=$(find . -name '*.tmp*' | sort)
if [[ -z $leftovers ]]; then pass "no temporary files"; else fail "temporary files left: $leftovers"; fi

echo "$passed passed, $failed failed"
[[ $failed == 0 ]]
