"""python -m topotet: the command line's main commands on the Python package.

    python -m topotet simplify IN -o OUT [--ratio R | --target-vertices N] [--tolerance-rel H]
        [--feature-angle A] [--hard-limits] [--threads T] [--optimize none|light|full] [--isosurface FIELD=V[,V...]]
        [--field-weight NAME=W] [--max-field-error E] [--max-field-error-rel E] [--field-bounds]
        [--field-bound-mode vertices|everywhere]
        [--extensive NAME] [--categorical NAME] [--vertex-map MAP.npy|MAP.txt] [--quiet]
    python -m topotet info IN

IN and OUT are what topotet.read and topotet.write take (MEDIT .mesh + .sol, Gmsh .msh, optionally
.gz; OUT may also be .vtu). Every option left out takes the library's default (topotet.default_options());
the run is the one `topotet simplify` makes, without the measurements (run `topotet check IN OUT`
for the topology verdict). Exit status 0, or 2 with one line `topotet: error: ...` on stderr.
"""
import argparse
import sys
import time

from . import _core

DEFAULTS = _core.default_options()


def _pairs(items, what):
    out = {}
    for item in items:
        name, sep, value = item.rpartition("=")
        if not sep or not name:
            raise ValueError(f"{what} {item!r}: expected NAME=VALUE")
        out[name] = value
    return out


def _asked(report, limit):
    """The value a relaxed limit started from (the first relaxation's), or the value used."""
    for step in report["relaxations"]:
        if step["limit"] == limit:
            return f"{step['from']:.3g}"
    return f"{report[limit + '_used']:.3g}"


def _simplify(args):
    start = time.perf_counter()
    mesh = _core.read(args.input)
    read_seconds = time.perf_counter() - start
    options = {k: getattr(args, k) for k in ("ratio", "target_vertices", "tolerance_rel", "tolerance", "feature_angle",
                                             "threads", "optimize", "max_field_error", "max_field_error_rel",
                                             "min_quality", "min_dihedral", "size_weight", "field_bound_mode")
               if getattr(args, k) is not None}
    # A limit given holds as given; the defaults relax where they would stop the run before its
    # target (SimplifyOptions::relax_tolerance, relax_quality), as `topotet simplify` does.
    options["relax_tolerance"] = not args.hard_limits and args.tolerance is None and args.tolerance_rel is None
    options["relax_quality"] = not args.hard_limits and args.min_quality is None and args.min_dihedral is None
    options["relax_features"] = not args.hard_limits and args.feature_angle is None
    if args.field_bounds:
        options["field_bounds"] = True
    if args.field_weight:
        options["field_weights"] = {k: float(v) for k, v in _pairs(args.field_weight, "--field-weight").items()}
    if args.isosurface:
        options["isosurfaces"] = list(args.isosurface)  # "FIELD=V[,V...]" specs, as the CLI's
    kinds = dict(mesh["cell_kinds"])
    for name in args.extensive + args.categorical:
        if name not in kinds:
            raise ValueError(f"{args.input}: no cell array {name!r} (its cell arrays: {sorted(kinds) or 'none'})")
    kinds.update({n: "extensive" for n in args.extensive})
    kinds.update({n: "categorical" for n in args.categorical})
    keys = ("materials", "fields", "triangles", "triangle_refs", "segments", "segment_refs", "corners")
    result = _core.simplify(mesh["points"], mesh["tets"], **{k: mesh[k] for k in keys}, **options,
                            cell_fields=mesh["cell_fields"] or None, cell_kinds=kinds or None)
    _core.write(args.output, result)
    if args.vertex_map:
        _core.write_vertex_map(args.vertex_map, result["vertex_map"])
    report = result["report"]
    if not args.quiet:
        seconds = report.get("seconds", 0.0)
        print(f"input     {args.input}: {len(mesh['points']):,} vertices, {len(mesh['tets']):,} tets (read {read_seconds:.2f} s)")
        print(f"output    {args.output}: {len(result['points']):,} vertices ({len(result['points']) / len(mesh['points']):.1%}), "
              f"{len(result['tets']):,} tets")
        print(f"status    {report['status']}" + (f": {report['message']}" if report.get("message") else ""))
        if report["relaxations"]:
            print(f"relaxed   to reach the target: tolerance {report['tolerance_asked']:.3g} -> {report['tolerance']:.3g}, "
                  f"min dihedral {_asked(report, 'min_dihedral')} -> {report['min_dihedral_used']:.3g}, "
                  f"min quality {_asked(report, 'min_quality')} -> {report['min_quality_used']:.3g}"
                  + (f", {report['features_dropped']:,} feature edges dropped" if report["features_dropped"] else "")
                  + " (--hard-limits keeps them)")
        if report["stall_flips"]:
            print(f"flipped   {report['stall_flips']:,} bad tets' faces and edges where inverted tets held the collapses "
                  "(every guarantee kept; --optimize none does not)")
        collapses = report.get("collapses", 0)
        print(f"time      {seconds:.2f} s, {collapses:,} collapses" + (f", {collapses / seconds:,.0f} collapses/s" if seconds > 0 else ""))
        if report["field_bound_rel"] is not None:
            print(f"bounds    field error bound {report['field_bound_rel']:.3g} (relative to the range, worst component), "
                  "at every original vertex")
        if result["cell_fields"]:
            print("cell data " + ", ".join(f"{n}: {k}" for n, k in result["cell_kinds"].items()))
        if args.vertex_map:
            print(f"vertex map {args.vertex_map}: every input vertex -> its output vertex")
        print("topology  not checked here: topotet check IN OUT gives the verdict")
    return 0


def _info(args):
    mesh = _core.read(args.input)
    print(f"file        {args.input}")
    print(f"vertices    {len(mesh['points']):,}")
    print(f"tets        {len(mesh['tets']):,}")
    materials = sorted(set(int(m) for m in mesh["materials"]))
    print(f"materials   {len(materials)} ({', '.join(map(str, materials[:20]))}{', ...' if len(materials) > 20 else ''})")
    print(f"triangles   {len(mesh['triangles']):,}; segments {len(mesh['segments']):,}; corners {len(mesh['corners']):,}")
    print(f"fields      {', '.join(mesh['fields']) or 'none'}")
    print(f"cell arrays {', '.join(f'{n} ({k})' for n, k in mesh['cell_kinds'].items()) or 'none'}")
    return 0


def main(argv=None):
    parser = argparse.ArgumentParser(prog="python -m topotet", description=__doc__.split("\n\n")[0])
    commands = parser.add_subparsers(dest="command", required=True)
    s = commands.add_parser("simplify", help="simplify a tetrahedral mesh, keeping its topology")
    s.add_argument("input")
    s.add_argument("-o", "--output", required=True)
    d = DEFAULTS
    s.add_argument("--ratio", type=float, help=f"keep this fraction of the vertices (default {d['ratio']})")
    s.add_argument("--target-vertices", type=int, help="keep this many vertices (wins over --ratio)")
    s.add_argument("--tolerance-rel", type=float, help=f"surfaces within this fraction of the diagonal (default {d['tolerance_rel']}; 0 = off)")
    s.add_argument("--tolerance", type=float, help="the same in mesh units (wins over --tolerance-rel)")
    s.add_argument("--feature-angle", type=float, help=f"sharp edges kept as curves, degrees (default {d['feature_angle']}; 180 = none)")
    s.add_argument("--min-quality", type=float, help=f"quality floor, mean ratio (default {d['min_quality']})")
    s.add_argument("--min-dihedral", type=float,
                   help=f"dihedral angle floor, degrees (default {d['min_dihedral']}; 0 = off)")
    s.add_argument("--hard-limits", action="store_true",
                   help="keep the default tolerance, quality floors and feature curves even where they stop the run "
                        "before its target (by default they relax there: H doubles, the floors halve, the features "
                        "go; a limit given is always hard)")
    s.add_argument("--size-weight", type=float, help="size term in the ranking of collapses (0 = error only; default: auto, 3e-4 when no field steers the cost, else 0)")
    s.add_argument("--threads", type=int, help="threads (default: all; the output is the same for every count)")
    s.add_argument("--optimize", choices=("none", "light", "full"), help=f"after the collapses (default {d['optimize']})")
    s.add_argument("--max-field-error", type=float, help="field error bound per component, field units")
    s.add_argument("--max-field-error-rel", type=float, help="the same relative to each component's range")
    s.add_argument("--field-bounds", action="store_true", help="keep the field error bounds and report them, without a limit")
    s.add_argument("--field-bound-mode", choices=["vertices", "everywhere"], default=None,
                   help="where the bound holds: the original vertices (default) or every point the output covers")
    s.add_argument("--field-weight", action="append", default=[], metavar="NAME=W", help="a field's weight in the cost")
    s.add_argument("--isosurface", action="append", default=[], metavar="FIELD=V[,V...]", help="keep these level sets' topology")
    s.add_argument("--extensive", action="append", default=[], metavar="NAME", help="a cell array conserved as a sum")
    s.add_argument("--categorical", action="append", default=[], metavar="NAME", help="a cell array remapped as labels")
    s.add_argument("--vertex-map", metavar="FILE", help="also write, for every input vertex, the output vertex it became (.npy or .txt)")
    s.add_argument("-q", "--quiet", action="store_true", help="no report")
    s.set_defaults(run=_simplify)
    i = commands.add_parser("info", help="what a mesh file holds")
    i.add_argument("input")
    i.set_defaults(run=_info)
    args = parser.parse_args(argv)
    try:
        return args.run(args)
    except (ValueError, OSError, RuntimeError) as e:
        print(f"topotet: error: {e}", file=sys.stderr)
        return 2


if __name__ == "__main__":
    sys.exit(main())
