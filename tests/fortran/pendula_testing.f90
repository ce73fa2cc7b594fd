!> Minimal assertion toolkit for the Fortran tests (test code, not library).
!>
!> Each test program creates a `checker_t`, calls `check_*`, and ends with
!> `call t%report()`, which prints "N passed, N failed" and sets the exit code
!> (meson reads the exit code; the line is for people and CI logs).
module pendula_testing
  use, intrinsic :: ieee_arithmetic, only: ieee_is_nan, ieee_is_finite
  use pendula_kinds, only: wp
  use pendula_status, only: status_t
  implicit none
  private
  public :: checker_t, ulps_between, time_grid, quick_mode

  type :: checker_t
    integer :: passed = 0
    integer :: failed = 0
  contains
    procedure :: check_true
    procedure :: check_close
    procedure :: check_ulps
    procedure :: check_status
    procedure :: report
  end type checker_t

contains

  !> Distance between a and b in units of eps * max(|a|, |b|, tiny).
  elemental real(wp) function ulps_between(a, b) result(u)
    real(wp), intent(in) :: a, b
    real(wp) :: scale
    if (a == b) then
      u = 0
    else if (ieee_is_nan(a) .or. ieee_is_nan(b)) then
      u = huge(1.0_wp)
    else
      scale = max(abs(a), abs(b), tiny(1.0_wp))
      u = abs(a - b)/(epsilon(1.0_wp)*scale)
    end if
  end function ulps_between

  subroutine check_true(self, cond, label)
    class(checker_t), intent(inout) :: self
    logical, intent(in) :: cond
    character(len=*), intent(in) :: label
    if (cond) then
      self%passed = self%passed + 1
    else
      self%failed = self%failed + 1
      write (*, '(a)') 'FAIL: '//label
    end if
  end subroutine check_true

  !> |got - want| <= abs_tol + rel_tol*|want|
  subroutine check_close(self, got, want, rel_tol, abs_tol, label)
    class(checker_t), intent(inout) :: self
    real(wp), intent(in) :: got, want, rel_tol, abs_tol
    character(len=*), intent(in) :: label
    logical :: ok
    ok = abs(got - want) <= abs_tol + rel_tol*abs(want)
    if (ieee_is_nan(want)) ok = ieee_is_nan(got)
    if (.not. ok) write (*, '(a, 2es26.17)') 'FAIL: '//label//' got, want =', got, want
    call self%check_true(ok, label)
  end subroutine check_close

  !> got within max_ulps of want (relative, in eps units).
  subroutine check_ulps(self, got, want, max_ulps, label)
    class(checker_t), intent(inout) :: self
    real(wp), intent(in) :: got, want, max_ulps
    character(len=*), intent(in) :: label
    real(wp) :: u
    u = ulps_between(got, want)
    if (u > max_ulps) write (*, '(a, 2es26.17, a, es10.3)') 'FAIL: '//label//' got, want =', &
      got, want, ' ulps =', u
    call self%check_true(u <= max_ulps, label)
  end subroutine check_ulps

  !> A status with the given code whose message contains fragment (two checks:
  !> the code, then the message, which the failure line prints).
  subroutine check_status(self, st, code, fragment, label)
    class(checker_t), intent(inout) :: self
    type(status_t), intent(in) :: st
    integer, intent(in) :: code
    character(len=*), intent(in) :: fragment, label
    call self%check_true(st%code == code, 'code: '//label)
    call self%check_true(index(st%message, fragment) > 0, 'message: '//label//' -> '//trim(st%message))
  end subroutine check_status

  !> n equally spaced times t0, t0 + dt, ..., t0 + (n - 1) dt [s] (each t0 + dt*i, no accumulation).
  pure function time_grid(t0, dt, n) result(t)
    real(wp), intent(in) :: t0, dt
    integer, intent(in) :: n
    real(wp) :: t(n)
    integer :: i
    t = [(t0 + dt*i, i=0, n - 1)]
  end function time_grid

  !> True when PENDULA_TEST_QUICK is set and not '0' (tools/memcheck.sh and
  !> tools/checked-build.sh set it: slow legs run fewer cases).
  logical function quick_mode()
    character(len=8) :: v
    integer :: vlen, vstat
    call get_environment_variable('PENDULA_TEST_QUICK', v, vlen, vstat)
    quick_mode = .false.
    if (vstat == 0 .and. vlen > 0) quick_mode = v(1:1) /= '0'
  end function quick_mode

  !> Print the closing line and exit non-zero on any failure.
  subroutine report(self, name)
    class(checker_t), intent(in) :: self
    character(len=*), intent(in) :: name
    write (*, '(a, i0, a, i0, a)') name//': ', self%passed, ' passed, ', self%failed, ' failed'
    if (self%failed > 0) error stop 1
  end subroutine report

end module pendula_testing
