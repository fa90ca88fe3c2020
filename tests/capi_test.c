/* The C API, compiled as C: strided float32 positions inside an array of structs, 0-based int32
 * tets, a field, the library-owned and the caller-provided results, the vertex map, embedded
 * isosurfaces, and the errors (status + message, never a crash). Exit status 0 = pass. */
#include <stdio.h>
#include <string.h>

#include <topotet/topotet_c.h>

#include "capi_check.h"


enum { N = 4, NV = (N + 1) * (N + 1) * (N + 1), NT = 6 * N * N * N };

struct Vertex { /* a solver's own vertex record: the positions are strided */
  int id;
  float x[3];
  double temperature;
};

static int32_t vid(const int c[3]) { return c[0] + (N + 1) * (c[1] + (N + 1) * c[2]); }

int main(void) {
  static struct Vertex vertices[NV];
  static int32_t tets[NT][4];
  for (int v = 0; v < NV; ++v) {
    vertices[v].id = v;
    vertices[v].x[0] = (float)(v % (N + 1));
    vertices[v].x[1] = (float)(v / (N + 1) % (N + 1));
    vertices[v].x[2] = (float)(v / ((N + 1) * (N + 1)));
    vertices[v].temperature = vertices[v].x[0] + 2.0 * vertices[v].x[1];
  }
  static const int order[6][3] = {{0, 1, 2}, {1, 2, 0}, {2, 0, 1}, {0, 2, 1}, {1, 0, 2}, {2, 1, 0}};
  int t = 0;
  for (int cube = 0; cube < N * N * N; ++cube)
    for (int p = 0; p < 6; ++p, ++t) {
      int c[3] = {cube % N, cube / N % N, cube / (N * N)};
      tets[t][0] = vid(c);
      for (int s = 0; s < 3; ++s) {
        ++c[order[p][s]];
        tets[t][s + 1] = vid(c);
      }
      if (p >= 3) {
        const int32_t swap = tets[t][2];
        tets[t][2] = tets[t][3];
        tets[t][3] = swap;
      }
    }

  /* Listed substructures: the bottom face (ref 3) and a polyline along x through the middle (ref 7). */
  static int64_t triangles[2 * N * N][3], segments[N][2];
  static int32_t triangle_refs[2 * N * N], segment_refs[N];
  for (int i = 0; i < N; ++i)
    for (int j = 0; j < N; ++j) {
      const int c00[3] = {i, j, 0}, c10[3] = {i + 1, j, 0}, c01[3] = {i, j + 1, 0}, c11[3] = {i + 1, j + 1, 0};
      const int64_t tri[2][3] = {{vid(c00), vid(c11), vid(c10)}, {vid(c00), vid(c01), vid(c11)}};
      memcpy(triangles[2 * (i * N + j)], tri, sizeof tri);
      triangle_refs[2 * (i * N + j)] = triangle_refs[2 * (i * N + j) + 1] = 3;
    }
  for (int i = 0; i < N; ++i) {
    const int a[3] = {i, N / 2, N / 2}, b[3] = {i + 1, N / 2, N / 2};
    segments[i][0] = vid(a);
    segments[i][1] = vid(b);
    segment_refs[i] = 7;
  }

  topotet_field_view temperature = {"temperature", 1, {&vertices[0].temperature, TOPOTET_FLOAT64, sizeof(struct Vertex)}};
  topotet_mesh_arrays in;
  topotet_mesh_arrays_init(&in);
  in.vertex_count = NV;
  in.positions = (topotet_view){vertices[0].x, TOPOTET_FLOAT32, sizeof(struct Vertex)};
  in.tet_count = NT;
  in.tets = (topotet_view){tets, TOPOTET_INT32, 0};
  in.triangle_count = 2 * N * N;
  in.triangles = (topotet_view){triangles, TOPOTET_INT64, 0};
  in.triangle_refs = (topotet_view){triangle_refs, TOPOTET_INT32, 0};
  in.segment_count = N;
  in.segments = (topotet_view){segments, TOPOTET_INT64, 0};
  in.segment_refs = (topotet_view){segment_refs, TOPOTET_INT32, 0};
  in.field_count = 1;
  in.fields = &temperature;
  topotet_mesh* mesh = NULL;
  CHECK(topotet_mesh_build(&in, 1, &mesh) == TOPOTET_OK);
  CHECK(topotet_mesh_vertex_count(mesh) == NV);
  CHECK(topotet_mesh_tet_count(mesh) == NT);
  CHECK(topotet_mesh_positions(mesh)[3 * 7 + 1] == vertices[7].x[1]);
  CHECK(topotet_mesh_vertex_map_size(mesh) == 0);

  topotet_options options;
  topotet_options_init(&options);
  CHECK(options.target_vertex_ratio == 0.25 && options.min_quality > 0.0);
  /* The library's defaults, guarantees included: the same call gives the same run as C++ and the CLI. */
  CHECK(options.tolerance_rel == 0.004 && options.tolerance == 0.0 && options.feature_angle == 45.0);
  CHECK(options.max_field_error == 0.0 && options.max_field_error_rel == 0.0 && options.field_weight_count == 0);
  CHECK(options.optimize == 1); /* light */
  options.target_vertex_ratio = 0.3;
  options.num_threads = 2;
  static const char* weighted[] = {"temperature"};
  static const double weights[] = {2.0};
  options.field_weight_count = 1;
  options.field_weight_names = weighted;
  options.field_weights = weights;
  topotet_report report;
  const topotet_status status = topotet_simplify(mesh, &options, &report);
  CHECK(status == TOPOTET_OK || status == TOPOTET_STOPPED_EARLY);
  CHECK(report.status == status);
  CHECK(report.vertices_before == NV && report.tets_before == NT);
  const int64_t nv = topotet_mesh_vertex_count(mesh), nt = topotet_mesh_tet_count(mesh);
  CHECK(nv == report.vertices_after && nt == report.tets_after);
  CHECK(nv < NV / 2 && report.collapses == NV - nv);
  CHECK(report.legality_checks > 0);
  CHECK(report.tolerance > 0.0 && report.rejected_field_error == 0); /* guarded; no field limit asked */

  /* The vertex map, both ways: library-owned 0-based, and copied 1-based into int64. */
  static int64_t map[NV];
  CHECK(topotet_mesh_vertex_map_size(mesh) == NV);
  CHECK(topotet_mesh_copy_vertex_map(mesh, (topotet_out_view){map, TOPOTET_INT64, 0}, 1) == TOPOTET_OK);
  const uint32_t* map0 = topotet_mesh_vertex_map(mesh);
  static int hit[NV];
  for (int v = 0; v < NV; ++v) {
    CHECK(map[v] >= 1 && map[v] <= nv);
    CHECK(map0[v] + 1 == map[v]);
    hit[map0[v]] = 1;
  }
  for (int64_t o = 0; o < nv; ++o) CHECK(hit[o]); /* every output vertex is some input vertex */

  /* Output tets into a strided int64 buffer (every other row used), checked against the owned ones. */
  static int64_t out_tets[2 * NT][4];
  CHECK(topotet_mesh_copy_tets(mesh, (topotet_out_view){out_tets, TOPOTET_INT64, 2 * sizeof out_tets[0]}, 0) == TOPOTET_OK);
  const uint32_t* owned = topotet_mesh_tets(mesh);
  for (int64_t i = 0; i < nt; ++i)
    for (int c = 0; c < 4; ++c) CHECK(out_tets[2 * i][c] == owned[4 * i + c] && owned[4 * i + c] < nv);
  static float out_xyz[NV][3];
  CHECK(topotet_mesh_copy_positions(mesh, (topotet_out_view){out_xyz, TOPOTET_FLOAT32, 0}) == TOPOTET_OK);
  CHECK(out_xyz[nv - 1][2] == (float)topotet_mesh_positions(mesh)[3 * (nv - 1) + 2]);

  /* The substructures survive, fewer, with their refs, as faces and edges of the output. */
  const int64_t nf = topotet_mesh_triangle_count(mesh), ns = topotet_mesh_segment_count(mesh);
  CHECK(nf > 0 && nf < 2 * N * N && ns > 0 && ns <= N);
  static int32_t out_triangles[2 * N * N][3], out_triangle_refs[2 * N * N];
  static int64_t out_segments[N][2];
  CHECK(topotet_mesh_copy_triangles(mesh, (topotet_out_view){out_triangles, TOPOTET_INT32, 0},
                                    (topotet_out_view){out_triangle_refs, TOPOTET_INT32, 0}, 1) == TOPOTET_OK);
  for (int64_t i = 0; i < nf; ++i) {
    CHECK(out_triangle_refs[i] == 3);
    for (int c = 0; c < 3; ++c) CHECK(out_triangles[i][c] >= 1 && out_triangles[i][c] <= nv);
  }
  CHECK(topotet_mesh_copy_segments(mesh, (topotet_out_view){out_segments, TOPOTET_INT64, 0},
                                   (topotet_out_view){NULL, TOPOTET_INT32, 0}, 0) == TOPOTET_OK);
  for (int64_t i = 0; i < ns; ++i) CHECK(out_segments[i][0] < nv && out_segments[i][1] < nv);

  /* The field survives, by name; a linear field stays linear at the kept vertices. */
  const char* name = NULL;
  int components = 0;
  CHECK(topotet_mesh_field_count(mesh) == 1);
  CHECK(topotet_mesh_field_info(mesh, 0, &name, &components) == TOPOTET_OK);
  CHECK(strcmp(name, "temperature") == 0 && components == 1);
  static double values[NV];
  CHECK(topotet_mesh_copy_field(mesh, 0, (topotet_out_view){values, TOPOTET_FLOAT64, 0}) == TOPOTET_OK);

  /* A target the substructures cannot reach: the report says what holds the vertices left. */
  if (status == TOPOTET_OK) CHECK(report.stop_vertices == 0 && report.stop_dominant[0] == 0); /* nothing to explain */
  topotet_options stuck = options;
  stuck.field_weight_count = 0;
  stuck.target_vertices = 2;
  CHECK(topotet_simplify(mesh, &stuck, &report) == TOPOTET_STOPPED_EARLY);
  CHECK(report.stop_vertices == report.vertices_after && report.stop_vertices > 2);
  CHECK(report.held_topology + report.held_pinned + report.held_inversion + report.held_quality +
            report.held_tolerance + report.held_field_error + report.held_collapsible ==
        report.stop_vertices);
  CHECK(report.stop_dominant[0] != 0 && report.stop_dominant_share > 0.0 && report.stop_dominant_share <= 1.0);
  CHECK(memchr(report.stop_suggestion, 0, sizeof report.stop_suggestion) != NULL);

  /* Errors: a status and a message naming the culprit; the handle is not touched. */
  CHECK(topotet_mesh_copy_field(mesh, 3, (topotet_out_view){values, TOPOTET_FLOAT64, 0}) == TOPOTET_INVALID_INPUT);
  CHECK(strstr(topotet_last_error(), "field 3") != NULL);
  CHECK(topotet_mesh_copy_tets(mesh, (topotet_out_view){values, TOPOTET_FLOAT64, 0}, 0) == TOPOTET_INVALID_INPUT);
  static const char* unknown[] = {"pressure"};
  options.field_weight_names = unknown;
  CHECK(topotet_simplify(mesh, &options, NULL) == TOPOTET_INVALID_INPUT);
  CHECK(strstr(topotet_last_error(), "pressure") != NULL);
  options.field_weight_count = 0;
  options.target_vertex_ratio = 2.0;
  CHECK(topotet_simplify(mesh, &options, NULL) == TOPOTET_INVALID_INPUT);
  CHECK(strstr(topotet_last_error(), "target_vertex_ratio") != NULL);
  topotet_mesh_free(mesh);

  /* Isosurfaces: temperature = x + 2y at 2.5 and 6.5 (through no vertex) become listed surfaces that
   * simplification keeps, every vertex of theirs exactly on its level. */
  topotet_mesh* iso = NULL;
  CHECK(topotet_mesh_build(&in, 1, &iso) == TOPOTET_OK);
  const double levels[2] = {2.5, 6.5};
  int32_t level_refs[2] = {0, 0};
  CHECK(topotet_mesh_embed_isosurfaces(iso, "temperature", 0, levels, 2, -1.0, level_refs) == TOPOTET_OK);
  CHECK(level_refs[0] != 3 && level_refs[1] != 3 && level_refs[0] != level_refs[1]);
  CHECK(topotet_mesh_vertex_count(iso) > NV && topotet_mesh_tet_count(iso) > NT);
  topotet_options iso_options;
  topotet_options_init(&iso_options);
  iso_options.num_threads = 1;
  iso_options.target_vertex_ratio = 0.5;
  const topotet_status iso_status = topotet_simplify(iso, &iso_options, NULL);
  CHECK(iso_status == TOPOTET_OK || iso_status == TOPOTET_STOPPED_EARLY);
  enum { ISO_MAX = 8192 };
  const int64_t iso_nv = topotet_mesh_vertex_count(iso), iso_nf = topotet_mesh_triangle_count(iso);
  CHECK(iso_nv <= ISO_MAX && iso_nf <= ISO_MAX);
  static int32_t iso_triangles[ISO_MAX][3], iso_refs[ISO_MAX];
  static double iso_values[ISO_MAX];
  CHECK(topotet_mesh_copy_triangles(iso, (topotet_out_view){iso_triangles, TOPOTET_INT32, 0},
                                    (topotet_out_view){iso_refs, TOPOTET_INT32, 0}, 0) == TOPOTET_OK);
  CHECK(topotet_mesh_copy_field(iso, 0, (topotet_out_view){iso_values, TOPOTET_FLOAT64, 0}) == TOPOTET_OK);
  int on_level[2] = {0, 0};
  for (int64_t i = 0; i < iso_nf; ++i)
    for (int l = 0; l < 2; ++l)
      if (iso_refs[i] == level_refs[l]) {
        ++on_level[l];
        for (int c = 0; c < 3; ++c) CHECK(iso_values[iso_triangles[i][c]] == levels[l]);
      }
  CHECK(on_level[0] > 0 && on_level[1] > 0);
  const int64_t iso_before = topotet_mesh_vertex_count(iso);
  CHECK(topotet_mesh_embed_isosurfaces(iso, "pressure", 0, levels, 1, -1.0, NULL) == TOPOTET_INVALID_INPUT);
  CHECK(strstr(topotet_last_error(), "pressure") != NULL && topotet_mesh_vertex_count(iso) == iso_before);
  topotet_mesh_free(iso);

  tets[5][2] = NV + 3; /* out of range */
  topotet_mesh* bad = (topotet_mesh*)&in; /* must be reset to NULL on failure */
  CHECK(topotet_mesh_build(&in, 0, &bad) == TOPOTET_INVALID_INPUT && bad == NULL);
  CHECK(strstr(topotet_last_error(), "out of range") != NULL);
  tets[5][2] = -1;
  in.index_base = 0;
  CHECK(topotet_mesh_build(&in, 0, &bad) == TOPOTET_INVALID_INPUT);
  /* elements are counted from 1, as in every message of the builder; the index in the caller's base */
  CHECK(strstr(topotet_last_error(), "tet 6: vertex index -1 out of range (index_base 0)") != NULL);
  in.index_base = 2;
  CHECK(topotet_mesh_build(&in, 0, &bad) == TOPOTET_INVALID_INPUT);
  /* A type member holding no enumerator (a caller's garbage): an error, read without loading it as
     the enum (UBSan's enum check runs this in CI) */
  tets[5][2] = 1;
  in.index_base = 0;
  const topotet_type positions_type = in.positions.type;
  const int garbage = 7;
  memcpy(&in.positions.type, &garbage, sizeof garbage);
  CHECK(topotet_mesh_build(&in, 0, &bad) == TOPOTET_INVALID_INPUT);
  CHECK(strstr(topotet_last_error(), "positions: unknown element type") != NULL);
  in.positions.type = positions_type;
  CHECK(topotet_mesh_read("/nonexistent/x.mesh", 0, &bad) == TOPOTET_INVALID_INPUT);
  CHECK(strstr(topotet_last_error(), "x.mesh") != NULL);
  CHECK(strcmp(topotet_version(), TOPOTET_VERSION_STRING) == 0);
  CHECK(strcmp(topotet_status_string(TOPOTET_INTERNAL_ERROR), "internal_error") == 0);
  topotet_mesh_free(NULL);
  printf("capi_test: %d -> %lld vertices, %d -> %lld tets: pass\n", NV, (long long)nv, NT, (long long)nt);
  return 0;
}
