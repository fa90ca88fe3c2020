/* The C API's out-of-core entry (topotet_simplify_out_of_core), compiled as C: a grid built from
 * arrays and written as MEDIT, simplified out of core in 4 pieces with a vertex map; the report,
 * the output (read back) and the map agree; the errors are a status and a message naming what is
 * wrong, and leave no output. Exit status 0 = pass.
 *   usage: capi_out_of_core_test FOLDER */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <topotet/topotet_c.h>

#include "capi_check.h"


enum { N = 14, NV = (N + 1) * (N + 1) * (N + 1), NT = 6 * N * N * N };

static int32_t vid(int i, int j, int k) { return i + (N + 1) * (j + (N + 1) * k); }

int main(int argc, char** argv) {
  if (argc != 2) return 2;
  static double xyz[NV][3], temperature[NV];
  static int32_t tets[NT][4];
  for (int v = 0; v < NV; ++v) {
    xyz[v][0] = v % (N + 1);
    xyz[v][1] = v / (N + 1) % (N + 1);
    xyz[v][2] = v / ((N + 1) * (N + 1));
    temperature[v] = xyz[v][0] * xyz[v][1] + xyz[v][2];
  }
  /* Kuhn's 6 tets per cube, all positively oriented. */
  static const int order[6][3] = {{0, 1, 2}, {1, 2, 0}, {2, 0, 1}, {0, 2, 1}, {1, 0, 2}, {2, 1, 0}};
  int t = 0;
  for (int cube = 0; cube < N * N * N; ++cube)
    for (int p = 0; p < 6; ++p, ++t) {
      int c[3] = {cube % N, cube / N % N, cube / (N * N)};
      tets[t][0] = vid(c[0], c[1], c[2]);
      for (int s = 0; s < 3; ++s) {
        ++c[order[p][s]];
        tets[t][s + 1] = vid(c[0], c[1], c[2]);
      }
      if (p >= 3) {
        const int32_t swap = tets[t][2];
        tets[t][2] = tets[t][3];
        tets[t][3] = swap;
      }
    }
  topotet_field_view field = {"temperature", 1, {temperature, TOPOTET_FLOAT64, 0}};
  topotet_mesh_arrays in;
  topotet_mesh_arrays_init(&in);
  in.vertex_count = NV;
  in.positions = (topotet_view){xyz, TOPOTET_FLOAT64, 0};
  in.tet_count = NT;
  in.tets = (topotet_view){tets, TOPOTET_INT32, 0};
  in.field_count = 1;
  in.fields = &field;
  topotet_mesh* mesh = NULL;
  CHECK(topotet_mesh_build(&in, 0, &mesh) == TOPOTET_OK);
  char input[4096], output[4096], map_path[4096];
  snprintf(input, sizeof input, "%s/capi_ooc_in.mesh", argv[1]);
  snprintf(output, sizeof output, "%s/capi_ooc_out.mesh", argv[1]);
  snprintf(map_path, sizeof map_path, "%s/capi_ooc_map.txt", argv[1]);
  CHECK(topotet_mesh_write(mesh, input) == TOPOTET_OK);
  topotet_mesh_free(mesh);
  remove(output);

  topotet_options options;
  topotet_options_init(&options);
  options.target_vertex_ratio = 0.2;
  options.optimize = 0;
  topotet_out_of_core_options ooc;
  topotet_out_of_core_options_init(&ooc);
  CHECK(ooc.memory_limit_bytes == 0 && ooc.pieces == 0 && ooc.vertex_map_path == NULL);
  /* Neither a limit nor pieces: refused before any work. */
  topotet_report report;
  CHECK(topotet_simplify_out_of_core(input, output, &options, &ooc, &report, NULL) == TOPOTET_INVALID_INPUT);
  CHECK(strstr(topotet_last_error(), "memory limit") != NULL);
  ooc.pieces = 4;
  ooc.vertex_map_path = map_path;
  topotet_out_of_core_report pieces;
  const topotet_status status = topotet_simplify_out_of_core(input, output, &options, &ooc, &report, &pieces);
  CHECK(status == TOPOTET_OK || status == TOPOTET_STOPPED_EARLY);
  CHECK(report.status == status && report.vertices_before == NV && report.tets_before == NT);
  CHECK(report.vertices_after < NV / 3 && report.collapses > 0 && report.tolerance > 0.0);
  CHECK(pieces.pieces == 4 && pieces.pieces_left == 1 && pieces.levels == 3);
  CHECK(pieces.peak_rss_bytes > 0 && pieces.scratch_peak_bytes > 0);
  topotet_mesh* out = NULL;
  CHECK(topotet_mesh_read(output, 0, &out) == TOPOTET_OK);
  const int64_t nv = topotet_mesh_vertex_count(out);
  CHECK(nv == report.vertices_after && topotet_mesh_tet_count(out) == report.tets_after);
  CHECK(topotet_mesh_field_count(out) == 1);
  topotet_mesh_free(out);
  /* The map: a comment line, then one output vertex per input vertex, onto the output. */
  FILE* f = fopen(map_path, "r");
  CHECK(f != NULL);
  char line[512];
  CHECK(fgets(line, sizeof line, f) != NULL && line[0] == '#');
  static char hit[NV];
  int64_t entries = 0, o = 0;
  while (fscanf(f, "%lld", (long long*)&o) == 1) {
    CHECK(o >= 0 && o < nv);
    hit[o] = 1;
    ++entries;
  }
  fclose(f);
  CHECK(entries == NV);
  for (int64_t v = 0; v < nv; ++v) CHECK(hit[v]);

  /* Errors: a status, a message naming the problem, no output. */
  remove(output);
  ooc.vertex_map_path = "map.csv";
  CHECK(topotet_simplify_out_of_core(input, output, &options, &ooc, NULL, NULL) == TOPOTET_INVALID_INPUT);
  CHECK(strstr(topotet_last_error(), "map.csv") != NULL);
  ooc.vertex_map_path = NULL;
  CHECK(report.field_bounds == 0);
  /* A field error limit holds out of core: the report gives the bound (at every input vertex). */
  options.max_field_error_rel = 0.001;
  const topotet_status bounded = topotet_simplify_out_of_core(input, output, &options, &ooc, &report, NULL);
  CHECK(bounded == TOPOTET_OK || bounded == TOPOTET_STOPPED_EARLY);
  CHECK(report.field_bounds == 1 && report.field_bound_rel > 0.0 && report.field_bound_rel <= 0.001);
  remove(output);
  options.max_field_error_rel = 0.0;
  /* Pieces of at most 30% of the tets (piece_tets): two halves at 30% of their vertices no longer
     fit together; a seam joins them (more than two pieces left) and the target is reached. */
  ooc.pieces = 2;
  ooc.piece_tets = NT * 3 / 10;
  options.target_vertex_ratio = 0.3;
  CHECK(topotet_simplify_out_of_core(input, output, &options, &ooc, &report, &pieces) == TOPOTET_OK);
  CHECK(pieces.pieces_left >= 3 && report.vertices_after <= NV * 31 / 100);
  remove(output);
  ooc.piece_tets = -1;
  CHECK(topotet_simplify_out_of_core(input, output, &options, &ooc, NULL, NULL) == TOPOTET_INVALID_INPUT);
  CHECK(strstr(topotet_last_error(), "piece_tets") != NULL);
  ooc.piece_tets = 0;
  ooc.pieces = 3;
  CHECK(topotet_simplify_out_of_core(input, output, &options, &ooc, NULL, NULL) == TOPOTET_INVALID_INPUT);
  CHECK(strstr(topotet_last_error(), "power of two") != NULL);
  CHECK(topotet_simplify_out_of_core(NULL, output, &options, &ooc, NULL, NULL) == TOPOTET_INVALID_INPUT);
  CHECK(fopen(output, "r") == NULL);
  printf("capi_out_of_core_test: %d -> %lld vertices in %d pieces, %d levels: pass\n", NV, (long long)nv, pieces.pieces,
         pieces.levels);
  return 0;
}
