/* topotet C API: topology-preserving simplification of tetrahedral meshes, for C, Fortran (module
 * topotet, fortran/topotet.f90) and any language with a C FFI.
 *
 *   topotet_mesh_arrays in;                 // views of the caller's arrays: nothing is copied by the caller
 *   topotet_mesh_arrays_init(&in);
 *   in.vertex_count = nv;  in.positions = (topotet_view){xyz, TOPOTET_FLOAT64, 0};
 *   in.tet_count = nt;     in.tets = (topotet_view){tets, TOPOTET_INT32, 0};  in.index_base = 1;
 *   topotet_mesh* mesh = NULL;
 *   if (topotet_mesh_build(&in, 0, &mesh) != TOPOTET_OK) { puts(topotet_last_error()); ... }
 *   topotet_options options;  topotet_options_init(&options);  options.target_vertex_ratio = 0.2;
 *   topotet_report report;
 *   topotet_simplify(mesh, &options, &report);
 *   const double* xyz_out = topotet_mesh_positions(mesh);      // library-owned, or
 *   topotet_mesh_copy_tets(mesh, out_view, 1);                  // into the caller's arrays
 *   topotet_mesh_copy_vertex_map(mesh, map_view, 1);           // input vertex -> output vertex
 *   topotet_mesh_free(mesh);
 *
 * Conventions:
 *  - Every function returns a topotet_status; on failure topotet_last_error() gives a one-line
 *    message (per thread, valid until the next failing call on that thread). No function aborts
 *    or throws on bad input.
 *  - Arrays are passed as a topotet_view: base pointer, element type and the stride in bytes from
 *    one row (a vertex, a tet, ...) to the next; 0 means packed rows. A row of positions is 3
 *    values, of tets 4, of triangles 3, of segments 2, of a field `components` values; the values
 *    inside a row are contiguous. Row-major C arrays, Fortran arrays of shape (3, n), NumPy arrays
 *    with any row stride all fit.
 *  - Vertex indices in tets, triangles, segments, corners and in the output tets and vertex map
 *    are 0- or 1-based, as the caller chooses (index_base).
 *  - A topotet_mesh is used by one thread at a time; different meshes may be used concurrently.
 *    num_threads (build, options) bounds every parallel loop of the call; 0 = all cores, or the
 *    limit of the caller's oneTBB task arena.
 *  - Pointers returned by topotet_mesh_positions() and friends stay valid until the mesh is
 *    simplified again or freed; the names and values of cell arrays, until then or until a cell
 *    array is added.
 */
#ifndef TOPOTET_TOPOTET_C_H
#define TOPOTET_TOPOTET_C_H

#include <stddef.h>
#include <stdint.h>

#include "topotet/version.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Same values as topotet::Status (topotet/simplify.h). */
typedef enum topotet_status {
  TOPOTET_OK = 0,             /* done; simplify: the target was reached */
  TOPOTET_STOPPED_EARLY = 1,  /* simplify: mesh valid, no legal collapse was left before the target */
  TOPOTET_INVALID_INPUT = 2,  /* bad argument, file or mesh; nothing changed; see topotet_last_error() */
  TOPOTET_OUT_OF_MEMORY = 3,  /* mesh valid, possibly partly simplified */
  TOPOTET_CANCELLED = 4,      /* reserved for progress callbacks; mesh valid */
  TOPOTET_INTERNAL_ERROR = 5  /* a bug: mesh valid but unfinished; please report the message */
} topotet_status;

typedef enum topotet_type {
  TOPOTET_FLOAT64 = 0,
  TOPOTET_FLOAT32 = 1,
  TOPOTET_INT32 = 2,
  TOPOTET_INT64 = 3
} topotet_type;

/* A read-only strided array (see the conventions above). data == NULL means "not given". */
typedef struct topotet_view {
  const void* data;
  topotet_type type;
  int64_t stride; /* bytes between rows; 0 = packed */
} topotet_view;

/* A writable strided array, for results written into the caller's memory. */
typedef struct topotet_out_view {
  void* data;
  topotet_type type;
  int64_t stride; /* bytes between rows; 0 = packed */
} topotet_out_view;

/* One per-vertex field to preserve (a scalar, a vector, a tensor: every component counts). */
typedef struct topotet_field_view {
  const char* name;
  int components;
  topotet_view values; /* FLOAT64 or FLOAT32, vertex_count rows of `components` values */
} topotet_field_view;

/* How a per-tet ("cell") array is carried onto the tets of the simplified mesh (topotet/cell_fields.h:
 * an exact overlap-volume remap within each material). Same values as topotet::CellFieldKind. */
typedef enum topotet_cell_kind {
  TOPOTET_CELL_INTENSIVE = 0,   /* density-like (pressure, conductivity): volume-weighted average */
  TOPOTET_CELL_CATEGORICAL = 1, /* a label (region id, flag): the value of the largest overlap volume */
  TOPOTET_CELL_EXTENSIVE = 2    /* an amount (mass, heat): shared out by covered volume, sum conserved */
} topotet_cell_kind;

/* One per-tet array: tet_count rows of `components` values, FLOAT64, FLOAT32, INT32 or INT64
 * (kept as doubles: an integer must fit in 53 bits). Names are unique among the cell arrays;
 * values are finite. */
typedef struct topotet_cell_field_view {
  const char* name; /* NULL = "cell<i>" */
  int components;
  topotet_cell_kind kind;
  topotet_view values;
} topotet_cell_field_view;

/* The input mesh: views of the caller's arrays. Only positions and tets are required. */
typedef struct topotet_mesh_arrays {
  int64_t vertex_count;
  topotet_view positions;   /* FLOAT64 or FLOAT32, rows of 3 */
  int64_t tet_count;
  topotet_view tets;        /* INT32 or INT64, rows of 4 vertex indices */
  topotet_view materials;   /* INT32 or INT64, one per tet; not given = all 0 */
  topotet_view vertex_refs; /* INT32 or INT64, one per vertex; not given = all 0 */
  int64_t triangle_count;   /* listed surfaces: faces of tets, each with a ref */
  topotet_view triangles;   /* INT32 or INT64, rows of 3 vertex indices */
  topotet_view triangle_refs;
  int64_t segment_count;    /* listed polylines: edges of tets, each with a ref */
  topotet_view segments;    /* INT32 or INT64, rows of 2 vertex indices */
  topotet_view segment_refs;
  int64_t corner_count;     /* pinned vertices: never moved, never removed */
  topotet_view corners;     /* INT32 or INT64 vertex indices */
  int field_count;
  const topotet_field_view* fields;
  int index_base;           /* 0 or 1: the first vertex is numbered index_base everywhere */
  int cell_field_count;     /* per-tet arrays, carried through topotet_simplify (kinds above) */
  const topotet_cell_field_view* cell_fields;
} topotet_mesh_arrays;

/* Same meaning and defaults as topotet::SimplifyOptions (topotet/simplify.h). */
typedef struct topotet_options {
  double target_vertex_ratio; /* keep this fraction of the vertices, in (0, 1]; default 0.25 */
  int64_t target_vertices;    /* if > 0, wins over the ratio */
  double max_cost;            /* 0 = no limit */
  double min_quality;         /* default 0.05 (mean ratio) */
  double boundary_weight;     /* default 100 */
  double polyline_weight;     /* default 100 */
  double tolerance;           /* geometric tolerance in mesh units, 0 = use tolerance_rel */
  double tolerance_rel;       /* relative to the bounding box diagonal, 0 = unchecked */
  int engine;                 /* 0 = parallel rounds (default), 1 = sequential reference */
  int num_threads;            /* 0 = all cores / the caller's arena; the result is the same for every value */
  double round_fraction;      /* default 0.015 */
  double feature_angle;       /* sharp edges kept as curves, degrees; default 45; 180 = none */
  double max_field_error;     /* field error bound per component, in its units; 0 = no limit */
  double max_field_error_rel; /* the same relative to each component's range; 0 = no limit */
  int field_weight_count;     /* entries below; 0 = every field weighs 1 in the cost */
  const char* const* field_weight_names; /* field names (as topotet_mesh_field_info gives them) */
  const double* field_weights;           /* their weights, >= 0 */
  int optimize;               /* after the collapses: 0 = none, 1 = light (default), 2 = full */
  int track_field_bounds;     /* 1 = keep the per-tet field error bounds without a limit and report
                                 them (topotet_mesh_field_bounds), as `--field-bounds`; default 0 */
  /* Called now and then with the fraction done (0..1), on any thread but never concurrently with
     itself; return 0 to cancel (TOPOTET_CANCELLED, the mesh valid and partly simplified). NULL = none. */
  int (*progress)(double done_fraction, void* user_data);
  void* progress_user_data;
  double min_dihedral;        /* degrees; no new tet below min(this, the smallest angle of the tets it
                                 replaces); default 5; 0 = no floor */
  double size_weight;         /* size term in the ranking of collapses (--size-weight); 0 = error only;
                                 negative = auto (default): 3e-4 when no field steers the cost, else 0 */
  int relax_tolerance;        /* 1 (default): where the tolerance would stop the run before its target, H
                                 doubles (the report gives the H that holds); 0: a hard limit */
  int relax_quality;          /* 1 (default): the same for min_quality and min_dihedral, halved; 0: hard */
  int relax_features;         /* 1 (default): where their corners would stop the run before its target, the
                                 feature curves lower than the relaxed H are dropped; 0: kept */
  int field_bound_mode;       /* what the field error bound covers: 0 = the original vertices (default), 1 =
                                 every point the output covers (needs a limit; a curved boundary stays) */
} topotet_options;

/* Same counters as topotet::Report. */
typedef struct topotet_report {
  topotet_status status;
  int64_t vertices_before, vertices_after;
  int64_t tets_before, tets_after;
  int64_t collapses, evaluations, legality_checks, rounds;
  /* rejected collapse placements, by reason */
  int64_t rejected_link_k, rejected_link_ktilde, rejected_pinned, rejected_inversion, rejected_quality,
      rejected_tolerance;
  double seconds;
  double max_cost;  /* largest accepted collapse cost */
  double tolerance; /* geometric tolerance used, mesh units; 0 = none */
  int64_t rejected_field_error;           /* placements refused by the field error bound */
  int64_t feature_edges, feature_corners; /* sharp edges kept as curves, vertices pinned at their corners */
  /* Why a run stopped before its target (status TOPOTET_STOPPED_EARLY; all 0 and empty when it
     reached it), as topotet::StopDiagnosis: the vertices left, by the check that holds each one,
     the pinned ones by cause, the dominant reason and one suggested change in words. */
  int64_t stop_vertices;
  int64_t held_topology, held_pinned, held_inversion, held_quality, held_tolerance, held_field_error,
      held_collapsible;
  int64_t pinned_corners, pinned_required, pinned_features, pinned_other;
  double stop_dominant_share;
  char stop_dominant[16];    /* "topology", "pinned", "inversion", "quality", "tolerance", ... */
  char stop_suggestion[512]; /* NUL-terminated (cut to fit) */
  int64_t optimize_moves, optimize_flips; /* the optimisation: vertices moved, flips and edge removals */
  /* Field error bounds (a field error limit or track_field_bounds): field_bounds 1 when they were
     kept, the largest bound relative to its component's range; per component from
     topotet_mesh_field_bounds. */
  int field_bounds;
  double field_bound_rel;
  /* The cell arrays' remap (topotet::CellRemapReport; all 0 when the mesh has none): (new tet,
     original tet) pairs with a positive overlap, new tets that overlapped no original tet of their
     material (given the nearest one's value), original tets that no new tet of their material
     covered (their amount went to the nearest), the covered share of the original volume, and its
     time (not included in seconds). */
  int64_t cell_overlap_pairs, cell_nearest_new_tets, cell_nearest_original_tets;
  double cell_covered_volume_fraction, cell_remap_seconds;
  /* The limits as asked and as they hold for the output (relax_tolerance, relax_quality), and how
     many times the run relaxed one to reach its target. */
  double tolerance_asked, min_quality_used, min_dihedral_used;
  int64_t relaxations;
  int64_t stop_beyond_reach; /* 1: the topology and the input's pinned vertices alone hold the target */
  int64_t features_dropped;  /* feature edges relaxing dropped (relax_features: lower than the relaxed H) */
  int64_t stall_flips;       /* flips made where the collapses stalled, held by inverted tets (optimize != none) */
  /* How far the quality floors may relax (relax_quality): min(asked floor, the input's worst tet). */
  double min_quality_lowest, min_dihedral_lowest;
} topotet_report;

typedef struct topotet_mesh topotet_mesh;

const char* topotet_version(void); /* TOPOTET_VERSION_STRING of the library actually linked */
const char* topotet_last_error(void);
const char* topotet_status_string(topotet_status status);

void topotet_mesh_arrays_init(topotet_mesh_arrays* arrays); /* everything absent, index_base 0 */
void topotet_options_init(topotet_options* options);        /* the defaults */

/* Builds a validated mesh from the caller's arrays (copied: the arrays may be freed afterwards). */
topotet_status topotet_mesh_build(const topotet_mesh_arrays* arrays, int num_threads, topotet_mesh** mesh);
/* Reads MEDIT .mesh(+.sol), Gmsh .msh (optionally .gz); writes .mesh, .msh, .vtu. Both keep the
 * per-tet arrays (SolAtTetrahedra, $ElementData; VTU CellData when written). */
topotet_status topotet_mesh_read(const char* path, int num_threads, topotet_mesh** mesh);
topotet_status topotet_mesh_write(const topotet_mesh* mesh, const char* path);
void topotet_mesh_free(topotet_mesh* mesh); /* NULL is allowed */

/* Isosurfaces as embedded surfaces (paper 001 section 6.1, topotet/isosurface.h): splits the tets
 * that the level sets field(component) = values[0..count-1] cross (component 0-based), so that each
 * level becomes a listed surface with a ref of its own (written to refs_out[i] when refs_out is not
 * NULL); a crossing within `snap` of an edge end moves onto that vertex (snap < 0: the default,
 * 1e-6). The mesh remembers the levels: every later topotet_simplify keeps their topology and
 * their vertices exactly on their values. New vertices come after the existing ones; the vertex map
 * is cleared. An unknown field, a component out of range or a non-finite value is an error that
 * leaves the mesh as it was. */
topotet_status topotet_mesh_embed_isosurfaces(topotet_mesh* mesh, const char* field, int component, const double* values,
                                              int count, double snap, int32_t* refs_out);

/* Simplifies in place and records the vertex map. options NULL = defaults; report may be NULL. */
topotet_status topotet_simplify(topotet_mesh* mesh, const topotet_options* options, topotet_report* report);

/* Sizes of the current mesh. */
int64_t topotet_mesh_vertex_count(const topotet_mesh* mesh);
int64_t topotet_mesh_tet_count(const topotet_mesh* mesh);
int topotet_mesh_field_count(const topotet_mesh* mesh);
/* Name (owned by the mesh) and component count of field i, 0 <= i < field count. */
topotet_status topotet_mesh_field_info(const topotet_mesh* mesh, int i, const char** name, int* components);
/* Per-tet arrays (topotet_mesh_arrays.cell_fields, or the file's: MEDIT SolAtTetrahedra, Gmsh
 * $ElementData, VTU CellData), aligned with the current tets: every topotet_simplify remaps them
 * from the mesh as it was before that call (rules in topotet_cell_kind; docs/library.md), and
 * topotet_mesh_embed_isosurfaces splits them with the tets. Name and kind as for fields; the values
 * (tet count x components doubles, library-owned) are NULL for an index out of range. */
int topotet_mesh_cell_field_count(const topotet_mesh* mesh);
topotet_status topotet_mesh_cell_field_info(const topotet_mesh* mesh, int i, const char** name, int* components,
                                            topotet_cell_kind* kind);
const double* topotet_mesh_cell_field_values(const topotet_mesh* mesh, int i);
/* Adds one array to the mesh (copied): row_count, the rows the caller's array has, must be the tet
 * count. The same checks as topotet_mesh_build; on error the mesh is unchanged. */
topotet_status topotet_mesh_add_cell_field(topotet_mesh* mesh, const topotet_cell_field_view* field, int64_t row_count);
/* Changes how array i is carried by the next topotet_simplify (a file stores labels as reals:
 * `--categorical`, amounts: `--extensive` on the CLI). */
topotet_status topotet_mesh_set_cell_field_kind(topotet_mesh* mesh, int i, topotet_cell_kind kind);
/* Field error bounds of the last topotet_simplify that kept them (report.field_bounds): the largest
 * over the output's tets per field component (fields in order, then components; field units);
 * NULL when it kept none. */
const double* topotet_mesh_field_bounds(const topotet_mesh* mesh);
/* Entries of the vertex map: the vertex count before the last topotet_simplify (0 before any). */
int64_t topotet_mesh_vertex_map_size(const topotet_mesh* mesh);

/* Library-owned arrays (no copy): positions as x,y,z per vertex, tets as 4 0-based uint32 per
 * tet, one material per tet, and the 0-based vertex map (UINT32_MAX for an input vertex that no
 * tet used). */
const double* topotet_mesh_positions(const topotet_mesh* mesh);
const uint32_t* topotet_mesh_tets(const topotet_mesh* mesh);
const int32_t* topotet_mesh_materials(const topotet_mesh* mesh);
const uint32_t* topotet_mesh_vertex_map(const topotet_mesh* mesh);

/* Copies into the caller's arrays (sized from the counts above), converting the types. */
topotet_status topotet_mesh_copy_positions(const topotet_mesh* mesh, topotet_out_view out);
topotet_status topotet_mesh_copy_tets(const topotet_mesh* mesh, topotet_out_view out, int index_base);
topotet_status topotet_mesh_copy_materials(const topotet_mesh* mesh, topotet_out_view out);
topotet_status topotet_mesh_copy_field(const topotet_mesh* mesh, int i, topotet_out_view out);
/* Cell array i, tet count rows of its components; an integer output takes only integer values. */
topotet_status topotet_mesh_copy_cell_field(const topotet_mesh* mesh, int i, topotet_out_view out);
/* For every input vertex of the last simplify, the output vertex it became or merged into. */
topotet_status topotet_mesh_copy_vertex_map(const topotet_mesh* mesh, topotet_out_view out, int index_base);

/* The listed surfaces and polylines of the current mesh (input triangles and segments, merged and
 * renamed by the collapses; implicit material interfaces are not listed), with their refs.
 * refs_out may have data == NULL. The counts are -1 when memory runs out (see topotet_last_error). */
int64_t topotet_mesh_triangle_count(const topotet_mesh* mesh);
int64_t topotet_mesh_segment_count(const topotet_mesh* mesh);
topotet_status topotet_mesh_copy_triangles(const topotet_mesh* mesh, topotet_out_view out, topotet_out_view refs_out,
                                           int index_base);
topotet_status topotet_mesh_copy_segments(const topotet_mesh* mesh, topotet_out_view out, topotet_out_view refs_out,
                                          int index_base);

/* Out of core (topotet/out_of_core.h, `topotet simplify --memory-limit`): a file larger than memory
 * simplified into another, the peak resident memory under a limit. The input is MEDIT (.mesh,
 * .mesh.gz, .meshb, with its .sol / .solb) or Gmsh MSH 4.1 with its fields (.msh, .msh.gz), streamed and cut into
 * pieces kept in a scratch folder, simplified with frozen borders and merged pairwise; the output is
 * written when complete (a failed run leaves none, nor the scratch folder). Field error bounds
 * (max_field_error*, track_field_bounds) hold at every input vertex as in core (report->field_bounds,
 * field_bound_rel); progress is not called. */
typedef struct topotet_out_of_core_options {
  int64_t memory_limit_bytes;  /* the peak resident memory to stay under; 0 = none (then pieces > 0) */
  int pieces;                  /* exactly this many pieces (a power of two <= 4096); 0 = from the limit */
  const char* scratch_parent;  /* where the scratch folder goes; NULL or "" = the output's folder */
  /* NULL or "" = none; else a .npy (int64) or .txt path: for every input vertex, the 0-based output
     vertex it became or merged into, -1 for a vertex no tet uses (topotet/vertex_map_file.h) */
  const char* vertex_map_path;
  /* Cell arrays carried as amounts (sums conserved) and as labels (largest overlap), by name, as
     the CLI's --extensive / --categorical; the rest are volume-averaged. */
  int extensive_count;
  const char* const* extensive_names;
  int categorical_count;
  const char* const* categorical_names;
  /* pieces of at most this many tets, at the cut and in every merge, whatever the limit allows
     (tests, benchmarks); 0 = from the limit */
  int64_t piece_tets;
} topotet_out_of_core_options;

typedef struct topotet_out_of_core_report {
  int pieces;                 /* after the cut */
  int pieces_left;            /* at the end: 1 unless the limit kept pieces apart */
  int levels;                 /* levels run (level 0 = the cut's pieces) */
  int64_t piece_tet_limit;    /* the memory model's largest piece */
  int64_t peak_rss_bytes;     /* measured (VmHWM) */
  int64_t scratch_peak_bytes; /* the scratch folder's largest size */
  double cut_seconds, write_seconds;
} topotet_out_of_core_report;

void topotet_out_of_core_options_init(topotet_out_of_core_options* ooc); /* no limit, no pieces, no map */
/* options NULL = the defaults; report and ooc_report may be NULL. A limit too small for the input, an
 * input it cannot stream or an option it cannot honour is TOPOTET_INVALID_INPUT before any work. */
topotet_status topotet_simplify_out_of_core(const char* input, const char* output, const topotet_options* options,
                                            const topotet_out_of_core_options* ooc, topotet_report* report,
                                            topotet_out_of_core_report* ooc_report);

#ifdef __cplusplus
}
#endif

#endif
