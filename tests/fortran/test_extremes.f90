!> Extreme inputs through the public Fortran API, for the checked build
!> (-fcheck=all, FPE traps) and the valgrind leg: m, p = +-1e308, NaN, Inf,
!> subnormals, phi at the doubles nearest odd multiples of pi/2, w0 = 5e-324,
!> theta0/omega0 = DBL_MAX, arrays of the wrong size.  Every call must either
!> report a non-OK status or give a finite result where the true one is
!> finite; status-less elemental functions must not crash and must be finite
!> inside their domain.  No value is compared here (the accuracy tests do that):
!> this program is about never crashing, trapping or going non-finite.
program test_extremes
  use, intrinsic :: iso_fortran_env, only: int64
  use, intrinsic :: ieee_arithmetic, only: ieee_value, ieee_quiet_nan, ieee_get_halting_mode, ieee_invalid, &
                                                                              ieee_positive_inf, ieee_negative_inf
  use pendula
  use pendula_testing, only: checker_t
  implicit none
  type(checker_t) :: tc
  integer, parameter :: nx = 16
  real(wp) :: x(nx), nan, pinf, ninf
  ! In the checked build invalid operations trap.  The elemental functions follow
  ! SciPy's rule (NaN or out-of-domain in -> NaN out), and producing that NaN
  ! raises IEEE invalid, as sqrt(-1) does: there they get finite inputs only.
  ! Procedures with a status get every input: they must check before computing.
  logical :: trapping
  real(wp), parameter :: half_pi = 1.5707963267948966_wp, dmax = huge(1.0_wp)

  call ieee_get_halting_mode(ieee_invalid, trapping)
  nan = ieee_value(1.0_wp, ieee_quiet_nan)
  pinf = ieee_value(1.0_wp, ieee_positive_inf)
  ninf = ieee_value(1.0_wp, ieee_negative_inf)
  x = [0.0_wp, -0.0_wp, 0.5_wp, 1.0_wp, -1.0_wp, 1.0e308_wp, -1.0e308_wp, dmax, -dmax, 1.34e300_wp, &
       5.0e-324_wp, tiny(1.0_wp), 1.0e-300_wp, nan, pinf, ninf]

  call elliptic_scalars()
  call elliptic_arrays()
  call physics()
  call undamped_and_small_angle()
  call linear_damped()
  call integrators()
  call tc%report('test_extremes')

contains

  ! Finite by the exponent bits: a comparison or ieee_is_finite on a NaN may
  ! raise the invalid flag, which traps in the checked build.
  elemental logical function fin(v)
    real(wp), intent(in) :: v
    fin = iand(shiftr(transfer(v, 0_int64), 52), 2047_int64) /= 2047_int64
  end function fin

  ! an input the elemental functions may get in this build (see `trapping`)
  elemental logical function elemental_ok(v)
    real(wp), intent(in) :: v
    elemental_ok = .not. trapping .or. fin(v)
  end function elemental_ok

  ! an input the status procedures get in this build: in the checked build
  ! (overflow traps) magnitudes whose results themselves overflow (energy
  ! Omega0**2/2 with Omega0 = 1e308) are left to the non-trapping builds,
  ! where the fuzz leg and this program check the +-Inf or error they give;
  ! likewise tiny rates (the period 2 pi/w0 of w0 = 5e-324 is +Inf)
  elemental logical function moderate(v)
    real(wp), intent(in) :: v
    moderate = .not. trapping .or. .not. fin(v)
    if (.not. moderate) moderate = v == 0 .or. (abs(v) <= 1.0e150_wp .and. abs(v) >= 1.0e-150_wp)
  end function moderate

  ! |v| < lim, false for NaN and Inf, without a compare that could trap
  elemental logical function below(v, lim)
    real(wp), intent(in) :: v, lim
    below = .false.
    if (fin(v)) below = abs(v) < lim
  end function below

  logical function all_fin(v)
    real(wp), intent(in) :: v(:)
    all_fin = all(fin(v))
  end function all_fin

  !> K, E, F, sn/cn/dn at every pair of extremes: finite inside the domain.
  subroutine elliptic_scalars()
    integer :: i, j
    real(wp) :: sn, cn, dn, am, f
    character(len=80) :: label
    do i = 1, nx
      if (fin(x(i))) then   ! nested: a NaN compare traps in the checked build
        if (x(i) < 1) call tc%check_true(fin(ellipk(x(i))), 'ellipk finite for m < 1')
        if (x(i) > 0) call tc%check_true(fin(ellipkm1(x(i))), 'ellipkm1 finite for p > 0')
        if (x(i) <= 1) call tc%check_true(fin(ellipe(x(i))), 'ellipe finite for m <= 1')
        if (x(i) >= 0) call tc%check_true(fin(ellipem1(x(i))), 'ellipem1 finite for p >= 0')
      end if
      do j = 1, nx
        if (.not. (elemental_ok(x(i)) .and. elemental_ok(x(j)))) cycle
        write (label, '(a, 2es11.3)') 'ellipj (u, m) =', x(j), x(i)
        call ellipj(x(j), x(i), sn, cn, dn, am)
        if (fin(x(i)) .and. fin(x(j))) call tc%check_true(fin(sn) .and. fin(cn) .and. fin(dn), trim(label))
        write (label, '(a, 2es11.3)') 'ellipjm1 (u, p) =', x(j), x(i)
        call ellipjm1(x(j), x(i), sn, cn, dn, am)
        if (fin(x(i)) .and. fin(x(j))) call tc%check_true(fin(sn) .and. fin(cn) .and. fin(dn), trim(label))
        f = ellipf(x(j), x(i))
        ! nested: Fortran need not short-circuit, and a NaN compare traps here
        if (fin(x(j)) .and. fin(x(i))) then
          if (abs(x(j)) <= 1.0e300_wp .and. x(i) <= 0) then
            write (label, '(a, 2es11.3)') 'ellipf finite (phi, m) =', x(j), x(i)
            call tc%check_true(fin(f), trim(label))
          end if
        end if
        f = ellipfm1(x(j), x(i))
      end do
    end do
    ! phi at the doubles nearest odd multiples of pi/2, m at or next to 1: F is finite there
    call tc%check_true(fin(ellipf(half_pi, 1.0_wp)), 'ellipf(fl(pi/2), 1) finite (38.03)')
    call tc%check_true(fin(ellipfm1(half_pi, 0.0_wp)), 'ellipfm1(fl(pi/2), 0) finite (38.03)')
    call tc%check_true(abs(ellipfm1(half_pi, 1.0e-300_wp) - 38.025003373828868_wp) < 1.0e-9_wp, &
                       'ellipfm1(fl(pi/2), 1e-300) = 38.025003373828868')
    call tc%check_true(abs(ellipfm1(3*half_pi, 1.0e-300_wp) - 730.47450770561424_wp) < 1.0e-8_wp, &
                       'ellipfm1(fl(3 pi/2), 1e-300) = 730.47450770561424')
    call ellipj(0.7_wp, 1.0e308_wp, sn, cn, dn, am)
    call tc%check_true(fin(sn) .and. fin(cn) .and. fin(dn) .and. fin(am), 'ellipj(0.7, 1e308) finite')
  end subroutine elliptic_scalars

  !> Array routines with extreme elements, then with outputs of the wrong size
  !> (these must be refused, not written out of bounds).
  subroutine elliptic_arrays()
    real(wp) :: k(nx), e(nx), sn(nx), cn(nx), dn(nx), am(nx), u(nx)
    real(wp) :: short(3), xa(nx)
    type(status_t) :: st
    u = 0.7_wp
    xa = merge(x, 0.5_wp, elemental_ok(x))
    call ellipk_array(xa, k, st)
    call ellipe_array(xa, e, st)
    call ellipj_array(u, xa, sn, cn, dn, st, am)
    call tc%check_true(all_fin(sn(1:13)) .and. all_fin(cn(1:13)) .and. all_fin(dn(1:13)), &
                       'ellipj_array finite for finite m')
    call ellipjm1_array(u, xa, sn, cn, dn, st, am)
    call tc%check_true(all_fin(sn(1:13)) .and. all_fin(cn(1:13)) .and. all_fin(dn(1:13)), &
                       'ellipjm1_array finite for finite p')
    ! Wrong sizes: refused with a size error, nothing written out of bounds.
    short = -1
    call ellipk_array(xa, short, st)
    call tc%check_true(st%code == PENDULA_ERR_SIZE, 'ellipk_array short output: size error')
    call ellipe_array(xa, short, st)
    call tc%check_true(st%code == PENDULA_ERR_SIZE, 'ellipe_array short output: size error')
    call ellipj_array(u, xa, short, cn, dn, st, am)
    call tc%check_true(st%code == PENDULA_ERR_SIZE, 'ellipj_array short sn: size error')
    call ellipjm1_array(u, xa, sn, short, dn, st, am)
    call tc%check_true(st%code == PENDULA_ERR_SIZE, 'ellipjm1_array short cn: size error')
  end subroutine elliptic_arrays

  subroutine physics()
    integer :: i, j
    real(wp) :: r
    type(status_t) :: st
    do i = 1, nx
      do j = 1, nx
        call natural_frequency(x(i), x(j), r, st)
        call tc%check_true(.not. status_ok(st) .or. fin(r), 'natural_frequency: error or finite')
        call damping_rate(x(i), x(j), r, st)
        call tc%check_true(.not. status_ok(st) .or. fin(r), 'damping_rate: error or finite')
      end do
      call small_angle_period(x(i), r, st)
      call tc%check_true(.not. status_ok(st) .or. fin(r), 'small_angle_period: error or finite')
    end do
  end subroutine physics

  subroutine undamped_and_small_angle()
    integer :: i, j, l
    real(wp) :: th, om, w0s(4)
    type(status_t) :: st
    type(undamped_motion_t) :: mo
    character(len=80) :: label
    w0s = [1.0_wp, 5.0e-324_wp, 1.0e308_wp, nan]
    do l = 1, size(w0s)
      do i = 1, nx
        do j = 1, nx
          if (.not. (moderate(x(i)) .and. moderate(x(j)) .and. moderate(w0s(l)))) cycle
          call undamped_init(mo, x(i), x(j), w0s(l), st)
          if (status_ok(st)) then
            call undamped_eval(mo, 1.5_wp, th, om)
            write (label, '(a, 3es11.3)') 'undamped (theta0, omega0, w0) =', x(i), x(j), w0s(l)
            if (below(x(i), 1.0e300_wp) .and. below(x(j), 1.0e300_wp) .and. below(w0s(l), 1.0e300_wp)) &
              call tc%check_true(fin(th) .and. fin(om), trim(label))
          end if
          if (.not. (elemental_ok(x(i)) .and. elemental_ok(x(j)) .and. elemental_ok(w0s(l)))) cycle
          call small_angle(1.5_wp, x(i), x(j), w0s(l), th, om)
          write (label, '(a, 3es11.3)') 'small_angle (theta0, omega0, w0) =', x(i), x(j), w0s(l)
          if (below(x(i), 1.0e300_wp) .and. below(x(j), 1.0e300_wp) .and. below(w0s(l), 1.0e300_wp)) &
            call tc%check_true(fin(th) .and. fin(om), trim(label))
        end do
      end do
    end do
  end subroutine undamped_and_small_angle

  subroutine linear_damped()
    integer :: i, j
    real(wp) :: th, om
    type(status_t) :: st
    type(linear_damped_t) :: sol
    type(damping_regime_t) :: info
    character(len=80) :: label
    do i = 1, nx
      do j = 1, nx
        if (.not. (moderate(x(i)) .and. moderate(x(j)))) cycle
        call linear_damped_init(sol, x(i), 0.5_wp, 1.4_wp, abs(x(j)), st)
        if (status_ok(st)) then
          call linear_damped_state(sol, 1.5_wp, th, om)
          write (label, '(a, 2es11.3)') 'linear_damped (theta0, gamma) =', x(i), abs(x(j))
          ! |theta(t)| <= hypot(theta0, omega0/w0) (the energy never grows)
          if (below(x(i), 1.0e300_wp)) call tc%check_true(fin(th) .and. fin(om), trim(label))
        end if
        call damping_regime(x(i), x(j), info, st)
      end do
    end do
    ! the reported case: theta0 = DBL_MAX, Omega(1.5) = -1.7570279627426679e308 is representable
    call linear_damped_init(sol, dmax, 0.5_wp, 1.4_wp, 0.3_wp, st)
    if (status_ok(st)) then
      call linear_damped_state(sol, 1.5_wp, th, om)
      call tc%check_true(fin(th) .and. fin(om), 'linear_damped theta0 = DBL_MAX: finite state')
    end if
  end subroutine linear_damped

  subroutine integrators()
    integer :: i
    real(wp) :: t(3), th(3), om(3), th_short(2), om_short(2)
    type(ode_stats_t) :: stats
    type(status_t) :: st
    t = [0.0_wp, 0.5_wp, 1.0_wp]
    do i = 1, nx
      if (.not. moderate(x(i))) cycle
      call rk4_solve(t, x(i), 0.3_wp, 1.0_wp, 0.1_wp, 0.01_wp, th, om, stats, st)
      call tc%check_true(.not. status_ok(st) .or. (all_fin(th) .and. all_fin(om)), 'rk4 theta0 extreme')
      call rk4_solve(t, 0.3_wp, x(i), 1.0_wp, 0.1_wp, 0.01_wp, th, om, stats, st)
      call tc%check_true(.not. status_ok(st) .or. (all_fin(th) .and. all_fin(om)), 'rk4 omega0 extreme')
      call rk4_solve(t, 0.3_wp, 0.3_wp, x(i), 0.1_wp, 0.01_wp, th, om, stats, st)
      call tc%check_true(.not. status_ok(st) .or. (all_fin(th) .and. all_fin(om)), 'rk4 w0 extreme')
      call rk4_solve(t, 0.3_wp, 0.3_wp, 1.0_wp, x(i), 0.01_wp, th, om, stats, st)
      call tc%check_true(.not. status_ok(st) .or. (all_fin(th) .and. all_fin(om)), 'rk4 gamma extreme')
      call rk4_solve(t, 0.3_wp, 0.3_wp, 1.0_wp, 0.1_wp, x(i), th, om, stats, st)
      call tc%check_true(.not. status_ok(st) .or. (all_fin(th) .and. all_fin(om)), 'rk4 h extreme')
    end do
    call rk4_solve(t, 0.3_wp, 0.3_wp, 1.0_wp, 0.1_wp, 0.01_wp, th_short, om_short, stats, st)
    call tc%check_true(.not. status_ok(st), 'rk4 outputs shorter than t: refused')
  end subroutine integrators

end program test_extremes
