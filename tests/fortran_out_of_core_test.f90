! The Fortran binding's out-of-core call (topotet_simplify_out_of_core): a grid of 12^3 cells built
! from Fortran arrays and written as MEDIT, simplified out of core in 4 pieces with a vertex map
! given as a Fortran string; the reports, the output read back and the map file agree; a field
! error limit holds (the report's bound); a limit too small is an error with a message.
!   usage: fortran_out_of_core_test FOLDER
program fortran_out_of_core_test
  use, intrinsic :: iso_c_binding
  use topotet
  use fortran_test_grid
  implicit none
  integer, parameter :: n = 12, nv = (n + 1)**3, nt = 6 * n**3
  real(c_double), target :: xyz(3, nv), r(nv)
  integer(c_int32_t), target :: tets(4, nt)
  character(kind=c_char, len=2), target :: name = "r"//c_null_char
  type(topotet_field_view), target :: field(1)
  type(topotet_mesh_arrays) :: in
  type(topotet_options) :: options
  type(topotet_out_of_core_options) :: ooc
  type(topotet_out_of_core_report) :: ooc_report
  type(topotet_report) :: report
  type(c_ptr) :: mesh, out
  integer(c_int) :: status
  integer :: unit, o, entries, v
  logical :: hit(nv)
  character(4096) :: folder
  character(:), allocatable :: input, output, map, message

  call get_command_argument(1, folder)
  input = trim(folder)//"/fortran_ooc_in.mesh"
  output = trim(folder)//"/fortran_ooc_out.mesh"
  map = trim(folder)//"/fortran_ooc_map.txt"
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
  in%index_base = 1
  in%field_count = 1
  in%fields = c_loc(field)
  if (topotet_mesh_build(in, 0, mesh) /= TOPOTET_OK) error stop "build"
  if (topotet_mesh_write(mesh, input) /= TOPOTET_OK) error stop "write"
  call topotet_mesh_free(mesh)

  call topotet_options_init(options)
  options%target_vertex_ratio = 0.2d0
  call topotet_out_of_core_options_init(ooc)
  ooc%memory_limit_bytes = 1024_c_int64_t  ! far too small: refused before any work
  status = topotet_simplify_out_of_core(input, output, options, ooc, report, ooc_report)
  if (status /= TOPOTET_INVALID_INPUT) error stop "a 1 kB limit was not refused"
  message = topotet_error_message()
  if (index(message, "memory-limit") == 0) error stop "a 1 kB limit was refused without saying why"
  ooc%memory_limit_bytes = 0
  ooc%pieces = 4
  status = topotet_simplify_out_of_core(input, output, options, ooc, report, ooc_report, vertex_map=map)
  if (status /= TOPOTET_OK .and. status /= TOPOTET_STOPPED_EARLY) error stop "out of core failed"
  if (report%vertices_before /= nv .or. report%tets_before /= nt .or. 3 * report%vertices_after >= nv) &
    error stop "report counts"
  if (ooc_report%pieces /= 4 .or. ooc_report%pieces_left /= 1 .or. ooc_report%levels /= 3) error stop "pieces"
  if (topotet_mesh_read(output, 0, out) /= TOPOTET_OK) error stop "read the output"
  if (topotet_mesh_vertex_count(out) /= report%vertices_after) error stop "the output's vertex count is not the report's"
  if (topotet_mesh_tet_count(out) /= report%tets_after) error stop "the output's tet count is not the report's"
  call topotet_mesh_free(out)
  ! The map: a comment line, then one 0-based output vertex per input vertex, onto the output.
  hit = .false.
  entries = 0
  open (newunit=unit, file=map, status="old", action="read")
  read (unit, *)
  do
    read (unit, *, end=10) o
    if (o < 0 .or. o >= report%vertices_after) error stop "a map entry out of range"
    hit(o + 1) = .true.
    entries = entries + 1
  end do
10 close (unit)
  if (entries /= nv .or. count(hit) /= report%vertices_after) error stop "the map is not one entry per input vertex, onto"
  if (report%field_bounds /= 0) error stop "field bounds reported without being asked for"
  ! A field error limit out of core: the bound the report gives is within it.
  options%max_field_error_rel = 0.002d0
  status = topotet_simplify_out_of_core(input, output, options, ooc, report, ooc_report)
  if (status /= TOPOTET_OK .and. status /= TOPOTET_STOPPED_EARLY) error stop "out of core with a field error limit failed"
  if (report%field_bounds /= 1 .or. report%field_bound_rel <= 0 .or. report%field_bound_rel > 0.002d0) &
    error stop "the field error bound out of core"
  print '("fortran_out_of_core_test: ", i0, " -> ", i0, " vertices in ", i0, " pieces: pass")', nv, &
    report%vertices_after, ooc_report%pieces
  ! A main program's variables are saved: free them, or LeakSanitizer reports them at exit.
  deallocate (input, output, map, message)

end program
