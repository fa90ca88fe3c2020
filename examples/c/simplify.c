/* Simplifies a mesh held in this program's own arrays through the C API: a cube of 8^3 cells,
 * 6 tets each, with a ball of material 2 inside; tets numbered from 1, as a Fortran code would.
 * Usage: simplify_c [DIR]   (also writes DIR/in.mesh and DIR/out.mesh, for `topotet check`) */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <topotet/topotet_c.h>

enum { N = 8, NV = (N + 1) * (N + 1) * (N + 1), NT = 6 * N * N * N };

static int64_t vid(const int c[3]) { return c[0] + (N + 1) * (c[1] + (N + 1) * c[2]) + 1; }

int main(int argc, char** argv) {
  static double xyz[NV][3];
  static int64_t tets[NT][4];
  static int32_t material[NT];
  for (int v = 0; v < NV; ++v) {
    xyz[v][0] = v % (N + 1);
    xyz[v][1] = v / (N + 1) % (N + 1);
    xyz[v][2] = v / ((N + 1) * (N + 1));
  }
  /* Each cube: the 6 paths from its low corner to its high corner along the axes, in every order.
   * An odd axis order gives a negatively oriented tet: swap two corners. */
  static const int order[6][3] = {{0, 1, 2}, {1, 2, 0}, {2, 0, 1}, {0, 2, 1}, {1, 0, 2}, {2, 1, 0}};
  int t = 0;
  for (int cube = 0; cube < N * N * N; ++cube)
    for (int p = 0; p < 6; ++p, ++t) {
      int c[3] = {cube % N, cube / N % N, cube / (N * N)};
      const double dx = c[0] + 0.5 - N / 2.0, dy = c[1] + 0.5 - N / 2.0, dz = c[2] + 0.5 - N / 2.0;
      material[t] = dx * dx + dy * dy + dz * dz < 6.0 ? 2 : 1;
      tets[t][0] = vid(c);
      for (int s = 0; s < 3; ++s) {
        ++c[order[p][s]];
        tets[t][s + 1] = vid(c);
      }
      if (p >= 3) {
        const int64_t swap = tets[t][2];
        tets[t][2] = tets[t][3];
        tets[t][3] = swap;
      }
    }

  /* Per-tet arrays travel with the tets: the material as a label (each output tet takes the one of
   * the largest part of its volume) and an amount of heat, shared out so that its sum is kept. */
  static double heat[NT];
  double heat_in = 0.0;
  for (int i = 0; i < NT; ++i) heat_in += heat[i] = material[i] == 2 ? 3.0 : 1.0;
  const topotet_cell_field_view cells[2] = {{"region", 1, TOPOTET_CELL_CATEGORICAL, {material, TOPOTET_INT32, 0}},
                                            {"heat", 1, TOPOTET_CELL_EXTENSIVE, {heat, TOPOTET_FLOAT64, 0}}};

  topotet_mesh_arrays in;
  topotet_mesh_arrays_init(&in);
  in.vertex_count = NV;
  in.positions = (topotet_view){xyz, TOPOTET_FLOAT64, 0};
  in.tet_count = NT;
  in.tets = (topotet_view){tets, TOPOTET_INT64, 0};
  in.materials = (topotet_view){material, TOPOTET_INT32, 0};
  in.index_base = 1;
  in.cell_field_count = 2;
  in.cell_fields = cells;
  topotet_mesh* mesh = NULL;
  if (topotet_mesh_build(&in, 0, &mesh) != TOPOTET_OK) {
    fprintf(stderr, "build: %s\n", topotet_last_error());
    return 1;
  }
  char path[4096];
  if (argc > 1) {
    snprintf(path, sizeof path, "%s/in.mesh", argv[1]);
    if (topotet_mesh_write(mesh, path) != TOPOTET_OK) fprintf(stderr, "write: %s\n", topotet_last_error());
  }

  topotet_options options;
  topotet_options_init(&options);
  options.target_vertex_ratio = 0.2;
  topotet_report report;
  const topotet_status status = topotet_simplify(mesh, &options, &report);
  if (status != TOPOTET_OK && status != TOPOTET_STOPPED_EARLY) {
    fprintf(stderr, "simplify: %s\n", topotet_last_error());
    return 1;
  }

  /* The result in our own arrays (1-based, like the input), and where every input vertex went. */
  const int64_t nv = topotet_mesh_vertex_count(mesh), nt = topotet_mesh_tet_count(mesh);
  int64_t(*out_tets)[4] = malloc((size_t)nt * sizeof *out_tets);
  int64_t* map = malloc(NV * sizeof *map);
  topotet_mesh_copy_tets(mesh, (topotet_out_view){out_tets, TOPOTET_INT64, 0}, 1);
  topotet_mesh_copy_vertex_map(mesh, (topotet_out_view){map, TOPOTET_INT64, 0}, 1);
  const double* out_xyz = topotet_mesh_positions(mesh); /* owned by the mesh */
  double farthest = 0.0;
  for (int v = 0; v < NV; ++v) {
    if (map[v] < 1 || map[v] > nv) {
      fprintf(stderr, "vertex %d maps to %lld, not an output vertex\n", v + 1, (long long)map[v]);
      return 1;
    }
    const double* p = out_xyz + 3 * (map[v] - 1);
    farthest = fmax(farthest, hypot(hypot(p[0] - xyz[v][0], p[1] - xyz[v][1]), p[2] - xyz[v][2]));
  }
  /* The cell arrays on the output tets (owned by the mesh, in the order given): a region is a
   * material, and the heat's sum is the input's. */
  const double* region = topotet_mesh_cell_field_values(mesh, 0);
  const double* heat_out = topotet_mesh_cell_field_values(mesh, 1);
  const int32_t* out_material = topotet_mesh_materials(mesh);
  double heat_sum = 0.0;
  for (int64_t i = 0; i < nt; ++i) {
    heat_sum += heat_out[i];
    if (region[i] != out_material[i]) {
      fprintf(stderr, "tet %lld: region %g in material %d\n", (long long)i + 1, region[i], out_material[i]);
      return 1;
    }
  }
  if (fabs(heat_sum - heat_in) > 1e-9 * heat_in) {
    fprintf(stderr, "heat %.17g -> %.17g: not conserved\n", heat_in, heat_sum);
    return 1;
  }
  printf("%s: %lld -> %lld vertices, %lld -> %lld tets, farthest merge %.2f cells, heat %g kept\n",
         topotet_status_string(status), (long long)report.vertices_before, (long long)nv, (long long)report.tets_before,
         (long long)nt, farthest, heat_sum);
  if (argc > 1) {
    snprintf(path, sizeof path, "%s/out.mesh", argv[1]);
    if (topotet_mesh_write(mesh, path) != TOPOTET_OK) fprintf(stderr, "write: %s\n", topotet_last_error());
  }
  free(out_tets);
  free(map);
  topotet_mesh_free(mesh);
  return 0;
}
