! The grid the Fortran tests build their meshes on: a cube of n^3 unit cells, each cut into Kuhn's 6
! positively oriented tets (vertex v at ((v-1) mod (n+1), ...), 1-based, tets in cell order, cell
! (i, j, k) with i fastest: tet t lies in cell i = mod((t-1)/6, n), ...).
module fortran_test_grid
  use, intrinsic :: iso_c_binding
  implicit none
  private
  public :: kuhn_grid

contains

  subroutine kuhn_grid(n, xyz, tets)
    integer, intent(in) :: n
    real(c_double), intent(out) :: xyz(3, (n + 1)**3)
    integer(c_int32_t), intent(out) :: tets(4, 6 * n**3)
    integer, parameter :: order(3, 6) = reshape([1, 2, 3, 2, 3, 1, 3, 1, 2, 1, 3, 2, 2, 1, 3, 3, 2, 1], [3, 6])
    integer :: i, j, k, p, s, t, c(3), v
    do v = 1, (n + 1)**3
      xyz(:, v) = [real(mod(v - 1, n + 1), c_double), real(mod((v - 1) / (n + 1), n + 1), c_double), &
                   real((v - 1) / (n + 1)**2, c_double)]
    end do
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
          end do
        end do
      end do
    end do
  contains
    integer(c_int32_t) function vid(cell)
      integer, intent(in) :: cell(3)
      vid = int(1 + cell(1) + (n + 1) * (cell(2) + (n + 1) * cell(3)), c_int32_t)
    end function
  end subroutine

end module
