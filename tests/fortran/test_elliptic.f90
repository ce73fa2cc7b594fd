!> Tests of pendula_elliptic: mpmath references (40+ digits, exact double inputs,
!> values from tools/gen/gen_elliptic_refs.py), identities over grids in every
!> parameter region, plan = elementwise, NaN/domain behaviour.
program test_elliptic
  use, intrinsic :: ieee_arithmetic, only: ieee_is_nan, ieee_is_finite, ieee_value, ieee_quiet_nan, ieee_positive_inf
  use pendula_kinds, only: wp
  use pendula_elliptic
  use pendula_elliptic_ke, only: k_double_double
  use pendula_elliptic_k_block, only: k_double_double_block
  use pendula_status, only: status_t, PENDULA_OK, PENDULA_ERR_SIZE
  use pendula_testing, only: checker_t, ulps_between
  implicit none
  type(checker_t) :: t
  real(wp), parameter :: eps = epsilon(1.0_wp)
  real(wp) :: sn, cn, dn, am, nan, x
  real(wp) :: u(2001), s(2001), c(2001), d(2001), a(2001), s2(2001), c2(2001), d2(2001), a2(2001)
  real(wp) :: ms(10), pcs(5)
  real(wp) :: sn_e(2001), cn_e(2001), dn_e(2001), am_e(2001), pcs_a(2001), ua(2001)
  type(status_t) :: st
  type(ellipj_plan_t) :: plan
  integer :: i, j

  nan = ieee_value(1.0_wp, ieee_quiet_nan)

  ! ---- complete and incomplete integrals (mpmath, 4 ulps)
  call t%check_ulps(ellipk(0.5_wp), 1.8540746773013719_wp, 4.0_wp, 'K(0.5)')
  call t%check_ulps(ellipe(0.5_wp), 1.3506438810476755_wp, 4.0_wp, 'E(0.5)')
  call t%check_ulps(ellipk(-1.0e10_wp), 0.00012899219825792638_wp, 4.0_wp, 'K(-1e10)')
  call t%check_ulps(ellipe(-1.0e10_wp), 100000.0000669961_wp, 4.0_wp, 'E(-1e10)')
  call t%check_ulps(ellipkm1(1.0e-300_wp), 346.77405831022674_wp, 4.0_wp, 'K(mc=1e-300)')
  call t%check_ulps(ellipkm1(5.0e-324_wp), 373.6063303218105_wp, 4.0_wp, 'K(mc=5e-324)')
  call t%check_ulps(ellipem1(1.0e-300_wp), 1.0_wp, 4.0_wp, 'E(mc=1e-300)')
  call t%check_ulps(ellipf(1.2_wp, 0.9_wp), 1.5648981345066715_wp, 4.0_wp, 'F(1.2|0.9)')
  call t%check_ulps(ellipf(10.0_wp, 0.3_wp), 10.867848645988321_wp, 4.0_wp, 'F(10|0.3)')
  call t%check_ulps(ellipfm1(1.5_wp, 1.0e-200_wp), 3.340677542798311_wp, 4.0_wp, 'F(1.5|mc=1e-200)')
  call t%check_ulps(ellipf(0.3_wp, 4.0_wp), 0.321243014549783_wp, 4.0_wp, 'F(0.3|4)')
  call t%check_true(.not. ieee_is_finite(ellipk(1.0_wp)) .and. ellipk(1.0_wp) > 0, 'K(1) = +Inf')
  call t%check_true(.not. ieee_is_finite(ellipkm1(0.0_wp)), 'K(mc=0) = +Inf')
  call t%check_true(ellipe(1.0_wp) == 1, 'E(1) = 1')

  ! ---- Jacobi functions (mpmath; tolerance 8 eps * cond, cond from the generator)
  call jac(0.7_wp, 0.3_wp, .false., [0.6323047763108646_wp, 0.7747197363269298_wp, &
                                     0.9381136396814302_wp, 0.6845245936612939_wp], [1.0_wp, 1.0_wp, 1.0_wp, 1.0_wp], 'generic')
  ! large u: raw error checked at 64 eps, far below u*eps = 1e6 eps
  call jac(1.0e6_wp, 0.3_wp, .false., [0.34227400996444113_wp, 0.9396001820470564_wp, &
                                       0.9822701006499478_wp, 916509.7405383877_wp], [8.0_wp, 8.0_wp, 8.0_wp, 1.0_wp], 'u=1e6')
  call jac(300.0_wp, 1.0e-300_wp, .true., [1.0_wp, 1.0296400444824027e-130_wp, &
                              1.0296400444824027e-130_wp, 1.5707963267948966_wp], [1.0_wp, 300.0_wp, 300.0_wp, 1.0_wp], 'mc=1e-300')
  call jac(20.0_wp, 1.0e-10_wp, .true., [0.9999816107201293_wp, -0.006064505056132994_wp, &
                                   0.0060645133005200694_wp, 1.5768608690252632_wp], [1.0_wp, 21.0_wp, 21.0_wp, 1.0_wp], 'mc=1e-10')
  call jac(0.5_wp, -1.0e10_wp, .false., [6.858821793081104e-05_wp, 0.9999999976478282_wp, &
                                  6.93133727279551_wp, 6088.406631245237_wp], [73833.95_wp, 1.0_wp, 72297.63_wp, 1.0_wp], 'm=-1e10')
  call jac(0.4_wp, 4.0_wp, .false., [0.35210607077358375_wp, 0.9359601032759827_wp, &
                                     0.7099896194294337_wp, 0.3598203254761276_wp], [1.0_wp, 1.0_wp, 1.13_wp, 1.0_wp], 'm=4')

  ! ---- exact m = 0 and m = 1
  call ellipj(0.3_wp, 0.0_wp, sn, cn, dn, am)
  call t%check_ulps(sn, sin(0.3_wp), 2.0_wp, 'sn(u|0) = sin')
  call t%check_ulps(cn, cos(0.3_wp), 2.0_wp, 'cn(u|0) = cos')
  call t%check_true(dn == 1, 'dn(u|0) = 1')
  call ellipj(400.0_wp, 1.0_wp, sn, cn, dn, am)
  call t%check_true(sn == 1 .and. cn > 0 .and. cn < 1.0e-170_wp .and. dn == cn, 'm=1, u=400: tanh, sech')

  ! ---- identities on grids, every region; plan equals elementwise to a few eps
  ms = [-1.0e10_wp, -3.0_wp, -0.1_wp, 0.0_wp, 0.3_wp, 0.9_wp, 0.999999_wp, 1.0_wp, 1.5_wp, 1.0e4_wp]
  u = [(-60.0_wp + 0.06_wp*i, i=0, 2000)]
  do j = 1, size(ms)
    call ellipj(u, ms(j), s, c, d, a)
    call t%check_true(maxval(abs(s**2 + c**2 - 1)) <= 4*eps, 'sn^2 + cn^2 = 1')
    call t%check_true(maxval(abs(d**2 + ms(j)*s**2 - 1)) <= 8*eps*max(1.0_wp, abs(ms(j))), &
                      'dn^2 + m sn^2 = 1')
    plan = ellipj_plan(ms(j))
    call ellipj_eval(plan, u, s2, c2, d2, a2)
    x = max(maxval(abs(s2 - s)), maxval(abs(c2 - c)), maxval(abs(d2 - d)/max(1.0_wp, abs(d))))
    call t%check_true(x <= 64*eps, 'plan = elementwise')
  end do
  pcs = [1.0e-3_wp, 1.0e-10_wp, 1.0e-100_wp, 1.0e-300_wp, 5.0e-324_wp]
  do j = 1, size(pcs)
    call ellipjm1(u, pcs(j), s, c, d, a)
    call t%check_true(maxval(abs(s**2 + c**2 - 1)) <= 4*eps, 'complement: sn^2 + cn^2 = 1')
    call t%check_true(maxval(abs(d**2 - pcs(j)*s**2 - c**2)) <= 8*eps, 'complement: dn^2 = cn^2 + mc sn^2')
    plan = ellipj_planm1(pcs(j))
    call ellipj_eval(plan, u, s2, c2, d2)
    x = max(maxval(abs(s2 - s)), maxval(abs(c2 - c)), maxval(abs(d2 - d)))
    call t%check_true(x <= 64*eps, 'planc = elementwise')
  end do

  ! ---- array forms give the same numbers as the elemental ones
  do j = 1, size(ms)
    plan = ellipj_plan(ms(j))
    call ellipj_eval(plan, u, s, c, d, a)
    call ellipj_eval_array(plan, u, s2, c2, d2, st, a2)
    x = max(maxval(abs(s2 - s)), maxval(abs(c2 - c)), maxval(abs(d2 - d)/max(1.0_wp, abs(d))), &
            maxval(abs(a2 - a)/max(1.0_wp, abs(a))))
    call t%check_true(x <= 4*eps, 'ellipj_eval_array = ellipj_eval')
  end do
  ! F and the Jacobi functions over arrays (blocks of 64 with a second pass for the rare
  ! points): bit for bit the elemental forms, on phi and u over many periods, m from -2
  ! to 2 with NaN, Inf and m = 1 mixed in, and complements down to 1e-300
  s = -2.0_wp + 0.002_wp*[(i, i=0, 2000)]
  s(17) = 1; s(300) = ieee_value(1.0_wp, ieee_quiet_nan); s(1500) = ieee_value(1.0_wp, ieee_positive_inf)
  ua = 0.37_wp*[(i - 1000, i=0, 2000)]
  ua(5) = ieee_value(1.0_wp, ieee_quiet_nan); ua(900) = 1.0e30_wp
  call ellipf_array(ua, s, c, st)
  call t%check_true(all(c == ellipf(ua, s) .or. (c /= c .and. ellipf(ua, s) /= ellipf(ua, s))), 'ellipf_array = ellipf')
  call ellipj_array(ua, s, s2, c2, d2, st, a2)
  call ellipj(ua, s, sn_e, cn_e, dn_e, am_e)
  call t%check_true(all(same_bits(s2, sn_e) .and. same_bits(c2, cn_e) .and. same_bits(d2, dn_e) &
                        .and. same_bits(a2, am_e)), 'ellipj_array = ellipj')
  pcs_a = [(10.0_wp**(-300 + 0.15_wp*i), i=0, 2000)]
  call ellipfm1_array(ua, pcs_a, c, st)
  call t%check_true(all(same_bits(c, ellipfm1(ua, pcs_a))), 'ellipfm1_array = ellipfm1')
  call ellipjm1_array(ua, pcs_a, s2, c2, d2, st)
  call ellipjm1(ua, pcs_a, sn_e, cn_e, dn_e)
  call t%check_true(all(same_bits(s2, sn_e) .and. same_bits(c2, cn_e) .and. same_bits(d2, dn_e)), &
                    'ellipjm1_array = ellipjm1')
  call ellipf_array(ua, s(1:3), c, st)
  call t%check_true(st%code == PENDULA_ERR_SIZE, 'ellipf_array short m: size error')
  s = -2.0_wp + 0.0015_wp*[(i, i=0, 2000)]
  call ellipk_array(s, c, st)
  call ellipe_array(s, d, st)
  call t%check_true(all(c == ellipk(s) .or. (c /= c .and. ellipk(s) /= ellipk(s))), 'ellipk_array = ellipk')
  call t%check_true(all(d == ellipe(s) .or. (d /= d .and. ellipe(s) /= ellipe(s))), 'ellipe_array = ellipe')
  ! complements from 1e-320 to 1 (whole blocks of 256 in the logarithmic forms, then mixed
  ! ones), with 0, p > 1 and NaN; and m = 1 - p through ellipk_array/ellipe_array
  s = [(10.0_wp**(-320 + 0.16_wp*i), i=0, 2000)]
  s(700) = 0; s(1900) = 2.5_wp; s(1950) = ieee_value(1.0_wp, ieee_quiet_nan)
  call ellipkm1_array(s, c, st)
  call ellipem1_array(s, d, st)
  call t%check_true(all(c == ellipkm1(s) .or. (c /= c .and. ellipkm1(s) /= ellipkm1(s))), 'ellipkm1_array = ellipkm1')
  call t%check_true(all(d == ellipem1(s) .or. (d /= d .and. ellipem1(s) /= ellipem1(s))), 'ellipem1_array = ellipem1')
  s = 1 - s
  call ellipk_array(s, c, st)
  call ellipe_array(s, d, st)
  call t%check_true(all(c == ellipk(s) .or. (c /= c .and. ellipk(s) /= ellipk(s))), 'ellipk_array = ellipk near m = 1')
  call t%check_true(all(d == ellipe(s) .or. (d /= d .and. ellipe(s) /= ellipe(s))), 'ellipe_array = ellipe near m = 1')
  call ellipkm1_array(s(1:10), c(1:3), st)
  call t%check_true(st%code == PENDULA_ERR_SIZE .and. all(ieee_is_nan(c(1:3))), 'ellipkm1_array size check')
  ! blocks of mostly one kind with a few of the other (gathered into their own pass):
  ! uniform m with every 9th element near m = 1, one subnormal complement; and the reverse
  s = [(modulo(0.6180339887498949_wp*i, 1.0_wp), i=1, 2001)]
  s(9:2001:9) = 1 - 10.0_wp**(-2 - 0.14_wp*[(i, i=1, 222)])
  s(1000) = 1 - 1.0e-310_wp
  pcs_a = 1 - s
  pcs_a(1000) = 1.0e-310_wp
  call ellipkm1_array(pcs_a, c, st)
  call ellipem1_array(pcs_a, d, st)
  call t%check_true(all(same_bits(c, ellipkm1(pcs_a))) .and. all(same_bits(d, ellipem1(pcs_a))), &
                    'ellipkm1_array, ellipem1_array = scalars in mixed blocks')
  call ellipk_array(s, c, st)
  call ellipe_array(s, d, st)
  call t%check_true(all(same_bits(c, ellipk(s))) .and. all(same_bits(d, ellipe(s))), &
                    'ellipk_array, ellipe_array = scalars in mixed blocks')
  pcs_a = 10.0_wp**(-2 - 0.14_wp*[(modulo(i*37, 222), i=1, 2001)])
  pcs_a(5:2001:11) = [(modulo(0.6180339887498949_wp*i, 1.0_wp) + 0.01_wp, i=1, 182)]
  call ellipkm1_array(pcs_a, c, st)
  call ellipem1_array(pcs_a, d, st)
  call t%check_true(all(same_bits(c, ellipkm1(pcs_a))) .and. all(same_bits(d, ellipem1(pcs_a))), &
                    'ellipkm1_array, ellipem1_array = scalars in mostly logarithmic blocks')

  ! ---- 4K period and F(am(u)) = u
  x = ellipk(0.8_wp)
  call ellipj(u, 0.8_wp, s, c, d, a)
  call ellipj(u + 4*x, 0.8_wp, s2, c2, d2, a2)
  call t%check_true(maxval(abs(s2 - s)) <= 256*eps .and. maxval(abs(c2 - c)) <= 256*eps, '4K period')
  call t%check_true(maxval(abs(a2 - a - 8*atan(1.0_wp))) <= 256*eps, 'am(u + 4K) = am(u) + 2 pi')
  call t%check_true(maxval(abs(ellipf(a, 0.8_wp) - u)/max(1.0_wp, abs(u))) <= 16*eps, 'F(am(u)) = u')

  ! ---- NaN and domain (NaN, no stop)
  call t%check_true(ieee_is_nan(ellipk(1.5_wp)) .and. ieee_is_nan(ellipe(2.0_wp)), 'K, E: m > 1 -> NaN')
  call t%check_true(ieee_is_nan(ellipkm1(-1.0_wp)) .and. ieee_is_nan(ellipem1(-1.0_wp)), 'mc < 0 -> NaN')
  call t%check_true(ieee_is_nan(ellipf(1.2_wp, 2.0_wp)), 'F: m sin^2 > 1 -> NaN')
  call t%check_true(ieee_is_nan(ellipk(nan)) .and. ieee_is_nan(ellipf(nan, 0.5_wp)), 'NaN in, NaN out')
  call ellipj(nan, 0.5_wp, sn, cn, dn, am)
  call t%check_true(ieee_is_nan(sn) .and. ieee_is_nan(cn) .and. ieee_is_nan(dn) .and. ieee_is_nan(am), &
                    'ellipj NaN u')
  call ellipj(0.5_wp, nan, sn, cn, dn)
  call t%check_true(ieee_is_nan(sn) .and. ieee_is_nan(cn) .and. ieee_is_nan(dn), 'ellipj NaN m')

  ! ---- F at the double nearest an odd multiple of pi/2 (mpmath, 400 digits, exact double
  ! inputs): the multiple of pi is decided on the exact residue, not on anint(phi/pi)
  call t%check_ulps(ellipfm1(1.5707963267948966_wp, 1.0e-300_wp), 38.025003373828868_wp, 4.0_wp, &
                    'F(fl(pi/2)|mc=1e-300)')
  call t%check_ulps(ellipfm1(1.5707963267948966_wp, 1.0e-40_wp), 38.025003367161134_wp, 4.0_wp, &
                    'F(fl(pi/2)|mc=1e-40)')
  call t%check_ulps(ellipf(1.5707963267948966_wp, 1.0_wp), 38.025003373828868_wp, 4.0_wp, 'F(fl(pi/2)|1)')
  call t%check_ulps(ellipf(-1.5707963267948966_wp, 1.0_wp), -38.025003373828868_wp, 4.0_wp, 'F(-fl(pi/2)|1)')
  call t%check_ulps(ellipfm1(4.71238898038469_wp, 1.0e-300_wp), 730.47450770561424_wp, 4.0_wp, &
                    'F(fl(3 pi/2)|mc=1e-300)')
  call t%check_ulps(ellipfm1(-4.71238898038469_wp, 1.0e-300_wp), -730.47450770561424_wp, 4.0_wp, &
                    'F(-fl(3 pi/2)|mc=1e-300)')
  ! |phi| near huge(): phi = n pi + r with n beyond 2**53 (the quotient is reduced in steps)
  x = ellipf(1.0e300_wp, 0.5_wp)/(1.0e300_wp*ellipk(0.5_wp)/(2*atan(1.0_wp)))
  call t%check_true(abs(x - 1) <= 4*eps, 'F(1e300|0.5) = phi 2K/pi to 4 eps')
  call t%check_true(ellipf(huge(1.0_wp), 0.5_wp) > huge(1.0_wp), 'F(huge|0.5) overflows to +Inf')

  ! ---- |m| up to huge(): the modulus transformations in double-double without overflow
  ! (mpmath, 400 digits, through DLMF 22.6.11/12 at the exact doubles; cond ~ 1 here)
  call jac(1.0e-160_wp, 1.0e308_wp, .false., [9.9999999999983332e-161_wp, 1.0_wp, 0.9999999999995_wp, &
                                              9.9999999999983332e-161_wp], [1.0_wp, 1.0_wp, 1.0_wp, 1.0_wp], 'm = 1e308')
  call jac(1.0e-155_wp, huge(1.0_wp), .false., [9.9700653670665692e-156_wp, 1.0_wp, 0.99102499167857732_wp, &
                                                9.9700653670665692e-156_wp], [1.0_wp, 1.0_wp, 1.0_wp, 1.0_wp], 'm = huge')
  call jac(1.0e-155_wp, -1.0e308_wp, .false., [1.0016675001984403e-155_wp, 1.0_wp, 1.0050041680558036_wp, &
                                               1.0016675001984403e-155_wp], [1.0_wp, 1.0_wp, 1.0_wp, 1.0_wp], 'm = -1e308')
  call jac(1.0e-155_wp, -huge(1.0_wp), .false., [1.0029988494615973e-155_wp, 1.0_wp, 1.0090019391649959_wp, &
                                                 1.0029988494615973e-155_wp], [1.0_wp, 1.0_wp, 1.0_wp, 1.0_wp], 'm = -huge')
  call jac(1.0e-155_wp, -1.0e308_wp, .true., [9.9833416646828154e-156_wp, 1.0_wp, 0.99500416527802577_wp, &
                                            9.9833416646828154e-156_wp], [1.0_wp, 1.0_wp, 1.0_wp, 1.0_wp], 'p = -1e308 (m = 1e308)')
  ! u sqrt|m| ~ 1e154: the phase is below the resolution of u; the values must still be
  ! finite and consistent (sn^2 + cn^2 = 1 for m > 1 scaled, dn^2 = 1 - m sn^2)
  pcs(1:4) = [1.0e308_wp, -1.0e308_wp, huge(1.0_wp), -huge(1.0_wp)]
  do j = 1, 4
    x = pcs(j)
    call ellipj(0.7_wp, x, sn, cn, dn, am)
    call t%check_true(ieee_is_finite(sn) .and. ieee_is_finite(cn) .and. ieee_is_finite(dn) .and. &
                      ieee_is_finite(am), 'ellipj(0.7, +-1e308/huge) finite')
    call t%check_true(abs(sn*sn + cn*cn - 1) <= 8*eps, 'ellipj(0.7, +-1e308/huge): sn^2 + cn^2 = 1')
    plan = ellipj_plan(x)
    call ellipj_eval(plan, [(0.7_wp*i, i=1, 5)], s(1:5), c(1:5), d(1:5))
    call t%check_true(all(ieee_is_finite(s(1:5)) .and. ieee_is_finite(c(1:5)) .and. ieee_is_finite(d(1:5))), &
                      'plan at +-1e308/huge: finite')
  end do
  plan = ellipj_plan(nan)
  call ellipj_eval(plan, 0.5_wp, sn, cn, dn)
  call t%check_true(ieee_is_nan(sn) .and. ieee_is_nan(cn) .and. ieee_is_nan(dn), 'plan at NaN m: NaN')

  ! ---- array forms: sizes checked before anything is written
  call ellipk_array(s(1:10), c(1:3), st)
  call t%check_true(st%code == PENDULA_ERR_SIZE .and. all(ieee_is_nan(c(1:3))), 'ellipk_array size check')
  call ellipk_array(s(1:10), c(1:10), st)
  call t%check_true(st%code == PENDULA_OK, 'ellipk_array equal sizes: ok')

  ! ---- K in double-double (compensated AGM) against mpmath at 800 digits: hi + lo to
  ! 1e-30 relative (the period reductions need well below eps; measured <= 1.1e-31)
  call kdd(0.5_wp, 0.0_wp, 1.8540746773013719_wp, 4.2208106329620787e-17_wp, 'K dd (mc = 0.5)')
  call kdd(0.9_wp, -2.7755575615628914e-17_wp, 1.6124413487202194_wp, 2.003107034822165e-17_wp, &
           'K dd (m = 0.1: mc with its low part)')
  call kdd(0.999_wp, 0.0_wp, 1.5711892469233444_wp, 3.3916792374222226e-17_wp, 'K dd (mc = 0.999)')
  call kdd(1.0e-3_wp, 0.0_wp, 4.841132560550297_wp, 1.8272748097769278e-16_wp, 'K dd (mc = 1e-3)')
  call kdd(1.0e-300_wp, 0.0_wp, 346.77405831022674_wp, 8.106670740906309e-15_wp, 'K dd (mc = 1e-300)')
  call kdd(5.0e-324_wp, 0.0_wp, 373.6063303218105_wp, 1.8383844357144884e-14_wp, 'K dd (mc = 5e-324)')
  call kdd_block()

  call t%report('test_elliptic')

contains

  subroutine kdd(mch, mcl, refh, refl, label)
    real(wp), intent(in) :: mch, mcl, refh, refl
    character(len=*), intent(in) :: label
    real(wp) :: kh, kl
    call k_double_double(mch, mcl, kh, kl)
    call t%check_true(abs((kh - refh) + (kl - refl)) <= 1.0e-30_wp*refh, label)
  end subroutine kdd

  ! the block form (the kernel of the running path, compiled per instruction set) gives
  ! k_double_double's bits at every point: mc over the whole range (tiny ones scaled,
  ! subnormals, mc = 1 that needs no step, mc > 1) with and without low parts, in a block
  ! whose points converge after different numbers of steps
  subroutine kdd_block()
    integer, parameter :: nb = 64
    real(wp) :: mch(nb), mcl(nb), kh(nb), kl(nb), sh, sl
    integer :: j
    logical :: same
    do j = 1, nb
      mch(j) = 10.0_wp**(-323 + 5.1_wp*(j - 1))
      mcl(j) = merge(mch(j)*1.0e-17_wp*(-1)**j, 0.0_wp, mod(j, 3) /= 0)
    end do
    mch(1) = 5.0e-324_wp; mcl(1) = 0
    mch([10, 40, 63]) = [1.0_wp, 0.5_wp, 1.0e6_wp]
    call k_double_double_block(nb, mch, mcl, kh, kl)
    same = .true.
    do j = 1, nb
      call k_double_double(mch(j), mcl(j), sh, sl)
      same = same .and. kh(j) == sh .and. kl(j) == sl
    end do
    call t%check_true(same, 'k_double_double_block = k_double_double (bits)')
  end subroutine kdd_block

  subroutine jac(uu, p, comp, ref, cond, label)
    real(wp), intent(in) :: uu, p, ref(4), cond(4)
    logical, intent(in) :: comp
    character(len=*), intent(in) :: label
    real(wp) :: v(4)
    type(ellipj_plan_t) :: pl
    if (comp) then
      call ellipjm1(uu, p, v(1), v(2), v(3), v(4))
    else
      call ellipj(uu, p, v(1), v(2), v(3), v(4))
    end if
    call t%check_true(all(ulps_between(v, ref) <= 8*cond), label//' (elementwise)')
    if (.not. all(ulps_between(v, ref) <= 8*cond)) print '(4es25.16)', v, ref
    if (comp) then
      pl = ellipj_planm1(p)
    else
      pl = ellipj_plan(p)
    end if
    call ellipj_eval(pl, uu, v(1), v(2), v(3), v(4))
    call t%check_true(all(ulps_between(v, ref) <= 8*cond), label//' (plan)')
  end subroutine jac

  ! equal bits, NaN equal to NaN
  elemental logical function same_bits(a, b)
    real(wp), intent(in) :: a, b
    same_bits = a == b .or. (a /= a .and. b /= b)
  end function same_bits

end program test_elliptic
