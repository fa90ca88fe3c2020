! Simplifies a mesh held in this program's own arrays through module topotet: a cube of 8^3
! cells, 6 tets each, with a ball of material 2 inside; 1-based indices, arrays of shape (3, nv)
! and (4, nt). Usage: simplify_f90 [DIR]  (also writes DIR/in.mesh and DIR/out.mesh)
program simplify_f90
  use, intrinsic :: iso_c_binding
  use topotet
  implicit none
  integer, parameter :: n = 8, nv = (n + 1)**3, nt = 6 * n**3
  integer, parameter :: order(3, 6) = reshape([1, 2, 3, 2, 3, 1, 3, 1, 2, 1, 3, 2, 2, 1, 3, 3, 2, 1], [3, 6])
  real(c_double), target :: xyz(3, nv), heat(nt)
  integer(c_int32_t), target :: tets(4, nt), material(nt), vertex_map(nv)
  integer(c_int32_t), allocatable, target :: out_tets(:, :)
  real(c_double), allocatable, target :: out_xyz(:, :), out_heat(:)
  type(topotet_mesh_arrays) :: in
  type(topotet_options) :: options
  type(topotet_report) :: report
  type(c_ptr) :: mesh
  integer(c_int) :: status
  integer :: i, j, k, p, s, t, c(3), v
  character(4096) :: dir

  do v = 1, nv
    xyz(:, v) = [mod(v - 1, n + 1), mod((v - 1) / (n + 1), n + 1), (v - 1) / (n + 1)**2]
  end do
  ! Each cube: the 6 paths from its low corner to its high corner along the axes, in every order;
  ! the last 3 orders are odd, their tets negatively oriented: swap two corners.
  t = 0
  do k = 0, n - 1
    do j = 0, n - 1
      do i = 0, n - 1
        do p = 1, 6
          t = t + 1
          c = [i, j, k]
          tets(1, t) = vid(c)
          do s = 1, 3
            c(order(s, p)) = c(order(s, p)) + 1
            tets(s + 1, t) = vid(c)
          end do
          if (p > 3) tets(3:4, t) = tets([4, 3], t)
          material(t) = merge(2, 1, (i + 0.5d0 - n / 2d0)**2 + (j + 0.5d0 - n / 2d0)**2 + (k + 0.5d0 - n / 2d0)**2 < 6)
        end do
      end do
    end do
  end do

  call topotet_mesh_arrays_init(in)
  in%vertex_count = nv
  in%positions = topotet_view(c_loc(xyz), TOPOTET_FLOAT64, 0)
  in%tet_count = nt
  in%tets = topotet_view(c_loc(tets), TOPOTET_INT32, 0)
  in%materials = topotet_view(c_loc(material), TOPOTET_INT32, 0)
  in%index_base = 1
  status = topotet_mesh_build(in, 0, mesh)
  if (status /= TOPOTET_OK) error stop topotet_error_message()
  ! Per-tet arrays travel with the tets: the material as a label, and an amount of heat whose sum
  ! is kept (a Fortran name and array; cell arrays can also be views in `in`, as in C).
  heat = merge(3d0, 1d0, material == 2)
  status = topotet_mesh_add_cell_field(mesh, "region", TOPOTET_CELL_CATEGORICAL, material)
  if (status == TOPOTET_OK) status = topotet_mesh_add_cell_field(mesh, "heat", TOPOTET_CELL_EXTENSIVE, heat)
  if (status /= TOPOTET_OK) error stop topotet_error_message()
  dir = ""
  if (command_argument_count() > 0) call get_command_argument(1, dir)
  if (len_trim(dir) > 0) status = topotet_mesh_write(mesh, trim(dir)//"/in.mesh")

  call topotet_options_init(options)
  options%target_vertex_ratio = 0.2d0
  status = topotet_simplify(mesh, options, report)
  if (status /= TOPOTET_OK .and. status /= TOPOTET_STOPPED_EARLY) error stop topotet_error_message()

  ! The result in our own arrays, 1-based, and where every input vertex went.
  allocate (out_tets(4, topotet_mesh_tet_count(mesh)), out_xyz(3, topotet_mesh_vertex_count(mesh)))
  status = topotet_mesh_copy_tets(mesh, topotet_out_view(c_loc(out_tets), TOPOTET_INT32, 0), 1)
  status = topotet_mesh_copy_positions(mesh, topotet_out_view(c_loc(out_xyz), TOPOTET_FLOAT64, 0))
  status = topotet_mesh_copy_vertex_map(mesh, topotet_out_view(c_loc(vertex_map), TOPOTET_INT32, 0), 1)
  if (any(vertex_map < 1) .or. any(vertex_map > size(out_xyz, 2))) error stop "vertex map out of range"
  if (any(out_tets < 1) .or. any(out_tets > size(out_xyz, 2))) error stop "tet index out of range"
  ! The cell arrays on the output tets, copied like the fields (numbered from 0, as in C).
  allocate (out_heat(size(out_tets, 2)))
  status = topotet_mesh_copy_cell_field(mesh, 1, topotet_out_view(c_loc(out_heat), TOPOTET_FLOAT64, 0))
  if (abs(sum(out_heat) - sum(heat)) > 1d-9 * sum(heat)) error stop "the heat is not conserved"
  print '(a, ": ", i0, " -> ", i0, " vertices, ", i0, " -> ", i0, " tets, farthest merge ", f0.2, " cells")', &
    topotet_status_name(report%status), report%vertices_before, size(out_xyz, 2), report%tets_before, &
    size(out_tets, 2), maxval(norm2(out_xyz(:, vertex_map) - xyz, dim=1))
  if (len_trim(dir) > 0) status = topotet_mesh_write(mesh, trim(dir)//"/out.mesh")
  call topotet_mesh_free(mesh)
  deallocate (out_tets, out_xyz, out_heat)

contains

  integer(c_int32_t) function vid(c)
    integer, intent(in) :: c(3)
    vid = c(1) + (n + 1) * (c(2) + (n + 1) * c(3)) + 1
  end function

end program simplify_f90
