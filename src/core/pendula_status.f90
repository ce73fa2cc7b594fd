!> Status codes, messages and argument checks shared by every non-elemental procedure.
!>
!> Library code never stops or prints: a procedure that can fail takes a
!> `type(status_t), intent(out) :: status` and fills it.  The codes below are the
!> single table of failure kinds; the Python layer maps them to exceptions
!> (argument errors -> ValueError, solver failures -> RuntimeError).
module pendula_status
  use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
  use pendula_kinds, only: wp, i8
  use pendula_format, only: format_general, format_int, code_text
  implicit none
  private

  public :: status_t, status_ok, set_error, code_name, status_unpack
  public :: check_finite, check_positive, check_nonnegative, check_range, &
            check_all_finite, check_increasing, check_size, check_same_size, check_alloc
  public :: PENDULA_OK, PENDULA_ERR_NONFINITE, PENDULA_ERR_DOMAIN, PENDULA_ERR_SIZE, &
            PENDULA_ERR_ORDER, PENDULA_ERR_UNSTABLE, PENDULA_ERR_SOLVER, &
            PENDULA_ERR_UNAVAILABLE, PENDULA_ERR_MAXSTEPS, PENDULA_ERR_CANCELLED, PENDULA_ERR_MEMORY, PENDULA_MSG_LEN

  integer, parameter :: PENDULA_OK = 0
  !> An argument is NaN or infinite where a finite value is required.
  integer, parameter :: PENDULA_ERR_NONFINITE = 1
  !> An argument is finite but outside its valid range.
  integer, parameter :: PENDULA_ERR_DOMAIN = 2
  !> Array sizes disagree, or an array is empty where values are required.
  integer, parameter :: PENDULA_ERR_SIZE = 3
  !> Output times are not strictly increasing.
  integer, parameter :: PENDULA_ERR_ORDER = 4
  !> A fixed step lies outside the method's stability region.
  integer, parameter :: PENDULA_ERR_UNSTABLE = 5
  !> An integrator (CVODE) reported a failure.
  integer, parameter :: PENDULA_ERR_SOLVER = 6
  !> The requested feature was not built (e.g. CVODE without SUNDIALS).
  integer, parameter :: PENDULA_ERR_UNAVAILABLE = 7
  !> The step budget was exhausted before the end of the window.
  integer, parameter :: PENDULA_ERR_MAXSTEPS = 8
  !> The caller cancelled the call (pendula_control); finished work is kept.
  integer, parameter :: PENDULA_ERR_CANCELLED = 9
  !> An allocation failed: the memory asked for (named, with its size) is not available.
  integer, parameter :: PENDULA_ERR_MEMORY = 10

  include 'pendula_msg_len.inc'

  ! code_name's table
  integer, parameter :: STATUS_CODES(11) = [PENDULA_OK, PENDULA_ERR_NONFINITE, PENDULA_ERR_DOMAIN, &
                                            PENDULA_ERR_SIZE, PENDULA_ERR_ORDER, PENDULA_ERR_UNSTABLE, PENDULA_ERR_SOLVER, &
                                           PENDULA_ERR_UNAVAILABLE, PENDULA_ERR_MAXSTEPS, PENDULA_ERR_CANCELLED, PENDULA_ERR_MEMORY]
  character(len=27), parameter :: STATUS_NAMES(11) = [character(len=27) :: 'ok', 'non-finite argument', &
                                               'argument out of range', 'bad array size', 'times not increasing', 'unstable step', &
                             'solver failure', 'not available in this build', 'step budget exhausted', 'cancelled', 'out of memory']

  !> Outcome of a call: `code == PENDULA_OK` on success, otherwise a code from
  !> the table above and a message naming the argument and its valid range.
  type :: status_t
    integer :: code = PENDULA_OK
    character(len=PENDULA_MSG_LEN) :: message = ''
  end type status_t

contains

  !> True when `status` holds no error.
  elemental logical function status_ok(status)
    type(status_t), intent(in) :: status  !< the status to read
    status_ok = status%code == PENDULA_OK
  end function status_ok

  !> Record an error (only the first error of a call is kept).
  pure subroutine set_error(status, code, message)
    type(status_t), intent(inout) :: status  !< receives code and message unless an error is already set
    integer, intent(in) :: code  !< status code (PENDULA_OK or a PENDULA_ERR_* constant)
    character(len=*), intent(in) :: message  !< error message (names the argument and the valid range)
    if (status%code /= PENDULA_OK) return
    status%code = code
    status%message = message
  end subroutine set_error

  !> The code and message of `status` as plain variables (for the f2py glue,
  !> which hands them to Python).
  pure subroutine status_unpack(status, code, message)
    type(status_t), intent(in) :: status  !< the status to read
    integer, intent(out) :: code  !< status%code
    character(len=*), intent(out) :: message  !< status%message (truncated to the length of message)
    code = status%code
    message = status%message
  end subroutine status_unpack

  !> Short name of a status code, for messages and logs.
  pure function code_name(code) result(name)
    integer, intent(in) :: code  !< status code (PENDULA_OK or a PENDULA_ERR_* constant)
    ! explicit length (not deferred): see pendula_format on gfortran's static lengths
    character(len=len(code_text(code, STATUS_CODES, STATUS_NAMES, 'unknown status'))) :: name
    name = code_text(code, STATUS_CODES, STATUS_NAMES, 'unknown status')
  end function code_name

  ! A real as it appears in messages, like C's "%.15g": 0.1 -> 0.1, 1e300 -> 1e+300.
  pure function fmt(x) result(s)
    real(wp), intent(in) :: x
    character(len=len(format_general(x, 15))) :: s
    s = format_general(x, 15)
  end function fmt

  !> Require `x` finite.
  pure subroutine check_finite(name, x, status)
    character(len=*), intent(in) :: name  !< argument name used in the error message
    real(wp), intent(in) :: x  !< value that must be finite
    type(status_t), intent(inout) :: status
    !< receives the error if the check fails and no earlier error is set
    if (status%code /= PENDULA_OK) return
    if (.not. ieee_is_finite(x)) call set_error(status, PENDULA_ERR_NONFINITE, &
                                                name//' = '//fmt(x)//' is invalid: it must be a finite real number')
  end subroutine check_finite

  !> Require `x` finite and > 0.
  pure subroutine check_positive(name, x, status)
    character(len=*), intent(in) :: name  !< argument name used in the error message
    real(wp), intent(in) :: x  !< value that must be finite and > 0
    type(status_t), intent(inout) :: status
    !< receives the error if the check fails and no earlier error is set
    call check_sign(name, x, .true., status)
  end subroutine check_positive

  !> Require `x` finite and >= 0.
  pure subroutine check_nonnegative(name, x, status)
    character(len=*), intent(in) :: name  !< argument name used in the error message
    real(wp), intent(in) :: x  !< value that must be finite and >= 0
    type(status_t), intent(inout) :: status
    !< receives the error if the check fails and no earlier error is set
    call check_sign(name, x, .false., status)
  end subroutine check_nonnegative

  ! x finite and > 0 (strict) or >= 0: the one body of check_positive and
  ! check_nonnegative, so that their messages read alike.  The comparisons
  ! run only on a finite x; the text is built only for an error (these checks
  ! run per element in loops).
  pure subroutine check_sign(name, x, strict, status)
    character(len=*), intent(in) :: name
    real(wp), intent(in) :: x
    logical, intent(in) :: strict
    type(status_t), intent(inout) :: status
    if (status%code /= PENDULA_OK) return
    ! .not. ieee_is_finite first, as the other checks: the form that stays
    ! quiet on a NaN under -ffpe-trap=invalid (the checked build)
    if (.not. ieee_is_finite(x)) then
      call set_error(status, PENDULA_ERR_NONFINITE, name//' = '//fmt(x)// &
                     ' is invalid: it must be finite and '//trim(merge('> 0 ', '>= 0', strict)))
    else if ((strict .and. .not. x > 0) .or. (.not. strict .and. .not. x >= 0)) then
      call set_error(status, PENDULA_ERR_DOMAIN, name//' = '//fmt(x)// &
                     ' is out of range: it must be finite and '//trim(merge('> 0 ', '>= 0', strict)))
    end if
  end subroutine check_sign

  !> Require lo <= x <= hi (x finite). `range_text` describes the range for the
  !> message, e.g. '[0, 1]'.
  pure subroutine check_range(name, x, lo, hi, range_text, status)
    character(len=*), intent(in) :: name  !< argument name used in the error message
    character(len=*), intent(in) :: range_text  !< the valid range for the message, e.g. '[0, 1]'
    real(wp), intent(in) :: x  !< value that must lie in [lo, hi]
    real(wp), intent(in) :: lo  !< lower bound of x
    real(wp), intent(in) :: hi  !< upper bound of x, >= lo
    type(status_t), intent(inout) :: status
    !< receives the error if the check fails and no earlier error is set
    if (status%code /= PENDULA_OK) return
    if (.not. ieee_is_finite(x)) then
      call set_error(status, PENDULA_ERR_NONFINITE, &
                     name//' = '//fmt(x)//' is invalid: it must be finite and in '//range_text)
    else if (x < lo .or. x > hi) then
      call set_error(status, PENDULA_ERR_DOMAIN, &
                     name//' = '//fmt(x)//' is out of range: it must be in '//range_text)
    end if
  end subroutine check_range

  !> Require every element of `x` finite; the message names the first bad index.
  pure subroutine check_all_finite(name, x, status)
    character(len=*), intent(in) :: name  !< argument name used in the error message
    real(wp), intent(in) :: x(:)  !< array whose elements must be finite
    type(status_t), intent(inout) :: status
    !< receives the error if the check fails and no earlier error is set
    integer :: i
    if (status%code /= PENDULA_OK) return
    do i = 1, size(x)
      if (.not. ieee_is_finite(x(i))) then
        call set_error(status, PENDULA_ERR_NONFINITE, name//'['//format_int(i - 1)//'] = '// &
                       fmt(x(i))//' is invalid: every element must be a finite real number')
        return
      end if
    end do
  end subroutine check_all_finite

  !> Require `x` strictly increasing (and finite); the message names the first
  !> offending index (0-based, as Python users see it).
  pure subroutine check_increasing(name, x, status)
    character(len=*), intent(in) :: name  !< argument name used in the error message
    real(wp), intent(in) :: x(:)  !< array that must be finite and strictly increasing
    type(status_t), intent(inout) :: status
    !< receives the error if the check fails and no earlier error is set
    integer :: i
    call check_all_finite(name, x, status)
    if (status%code /= PENDULA_OK) return
    do i = 2, size(x)
      if (.not. x(i) > x(i - 1)) then
        call set_error(status, PENDULA_ERR_ORDER, name//' must be strictly increasing, but '// &
                       name//'['//format_int(i - 1)//'] = '//fmt(x(i))//' does not exceed the previous value '// &
                       fmt(x(i - 1)))
        return
      end if
    end do
  end subroutine check_increasing

  !> Require size(x) >= min_size.
  pure subroutine check_size(name, n, min_size, status)
    character(len=*), intent(in) :: name  !< argument name used in the error message
    integer, intent(in) :: n  !< size of the array name
    integer, intent(in) :: min_size  !< smallest allowed size
    type(status_t), intent(inout) :: status
    !< receives the error if the check fails and no earlier error is set
    if (status%code /= PENDULA_OK) return
    if (n < min_size) then
      call set_error(status, PENDULA_ERR_SIZE, name//' has '//format_int(n)// &
                     ' element(s): it needs at least '//format_int(min_size))
    end if
  end subroutine check_size

  !> Require size n of array `name` to equal n_like, the size of array `like`
  !> (an output sized like an input, or inputs that go together).  The one
  !> exact-size check of the library: every procedure uses it, so every size
  !> message reads alike.
  pure subroutine check_same_size(name, n, like, n_like, status)
    character(len=*), intent(in) :: name  !< argument name used in the error message
    character(len=*), intent(in) :: like  !< name of the array whose size n_like is
    integer, intent(in) :: n  !< size of the array checked
    integer, intent(in) :: n_like  !< size it must equal
    type(status_t), intent(inout) :: status
    !< receives the error if the check fails and no earlier error is set
    if (status%code /= PENDULA_OK) return
    if (n /= n_like) then
      call set_error(status, PENDULA_ERR_SIZE, name//' has '//format_int(n)// &
                     ' element(s): it must have the same size as '//like//' ('//format_int(n_like)//')')
    end if
  end subroutine check_same_size

  !> Report a failed allocation (`stat` from `allocate (..., stat=stat)`, nonzero
  !> on failure) as PENDULA_ERR_MEMORY, naming what was asked for and its size:
  !> `elements` values of `bytes_each` bytes.  Nothing happens when stat == 0.
  pure subroutine check_alloc(stat, what, elements, bytes_each, status)
    integer, intent(in) :: stat  !< the stat= of the allocate statement
    character(len=*), intent(in) :: what  !< what was allocated, for the message (e.g. 'the output times')
    integer(i8), intent(in) :: elements  !< number of values asked for, >= 0
    integer, intent(in) :: bytes_each  !< bytes per value (8 for real(wp))
    type(status_t), intent(inout) :: status
    !< receives the error if the allocation failed and no earlier error is set
    real(wp), parameter :: MIB = 1024.0_wp**2, GIB = 1024.0_wp**3
    real(wp) :: bytes
    if (stat == 0 .or. status%code /= PENDULA_OK) return
    ! 3 significant digits of MiB or GiB: 7.45 GiB, 0.0153 MiB (the exact count follows)
    bytes = real(elements, wp)*bytes_each
    if (bytes >= GIB) then
      call set_error(status, PENDULA_ERR_MEMORY, 'out of memory: '//what//' need '// &
                     format_general(bytes/GIB, 3)//' GiB ('//format_int(elements)// &
                     ' values of '//format_int(bytes_each)//' bytes), which could not be allocated')
    else
      call set_error(status, PENDULA_ERR_MEMORY, 'out of memory: '//what//' need '// &
                     format_general(bytes/MIB, 3)//' MiB ('//format_int(elements)// &
                     ' values of '//format_int(bytes_each)//' bytes), which could not be allocated')
    end if
  end subroutine check_alloc

end module pendula_status
