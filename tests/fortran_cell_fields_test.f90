! The Fortran binding's cell arrays and options (issue #27):
!  - the bind(c) types have the C structs' sizes, topotet_options_init from Fortran gives the values
!    C reads from a fresh topotet_options_init, and every options field set by its Fortran name is
!    the field C reads (tests/fortran_options_probe.c is the C side);
!  - a cube of 4^3 cells, 6 tets each, in two materials (x < 2: 2, else 1), with a density
!    constant per material (intensive; powers of two, so the averages are exact), a label
!    material * 10 (categorical) and a mass (extensive): after topotet_simplify every output tet
!    keeps its material's density and label, and the mass sum is conserved to 1e-9;
!  - the errors name the array.
module fortran_cell_fields_callbacks
  use, intrinsic :: iso_c_binding
  implicit none
contains
  ! A progress callback: counts its calls in the integer(c_int) user_data points to, never cancels.
  integer(c_int) function count_progress(done, user_data) bind(c)
    real(c_double), value :: done
    type(c_ptr), value :: user_data
    integer(c_int), pointer :: calls
    call c_f_pointer(user_data, calls)
    calls = calls + merge(1, 0, done >= 0d0 .and. done <= 1d0)
    count_progress = 1
  end function
end module

program fortran_cell_fields_test
  use, intrinsic :: iso_c_binding
  use, intrinsic :: ieee_arithmetic, only: ieee_value, ieee_quiet_nan
  use topotet
  use fortran_cell_fields_callbacks
  use fortran_test_grid
  implicit none
  interface
    integer(c_size_t) function probe_sizeof(which) bind(c, name="topotet_probe_sizeof")
      import :: c_size_t, c_int
      integer(c_int), value :: which
    end function
    integer(c_int) function probe_options(options, values, capacity) bind(c, name="topotet_probe_options")
      import :: c_int, c_ptr, c_double
      type(c_ptr), value :: options  ! c_null_ptr: a fresh topotet_options_init
      real(c_double), intent(out) :: values(*)
      integer(c_int), value :: capacity
    end function
  end interface
  integer, parameter :: n = 4, nv = (n + 1)**3, nt = 6 * n**3, nopt = 27
  real(c_double), target :: xyz(3, nv), density(nt), mass(1, nt), c_values(32), bad(nt)
  integer(c_int32_t), target :: tets(4, nt), material(nt), label(nt)
  integer(c_int), target :: progress_calls
  character(kind=c_char, len=8), target :: density_name = "density"//c_null_char
  type(topotet_cell_field_view), target :: cells(1)
  type(topotet_mesh_arrays) :: in
  type(topotet_options), target :: options
  type(topotet_report) :: report
  type(topotet_out_of_core_options) :: ooc
  type(topotet_out_of_core_report) :: ooc_report
  type(c_ptr) :: mesh
  integer(c_int) :: status, components, kind
  integer(c_int32_t), allocatable, target :: out_material(:), out_label(:)
  real(c_double), allocatable, target :: out_mass(:)
  real(c_double), pointer :: out_density(:)
  character(:), allocatable :: name, message
  integer :: i, t, m
  real(c_double) :: expected(nopt), mass_out
  integer(c_size_t) :: sizes(6)

  ! --- the options: sizes, defaults, and every field's place ---
  sizes = [(probe_sizeof(i), i = 0, 5)]
  if (any([c_sizeof(options), c_sizeof(report), c_sizeof(in), c_sizeof(cells(1)), c_sizeof(ooc), c_sizeof(ooc_report)] &
          /= sizes)) &
    error stop "a bind(c) type's size differs from its C struct's"
  call topotet_options_init(options)
  if (probe_options(c_null_ptr, c_values, size(c_values)) /= nopt) error stop "the C probe knows another field count"
  if (maxval(abs(options_as_reals(options) - c_values(1:nopt))) > 0d0) then
    print '("Fortran: ", 27g12.5)', options_as_reals(options)
    print '("C:       ", 27g12.5)', c_values(1:nopt)
    error stop "topotet_options_init from Fortran differs from C's"
  end if
  ! Every field set through its Fortran name to its position (pointers: to something) reads so in C.
  options = topotet_options(1d0, 2_c_int64_t, 3d0, 4d0, 5d0, 6d0, 7d0, 8d0, 9, 10, 11d0, 12d0, 13d0, 14d0, 15, &
                            c_loc(xyz), c_loc(xyz), 18, 19, c_funloc(count_progress), c_loc(progress_calls), &
                            22d0, 23d0, 24, 25, 26, 27)
  expected = [(real(i, c_double), i = 1, nopt)]
  expected([16, 17, 20, 21]) = 1d0
  if (probe_options(c_loc(options), c_values, size(c_values)) /= nopt) error stop "probe"
  if (maxval(abs(c_values(1:nopt) - expected)) > 0d0) then
    print '("C reads: ", 27f5.0)', c_values(1:nopt)
    error stop "a topotet_options field of the Fortran type is not where C has it"
  end if

  ! --- the mesh and its cell arrays ---
  call kuhn_grid(n, xyz, tets)
  do t = 1, nt
    material(t) = merge(2, 1, mod((t - 1) / 6, n) < n / 2)  ! the cell's i < n / 2
    mass(1, t) = 1d0 + 0.37d0 * mod(t, 11) + 0.01d0 * ((t - 1) / (6 * n * n))  ! + 0.01 k
  end do
  density = merge(0.5d0, 2d0, material == 2)
  label = 10 * material
  bad = 0
  ! density through the arrays (a view, as C has it); label and mass added with the wrappers.
  cells(1) = topotet_cell_field_view(c_loc(density_name), 1, TOPOTET_CELL_INTENSIVE, &
                                     topotet_view(c_loc(density), TOPOTET_FLOAT64, 0))
  call topotet_mesh_arrays_init(in)
  if (in%cell_field_count /= 0 .or. c_associated(in%cell_fields)) error stop "cell arrays not absent by default"
  in%vertex_count = nv
  in%positions = topotet_view(c_loc(xyz), TOPOTET_FLOAT64, 0)
  in%tet_count = nt
  in%tets = topotet_view(c_loc(tets), TOPOTET_INT32, 0)
  in%materials = topotet_view(c_loc(material), TOPOTET_INT32, 0)
  in%index_base = 1
  in%cell_field_count = 1
  in%cell_fields = c_loc(cells)
  status = topotet_mesh_build(in, 1, mesh)
  if (status /= TOPOTET_OK) error stop topotet_error_message()
  if (topotet_mesh_add_cell_field(mesh, "label", TOPOTET_CELL_CATEGORICAL, label) /= TOPOTET_OK) &
    error stop topotet_error_message()
  if (topotet_mesh_add_cell_field(mesh, "mass", TOPOTET_CELL_EXTENSIVE, mass) /= TOPOTET_OK) &
    error stop topotet_error_message()
  if (topotet_mesh_cell_field_count(mesh) /= 3) error stop "not 3 cell arrays"

  call topotet_options_init(options)
  options%target_vertex_ratio = 0.3d0
  options%num_threads = 1
  progress_calls = 0
  options%progress = c_funloc(count_progress)
  options%progress_user_data = c_loc(progress_calls)
  status = topotet_simplify(mesh, options, report)
  if (status /= TOPOTET_OK .and. status /= TOPOTET_STOPPED_EARLY) error stop topotet_error_message()
  if (progress_calls == 0) error stop "the progress callback was not called"
  m = int(topotet_mesh_tet_count(mesh))
  if (m >= nt / 2 .or. m /= report%tets_after) error stop "not simplified"
  if (report%cell_overlap_pairs < m .or. report%cell_covered_volume_fraction < 0.99d0 .or. &
      report%cell_covered_volume_fraction > 1d0 + 1d-9) error stop "the remap's counters"

  status = topotet_mesh_cell_field_info(mesh, 1, name, components, kind)
  if (status /= TOPOTET_OK .or. name /= "label" .or. components /= 1 .or. kind /= TOPOTET_CELL_CATEGORICAL) &
    error stop "cell array 1 is not the categorical label"
  allocate (out_material(m), out_label(m), out_mass(m))
  status = topotet_mesh_copy_materials(mesh, topotet_out_view(c_loc(out_material), TOPOTET_INT32, 0))
  if (status /= TOPOTET_OK) error stop topotet_error_message()
  status = topotet_mesh_copy_cell_field(mesh, 1, topotet_out_view(c_loc(out_label), TOPOTET_INT32, 0))
  if (status /= TOPOTET_OK) error stop topotet_error_message()
  if (any(out_label /= 10 * out_material)) error stop "a label is not 10 x its tet's material"
  call c_f_pointer(topotet_mesh_cell_field_values(mesh, 0), out_density, [m])  ! owned by the mesh
  if (maxval(abs(out_density - merge(0.5d0, 2d0, out_material == 2))) > 0d0) error stop "a density left its material's constant"
  status = topotet_mesh_copy_cell_field(mesh, 2, topotet_out_view(c_loc(out_mass), TOPOTET_FLOAT64, 0))
  if (status /= TOPOTET_OK) error stop topotet_error_message()
  mass_out = sum(out_mass)
  if (abs(mass_out - sum(mass)) > 1d-9 * sum(mass)) error stop "the mass sum is not conserved"

  ! --- errors: a status and a message naming the array; the mesh keeps its arrays ---
  status = topotet_mesh_add_cell_field(mesh, "label", TOPOTET_CELL_CATEGORICAL, out_label)
  message = topotet_error_message()
  if (status /= TOPOTET_INVALID_INPUT .or. index(message, "'label': the name is given twice") == 0) &
    error stop "a duplicate name is not refused"
  status = topotet_mesh_add_cell_field(mesh, "bad", TOPOTET_CELL_INTENSIVE, bad)  ! nt rows, not m
  message = topotet_error_message()
  if (status /= TOPOTET_INVALID_INPUT .or. index(message, "'bad': 384 rows for") == 0) &
    error stop "a wrong row count is not refused"
  out_mass(m) = ieee_value(out_mass(m), ieee_quiet_nan)
  status = topotet_mesh_add_cell_field(mesh, "bad", TOPOTET_CELL_INTENSIVE, out_mass)
  message = topotet_error_message()
  if (status /= TOPOTET_INVALID_INPUT .or. index(message, "'bad'") == 0 .or. index(message, "not finite") == 0) &
    error stop "a NaN is not refused"
  if (topotet_mesh_set_cell_field_kind(mesh, 0, 5) /= TOPOTET_INVALID_INPUT) error stop "an unknown kind is accepted"
  if (topotet_mesh_cell_field_count(mesh) /= 3) error stop "a refused array changed the mesh"

  print '("fortran_cell_fields_test: ", i0, " -> ", i0, " tets, mass ", f0.6, " -> ", f0.6, ": pass")', &
    nt, m, sum(mass), mass_out
  call topotet_mesh_free(mesh)
  ! A main program's variables are saved: free them, or LeakSanitizer reports them at exit.
  deallocate (out_material, out_label, out_mass, name, message)

contains

  ! The fields of a topotet_options in the order of topotet_probe_options, pointers as 1 / 0.
  function options_as_reals(o) result(r)
    type(topotet_options), intent(in) :: o
    real(c_double) :: r(nopt)
    r = [o%target_vertex_ratio, real(o%target_vertices, c_double), o%max_cost, o%min_quality, o%boundary_weight, &
         o%polyline_weight, o%tolerance, o%tolerance_rel, real(o%engine, c_double), real(o%num_threads, c_double), &
         o%round_fraction, o%feature_angle, o%max_field_error, o%max_field_error_rel, &
         real(o%field_weight_count, c_double), merge(1d0, 0d0, c_associated(o%field_weight_names)), &
         merge(1d0, 0d0, c_associated(o%field_weights)), real(o%optimize, c_double), &
         real(o%track_field_bounds, c_double), merge(1d0, 0d0, c_associated(o%progress)), &
         merge(1d0, 0d0, c_associated(o%progress_user_data)), o%min_dihedral, o%size_weight, &
         real(o%relax_tolerance, c_double), real(o%relax_quality, c_double), real(o%relax_features, c_double), &
         real(o%field_bound_mode, c_double)]
  end function

end program fortran_cell_fields_test
