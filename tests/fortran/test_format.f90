!> pendula_format (numbers as text without I/O) against gfortran's own WRITE.
!>
!> WRITE is fine here (test code): for every value and digit count the I/O-free
!> text must equal gfortran's correctly rounded ES / F0.d / I0 output (glibc
!> rounds exact decimal ties half-to-even, as pendula_format does), and the
!> general form must read back to x exactly at 17 digits.  Values: zeros,
!> subnormals down to 2**-1074, huge, exponent roll-overs (9.9999e99 -> 1e100),
!> exact ties (0.125, 2.5), 20,000 random bit patterns and 20,000 log-uniform
!> values.
program test_format
  use, intrinsic :: ieee_arithmetic, only: ieee_value, ieee_quiet_nan, ieee_positive_inf, &
                                                                              ieee_negative_inf
  use pendula_kinds, only: wp, i8
  use pendula_format, only: format_sci, format_fixed, format_general, format_short, format_int
  use pendula_testing, only: checker_t, quick_mode
  implicit none
  type(checker_t) :: t
  real(wp) :: nan, inf, x, u
  integer(i8) :: bits
  integer :: i, bad_sci, bad_fix, bad_gen, bad_int, n_sci, n_fix, n_gen, n_random
  real(wp), parameter :: fixed_values(*) = [0.0_wp, -0.0_wp, tiny(1.0_wp), -tiny(1.0_wp), &
                                            5.0e-324_wp, 2.2250738585072009e-308_wp, huge(1.0_wp), -huge(1.0_wp), 1.0_wp, 0.1_wp, &
                                            0.5_wp, 2.5_wp, 9.5_wp, 0.125_wp, 1.0e22_wp, 1.0e23_wp, 9.9999999e99_wp, &
                                         -9.99999999999e-100_wp, 999999.9999999_wp, 1.0e-3_wp, 0.0009999995_wp, 123456.7890125_wp, &
                                            1.0e-5_wp, 4503599627370497.0_wp, 9007199254740993.0_wp, 0.3_wp]
  integer, parameter :: sigs(*) = [1, 2, 3, 4, 6, 8, 12, 15, 16, 17, 20, 25]

  nan = ieee_value(nan, ieee_quiet_nan)
  inf = ieee_value(inf, ieee_positive_inf)

  ! ---- fixed texts
  call t%check_true(format_sci(nan, 4) == 'NaN', 'NaN')
  call t%check_true(format_sci(inf, 4) == '+Inf', '+Inf')
  call t%check_true(format_sci(ieee_value(x, ieee_negative_inf), 4) == '-Inf', '-Inf (not nan)')
  call t%check_true(format_general(-inf, 15) == '-Inf' .and. format_fixed(-inf, 6) == '-Inf' .and. &
                    format_short(-inf) == '-Inf', '-Inf in every form')
  call t%check_true(format_sci(0.0_wp, 4) == '0.000E+00', 'zero sci: '//format_sci(0.0_wp, 4))
  call t%check_true(format_sci(-0.0_wp, 4) == '-0.000E+00', 'signed zero sci: '//format_sci(-0.0_wp, 4))
  call t%check_true(format_general(-0.0_wp, 15) == '-0', 'signed zero general')
  call t%check_true(format_sci(5.0e-324_wp, 4) == '4.941E-324', 'min subnormal: '//format_sci(5.0e-324_wp, 4))
  call t%check_true(format_sci(huge(x), 17) == '1.7976931348623157E+308', 'huge: '//format_sci(huge(x), 17))
  call t%check_true(format_sci(9.99995e99_wp, 5) == '1.0000E+100', '3-digit exponent after carry')
  call t%check_true(format_sci(0.125_wp, 2) == '1.2E-01' .and. format_sci(0.375_wp, 2) == '3.8E-01', &
                    'exact ties round half to even')
  call t%check_true(format_general(0.1_wp, 15) == '0.1' .and. format_general(-1.0_wp, 15) == '-1' .and. &
                    format_general(1.0e300_wp, 15) == '1e+300' .and. format_general(1.5e-7_wp, 15) == '1.5e-7' .and. &
                    format_general(123456789012345.0_wp, 15) == '123456789012345' .and. &
                    format_general(1.0e15_wp, 15) == '1e+15' .and. format_general(1.0e-4_wp, 15) == '0.0001', &
                    'general form like %.15g')
  call t%check_true(format_short(1.437464_wp) == '1.437464' .and. format_short(2.5_wp) == '2.5' .and. &
                    format_short(-0.0005_wp) == '-5.00000E-04' .and. format_short(0.0_wp) == '0' .and. &
                    format_short(1.0e200_wp) == '1.00000E+200' .and. format_short(-0.25_wp) == '-0.25', &
                    'short form')
  call t%check_true(format_fixed(0.0000006_wp, 6) == '0.000001' .and. format_fixed(-1.0e-9_wp, 6) == &
                    '-0.000000' .and. format_fixed(0.0000004_wp, 0) == '0', 'fixed form rounding near zero')
  call t%check_true(format_int(0) == '0' .and. format_int(-huge(1_i8) - 1) == '-9223372036854775808' .and. &
                    format_int(huge(1)) == '2147483647', 'integer extremes')

  ! ---- against WRITE on extremes and random values
  bad_sci = 0; bad_fix = 0; bad_gen = 0; bad_int = 0; n_sci = 0; n_fix = 0; n_gen = 0
  do i = 1, size(fixed_values)
    call compare(fixed_values(i))
  end do
  n_random = 20000
  if (quick_mode()) n_random = 200               ! memcheck and checked legs
  call random_seed_fixed()
  do i = 1, n_random
    call random_number(u)
    bits = int((u - 0.5_wp)*2.0_wp**63, i8)
    x = transfer(bits, x)
    ! finite patterns only, by the exponent field: testing a signalling NaN
    ! would trap in the checked build
    if (ibits(bits, 52, 11) /= 2047) call compare(x)
    call random_number(u)
    x = 10.0_wp**(630*u - 322)      ! log-uniform over the finite range
    call random_number(u)
    if (u < 0.5_wp) x = -x
    call compare(x)
    call compare_int(bits)
    call compare_int(bits/2_i8**32)
  end do
  call t%check_true(bad_sci == 0, 'format_sci equals WRITE ES ('//format_int(n_sci)//' cases)')
  call t%check_true(bad_fix == 0, 'format_fixed equals WRITE F0.d ('//format_int(n_fix)//' cases)')
  call t%check_true(bad_gen == 0, 'format_general reads back exactly ('//format_int(n_gen)//' cases)')
  call t%check_true(bad_int == 0, 'format_int equals WRITE I0')
  call t%report('test_format')

contains

  subroutine random_seed_fixed()
    integer :: n
    call random_seed(size=n)
    call random_seed(put=[(12345 + 7*i, i=1, n)])
  end subroutine random_seed_fixed

  subroutine compare(x)
    real(wp), intent(in) :: x
    integer :: k, d
    character(len=80) :: buf
    character(len=400) :: fbuf
    character(len=:), allocatable :: got, want
    real(wp) :: back
    do k = 1, size(sigs)
      ! ES with a 3-digit exponent field; ours uses 2 digits when they suffice
      write (buf, '(es60.'//format_int(sigs(k) - 1)//'e3)') x
      want = trim(adjustl(buf))
      if (sigs(k) == 1) want = want(1:index(want, '.') - 1)//want(index(want, '.') + 1:)
      got = format_sci(x, sigs(k))
      n_sci = n_sci + 1
      if (len(want) > 4) then
        if (want(len(want) - 3:len(want) - 2) == '+0' .or. want(len(want) - 3:len(want) - 2) == '-0') &
          want = want(1:len(want) - 3)//want(len(want) - 1:)
      end if
      if (got /= want) then
        bad_sci = bad_sci + 1
        if (bad_sci <= 5) print '(a)', 'sci mismatch: '//got//' vs '//want
      end if
    end do
    do d = 0, 12, 3
      if (abs(x) > 1.0e30_wp) exit
      write (fbuf, '(f0.'//format_int(d)//')') x
      want = trim(adjustl(fbuf))
      if (want(1:1) == '.') want = '0'//want
      if (len(want) >= 2) then
        if (want(1:2) == '-.') want = '-0'//want(2:)
      end if
      if (want(len(want):len(want)) == '.') want = want(1:len(want) - 1)    ! F0.0 prints '3.'
      got = format_fixed(x, d)
      n_fix = n_fix + 1
      if (got /= want) then
        bad_fix = bad_fix + 1
        if (bad_fix <= 5) print '(a)', 'fixed mismatch: '//got//' vs '//want
      end if
    end do
    got = format_general(x, 17)
    read (got, *) back
    n_gen = n_gen + 1
    if (back /= x .or. sign(1.0_wp, back) /= sign(1.0_wp, x)) then
      bad_gen = bad_gen + 1
      if (bad_gen <= 5) print '(a)', 'general does not read back: '//got
    end if
  end subroutine compare

  subroutine compare_int(n)
    integer(i8), intent(in) :: n
    character(len=32) :: buf
    write (buf, '(i0)') n
    if (format_int(n) /= trim(buf)) then
      bad_int = bad_int + 1
      if (bad_int <= 5) print '(a)', 'int mismatch: '//format_int(n)//' vs '//trim(buf)
    end if
  end subroutine compare_int

end program test_format
