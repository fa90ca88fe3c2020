! module topotet: Fortran 2003 bindings of the topotet C API (include/topotet/topotet_c.h, which
! documents every call). The types mirror the C structs (bind(c)); arrays are passed as views
! made with c_loc of the caller's own arrays (which need the target attribute), so Fortran arrays
! of shape (3, nv) for positions and (4, nt) for tets fit as they are, with index_base = 1:
!
!   real(c_double), target :: xyz(3, nv)
!   integer(c_int32_t), target :: tets(4, nt)
!   type(topotet_mesh_arrays) :: in
!   call topotet_mesh_arrays_init(in)
!   in%vertex_count = nv; in%positions = topotet_view(c_loc(xyz), TOPOTET_FLOAT64, 0)
!   in%tet_count = nt;    in%tets = topotet_view(c_loc(tets), TOPOTET_INT32, 0); in%index_base = 1
!   status = topotet_mesh_build(in, 0, mesh)
!
! Errors: every function returns a status; topotet_error_message() gives the message.
module topotet
  use, intrinsic :: iso_c_binding
  implicit none
  private

  ! topotet_status
  integer(c_int), parameter, public :: TOPOTET_OK = 0, TOPOTET_STOPPED_EARLY = 1, TOPOTET_INVALID_INPUT = 2, &
                                       TOPOTET_OUT_OF_MEMORY = 3, TOPOTET_CANCELLED = 4, TOPOTET_INTERNAL_ERROR = 5
  ! topotet_type
  integer(c_int), parameter, public :: TOPOTET_FLOAT64 = 0, TOPOTET_FLOAT32 = 1, TOPOTET_INT32 = 2, TOPOTET_INT64 = 3
  ! topotet_cell_kind: how a per-tet array is carried onto the simplified tets
  integer(c_int), parameter, public :: TOPOTET_CELL_INTENSIVE = 0, TOPOTET_CELL_CATEGORICAL = 1, &
                                       TOPOTET_CELL_EXTENSIVE = 2

  type, bind(c), public :: topotet_view
    type(c_ptr) :: data = c_null_ptr
    integer(c_int) :: type = TOPOTET_FLOAT64
    integer(c_int64_t) :: stride = 0
  end type

  type, bind(c), public :: topotet_out_view
    type(c_ptr) :: data = c_null_ptr
    integer(c_int) :: type = TOPOTET_FLOAT64
    integer(c_int64_t) :: stride = 0
  end type

  type, bind(c), public :: topotet_field_view
    type(c_ptr) :: name = c_null_ptr  ! c_loc of a NUL-terminated character(kind=c_char) string
    integer(c_int) :: components = 1
    type(topotet_view) :: values
  end type

  ! One per-tet array: tet_count rows of `components` values (topotet_mesh_add_cell_field below
  ! makes one from a Fortran name and array).
  type, bind(c), public :: topotet_cell_field_view
    type(c_ptr) :: name = c_null_ptr  ! c_loc of a NUL-terminated character(kind=c_char) string
    integer(c_int) :: components = 1
    integer(c_int) :: kind = TOPOTET_CELL_INTENSIVE
    type(topotet_view) :: values
  end type

  type, bind(c), public :: topotet_mesh_arrays
    integer(c_int64_t) :: vertex_count = 0
    type(topotet_view) :: positions
    integer(c_int64_t) :: tet_count = 0
    type(topotet_view) :: tets, materials, vertex_refs
    integer(c_int64_t) :: triangle_count = 0
    type(topotet_view) :: triangles, triangle_refs
    integer(c_int64_t) :: segment_count = 0
    type(topotet_view) :: segments, segment_refs
    integer(c_int64_t) :: corner_count = 0
    type(topotet_view) :: corners
    integer(c_int) :: field_count = 0
    type(c_ptr) :: fields = c_null_ptr  ! c_loc of a topotet_field_view array
    integer(c_int) :: index_base = 0
    integer(c_int) :: cell_field_count = 0
    type(c_ptr) :: cell_fields = c_null_ptr  ! c_loc of a topotet_cell_field_view array
  end type

  type, bind(c), public :: topotet_options
    real(c_double) :: target_vertex_ratio
    integer(c_int64_t) :: target_vertices
    real(c_double) :: max_cost, min_quality, boundary_weight, polyline_weight, tolerance, tolerance_rel
    integer(c_int) :: engine, num_threads
    real(c_double) :: round_fraction
    real(c_double) :: feature_angle, max_field_error, max_field_error_rel
    integer(c_int) :: field_weight_count
    type(c_ptr) :: field_weight_names, field_weights  ! c_loc of c_ptr / real(c_double) arrays
    integer(c_int) :: optimize  ! 0 = none, 1 = light (default), 2 = full
    integer(c_int) :: track_field_bounds  ! 1 = keep and report the field error bounds (topotet_mesh_field_bounds)
    ! c_funloc of an integer(c_int) function f(done_fraction, user_data) bind(c), with
    ! real(c_double), value :: done_fraction and type(c_ptr), value :: user_data; 0 cancels.
    type(c_funptr) :: progress
    type(c_ptr) :: progress_user_data
    real(c_double) :: min_dihedral  ! degrees; default 5; 0 = no dihedral floor
    real(c_double) :: size_weight  ! size term in the ranking of collapses; 0 = error only; < 0 = auto (default)
    ! 1 (default): the tolerance (H doubled) / the quality floors (halved) relax where they would stop
    ! the run before its target, the report gives the values that hold; 0: hard limits
    integer(c_int) :: relax_tolerance, relax_quality
    integer(c_int) :: relax_features  ! 1 (default): feature curves dropped where they would stop the run short
    integer(c_int) :: field_bound_mode  ! 0 = bound at the original vertices (default), 1 = everywhere (needs a limit)
  end type

  type, bind(c), public :: topotet_report
    integer(c_int) :: status
    integer(c_int64_t) :: vertices_before, vertices_after, tets_before, tets_after
    integer(c_int64_t) :: collapses, evaluations, legality_checks, rounds
    integer(c_int64_t) :: rejected_link_k, rejected_link_ktilde, rejected_pinned, rejected_inversion, &
                          rejected_quality, rejected_tolerance
    real(c_double) :: seconds, max_cost, tolerance
    integer(c_int64_t) :: rejected_field_error, feature_edges, feature_corners
    integer(c_int64_t) :: stop_vertices
    integer(c_int64_t) :: held_topology, held_pinned, held_inversion, held_quality, held_tolerance, &
                          held_field_error, held_collapsible
    integer(c_int64_t) :: pinned_corners, pinned_required, pinned_features, pinned_other
    real(c_double) :: stop_dominant_share
    character(kind=c_char) :: stop_dominant(16), stop_suggestion(512)  ! NUL-terminated
    integer(c_int64_t) :: optimize_moves, optimize_flips
    integer(c_int) :: field_bounds
    real(c_double) :: field_bound_rel
    integer(c_int64_t) :: cell_overlap_pairs, cell_nearest_new_tets, cell_nearest_original_tets
    real(c_double) :: cell_covered_volume_fraction, cell_remap_seconds
    real(c_double) :: tolerance_asked, min_quality_used, min_dihedral_used  ! as asked / as they hold
    integer(c_int64_t) :: relaxations  ! limits relaxed to reach the target
    integer(c_int64_t) :: stop_beyond_reach  ! 1: the topology and the input's pins alone hold the target
    integer(c_int64_t) :: features_dropped  ! feature edges dropped (lower than the relaxed H)
    integer(c_int64_t) :: stall_flips  ! flips where the collapses stalled (held by inverted tets)
    real(c_double) :: min_quality_lowest, min_dihedral_lowest  ! how far the floors may relax
  end type

  ! Out of core (topotet_c.h): a file larger than memory simplified into another under a memory limit.
  type, bind(c), public :: topotet_out_of_core_options
    integer(c_int64_t) :: memory_limit_bytes
    integer(c_int) :: pieces
    type(c_ptr) :: scratch_parent, vertex_map_path
    integer(c_int) :: extensive_count
    type(c_ptr) :: extensive_names
    integer(c_int) :: categorical_count
    type(c_ptr) :: categorical_names
    integer(c_int64_t) :: piece_tets  ! pieces of at most this many tets (tests); 0 = from the limit
  end type

  type, bind(c), public :: topotet_out_of_core_report
    integer(c_int) :: pieces, pieces_left, levels
    integer(c_int64_t) :: piece_tet_limit, peak_rss_bytes, scratch_peak_bytes
    real(c_double) :: cut_seconds, write_seconds
  end type

  public :: topotet_mesh_arrays_init, topotet_options_init, topotet_mesh_build, topotet_mesh_read, &
            topotet_mesh_write, topotet_mesh_free, topotet_simplify, topotet_mesh_vertex_count, &
            topotet_mesh_tet_count, topotet_mesh_field_count, topotet_mesh_vertex_map_size, &
            topotet_mesh_copy_positions, topotet_mesh_copy_tets, topotet_mesh_copy_materials, &
            topotet_mesh_copy_field, topotet_mesh_copy_vertex_map, topotet_error_message, topotet_status_name, &
            topotet_mesh_triangle_count, topotet_mesh_segment_count, topotet_mesh_copy_triangles, &
            topotet_mesh_copy_segments, topotet_mesh_embed_isosurfaces, &
            topotet_mesh_cell_field_count, topotet_mesh_cell_field_info, topotet_mesh_cell_field_values, &
            topotet_mesh_copy_cell_field, topotet_mesh_add_cell_field, topotet_mesh_set_cell_field_kind, &
            topotet_mesh_field_bounds, topotet_c_string, topotet_out_of_core_options_init, &
            topotet_simplify_out_of_core

  ! topotet_mesh_add_cell_field(mesh, name, kind, values): a Fortran name and the array's values,
  ! real(c_double) values(m) or values(components, m), or integer(c_int32_t) labels(m).
  interface topotet_mesh_add_cell_field
    module procedure add_cell_field_real1, add_cell_field_real2, add_cell_field_int1
  end interface

  interface
    subroutine topotet_mesh_arrays_init(arrays) bind(c, name="topotet_mesh_arrays_init")
      import :: topotet_mesh_arrays
      type(topotet_mesh_arrays), intent(out) :: arrays
    end subroutine

    subroutine topotet_options_init(options) bind(c, name="topotet_options_init")
      import :: topotet_options
      type(topotet_options), intent(out) :: options
    end subroutine

    integer(c_int) function topotet_mesh_build(arrays, num_threads, mesh) bind(c, name="topotet_mesh_build")
      import :: c_int, c_ptr, topotet_mesh_arrays
      type(topotet_mesh_arrays), intent(in) :: arrays
      integer(c_int), value :: num_threads
      type(c_ptr), intent(out) :: mesh
    end function

    integer(c_int) function c_mesh_read(path, num_threads, mesh) bind(c, name="topotet_mesh_read")
      import :: c_int, c_ptr, c_char
      character(kind=c_char), intent(in) :: path(*)
      integer(c_int), value :: num_threads
      type(c_ptr), intent(out) :: mesh
    end function

    integer(c_int) function c_mesh_write(mesh, path) bind(c, name="topotet_mesh_write")
      import :: c_int, c_ptr, c_char
      type(c_ptr), value :: mesh
      character(kind=c_char), intent(in) :: path(*)
    end function

    integer(c_int) function c_mesh_embed_isosurfaces(mesh, field, component, values, count, snap, refs) &
        bind(c, name="topotet_mesh_embed_isosurfaces")
      import :: c_int, c_ptr, c_char, c_double, c_int32_t
      type(c_ptr), value :: mesh
      character(kind=c_char), intent(in) :: field(*)
      integer(c_int), value :: component, count
      real(c_double), intent(in) :: values(*)
      real(c_double), value :: snap
      integer(c_int32_t), intent(out) :: refs(*)
    end function

    subroutine topotet_mesh_free(mesh) bind(c, name="topotet_mesh_free")
      import :: c_ptr
      type(c_ptr), value :: mesh
    end subroutine

    subroutine topotet_out_of_core_options_init(ooc) bind(c, name="topotet_out_of_core_options_init")
      import :: topotet_out_of_core_options
      type(topotet_out_of_core_options), intent(out) :: ooc
    end subroutine

    integer(c_int) function c_simplify_out_of_core(input, output, options, ooc, report, ooc_report) &
        bind(c, name="topotet_simplify_out_of_core")
      import :: c_int, c_char, topotet_options, topotet_out_of_core_options, topotet_report, topotet_out_of_core_report
      character(kind=c_char), intent(in) :: input(*), output(*)
      type(topotet_options), intent(in) :: options
      type(topotet_out_of_core_options), intent(in) :: ooc
      type(topotet_report), intent(out) :: report
      type(topotet_out_of_core_report), intent(out) :: ooc_report
    end function

    integer(c_int) function topotet_simplify(mesh, options, report) bind(c, name="topotet_simplify")
      import :: c_int, c_ptr, topotet_options, topotet_report
      type(c_ptr), value :: mesh
      type(topotet_options), intent(in) :: options
      type(topotet_report), intent(out) :: report
    end function

    integer(c_int64_t) function topotet_mesh_vertex_count(mesh) bind(c, name="topotet_mesh_vertex_count")
      import :: c_int64_t, c_ptr
      type(c_ptr), value :: mesh
    end function

    integer(c_int64_t) function topotet_mesh_tet_count(mesh) bind(c, name="topotet_mesh_tet_count")
      import :: c_int64_t, c_ptr
      type(c_ptr), value :: mesh
    end function

    integer(c_int) function topotet_mesh_field_count(mesh) bind(c, name="topotet_mesh_field_count")
      import :: c_int, c_ptr
      type(c_ptr), value :: mesh
    end function

    integer(c_int64_t) function topotet_mesh_vertex_map_size(mesh) bind(c, name="topotet_mesh_vertex_map_size")
      import :: c_int64_t, c_ptr
      type(c_ptr), value :: mesh
    end function

    integer(c_int) function topotet_mesh_copy_positions(mesh, out) bind(c, name="topotet_mesh_copy_positions")
      import :: c_int, c_ptr, topotet_out_view
      type(c_ptr), value :: mesh
      type(topotet_out_view), value :: out
    end function

    integer(c_int) function topotet_mesh_copy_tets(mesh, out, index_base) bind(c, name="topotet_mesh_copy_tets")
      import :: c_int, c_ptr, topotet_out_view
      type(c_ptr), value :: mesh
      type(topotet_out_view), value :: out
      integer(c_int), value :: index_base
    end function

    integer(c_int) function topotet_mesh_copy_materials(mesh, out) bind(c, name="topotet_mesh_copy_materials")
      import :: c_int, c_ptr, topotet_out_view
      type(c_ptr), value :: mesh
      type(topotet_out_view), value :: out
    end function

    integer(c_int) function topotet_mesh_copy_field(mesh, i, out) bind(c, name="topotet_mesh_copy_field")
      import :: c_int, c_ptr, topotet_out_view
      type(c_ptr), value :: mesh
      integer(c_int), value :: i  ! 0-based, as in C
      type(topotet_out_view), value :: out
    end function

    integer(c_int) function topotet_mesh_copy_vertex_map(mesh, out, index_base) &
        bind(c, name="topotet_mesh_copy_vertex_map")
      import :: c_int, c_ptr, topotet_out_view
      type(c_ptr), value :: mesh
      type(topotet_out_view), value :: out
      integer(c_int), value :: index_base
    end function

    integer(c_int64_t) function topotet_mesh_triangle_count(mesh) bind(c, name="topotet_mesh_triangle_count")
      import :: c_int64_t, c_ptr
      type(c_ptr), value :: mesh
    end function

    integer(c_int64_t) function topotet_mesh_segment_count(mesh) bind(c, name="topotet_mesh_segment_count")
      import :: c_int64_t, c_ptr
      type(c_ptr), value :: mesh
    end function

    integer(c_int) function topotet_mesh_copy_triangles(mesh, out, refs_out, index_base) &
        bind(c, name="topotet_mesh_copy_triangles")
      import :: c_int, c_ptr, topotet_out_view
      type(c_ptr), value :: mesh
      type(topotet_out_view), value :: out, refs_out
      integer(c_int), value :: index_base
    end function

    integer(c_int) function topotet_mesh_copy_segments(mesh, out, refs_out, index_base) &
        bind(c, name="topotet_mesh_copy_segments")
      import :: c_int, c_ptr, topotet_out_view
      type(c_ptr), value :: mesh
      type(topotet_out_view), value :: out, refs_out
      integer(c_int), value :: index_base
    end function

    integer(c_int) function topotet_mesh_cell_field_count(mesh) bind(c, name="topotet_mesh_cell_field_count")
      import :: c_int, c_ptr
      type(c_ptr), value :: mesh
    end function

    integer(c_int) function c_mesh_cell_field_info(mesh, i, name, components, kind) &
        bind(c, name="topotet_mesh_cell_field_info")
      import :: c_int, c_ptr
      type(c_ptr), value :: mesh
      integer(c_int), value :: i
      type(c_ptr), intent(out) :: name
      integer(c_int), intent(out) :: components, kind
    end function

    ! The values of cell array i (0-based), tet count x components doubles owned by the mesh
    ! (c_f_pointer them to shape (components, tet count)); c_null_ptr for an index out of range.
    type(c_ptr) function topotet_mesh_cell_field_values(mesh, i) bind(c, name="topotet_mesh_cell_field_values")
      import :: c_int, c_ptr
      type(c_ptr), value :: mesh
      integer(c_int), value :: i
    end function

    integer(c_int) function topotet_mesh_copy_cell_field(mesh, i, out) bind(c, name="topotet_mesh_copy_cell_field")
      import :: c_int, c_ptr, topotet_out_view
      type(c_ptr), value :: mesh
      integer(c_int), value :: i  ! 0-based, as in C
      type(topotet_out_view), value :: out
    end function

    integer(c_int) function c_mesh_add_cell_field(mesh, field, row_count) bind(c, name="topotet_mesh_add_cell_field")
      import :: c_int, c_int64_t, c_ptr, topotet_cell_field_view
      type(c_ptr), value :: mesh
      type(topotet_cell_field_view), intent(in) :: field
      integer(c_int64_t), value :: row_count
    end function

    integer(c_int) function topotet_mesh_set_cell_field_kind(mesh, i, kind) &
        bind(c, name="topotet_mesh_set_cell_field_kind")
      import :: c_int, c_ptr
      type(c_ptr), value :: mesh
      integer(c_int), value :: i, kind  ! i 0-based, as in C
    end function

    ! Field error bounds of the last simplify that kept them: one double per field component.
    type(c_ptr) function topotet_mesh_field_bounds(mesh) bind(c, name="topotet_mesh_field_bounds")
      import :: c_ptr
      type(c_ptr), value :: mesh
    end function

    type(c_ptr) function c_last_error() bind(c, name="topotet_last_error")
      import :: c_ptr
    end function

    type(c_ptr) function c_status_string(status) bind(c, name="topotet_status_string")
      import :: c_ptr, c_int
      integer(c_int), value :: status
    end function

    integer(c_size_t) function c_strlen(s) bind(c, name="strlen")
      import :: c_size_t, c_ptr
      type(c_ptr), value :: s
    end function
  end interface

contains

  ! Fortran string -> NUL-terminated C string (for paths and field names).
  function topotet_c_string(s) result(c)
    character(*), intent(in) :: s
    character(kind=c_char), allocatable :: c(:)
    integer :: i
    allocate (c(len_trim(s) + 1))
    do i = 1, len_trim(s)
      c(i) = s(i:i)
    end do
    c(len_trim(s) + 1) = c_null_char
  end function

  function from_c(p) result(s)
    type(c_ptr), intent(in) :: p
    character(:), allocatable :: s
    character(kind=c_char), pointer :: chars(:)
    integer :: i, n
    n = int(c_strlen(p))
    call c_f_pointer(p, chars, [n])
    allocate (character(n) :: s)
    do i = 1, n
      s(i:i) = chars(i)
    end do
  end function

  integer(c_int) function topotet_mesh_read(path, num_threads, mesh)
    character(*), intent(in) :: path
    integer(c_int), intent(in) :: num_threads
    type(c_ptr), intent(out) :: mesh
    topotet_mesh_read = c_mesh_read(topotet_c_string(path), num_threads, mesh)
  end function

  integer(c_int) function topotet_mesh_write(mesh, path)
    type(c_ptr), intent(in) :: mesh
    character(*), intent(in) :: path
    topotet_mesh_write = c_mesh_write(mesh, topotet_c_string(path))
  end function

  ! Embeds the level sets field(component) = values(:) as listed surfaces (component counted from
  ! 1, as Fortran counts); refs(i) receives level i's ref for the first size(refs) levels. Every
  ! later topotet_simplify keeps them. snap < 0: the default (1e-6).
  integer(c_int) function topotet_mesh_embed_isosurfaces(mesh, field, component, values, snap, refs)
    type(c_ptr), intent(in) :: mesh
    character(*), intent(in) :: field
    integer(c_int), intent(in) :: component
    real(c_double), intent(in) :: values(:)
    real(c_double), intent(in) :: snap
    integer(c_int32_t), intent(out) :: refs(:)
    integer(c_int32_t) :: all(max(size(values), 1))
    integer :: n
    all = 0
    topotet_mesh_embed_isosurfaces = c_mesh_embed_isosurfaces(mesh, topotet_c_string(field), component - 1_c_int, &
        values, int(size(values), c_int), snap, all)
    n = min(size(refs), size(values))
    refs = 0
    refs(1:n) = all(1:n)
  end function

  ! Name, component count and kind (TOPOTET_CELL_...) of cell array i (0-based, as in C).
  integer(c_int) function topotet_mesh_cell_field_info(mesh, i, name, components, kind)
    type(c_ptr), intent(in) :: mesh
    integer(c_int), intent(in) :: i
    character(:), allocatable, intent(out) :: name
    integer(c_int), intent(out) :: components, kind
    type(c_ptr) :: p
    topotet_mesh_cell_field_info = c_mesh_cell_field_info(mesh, i, p, components, kind)
    if (topotet_mesh_cell_field_info == TOPOTET_OK) then
      name = from_c(p)
    else
      name = ""
    end if
  end function

  ! The array's size is checked against the mesh's tet count by the C call (rows).
  integer(c_int) function add_cell_field(mesh, name, kind, components, rows, values)
    type(c_ptr), intent(in) :: mesh
    character(*), intent(in) :: name
    integer(c_int), intent(in) :: kind, components
    integer, intent(in) :: rows
    type(topotet_view), intent(in) :: values
    character(kind=c_char), target :: c_name(len_trim(name) + 1)
    c_name = topotet_c_string(name)
    add_cell_field = c_mesh_add_cell_field(mesh, topotet_cell_field_view(c_loc(c_name), components, kind, values), &
                                           int(rows, c_int64_t))
  end function

  integer(c_int) function add_cell_field_real1(mesh, name, kind, values)
    type(c_ptr), intent(in) :: mesh
    character(*), intent(in) :: name
    integer(c_int), intent(in) :: kind
    real(c_double), contiguous, target, intent(in) :: values(:)
    add_cell_field_real1 = add_cell_field(mesh, name, kind, 1_c_int, size(values), &
                                          topotet_view(c_loc(values), TOPOTET_FLOAT64, 0))
  end function

  integer(c_int) function add_cell_field_real2(mesh, name, kind, values)
    type(c_ptr), intent(in) :: mesh
    character(*), intent(in) :: name
    integer(c_int), intent(in) :: kind
    real(c_double), contiguous, target, intent(in) :: values(:, :)  ! (components, tet count)
    add_cell_field_real2 = add_cell_field(mesh, name, kind, int(size(values, 1), c_int), size(values, 2), &
                                          topotet_view(c_loc(values), TOPOTET_FLOAT64, 0))
  end function

  integer(c_int) function add_cell_field_int1(mesh, name, kind, values)
    type(c_ptr), intent(in) :: mesh
    character(*), intent(in) :: name
    integer(c_int), intent(in) :: kind
    integer(c_int32_t), contiguous, target, intent(in) :: values(:)
    add_cell_field_int1 = add_cell_field(mesh, name, kind, 1_c_int, size(values), &
                                         topotet_view(c_loc(values), TOPOTET_INT32, 0))
  end function

  ! Simplifies the file `input` into `output` out of core (topotet_c.h). ooc: the limit and pieces
  ! (its paths and names are C pointers); scratch and vertex_map (optional) are Fortran strings that
  ! set its scratch_parent and vertex_map_path for the call.
  integer(c_int) function topotet_simplify_out_of_core(input, output, options, ooc, report, ooc_report, &
                                                       scratch, vertex_map)
    character(*), intent(in) :: input, output
    type(topotet_options), intent(in) :: options
    type(topotet_out_of_core_options), intent(in) :: ooc
    type(topotet_report), intent(out) :: report
    type(topotet_out_of_core_report), intent(out) :: ooc_report
    character(*), intent(in), optional :: scratch, vertex_map
    type(topotet_out_of_core_options) :: o
    character(kind=c_char), allocatable, target :: c_scratch(:), c_map(:)
    o = ooc
    if (present(scratch)) then
      c_scratch = topotet_c_string(scratch)
      o%scratch_parent = c_loc(c_scratch)
    end if
    if (present(vertex_map)) then
      c_map = topotet_c_string(vertex_map)
      o%vertex_map_path = c_loc(c_map)
    end if
    topotet_simplify_out_of_core = c_simplify_out_of_core(topotet_c_string(input), topotet_c_string(output), options, &
                                                          o, report, ooc_report)
  end function

  ! The message of the last failed call on this thread.
  function topotet_error_message() result(s)
    character(:), allocatable :: s
    s = from_c(c_last_error())
  end function

  function topotet_status_name(status) result(s)
    integer(c_int), intent(in) :: status
    character(:), allocatable :: s
    s = from_c(c_status_string(status))
  end function

end module topotet
