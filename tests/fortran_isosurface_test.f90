! The Fortran binding's isosurfaces: a cube of 6^3 cells with the field r = |x - centre|, the level
! r = 1.7 embedded (topotet_mesh_embed_isosurfaces), then simplified: the level's triangles survive
! with their ref, every vertex of theirs exactly on 1.7; an unknown field is an error.
program fortran_isosurface_test
  use, intrinsic :: iso_c_binding
  use topotet
  use fortran_test_grid
  implicit none
  integer, parameter :: n = 6, nv = (n + 1)**3, nt = 6 * n**3
  real(c_double), target :: xyz(3, nv), r(nv)
  integer(c_int32_t), target :: tets(4, nt)
  character(kind=c_char, len=2), target :: name = "r"//c_null_char
  type(topotet_field_view), target :: field(1)
  real(c_double), allocatable, target :: values(:)
  integer(c_int32_t), allocatable, target :: triangles(:, :), refs(:)
  integer(c_int32_t) :: level_ref(1)
  type(topotet_mesh_arrays) :: in
  type(topotet_options) :: options
  type(topotet_report) :: report
  type(c_ptr) :: mesh
  integer(c_int) :: status
  integer :: t, v, on
  character(:), allocatable :: message

  call kuhn_grid(n, xyz, tets)
  do v = 1, nv
    r(v) = norm2(xyz(:, v) - n / 2d0)
  end do
  field(1) = topotet_field_view(c_loc(name), 1, topotet_view(c_loc(r), TOPOTET_FLOAT64, 0))
  call topotet_mesh_arrays_init(in)
  in%vertex_count = nv
  in%positions = topotet_view(c_loc(xyz), TOPOTET_FLOAT64, 0)
  in%tet_count = nt
  in%tets = topotet_view(c_loc(tets), TOPOTET_INT32, 0)
  in%field_count = 1
  in%fields = c_loc(field)
  in%index_base = 1
  status = topotet_mesh_build(in, 1, mesh)
  if (status /= TOPOTET_OK) error stop topotet_error_message()

  status = topotet_mesh_embed_isosurfaces(mesh, "r", 1, [1.7d0], -1d0, level_ref)
  if (status /= TOPOTET_OK) error stop topotet_error_message()
  if (topotet_mesh_vertex_count(mesh) <= nv) error stop "nothing embedded"
  call topotet_options_init(options)
  options%num_threads = 1
  options%target_vertex_ratio = 0.3d0
  status = topotet_simplify(mesh, options, report)
  if (status /= TOPOTET_OK .and. status /= TOPOTET_STOPPED_EARLY) error stop topotet_error_message()

  allocate (values(topotet_mesh_vertex_count(mesh)), triangles(3, topotet_mesh_triangle_count(mesh)), &
            refs(topotet_mesh_triangle_count(mesh)))
  status = topotet_mesh_copy_field(mesh, 0, topotet_out_view(c_loc(values), TOPOTET_FLOAT64, 0))
  if (status /= TOPOTET_OK) error stop topotet_error_message()
  status = topotet_mesh_copy_triangles(mesh, topotet_out_view(c_loc(triangles), TOPOTET_INT32, 0), &
                                       topotet_out_view(c_loc(refs), TOPOTET_INT32, 0), 1)
  if (status /= TOPOTET_OK) error stop topotet_error_message()
  on = 0
  do t = 1, size(refs)
    if (refs(t) /= level_ref(1)) cycle
    on = on + 1
    if (maxval(abs(values(triangles(:, t)) - 1.7d0)) > 0d0) error stop "a vertex of the level left it"
  end do
  if (on == 0) error stop "the level's triangles are gone"

  status = topotet_mesh_embed_isosurfaces(mesh, "pressure", 1, [1d0], -1d0, level_ref)
  if (status /= TOPOTET_INVALID_INPUT) error stop "an unknown field is not an error"
  message = topotet_error_message()
  if (index(message, "pressure") == 0) error stop "the message does not name the field"
  print '("fortran_isosurface_test: ", i0, " -> ", i0, " vertices, ", i0, " triangles on the level: pass")', &
    report%vertices_before, report%vertices_after, on
  call topotet_mesh_free(mesh)
  ! A main program's variables are saved: free them, or LeakSanitizer reports them at exit.
  deallocate (values, triangles, refs, message)

end program fortran_isosurface_test
