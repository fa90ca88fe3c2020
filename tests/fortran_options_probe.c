/* The C side of tests/fortran_cell_fields_test.f90: the sizes of the C structs, and every field
 * of a topotet_options as C reads it, so that the Fortran program can compare them with its own
 * bind(c) types (a field the Fortran type misplaces or lacks reads differently here). */
#include <stddef.h>

#include <topotet/topotet_c.h>

size_t topotet_probe_sizeof(int which) {
  switch (which) {
    case 0: return sizeof(topotet_options);
    case 1: return sizeof(topotet_report);
    case 2: return sizeof(topotet_mesh_arrays);
    case 3: return sizeof(topotet_cell_field_view);
    case 4: return sizeof(topotet_out_of_core_options);
    case 5: return sizeof(topotet_out_of_core_report);
    default: return 0;
  }
}

/* The fields of *options (NULL: of a fresh topotet_options_init) in declaration order, as doubles
 * (pointers as 1 = set, 0 = NULL). Returns the count (27), or -1 when capacity is too small. */
int topotet_probe_options(const topotet_options* options, double* values, int capacity) {
  topotet_options fresh;
  if (options == NULL) {
    topotet_options_init(&fresh);
    options = &fresh;
  }
  const double v[] = {options->target_vertex_ratio,
                      (double)options->target_vertices,
                      options->max_cost,
                      options->min_quality,
                      options->boundary_weight,
                      options->polyline_weight,
                      options->tolerance,
                      options->tolerance_rel,
                      options->engine,
                      options->num_threads,
                      options->round_fraction,
                      options->feature_angle,
                      options->max_field_error,
                      options->max_field_error_rel,
                      options->field_weight_count,
                      options->field_weight_names != NULL,
                      options->field_weights != NULL,
                      options->optimize,
                      options->track_field_bounds,
                      options->progress != NULL,
                      options->progress_user_data != NULL,
                      options->min_dihedral,
                      options->size_weight,
                      options->relax_tolerance,
                      options->relax_quality,
                      options->relax_features,
                      options->field_bound_mode};
  const int n = (int)(sizeof v / sizeof v[0]);
  if (capacity < n) return -1;
  for (int i = 0; i < n; ++i) values[i] = v[i];
  return n;
}
