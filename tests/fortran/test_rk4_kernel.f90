!> The RK4 inner loop (pendula_rk4_kernel): its stage-sine evaluation against
!> sin of the exact argument in quadruple precision (libquadmath via real128)
!> and against libm, over a dense sweep and random theta up to |theta| = 1e6;
!> and the RK4 results against the plain formulation with four libm sines per
!> step (the previous implementation, kept here as the reference).
program test_rk4_kernel
  use pendula_kinds, only: wp, i8
  use pendula_rk4_kernel, only: rk4_grid, node_reduce, sin_node, sin_shift, stage_rmax, stage_xmax
  use pendula_testing, only: checker_t
  use, intrinsic :: iso_fortran_env, only: qp => real128
  implicit none
  type(checker_t) :: tc
  real(wp), parameter :: eps = epsilon(1.0_wp)
  real(qp), parameter :: pi_q = 3.14159265358979323846264338327950288_qp
  integer :: stride, qlen, qstat
  character(len=8) :: quick

  ! PENDULA_TEST_QUICK=1 (memcheck and checked legs): every 10th sweep point,
  ! which keeps each path exercised at a tenth of the cost under valgrind.
  stride = 1
  call get_environment_variable('PENDULA_TEST_QUICK', quick, qlen, qstat)
  if (qstat == 0 .and. qlen > 0) then
    if (quick(1:1) /= '0') stride = 10
  end if

  call test_sin_node()
  call test_sin_shift_sweep()
  call test_sin_shift_random()
  call test_against_libm()
  call test_reduce_extremes()
  call test_vs_plain_rk4()
  call tc%report('test_rk4_kernel')

contains

  real(wp) function err_eps(got, x, d) result(e)
    real(wp), intent(in) :: got, x, d
    e = real(abs(real(got, qp) - sin(real(x, qp) + real(d, qp))), wp)/eps
  end function err_eps

  !> Every node k (and its aliases k + 256 m) with 801 offsets r across
  !> [-stage_rmax, stage_rmax]: |sin_node(k, r) - sin(2 pi k / 256 + r)| <= 2 eps
  !> (sin_node is the Taylor form the RK4 step uses).
  subroutine test_sin_node()
    integer :: k, j
    real(wp) :: r, worst, e
    real(qp) :: xk
    worst = 0
    do k = -300, 300, stride
      xk = 2*pi_q*k/256
      do j = -400, 400
        r = stage_rmax*j/400
        e = real(abs(real(sin_node(k, r), qp) - sin(xk + real(r, qp))), wp)/eps
        worst = max(worst, e)
      end do
    end do
    print '(a, f6.3, a)', 'sin_node: max |error| over 601 nodes x 801 offsets = ', worst, ' eps'
    call tc%check_true(worst <= 2, 'sin_node within 2 eps of sin(x_k + r)')
  end subroutine test_sin_node

  !> Dense theta in [-10, 10] (20001 points) x 41 offsets d across the fast
  !> range |d| <= stage_rmax - pi/256: sin_shift(theta, d) vs sin(theta + d)
  !> of the exact sum; every point must take the table path's accuracy.
  subroutine test_sin_shift_sweep()
    integer :: i, j
    real(wp) :: th, d, worst, dmax
    dmax = stage_rmax - 0.0123_wp
    worst = 0
    do i = -10000, 10000, stride
      th = i*1.0e-3_wp + 1.0e-7_wp*modulo(i, 7)
      do j = -20, 20
        d = dmax*j/20
        worst = max(worst, err_eps(sin_shift(th, d), th, d))
      end do
    end do
    print '(a, f6.3, a)', 'sin_shift: max |error|, theta in [-10, 10], |d| <= 0.088 = ', worst, ' eps'
    call tc%check_true(worst <= 2, 'sin_shift dense sweep within 2 eps')
  end subroutine test_sin_shift_sweep

  !> Random theta, uniform in log |theta| over [1e-8, 1e6] and uniform in
  !> [-1e6, 1e6], with random d (|d| up to 0.5: beyond the table range the
  !> libm fallback is tested as well, there against the rounded sum).
  subroutine test_sin_shift_random()
    integer, parameter :: n = 100000
    real(wp) :: u(4), th, d, worst, worst_fb, e
    integer :: i, nfb
    integer, allocatable :: seed(:)
    call random_seed(size=i)
    allocate (seed(i))
    seed = 20261122
    call random_seed(put=seed)
    worst = 0
    worst_fb = 0
    nfb = 0
    do i = 1, n, stride
      call random_number(u)
      if (u(1) < 0.5_wp) then
        th = sign(10.0_wp**(-8 + 14*u(2)), u(3) - 0.5_wp)
      else
        th = 2.0e6_wp*(u(2) - 0.5_wp)
      end if
      d = (u(4) - 0.5_wp)*merge(0.22_wp, 1.0_wp, i <= 3*n/4)
      if (abs(d) <= stage_rmax - 0.0123_wp) then
        e = err_eps(sin_shift(th, d), th, d)
        worst = max(worst, e)
      else
        ! fallback or not, the result is libm's sin of the rounded sum at worst
        e = abs(sin_shift(th, d) - sin(th + d))/eps
        if (abs(d) > stage_rmax) then
          worst_fb = max(worst_fb, e)
          nfb = nfb + 1
        else
          ! the band where node offset + d may or may not exceed rmax: either path
          worst = max(worst, min(err_eps(sin_shift(th, d), th, d), e))
        end if
      end if
    end do
    print '(a, f6.3, a)', 'sin_shift: max |error|, random |theta| <= 1e6 = ', worst, ' eps'
    print '(a, i0, a, f6.3, a)', 'sin_shift fallback (|d| > rmax, ', nfb, ' points): max |diff| to libm = ', &
      worst_fb, ' eps'
    call tc%check_true(worst <= 2, 'sin_shift random theta within 2 eps of the exact sum')
    call tc%check_true(worst_fb <= 0, 'sin_shift beyond rmax is libm sin(theta + d)')
    call tc%check_true(nfb > 1000, 'fallback path exercised')
  end subroutine test_sin_shift_random

  !> Against libm itself: d' = fl(theta + d) - theta is exact (|theta| >= |d|),
  !> so theta + d' is a double and libm's sin(theta + d') is a fair reference.
  subroutine test_against_libm()
    integer, parameter :: n = 200000
    real(wp) :: u(3), th, d, worst
    integer :: i
    worst = 0
    do i = 1, n, stride
      call random_number(u)
      th = sign(10.0_wp**(-1 + 7*u(1)), u(2) - 0.5_wp)
      if (i <= 1000) th = -12.0_wp + 0.024_wp*i
      d = (u(3) - 0.5_wp)*2*(stage_rmax - 0.0123_wp)
      d = (th + d) - th
      worst = max(worst, abs(sin_shift(th, d) - sin(th + d))/eps)
    end do
    print '(a, f6.3, a)', 'sin_shift vs libm sin at exactly representable arguments: max |diff| = ', worst, ' eps'
    call tc%check_true(worst <= 2, 'sin_shift within 2 eps of libm sin')
  end subroutine test_against_libm

  !> node_reduce at the edges: exact multiples of the node spacing, the
  !> largest reduced |theta|, and what lies beyond (k = 0, rho = theta).
  subroutine test_reduce_extremes()
    integer :: k
    real(wp) :: rho, xs(6)
    integer :: i
    xs = [0.0_wp, -0.0_wp, 1.0e-300_wp, stage_xmax, -stage_xmax, 0.5_wp*stage_xmax + 0.3_wp]
    do i = 1, size(xs)
      call node_reduce(xs(i), k, rho)
      call tc%check_true(abs(rho) <= 0.0123_wp, 'node_reduce |rho| <= pi/256')
      call tc%check_true(abs(real(sin_node(k, rho), qp) - sin(real(xs(i), qp))) <= 2*eps, &
                         'sin_node(node_reduce(x)) = sin x')
    end do
    call node_reduce(2*stage_xmax, k, rho)
    call tc%check_true(k == 0 .and. rho == 2*stage_xmax, 'beyond stage_xmax: not reduced')
    call node_reduce(huge(1.0_wp), k, rho)
    call tc%check_true(k == 0 .and. rho == huge(1.0_wp), 'huge: not reduced, no overflow')
  end subroutine test_reduce_extremes

  !> The previous implementation: four libm sines per step.
  pure subroutine plain(theta, omega, w0sq, gamma, hs, n)
    real(wp), intent(inout) :: theta, omega
    real(wp), intent(in) :: w0sq, gamma, hs
    integer(i8), intent(in) :: n
    real(wp) :: y, u, k1, k2, k3, k4, m2, m3, m4, half, sixth
    integer(i8) :: i
    y = theta
    u = omega
    half = hs/2
    sixth = hs/6
    do i = 1, n
      k1 = -gamma*u - w0sq*sin(y)
      m2 = u + half*k1
      k2 = -gamma*m2 - w0sq*sin(y + half*u)
      m3 = u + half*k2
      k3 = -gamma*m3 - w0sq*sin(y + half*m2)
      m4 = u + hs*k3
      k4 = -gamma*m4 - w0sq*sin(y + hs*m3)
      y = y + sixth*(u + 2*(m2 + m3) + m4)
      u = u + sixth*(k1 + 2*(k2 + k3) + k4)
    end do
    theta = y
    omega = u
  end subroutine plain

  !> Text scenario (w0 = sqrt 2, gamma = 0.1 and 0.5, theta0 = 0, Omega0 = 2,
  !> outputs every 0.05 s to 30 s) with h = 0.05 and 0.001, plus a rotating
  !> start (Omega0 = 3), a large angle and a fast rotation (Omega0 = 4.2): max |difference| to the plain loop
  !> over the outputs must stay within 32 eps max(1, |theta|) (rounding only:
  !> both are the same RK4 scheme, each rounding theta and Omega once per step;
  !> measured <= 6.5), and the table path must carry the text scenario.
  subroutine test_vs_plain_rk4()
    real(wp), parameter :: w0sq = 2, hv(2) = [0.05_wp, 0.001_wp], gv(2) = [0.1_wp, 0.5_wp]
    real(wp) :: y1, u1, dmax, hs, scale, t(601), th(601), om(601)
    integer :: ih, ig, i, icase, bad, tol
    integer(i8) :: nsub, fast, total
    real(wp) :: th0(4), om0(4)
    character(len=80) :: label
    ! case 4 rotates fast enough (h Omega up to ~0.25) that some steps fall
    ! beyond the table path onto the libm step
    th0 = [0.0_wp, 0.0_wp, 1000.5_wp, 0.0_wp]
    om0 = [2.0_wp, 3.0_wp, 2.0_wp, 4.2_wp]
    t = [(0.05_wp*i, i=0, 600)]
    do icase = 1, 4
      do ig = 1, 2
        do ih = 1, 2
          hs = hv(ih)
          nsub = nint(0.05_wp/hs, i8)
          th(1) = th0(icase)
          om(1) = om0(icase)
          call rk4_grid(t, w0sq, gv(ig), hs, th, om, total, fast, bad)
          call tc%check_true(bad == 0 .and. total == 600*nsub, 'rk4_grid: steps and no failure')
          y1 = th0(icase)
          u1 = om0(icase)
          dmax = 0
          scale = 1
          do i = 1, 600
            ! the plain loop with the substep rk4_grid uses (t(i+1) - t(i)) / n
            call plain(y1, u1, w0sq, gv(ig), (t(i + 1) - t(i))/real(nsub, wp), nsub)
            dmax = max(dmax, abs(y1 - th(i + 1)), abs(u1 - om(i + 1)))
            scale = max(scale, abs(y1))
          end do
          write (label, '(a, i0, a, f4.2, a, f5.3, a)') 'case ', icase, ' gamma ', gv(ig), ' h ', hs, ': '
          print '(a, a, es9.2, a, f9.2, a, i0, a, i0)', trim(label), ' max |fast - plain| = ', dmax, &
            ' = ', dmax/(eps*scale), ' eps*max(1,|theta|); table steps ', fast, ' / ', total
          ! A fast rotation is neutrally stable: the two rounding sequences
          ! drift apart as a random walk (~28 eps after 30000 steps, the same
          ! with the earlier kernel), hence its wider bound.
          tol = merge(64, 32, icase == 4)
          call tc%check_true(dmax <= tol*eps*scale, trim(label)//' within 32 (rotation: 64) eps of plain')
          if (icase == 1) call tc%check_true(fast == total, trim(label)//' all steps on the table path')
        end do
      end do
    end do
  end subroutine test_vs_plain_rk4

end program test_rk4_kernel
