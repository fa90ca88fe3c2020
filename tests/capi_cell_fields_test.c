/* The C API's per-tet ("cell") arrays, compiled as C: a cube of 4^3 cells, 6 tets each, in two
 * materials (x < 2: material 2, else 1) with three arrays:
 *  - density, intensive, 3 components (.sol holds 1, 3, 6 or 9), constant per material: the output
 *    tets of a material keep the constant (exactly for components 0 and 2, whose constants are
 *    powers of two: an average of equal powers of two is exact in floating point; to 1e-14 for
 *    component 1's 7.85 and 2.7: the average's rounding);
 *  - region, categorical, int32: material * 10, which every output tet must equal;
 *  - mass, extensive: its sum is conserved to 1e-9 relative.
 * Then a .mesh + .sol round trip through topotet_mesh_write / topotet_mesh_read, a cancelled run
 * (the arrays follow the partly simplified mesh), and the errors: status + a message naming the
 * array. Usage: capi_cell_fields_test [DIR] (the files go to DIR, default "."). Exit 0 = pass. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include <topotet/topotet_c.h>

#include "capi_check.h"


enum { N = 4, NV = (N + 1) * (N + 1) * (N + 1), NT = 6 * N * N * N, MAX_T = NT };

static int32_t vid(const int c[3]) { return c[0] + (N + 1) * (c[1] + (N + 1) * c[2]); }

static double mass_sum(const topotet_mesh* mesh, int i) {
  const double* v = topotet_mesh_cell_field_values(mesh, i);
  double s = 0.0;
  for (int64_t t = 0; t < topotet_mesh_tet_count(mesh); ++t) s += v[t];
  return s;
}

static int cancel_calls = 0;
static int cancel_at_once(double done, void* user) {
  (void)done;
  ++*(int*)user;
  return 0;
}

/* Every output tet: density constant per material, region == 10 * material (checked on the
 * library-owned values and on a copy into int32). */
static int check_per_material(const topotet_mesh* mesh, int density, int region) {
  static int32_t materials[MAX_T * 4], labels[MAX_T];
  const int64_t nt = topotet_mesh_tet_count(mesh);
  CHECK(nt > 0 && nt <= MAX_T * 4);
  CHECK(topotet_mesh_copy_materials(mesh, (topotet_out_view){materials, TOPOTET_INT32, 0}) == TOPOTET_OK);
  CHECK(topotet_mesh_copy_cell_field(mesh, region, (topotet_out_view){labels, TOPOTET_INT32, 0}) == TOPOTET_OK);
  const double* d = topotet_mesh_cell_field_values(mesh, density);
  const double* r = topotet_mesh_cell_field_values(mesh, region);
  CHECK(d != NULL && r != NULL);
  for (int64_t t = 0; t < nt; ++t) {
    CHECK(materials[t] == 1 || materials[t] == 2);
    CHECK(d[3 * t] == (materials[t] == 1 ? 2.0 : 0.5) && d[3 * t + 2] == (materials[t] == 1 ? 0.25 : 1024.0));
    CHECK(fabs(d[3 * t + 1] - (materials[t] == 1 ? 7.85 : 2.7)) <= 1e-14 * 7.85);
    CHECK(r[t] == 10.0 * materials[t] && labels[t] == 10 * materials[t]);
  }
  return 0;
}

int main(int argc, char** argv) {
  const char* dir = argc > 1 ? argv[1] : ".";
  static double xyz[NV][3];
  static int32_t tets[NT][4], material[NT], region[NT];
  static double density[NT][3], mass[NT];
  for (int v = 0; v < NV; ++v) {
    xyz[v][0] = v % (N + 1);
    xyz[v][1] = v / (N + 1) % (N + 1);
    xyz[v][2] = v / ((N + 1) * (N + 1));
  }
  static const int order[6][3] = {{0, 1, 2}, {1, 2, 0}, {2, 0, 1}, {0, 2, 1}, {1, 0, 2}, {2, 1, 0}};
  double mass_in = 0.0;
  int t = 0;
  for (int cube = 0; cube < N * N * N; ++cube)
    for (int p = 0; p < 6; ++p, ++t) {
      int c[3] = {cube % N, cube / N % N, cube / (N * N)};
      material[t] = c[0] < N / 2 ? 2 : 1;
      region[t] = 10 * material[t];
      density[t][0] = material[t] == 1 ? 2.0 : 0.5;
      density[t][1] = material[t] == 1 ? 7.85 : 2.7;
      density[t][2] = material[t] == 1 ? 0.25 : 1024.0;
      mass[t] = 1.0 + 0.37 * (t % 11) + 0.01 * c[2]; /* uneven, so that the sharing matters */
      mass_in += mass[t];
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

  topotet_cell_field_view cells[3] = {
      {"density", 3, TOPOTET_CELL_INTENSIVE, {density, TOPOTET_FLOAT64, 0}},
      {"region", 1, TOPOTET_CELL_CATEGORICAL, {region, TOPOTET_INT32, 0}},
      {"mass", 1, TOPOTET_CELL_EXTENSIVE, {mass, TOPOTET_FLOAT64, 0}},
  };
  topotet_mesh_arrays in;
  topotet_mesh_arrays_init(&in);
  CHECK(in.cell_field_count == 0 && in.cell_fields == NULL); /* absent by default */
  in.vertex_count = NV;
  in.positions = (topotet_view){xyz, TOPOTET_FLOAT64, 0};
  in.tet_count = NT;
  in.tets = (topotet_view){tets, TOPOTET_INT32, 0};
  in.materials = (topotet_view){material, TOPOTET_INT32, 0};
  in.cell_field_count = 3;
  in.cell_fields = cells;
  topotet_mesh* mesh = NULL;
  CHECK(topotet_mesh_build(&in, 1, &mesh) == TOPOTET_OK);
  CHECK(topotet_mesh_cell_field_count(mesh) == 3);
  const char* name = NULL;
  int components = 0;
  topotet_cell_kind kind = TOPOTET_CELL_INTENSIVE;
  CHECK(topotet_mesh_cell_field_info(mesh, 1, &name, &components, &kind) == TOPOTET_OK);
  CHECK(strcmp(name, "region") == 0 && components == 1 && kind == TOPOTET_CELL_CATEGORICAL);
  CHECK(topotet_mesh_cell_field_values(mesh, 0)[3 * 5 + 1] == density[5][1]);
  CHECK(topotet_mesh_cell_field_values(mesh, 3) == NULL);

  /* An invalid option changes nothing, the arrays included. */
  topotet_options options;
  topotet_options_init(&options);
  options.target_vertex_ratio = 2.0;
  CHECK(topotet_simplify(mesh, &options, NULL) == TOPOTET_INVALID_INPUT);
  CHECK(topotet_mesh_cell_field_count(mesh) == 3 && topotet_mesh_tet_count(mesh) == NT);
  CHECK(memcmp(topotet_mesh_cell_field_values(mesh, 2), mass, sizeof mass) == 0);

  options.target_vertex_ratio = 0.3;
  options.num_threads = 2;
  topotet_report report;
  const topotet_status status = topotet_simplify(mesh, &options, &report);
  CHECK(status == TOPOTET_OK || status == TOPOTET_STOPPED_EARLY);
  const int64_t nt = topotet_mesh_tet_count(mesh);
  CHECK(nt < NT / 2 && nt == report.tets_after);
  CHECK(topotet_mesh_cell_field_count(mesh) == 3);
  CHECK(topotet_mesh_cell_field_info(mesh, 2, &name, &components, &kind) == TOPOTET_OK);
  CHECK(strcmp(name, "mass") == 0 && components == 1 && kind == TOPOTET_CELL_EXTENSIVE);
  if (check_per_material(mesh, 0, 1)) return 1;
  const double mass_out = mass_sum(mesh, 2);
  CHECK(fabs(mass_out - mass_in) <= 1e-9 * mass_in);
  /* The remap's counters: every output tet overlaps at least one input tet; the volume is covered. */
  CHECK(report.cell_overlap_pairs >= nt && report.cell_nearest_new_tets >= 0 && report.cell_nearest_original_tets >= 0);
  CHECK(report.cell_covered_volume_fraction > 0.99 && report.cell_covered_volume_fraction < 1.0 + 1e-9);
  CHECK(report.cell_remap_seconds >= 0.0 && report.field_bounds == 0);
  /* A float32 copy of a real array; an integer copy of a non-integer one is refused. */
  static float density32[MAX_T][3];
  static int32_t no_ints[MAX_T];
  CHECK(topotet_mesh_copy_cell_field(mesh, 0, (topotet_out_view){density32, TOPOTET_FLOAT32, 0}) == TOPOTET_OK);
  CHECK(density32[nt - 1][1] == (float)topotet_mesh_cell_field_values(mesh, 0)[3 * (nt - 1) + 1]);
  CHECK(topotet_mesh_copy_cell_field(mesh, 0, (topotet_out_view){no_ints, TOPOTET_INT32, 0}) == TOPOTET_INVALID_INPUT);
  CHECK(strstr(topotet_last_error(), "density") != NULL);

  /* Round trip: out.mesh + out.sol (SolAtTetrahedra) + out.sol.fields.txt (names, categorical). */
  char path[4096];
  snprintf(path, sizeof path, "%s/capi_cell_fields.mesh", dir);
  CHECK(topotet_mesh_write(mesh, path) == TOPOTET_OK);
  topotet_mesh* back = NULL;
  CHECK(topotet_mesh_read(path, 1, &back) == TOPOTET_OK);
  CHECK(topotet_mesh_tet_count(back) == nt && topotet_mesh_cell_field_count(back) == 3);
  static const char* names[3] = {"density", "region", "mass"};
  /* MEDIT keeps the categorical mark, not the extensive one: mass comes back intensive. */
  static const topotet_cell_kind kinds[3] = {TOPOTET_CELL_INTENSIVE, TOPOTET_CELL_CATEGORICAL, TOPOTET_CELL_INTENSIVE};
  for (int i = 0; i < 3; ++i) {
    const char* read_name = NULL;
    int read_components = 0;
    CHECK(topotet_mesh_cell_field_info(back, i, &read_name, &read_components, &kind) == TOPOTET_OK);
    CHECK(strcmp(read_name, names[i]) == 0 && read_components == (i == 0 ? 3 : 1) && kind == kinds[i]);
    CHECK(memcmp(topotet_mesh_cell_field_values(back, i), topotet_mesh_cell_field_values(mesh, i),
                 (size_t)(nt * read_components) * sizeof(double)) == 0);
  }
  CHECK(topotet_mesh_set_cell_field_kind(back, 2, TOPOTET_CELL_EXTENSIVE) == TOPOTET_OK);
  CHECK(topotet_mesh_set_cell_field_kind(back, 2, (topotet_cell_kind)9) == TOPOTET_INVALID_INPUT);
  CHECK(strstr(topotet_last_error(), "'mass': unknown kind 9") != NULL);
  CHECK(topotet_mesh_set_cell_field_kind(back, 3, TOPOTET_CELL_EXTENSIVE) == TOPOTET_INVALID_INPUT);
  /* The read mesh simplifies further with the same guarantees. */
  options.target_vertex_ratio = 0.6;
  const topotet_status again = topotet_simplify(back, &options, &report);
  CHECK(again == TOPOTET_OK || again == TOPOTET_STOPPED_EARLY);
  CHECK(topotet_mesh_tet_count(back) < nt);
  if (check_per_material(back, 0, 1)) return 1;
  CHECK(fabs(mass_sum(back, 2) - mass_in) <= 1e-9 * mass_in);
  topotet_mesh_free(back);
  topotet_mesh_free(mesh);

  /* A run cancelled after its first round: the arrays follow the partly simplified mesh. */
  CHECK(topotet_mesh_build(&in, 1, &mesh) == TOPOTET_OK);
  topotet_options_init(&options);
  options.num_threads = 1;
  options.progress = cancel_at_once;
  options.progress_user_data = &cancel_calls;
  CHECK(topotet_simplify(mesh, &options, &report) == TOPOTET_CANCELLED);
  CHECK(report.status == TOPOTET_CANCELLED && cancel_calls == 1 && strstr(topotet_last_error(), "cancel") != NULL);
  CHECK(topotet_mesh_tet_count(mesh) < NT && topotet_mesh_cell_field_count(mesh) == 3);
  if (check_per_material(mesh, 0, 1)) return 1;
  CHECK(fabs(mass_sum(mesh, 2) - mass_in) <= 1e-9 * mass_in);
  /* Added after the build, from float32: the same checks; a duplicate leaves the mesh as it was. */
  static float temperature[MAX_T];
  for (int64_t i = 0; i < topotet_mesh_tet_count(mesh); ++i) temperature[i] = 300.0f;
  topotet_cell_field_view extra = {"temperature", 1, TOPOTET_CELL_INTENSIVE, {temperature, TOPOTET_FLOAT32, 0}};
  const int64_t cancelled_nt = topotet_mesh_tet_count(mesh);
  CHECK(topotet_mesh_add_cell_field(mesh, &extra, NT) == TOPOTET_INVALID_INPUT && topotet_mesh_cell_field_count(mesh) == 3);
  CHECK(strstr(topotet_last_error(), "'temperature': 384 rows for ") != NULL);
  CHECK(topotet_mesh_add_cell_field(mesh, &extra, cancelled_nt) == TOPOTET_OK && topotet_mesh_cell_field_count(mesh) == 4);
  CHECK(topotet_mesh_cell_field_values(mesh, 3)[cancelled_nt - 1] == 300.0);
  CHECK(topotet_mesh_add_cell_field(mesh, &extra, cancelled_nt) == TOPOTET_INVALID_INPUT && topotet_mesh_cell_field_count(mesh) == 4);
  CHECK(strstr(topotet_last_error(), "'temperature': the name is given twice") != NULL);
  topotet_mesh_free(mesh);

  /* Errors at the build: a status, no mesh, and a message naming the array. */
  topotet_mesh* bad = (topotet_mesh*)&in;
  cells[2].name = "density";
  CHECK(topotet_mesh_build(&in, 1, &bad) == TOPOTET_INVALID_INPUT && bad == NULL);
  CHECK(strstr(topotet_last_error(), "'density': the name is given twice") != NULL);
  cells[2].name = "mass";
  cells[1].kind = (topotet_cell_kind)7;
  CHECK(topotet_mesh_build(&in, 1, &bad) == TOPOTET_INVALID_INPUT);
  CHECK(strstr(topotet_last_error(), "'region': unknown kind 7") != NULL);
  cells[1].kind = TOPOTET_CELL_CATEGORICAL;
  mass[17] = NAN;
  CHECK(topotet_mesh_build(&in, 1, &bad) == TOPOTET_INVALID_INPUT);
  CHECK(strstr(topotet_last_error(), "'mass'") != NULL && strstr(topotet_last_error(), "tet 18, component 1 is not finite") != NULL &&
        strstr(topotet_last_error(), "not finite") != NULL);
  mass[17] = INFINITY;
  CHECK(topotet_mesh_build(&in, 1, &bad) == TOPOTET_INVALID_INPUT && strstr(topotet_last_error(), "not finite") != NULL);
  mass[17] = 1.0;
  cells[0].components = 0;
  CHECK(topotet_mesh_build(&in, 1, &bad) == TOPOTET_INVALID_INPUT);
  CHECK(strstr(topotet_last_error(), "'density': components must be >= 1") != NULL);
  cells[0].components = 3;
  cells[2].values.data = NULL;
  CHECK(topotet_mesh_build(&in, 1, &bad) == TOPOTET_INVALID_INPUT);
  CHECK(strstr(topotet_last_error(), "'mass': values not given") != NULL);
  cells[2].values.data = mass;
  cells[2].values.type = (topotet_type)11;
  CHECK(topotet_mesh_build(&in, 1, &bad) == TOPOTET_INVALID_INPUT);
  CHECK(strstr(topotet_last_error(), "'mass': unknown element type") != NULL);
  cells[2].values.type = TOPOTET_FLOAT64;
  in.cell_field_count = -1;
  CHECK(topotet_mesh_build(&in, 1, &bad) == TOPOTET_INVALID_INPUT);
  CHECK(strstr(topotet_last_error(), "cell_field_count") != NULL);
  in.cell_field_count = 1;
  in.cell_fields = NULL;
  CHECK(topotet_mesh_build(&in, 1, &bad) == TOPOTET_INVALID_INPUT);
  CHECK(strstr(topotet_last_error(), "cell_fields not given") != NULL);
  CHECK(topotet_mesh_cell_field_info(NULL, 0, &name, &components, &kind) == TOPOTET_INVALID_INPUT);
  CHECK(topotet_mesh_cell_field_count(NULL) == 0 && topotet_mesh_cell_field_values(NULL, 0) == NULL);
  CHECK(topotet_mesh_add_cell_field(NULL, &extra, 0) == TOPOTET_INVALID_INPUT);

  printf("capi_cell_fields_test: %d -> %lld tets, mass %.12g -> %.12g: pass\n", NT, (long long)nt, mass_in, mass_out);
  return 0;
}
