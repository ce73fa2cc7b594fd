!> pendula_format_digits: the fast path (double-double scaling by a table of
!> powers of five) against the exact path (the double's full decimal expansion,
!> rounded half-to-even) on 1,000,000 doubles over the whole range: random bit
!> patterns, log-uniform values, subnormals, powers of ten and their
!> neighbours, the doubles next to the carry points 9.99..95 * 10**p, and exact
!> decimal ties (odd integers times 2**-t, tried at the digit count where the
!> last kept digit is followed by a lone 5).  Each value is rounded to
!> k = 1..40 significant digits and to 0..40 decimals in turn (every count the
!> format API allows) and once more to k = 1..18 (the fast path's range).
!>
!> Whenever the fast path decides, its digits must equal the exact path's
!> exactly (digits and exponent; the texts are built from them alone).  When it
!> declines, the exact path itself answered.  The test also checks that the
!> fast path decides nearly all random cases in its range and that exact ties
!> go to the exact path.
program test_format_digits
  use pendula_kinds, only: wp, i8
  use pendula_format_digits, only: sig_digits, fixed_digits, DIGITS_MAX
  use pendula_format, only: format_int, format_sci
  use pendula_testing, only: checker_t, quick_mode
  implicit none
  type(checker_t) :: t
  integer, parameter :: KINDS = 6
  character(len=*), parameter :: kind_names(KINDS) = [character(len=14) :: 'random bits', &
                                                           'log-uniform', 'subnormal', 'power of ten', 'carry 9.9..95', 'exact tie']
  integer(i8) :: n_fast(KINDS), n_sig(KINDS), n_fix(KINDS), n_tie_sig, n_tie_fast, n_range, n_declined
  integer :: i, kind, bad, n_values, e
  logical :: declined
  real(wp) :: x

  n_fast = 0; n_sig = 0; n_fix = 0; n_tie_sig = 0; n_tie_fast = 0; n_range = 0; n_declined = 0
  bad = 0
  n_values = 1000000
  if (quick_mode()) n_values = 3000              ! memcheck and checked legs
  call random_seed_fixed()

  ! every binary exponent (every entry of the power table, both ends of the
  ! range) with a random significand, to all fast digit counts
  do e = minexponent(x) - digits(x) + 1, maxexponent(x)
    x = scale(0.5_wp + 0.5_wp*rnd(), e)
    do i = 1, 18
      call check_sig(x, i, 1)
    end do
    call check_fixed(x, mod(e + 2000, 41), 1)
  end do

  do i = 1, n_values
    kind = 1 + mod(i, KINDS)
    x = draw(kind)
    call check_sig(x, 1 + mod(i, 40), kind)
    call check_sig(x, 1 + mod(i/KINDS, 18), kind, declined)
    if (kind <= 3) then
      n_range = n_range + 1
      if (declined) n_declined = n_declined + 1
    end if
    call check_fixed(x, mod(i, 41), kind)
    if (kind == KINDS) call check_ties(x)
  end do

  call t%check_true(bad == 0, 'fast digits equal the exact digits ('//format_int(sum(n_sig) + &
                                                     sum(n_fix))//' cases, '//format_int(sum(n_fast))//' decided by the fast path)')
  do kind = 1, KINDS
    print '(a)', '  '//kind_names(kind)//': '//format_int(n_sig(kind))//' sig + '// &
      format_int(n_fix(kind))//' fixed cases, '//format_int(n_fast(kind))//' fast'
  end do
  ! random values to at most 18 digits: the fast path declines only when the
  ! scaled fraction is within 2**-30 of 1/2 (or an exact tie), so nearly never
  call t%check_true(n_declined*10000 <= n_range, 'fast path declines '//format_int(n_declined)// &
                    ' of '//format_int(n_range)//' random values to 1..18 digits')
  call t%check_true(n_tie_sig > 0 .and. n_tie_fast == 0, 'exact ties ('//format_int(n_tie_sig)// &
                    ') all go to the exact path')
  call t%check_true(format_sci(1.0e23_wp, 16) == '9.999999999999999E+22' .and. &
                    format_sci(9.5_wp, 1) == '1E+01' .and. format_sci(0.125_wp, 2) == '1.2E-01', &
                    'carry and tie examples')
  call t%report('test_format_digits')

contains

  subroutine random_seed_fixed()
    integer :: n, j
    call random_seed(size=n)
    call random_seed(put=[(4242 + 13*j, j=1, n)])
  end subroutine random_seed_fixed

  real(wp) function rnd()
    call random_number(rnd)
  end function rnd

  ! A value of one kind (finite; either sign).
  real(wp) function draw(kind) result(v)
    integer, intent(in) :: kind
    integer(i8) :: bits
    integer :: p, k
    select case (kind)
    case (1)                                     ! any finite bit pattern
      do
        bits = ior(ishft(int(rnd()*2.0_wp**32, i8), 32), int(rnd()*2.0_wp**32, i8))
        if (ibits(bits, 52, 11) /= 2047) exit
      end do
      v = transfer(bits, v)
    case (2)                                     ! log-uniform over the finite range
      v = 10.0_wp**(630*rnd() - 322)
    case (3)                                     ! subnormal
      v = tiny(v)*rnd()
    case (4)                                     ! 10**p and up to 3 ulps either side
      p = int(632*rnd()) - 323
      v = 10.0_wp**real(p, wp)                    ! (10.0**p would overflow on the way)
      v = v + spacing(v)*(int(7*rnd()) - 3)
    case (5)                                     ! next to 9.99..95 * 10**p (k nines)
      k = 1 + int(17*rnd())
      p = int(600*rnd()) - 300
      v = (1 - 5*10.0_wp**(-k - 1))*10.0_wp**real(p, wp)
      v = v + spacing(v)*(int(5*rnd()) - 2)
    case default                                 ! odd integer * 2**-t: ends in 5
      v = real(2*int(rnd()*2.0_wp**int(1 + 51*rnd()), i8) + 1, wp)
      v = scale(v, -1 - int(60*rnd()))
    end select
    if (rnd() < 0.5_wp) v = -v
  end function draw

  ! sig_digits: the fast answer, when there is one, equals the exact one.
  subroutine check_sig(x, k, kind, declined)
    real(wp), intent(in) :: x
    integer, intent(in) :: k, kind
    logical, intent(out), optional :: declined  !< the fast path left it to the exact path
    integer :: d(DIGITS_MAX), w(DIGITS_MAX), e10, e10w
    logical :: fast
    call sig_digits(x, k, d, e10, fast=fast)
    n_sig(kind) = n_sig(kind) + 1
    if (present(declined)) declined = .not. fast
    if (.not. fast) return                       ! the exact path answered
    n_fast(kind) = n_fast(kind) + 1
    call sig_digits(x, k, w, e10w, exact=.true.)
    if (e10 /= e10w .or. any(d(1:k) /= w(1:k))) call mismatch('sig', x, k)
  end subroutine check_sig

  ! fixed_digits: likewise.
  subroutine check_fixed(x, dec, kind)
    real(wp), intent(in) :: x
    integer, intent(in) :: dec, kind
    integer :: d(DIGITS_MAX), w(DIGITS_MAX), n, nw
    logical :: fast
    call fixed_digits(x, dec, d, n, fast=fast)
    n_fix(kind) = n_fix(kind) + 1
    if (.not. fast) return
    n_fast(kind) = n_fast(kind) + 1
    call fixed_digits(x, dec, w, nw, exact=.true.)
    if (n /= nw) then
      call mismatch('fixed', x, dec)
    else if (any(d(1:n) /= w(1:n))) then
      call mismatch('fixed', x, dec)
    end if
  end subroutine check_fixed

  ! x has L <= 19 significant digits ending in 5: rounding to L - 1 digits
  ! (or at the matching decimal place) is an exact tie, which the fast path
  ! must leave to the exact path; one digit more or less is checked too.
  subroutine check_ties(x)
    real(wp), intent(in) :: x
    integer :: d(DIGITS_MAX), e10, last, k
    logical :: fast
    call sig_digits(x, DIGITS_MAX, d, e10, exact=.true.)
    last = DIGITS_MAX
    do while (d(last) == 0)
      last = last - 1
    end do
    if (last < 2 .or. last > 19 .or. d(last) /= 5) return
    do k = last - 2, last
      if (k < 1) cycle
      call check_sig(x, k, KINDS)
      if (k - 1 - e10 >= 0 .and. k - 1 - e10 <= 40) call check_fixed(x, k - 1 - e10, KINDS)
    end do
    call sig_digits(x, last - 1, d, e10, fast=fast)
    n_tie_sig = n_tie_sig + 1
    if (fast) n_tie_fast = n_tie_fast + 1
  end subroutine check_ties

  subroutine mismatch(what, x, k)
    character(len=*), intent(in) :: what
    real(wp), intent(in) :: x
    integer, intent(in) :: k
    bad = bad + 1
    if (bad <= 10) print '(a, es25.17e3, a, i0)', what//' mismatch: x = ', x, ' count ', k
  end subroutine mismatch

end program test_format_digits
