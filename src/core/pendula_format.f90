!> Numbers as text for messages, without any I/O.
!>
!> Why no internal WRITE: an internal WRITE takes libgfortran's unit lock, and a
!> process forked while another thread holds that lock leaves the child blocked
!> for ever on its first own WRITE.  Error messages are built in threads, so
!> they are formatted here with integer arithmetic only.
!>
!> The digits come from pendula_format_digits: correctly rounded (half-to-even
!> on exact ties), so reading a text back gives x to within half a unit of its
!> last digit.  NaN prints as 'NaN', infinities as '+Inf' / '-Inf'; the sign of
!> a negative zero is kept ('-0.000E+00').  Cost: well under a microsecond for
!> up to 18 digits, a few microseconds on exact ties and longer texts.
!>
!> Why no deferred-length (`character(len=:), allocatable`) results:
!> gfortran 12 keeps the length of such a result in a static variable at
!> each call site, so two threads calling the same site race on it (garbled
!> or truncated messages).  The public functions here return an explicit
!> length computed by a specification function (the text is built twice,
!> once to measure it); the helpers append into a fixed buffer.
module pendula_format
  use, intrinsic :: ieee_arithmetic, only: ieee_is_finite, ieee_is_nan
  use pendula_kinds, only: wp, i8
  use pendula_format_digits, only: sig_digits, fixed_digits, DIGITS_MAX
  implicit none
  private

  public :: format_sci, format_fixed, format_general, format_short, format_int, code_text

  !> Largest number of significant digits (format_sci, format_general) or
  !> decimals (format_fixed) honoured; larger requests are clamped.
  integer, parameter, public :: FORMAT_MAX_DIGITS = 40

  integer, parameter :: STYLE_SCI = 1, STYLE_FIXED = 2, STYLE_GENERAL = 3, STYLE_SHORT = 4
  ! Longest text: sign, 309 integer digits of a double, point, the decimals
  integer, parameter :: TEXT_MAX = 309 + FORMAT_MAX_DIGITS + 16

  !> Decimal text of an integer (any default or 64-bit integer, like i0).
  interface format_int
    module procedure format_int_default, format_int_i8
  end interface format_int

contains

  ! Length functions first: the public results' lengths are specification
  ! expressions calling them, and a function must be defined before use there.

  ! The length of code_text(code, codes, names, fallback).
  pure integer function code_text_len(code, codes, names, fallback)
    integer, intent(in) :: code, codes(:)
    character(len=*), intent(in) :: names(:), fallback
    integer :: i
    i = code_index(code, codes, names)
    code_text_len = len(fallback)
    if (i > 0) code_text_len = len_trim(names(i))
  end function code_text_len

  ! The first i with codes(i) == code (within both tables), else 0.
  pure integer function code_index(code, codes, names)
    integer, intent(in) :: code, codes(:)
    character(len=*), intent(in) :: names(:)
    integer :: i
    code_index = 0
    do i = 1, min(size(codes), size(names))
      if (codes(i) == code) then
        code_index = i
        return
      end if
    end do
  end function code_index

  ! The length of format_int(n).
  pure integer function int_len(n)
    integer(i8), intent(in) :: n
    character(len=20) :: b
    integer :: p
    call int_chars(n, b, p)
    int_len = len(b) - p + 1
  end function int_len

  ! The length of x's text in a style.
  pure integer function text_len(x, style, ndig)
    real(wp), intent(in) :: x
    integer, intent(in) :: style, ndig
    character(len=TEXT_MAX) :: buf
    call build_text(x, style, ndig, buf, text_len)
  end function text_len

  ! s := x's text in a style (s as long as text_len says).  A subroutine, not
  ! a function with text_len in its result's length: that would build the
  ! text a third time.
  pure subroutine text_into(x, style, ndig, s)
    real(wp), intent(in) :: x
    integer, intent(in) :: style, ndig
    character(len=*), intent(out) :: s
    character(len=TEXT_MAX) :: buf
    integer :: n
    call build_text(x, style, ndig, buf, n)
    s = buf(1:n)
  end subroutine text_into

  !> Scientific form with `sig` significant digits, like Fortran's ES edit
  !> descriptor: '-1.235E+00', '5.000E-324' (two exponent digits, three when
  !> needed).  sig is clamped to [1, FORMAT_MAX_DIGITS]; sig = 1 gives '5E-01'.
  pure function format_sci(x, sig) result(s)
    real(wp), intent(in) :: x  !< value to format
    integer, intent(in) :: sig  !< significant digits, clamped to [1, FORMAT_MAX_DIGITS]
    character(len=text_len(x, STYLE_SCI, sig)) :: s
    call text_into(x, STYLE_SCI, sig, s)
  end function format_sci

  !> Fixed form with `decimals` digits after the point, like Fortran's F0.d
  !> but always with a digit before the point: '0.500000', '-12.000000'.
  !> decimals is clamped to [0, FORMAT_MAX_DIGITS].
  pure function format_fixed(x, decimals) result(s)
    real(wp), intent(in) :: x  !< value to format
    integer, intent(in) :: decimals  !< digits after the point, clamped to [0, FORMAT_MAX_DIGITS]
    character(len=text_len(x, STYLE_FIXED, decimals)) :: s
    call text_into(x, STYLE_FIXED, decimals, s)
  end function format_fixed

  !> Shortest natural form with at most `sig` significant digits, like C's
  !> "%.<sig>g" without trailing zeros: 0.1 -> '0.1', -1 -> '-1',
  !> 1e300 -> '1e+300', 1.5e-7 -> '1.5e-7' (fixed when -4 <= exponent < sig).
  pure function format_general(x, sig) result(s)
    real(wp), intent(in) :: x  !< value to format
    integer, intent(in) :: sig  !< significant digits, clamped to [1, FORMAT_MAX_DIGITS]
    character(len=text_len(x, STYLE_GENERAL, sig)) :: s
    call text_into(x, STYLE_GENERAL, sig, s)
  end function format_general

  !> Short text for step sizes and rates: '0' for zero; six decimals without
  !> trailing zeros for 1e-3 <= |x| < 1e6 ('1.437464', '2.5'); otherwise six
  !> significant digits in scientific form ('1.23457E-05').
  pure function format_short(x) result(s)
    real(wp), intent(in) :: x  !< value to format
    character(len=text_len(x, STYLE_SHORT, 6)) :: s
    call text_into(x, STYLE_SHORT, 6, s)
  end function format_short

  !> The name of an integer code from a table: names(i) (trailing blanks
  !> dropped) where codes(i) == code, else `fallback`.  The one home of the
  !> library's code -> name lookups (status codes, regimes, solver flags).
  pure function code_text(code, codes, names, fallback) result(s)
    integer, intent(in) :: code  !< code to look up
    integer, intent(in) :: codes(:)  !< table of codes
    character(len=*), intent(in) :: names(:)  !< names(i) is the name of codes(i)
    character(len=*), intent(in) :: fallback  !< text returned when code is not in codes
    character(len=code_text_len(code, codes, names, fallback)) :: s
    integer :: i
    i = code_index(code, codes, names)
    if (i > 0) then
      s = names(i)
    else
      s = fallback
    end if
  end function code_text

  ! ---------------------------------------------------------------- helpers

  ! buf(1:n) := x in one of the styles; NaN and infinities have fixed texts
  ! in all but STYLE_SHORT's zero.
  pure subroutine build_text(x, style, ndig, buf, n)
    real(wp), intent(in) :: x
    integer, intent(in) :: style, ndig
    character(len=*), intent(inout) :: buf
    integer, intent(out) :: n
    n = 0
    if (style == STYLE_SHORT) then
      call short_text(x, buf, n)
    else if (.not. ieee_is_finite(x)) then
      call short_text(x, buf, n)              ! the same fixed texts
    else
      if (sign(1.0_wp, x) < 0) call put(buf, n, '-')
      select case (style)
      case (STYLE_SCI)
        call sci_text(x, ndig, buf, n)
      case (STYLE_FIXED)
        call fixed_text(x, ndig, buf, n)
      case default
        call general_text(x, ndig, buf, n)
      end select
    end if
  end subroutine build_text

  ! format_short's text: '0', fixed with six decimals less trailing zeros, or
  ! scientific with six digits (also NaN and the infinities).
  pure subroutine short_text(x, buf, n)
    real(wp), intent(in) :: x
    character(len=*), intent(inout) :: buf
    integer, intent(inout) :: n
    if (x == 0) then
      call put(buf, n, '0')
    else if (ieee_is_nan(x)) then
      call put(buf, n, 'NaN')
    else if (.not. ieee_is_finite(x)) then
      call put(buf, n, merge('+Inf', '-Inf', x > 0))
    else if (abs(x) >= 1.0e-3_wp .and. abs(x) < 1.0e6_wp) then
      if (x < 0) call put(buf, n, '-')
      call fixed_text(x, 6, buf, n)
      do while (buf(n:n) == '0')
        n = n - 1
      end do
      if (buf(n:n) == '.') n = n - 1
    else
      if (x < 0) call put(buf, n, '-')
      call sci_text(x, 6, buf, n)
    end if
  end subroutine short_text

  ! Append text to buf(1:n).
  pure subroutine put(buf, n, text)
    character(len=*), intent(inout) :: buf
    integer, intent(inout) :: n
    character(len=*), intent(in) :: text
    buf(n + 1:n + len(text)) = text
    n = n + len(text)
  end subroutine put

  ! Append max(0, count) zeros.
  pure subroutine put_zeros(buf, n, count)
    character(len=*), intent(inout) :: buf
    integer, intent(inout) :: n
    integer, intent(in) :: count
    integer :: i
    do i = 1, count
      buf(n + i:n + i) = '0'
    end do
    n = n + max(0, count)
  end subroutine put_zeros

  ! Append the digits d as characters.
  pure subroutine put_digits(buf, n, d)
    character(len=*), intent(inout) :: buf
    integer, intent(inout) :: n
    integer, intent(in) :: d(:)
    integer :: i
    do i = 1, size(d)
      buf(n + i:n + i) = achar(iachar('0') + d(i))
    end do
    n = n + size(d)
  end subroutine put_digits

  ! Append |x| (finite) in scientific form with sig significant digits.
  pure subroutine sci_text(x, sig, buf, n)
    real(wp), intent(in) :: x
    integer, intent(in) :: sig
    character(len=*), intent(inout) :: buf
    integer, intent(inout) :: n
    integer :: d(DIGITS_MAX), e10, k
    k = max(1, min(sig, FORMAT_MAX_DIGITS))
    call sig_digits(x, k, d, e10)
    call put_sci(buf, n, d(1:k), e10, 'E', 2)
  end subroutine sci_text

  ! Append |x| (finite) in fixed form with `decimals` digits after the point.
  pure subroutine fixed_text(x, decimals, buf, n)
    real(wp), intent(in) :: x
    integer, intent(in) :: decimals
    character(len=*), intent(inout) :: buf
    integer, intent(inout) :: n
    integer :: d(DIGITS_MAX), nd, dec
    dec = max(0, min(decimals, FORMAT_MAX_DIGITS))
    ! d(1:nd): the digits of round(|x| * 10**dec), no leading zeros
    call fixed_digits(x, dec, d, nd)
    if (nd <= dec) then
      call put(buf, n, '0')
    else
      call put_digits(buf, n, d(1:nd - dec))
    end if
    if (dec > 0) then
      call put(buf, n, '.')
      call put_zeros(buf, n, dec - nd)
      call put_digits(buf, n, d(max(1, nd - dec + 1):nd))
    end if
  end subroutine fixed_text

  ! Append |x| (finite) like "%.<sig>g" without trailing zeros.
  pure subroutine general_text(x, sig, buf, n)
    real(wp), intent(in) :: x
    integer, intent(in) :: sig
    character(len=*), intent(inout) :: buf
    integer, intent(inout) :: n
    integer :: d(DIGITS_MAX), e10, k, last
    k = max(1, min(sig, FORMAT_MAX_DIGITS))
    call sig_digits(x, k, d, e10)
    last = k
    do while (last > 1 .and. d(last) == 0)
      last = last - 1
    end do
    if (e10 >= -4 .and. e10 < k) then
      if (e10 < 0) then
        call put(buf, n, '0.')
        call put_zeros(buf, n, -e10 - 1)
        call put_digits(buf, n, d(1:last))
      else if (last <= e10 + 1) then
        call put_digits(buf, n, d(1:last))
        call put_zeros(buf, n, e10 + 1 - last)
      else
        call put_digits(buf, n, d(1:e10 + 1))
        call put(buf, n, '.')
        call put_digits(buf, n, d(e10 + 2:last))
      end if
    else
      call put_sci(buf, n, d(1:last), e10, 'e', 1)
    end if
  end subroutine general_text

  ! Append d(1).d(2:) (no point for one digit), the exponent letter and the
  ! signed exponent e10 with at least `width` digits: '+05', '-324', '+7'.
  pure subroutine put_sci(buf, n, d, e10, letter, width)
    character(len=*), intent(inout) :: buf
    integer, intent(inout) :: n
    integer, intent(in) :: d(:), e10, width
    character(len=1), intent(in) :: letter
    character(len=20) :: b
    integer :: p
    call put_digits(buf, n, d(1:1))
    if (size(d) > 1) then
      call put(buf, n, '.')
      call put_digits(buf, n, d(2:))
    end if
    call int_chars(int(abs(e10), i8), b, p)
    ! piece by piece: a concatenation would allocate a temporary per call
    call put(buf, n, letter)
    call put(buf, n, merge('+', '-', e10 >= 0))
    call put_zeros(buf, n, width - (21 - p))
    call put(buf, n, b(p:))
  end subroutine put_sci

  pure function format_int_default(n) result(s)
    integer, intent(in) :: n  !< integer to format
    character(len=int_len(int(n, i8))) :: s
    s = format_int_i8(int(n, i8))
  end function format_int_default

  pure function format_int_i8(n) result(s)
    integer(i8), intent(in) :: n  !< integer to format
    character(len=int_len(n)) :: s
    character(len=20) :: b
    integer :: p
    call int_chars(n, b, p)
    s = b(p:)
  end function format_int_i8

  ! b(p:) := n in decimal, with '-' when negative (len(b) = 20 fits any i8).
  pure subroutine int_chars(n, b, p)
    integer(i8), intent(in) :: n
    character(len=20), intent(out) :: b
    integer, intent(out) :: p
    integer(i8) :: v
    ! Work with -|n|: the most negative integer has no positive counterpart.
    v = -abs(n)
    if (n < 0) v = n
    b = ''
    p = len(b) + 1
    do
      p = p - 1
      b(p:p) = achar(iachar('0') - int(mod(v, 10_i8)))
      v = v/10
      if (v == 0) exit
    end do
    if (n < 0) then
      p = p - 1
      b(p:p) = '-'
    end if
  end subroutine int_chars

end module pendula_format
