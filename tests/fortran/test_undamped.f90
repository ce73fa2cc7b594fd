!> Undamped concern: exact motion, small-angle model and bound, equilibria.
!> References: mpmath at 60 digits from the exact double inputs
!> (tools/gen/gen_undamped_reference.py), with the condition number
!> cond = sum |x d(.)/dx| over theta0, Omega0, w0, t; required |error| <=
!> 16 eps (cond + |ref|) and <= 1e-11 absolute.
program test_undamped
  use, intrinsic :: ieee_arithmetic, only: ieee_value, ieee_quiet_nan, ieee_positive_inf
  use pendula
  use pendula_testing, only: checker_t
  implicit none
  type(checker_t) :: tc
  real(wp), parameter :: eps = epsilon(1.0_wp)
  ! theta0, omega0, w0, t, theta_ref, omega_ref, cond_theta, cond_omega
  real(wp), parameter :: refs(8, 19) = reshape([ &
                             1.0_wp, 0.5_wp, 1.4142135623730951_wp, 0.7_wp, 0.92602772258158033764_wp, -0.70202908268262889553_wp, &
                                               2.39184_wp, 4.35091_wp, &
                         1.0_wp, 0.5_wp, 1.4142135623730951_wp, -3.3_wp, -0.00047456773891349691201_wp, -1.4452647944575319934_wp, &
                                               10.4831_wp, 2.61536_wp, &
                            1.0_wp, 0.5_wp, 1.4142135623730951_wp, 250.0_wp, 0.43874407166759223057_wp, -1.3076445894747223967_wp, &
                                               712.872_wp, 462.807_wp, &
                       -2.0_wp, 3.9_wp, 1.3_wp, 1.1_wp, 2.6018005981964298711_wp, 3.703668406498491335_wp, 9.32504_wp, 5.84983_wp, &
                     -2.0_wp, 3.9_wp, 1.3_wp, -40.0_wp, -163.70521237631526134_wp, 4.4497616814753361502_wp, 392.275_wp, 44.88_wp, &
                    -2.0_wp, 3.9_wp, 1.3_wp, 500.0_wp, 2020.1980898933944679_wp, 3.6437047449354951489_wp, 3989.65_wp, 288.357_wp, &
                                  0.0_wp, 1.999999999998_wp, 1.0_wp, 5.0_wp, 3.1146412733778331004_wp, 0.026950564368454701557_wp, &
                                               148.541_wp, 148.555_wp, &
                                0.0_wp, 1.999999999998_wp, 1.0_wp, 30.0_wp, -0.57110695755558301719_wp, -1.9190117819820375766_wp, &
                                               3.83811e+12_wp, 1.08115e+12_wp, &
                                 0.0_wp, 1.999999999998_wp, 1.0_wp, 300.0_wp, 2.9206551734361872542_wp, 0.22048839161728893397_wp, &
                                               4.40987e+12_wp, 4.38299e+12_wp, &
                                  0.0_wp, 2.000000000002_wp, 1.0_wp, 5.0_wp, 3.1146412735263792341_wp, 0.026950564516771760641_wp, &
                                               148.541_wp, 148.555_wp, &
                                   0.0_wp, 2.000000000002_wp, 1.0_wp, 30.0_wp, 6.8545053074530045944_wp, 1.9189517594024735397_wp, &
                                               3.83756e+12_wp, 1.08139e+12_wp, &
                                 0.0_wp, 2.000000000002_wp, 1.0_wp, 300.0_wp, 65.752752893429990884_wp, 0.22024523305209571091_wp, &
                                               4.40451e+12_wp, 4.37772e+12_wp, &
                            3.141592653489793_wp, 0.0_wp, 1.0_wp, 10.0_wp, 3.1415915522650613722_wp, -1.1013247273261920715e-6_wp, &
                                               34599.1_wp, 34599.1_wp, &
                          3.141592653489793_wp, 0.0_wp, 1.0_wp, 50.0_wp, -3.1415926534875676532_wp, -2.1214243631566976608e-11_wp, &
                                               1.87858_wp, 5.75655_wp, &
                         3.141592653489793_wp, 0.0_wp, 1.0_wp, -200.0_wp, 3.1415926534521693127_wp, -9.4553258966457665379e-11_wp, &
                                               19.4402_wp, 31.6181_wp, &
                   20.0_wp, -0.3_wp, 0.8_wp, 2.0_wp, 18.542846314024864145_wp, -0.88764866102157374054_wp, 8.94665_wp, 15.2271_wp, &
                  20.0_wp, -0.3_wp, 0.8_wp, -9.0_wp, 20.06754781927644499_wp, -0.099671767917221799589_wp, 18.7181_wp, 26.8272_wp, &
                      0.0_wp, 2.0_wp, 1.0_wp, 3.0_wp, 2.9426086822343854829_wp, 0.19865585483886641566_wp, 20.6317_wp, 20.7283_wp, &
                           0.0_wp, 2.0_wp, 1.0_wp, -1000.0_wp, -3.1415926535897932385_wp, 0.0_wp, 2.27282e+24_wp, 1.07355e+22_wp], &
                                               [8, 19])

  call check_references()
  call check_periods_and_regimes()
  call check_invariants()
  call check_text_special_cases()
  call check_small_angle()
  call check_equilibria()
  call check_bad_input()
  call check_many_states()
  call check_many_states_bad_input()
  call tc%report('test_undamped')

contains

  subroutine check_references()
    type(undamped_motion_t) :: mo
    type(status_t) :: st
    real(wp) :: th, om, worst_t, worst_o
    character(len=80) :: label
    integer :: i
    worst_t = 0
    worst_o = 0
    do i = 1, size(refs, 2)
      call undamped_init(mo, refs(1, i), refs(2, i), refs(3, i), st)
      call tc%check_true(status_ok(st), 'init ok')
      call undamped_eval(mo, refs(4, i), th, om)
      write (label, '(a, i0)') 'mpmath reference row ', i
      call tc%check_true(abs(th - refs(5, i)) <= 16*eps*(refs(7, i) + abs(refs(5, i))), 'theta '//trim(label))
      call tc%check_true(abs(om - refs(6, i)) <= 16*eps*(refs(8, i) + abs(refs(6, i))) + tiny(1.0_wp), &
                         'omega '//trim(label))
      call tc%check_true(abs(th - refs(5, i)) <= 1.0e-11_wp, 'theta within 1e-11 rad, '//trim(label))
      call tc%check_true(abs(om - refs(6, i)) <= 1.0e-11_wp, 'omega within 1e-11 rad/s, '//trim(label))
      worst_t = max(worst_t, abs(th - refs(5, i))/(eps*(refs(7, i) + abs(refs(5, i)))))
      worst_o = max(worst_o, abs(om - refs(6, i))/(eps*(refs(8, i) + abs(refs(6, i)))))
      ! function forms agree with the subroutine
      call tc%check_true(undamped_theta(mo, refs(4, i)) == th .and. undamped_omega(mo, refs(4, i)) == om, &
                         'undamped_theta/omega == undamped_eval')
    end do
    write (*, '(a, 2f8.3)') 'worst err/(eps (cond + |ref|)) theta, omega:', worst_t, worst_o
  end subroutine check_references

  subroutine check_periods_and_regimes()
    type(undamped_motion_t) :: mo
    type(status_t) :: st
    call undamped_init(mo, 1.0_wp, 0.5_wp, sqrt(2.0_wp), st)
    call tc%check_close(undamped_period(mo), 4.7851695711764938518_wp, 4*eps, 0.0_wp, 'libration period')
    call tc%check_true(undamped_regime(mo) == REGIME_LIBRATION, 'libration regime')
    call tc%check_true(undamped_regime_name(undamped_regime(mo)) == 'libration', 'regime name')
    call undamped_init(mo, -2.0_wp, 3.9_wp, 1.3_wp, st)
    call tc%check_close(undamped_period(mo), 1.5536143727713928052_wp, 4*eps, 0.0_wp, 'time per turn (rotation)')
    call tc%check_true(undamped_regime(mo) == REGIME_ROTATION, 'rotation regime')
    call tc%check_true(undamped_amplitude(mo) > huge(1.0_wp), 'rotation amplitude +inf')
    call undamped_init(mo, 0.0_wp, 1.999999999998_wp, 1.0_wp, st)
    call tc%check_close(undamped_period(mo), 59.420969559175098849_wp, 1.0e-13_wp, 0.0_wp, 'near-separatrix period')
    call tc%check_close(mo%mc, 1.999955757e-12_wp, 1.0e-9_wp, 0.0_wp, '1 - m without cancellation')
    call undamped_init(mo, 0.0_wp, 2.000000000002_wp, 1.0_wp, st)
    call tc%check_close(undamped_period(mo), 29.710373760963109245_wp, 1.0e-13_wp, 0.0_wp, 'near-separatrix turn')
    call tc%check_close(mo%mc, -2.000177801e-12_wp, 1.0e-9_wp, 0.0_wp, '1 - m < 0 without cancellation')
    ! the slow hug of the top: period to 1e-12 relative (the target), 1 - m = 2.5e-21
    call undamped_init(mo, 3.141592653489793_wp, 0.0_wp, 1.0_wp, st)
    call tc%check_close(undamped_period(mo), 100.42116465693590901_wp, 1.0e-12_wp, 0.0_wp, 'hug of the top period')
    call tc%check_close(mo%mc, 2.500006537e-21_wp, 1.0e-9_wp, 0.0_wp, 'hug of the top 1 - m')
    call undamped_init(mo, 0.0_wp, 2.0_wp, 1.0_wp, st)
    call tc%check_true(undamped_regime(mo) == REGIME_SEPARATRIX, 'separatrix regime')
    call tc%check_true(undamped_period(mo) > huge(1.0_wp), 'separatrix period +inf')
    call tc%check_close(undamped_amplitude(mo), pi, eps, 0.0_wp, 'separatrix amplitude pi')
    call tc%check_close(undamped_energy(mo), 2.0_wp, eps, 0.0_wp, 'separatrix energy 2 w0^2')
  end subroutine check_periods_and_regimes

  subroutine check_invariants()
    type(undamped_motion_t) :: mo, mr
    type(status_t) :: st
    real(wp) :: t(200), th(200), om(200), thr(200), omr(200), e0, tmax
    integer :: i, j
    real(wp), parameter :: states(3, 5) = reshape([1.0_wp, 0.5_wp, 1.3_wp, -2.0_wp, 3.9_wp, 1.3_wp, &
                                         0.0_wp, 1.999999999_wp, 1.0_wp, 3.0_wp, -0.01_wp, 0.5_wp, 7.0_wp, 12.0_wp, 2.0_wp], [3, 5])
    do j = 1, size(states, 2)
      call undamped_init(mo, states(1, j), states(2, j), states(3, j), st)
      call undamped_init(mr, states(1, j), -states(2, j), states(3, j), st)
      tmax = 100*undamped_period(mo)
      t = [(tmax*(real(i, wp)/100 - 1), i=1, 200)]
      call undamped_eval(mo, t, th, om)
      e0 = pendulum_energy(states(1, j), states(2, j), states(3, j))
      call tc%check_close(e0, undamped_energy(mo), 4*eps, 0.0_wp, 'E(state) = 2 w0^2 m')
      call tc%check_true(all(abs(pendulum_energy(th, om, states(3, j)) - e0) <= &
                             8*eps*(e0 + states(3, j)**2*abs(sin(th)*th) + om**2)), 'energy constant over 100 periods')
      ! time reversal: theta(-t; Omega0) = theta(t; -Omega0), Omega flips
      call undamped_eval(mr, -t, thr, omr)
      call tc%check_true(all(abs(thr - th) <= 2*eps*abs(th)) .and. all(abs(omr + om) <= 2*eps*abs(om)), &
                         'time reversal')
      call undamped_eval(mo, 0.0_wp, th(1), om(1))
      call tc%check_close(th(1), states(1, j), 2*eps, 0.0_wp, 'theta(0) = theta0')
      call tc%check_close(om(1), states(2, j), 4*eps, 0.0_wp, 'Omega(0) = Omega0')
    end do
    ! the blocked path agrees with the elemental one (600 times: three blocks, one huge t);
    ! ellipj_eval_array and ellipj_eval may differ by an ulp or two
    do j = 1, size(states, 2)
      call undamped_init(mo, states(1, j), states(2, j), states(3, j), st)
      block
        real(wp) :: tm(600), a1(600), b1(600), a2(600), b2(600)
        tm = [(undamped_period(mo)*(0.37_wp*i - 90), i=1, 600)]
        tm(300) = 1.0e15_wp
        call undamped_eval(mo, tm, a1, b1)
        call undamped_eval_many(mo, tm, a2, b2, st)
        call tc%check_true(status_ok(st), 'eval_many status ok')
        call tc%check_true(all(abs(a2 - a1) <= 16*eps*max(1.0_wp, abs(a1))), 'eval_many theta == eval')
        call tc%check_true(all(abs(b2 - b1) <= 16*eps*max(states(3, j), abs(b1))), 'eval_many omega == eval')
        call undamped_eval_many(mo, tm, a2(1:599), b2, st)
        call tc%check_true(st%code == PENDULA_ERR_SIZE, 'eval_many rejects a short theta')
      end block
    end do
    ! array convenience
    call undamped_solve([0.0_wp, 1.0_wp, -1.0_wp], 1.0_wp, 0.5_wp, 1.3_wp, th(1:3), om(1:3), st)
    call tc%check_true(status_ok(st), 'undamped_solve ok')
    call undamped_init(mo, 1.0_wp, 0.5_wp, 1.3_wp, st)
    ! three times: undamped_solve builds a light motion (no plan); same values to a few ulps
    call tc%check_true(abs(th(2) - undamped_theta(mo, 1.0_wp)) <= 4*eps*abs(th(2)) .and. &
                       abs(om(3) - undamped_omega(mo, -1.0_wp)) <= 4*eps*abs(om(3)), 'undamped_solve == undamped_eval')
    ! a light motion (plan = .false.) against the mpmath rows
    block
      type(undamped_motion_t) :: ml
      real(wp) :: a, b
      do i = 1, size(refs, 2)
        call undamped_init(ml, refs(1, i), refs(2, i), refs(3, i), st, plan=.false.)
        call undamped_eval(ml, refs(4, i), a, b)
        call tc%check_true(abs(a - refs(5, i)) <= 16*eps*(refs(7, i) + abs(refs(5, i))) .and. &
                           abs(b - refs(6, i)) <= 16*eps*(refs(8, i) + abs(refs(6, i))) + tiny(1.0_wp), 'light motion vs mpmath')
      end do
    end block
  end subroutine check_invariants

  subroutine check_text_special_cases()
    ! eq. 1.52 (Omega0 = 0): theta = 2 asin{k sn(K - w0 t | k^2)}, k = sin(theta0/2);
    ! eq. 1.66 (theta0 = 0): theta = 2 asin{k sn(w0 t | k^2)}, k = Omega0/(2 w0).
    type(undamped_motion_t) :: mo
    type(status_t) :: st
    real(wp) :: k, sn, cn, dn, w0, t, th, om, kk
    integer :: i
    w0 = sqrt(2.0_wp)
    k = sin(0.5_wp*0.75_wp*pi)
    kk = ellipk(k*k)
    call undamped_init(mo, 0.75_wp*pi, 0.0_wp, w0, st)
    do i = 0, 20
      t = 0.37_wp*i
      call ellipj(kk - w0*t, k*k, sn, cn, dn)
      call undamped_eval(mo, t, th, om)
      call tc%check_close(th, 2*asin(k*sn), 0.0_wp, 1.0e-13_wp, 'eq. 1.52 from the general formula')
    end do
    k = 0.9_wp
    call undamped_init(mo, 0.0_wp, 2*k*w0, w0, st)
    do i = 0, 20
      t = 0.41_wp*i
      call ellipj(w0*t, k*k, sn, cn, dn)
      call undamped_eval(mo, t, th, om)
      call tc%check_close(th, 2*asin(k*sn), 0.0_wp, 1.0e-13_wp, 'eq. 1.66 from the general formula')
      call tc%check_close(om, 2*k*w0*cn, 0.0_wp, 1.0e-13_wp, 'Omega of eq. 1.66')
    end do
  end subroutine check_text_special_cases

  subroutine check_small_angle()
    type(undamped_motion_t) :: mo
    type(status_t) :: st
    real(wp) :: t(2001), th(2001), om(2001), ths(2001), oms(2001), dth, dom, tmax
    integer :: i
    call small_angle(0.5_wp, 0.2_wp, -0.1_wp, 1.5_wp, th(1), om(1))
    call tc%check_close(th(1), 0.2_wp*cos(0.75_wp) - (0.1_wp/1.5_wp)*sin(0.75_wp), 0.0_wp, 4*eps, &
                        'small-angle theta formula')
    call tc%check_close(om(1), -0.3_wp*sin(0.75_wp) - 0.1_wp*cos(0.75_wp), 0.0_wp, 4*eps, &
                        'small-angle omega formula')
    call undamped_init(mo, 0.3_wp, 0.2_wp, 1.1_wp, st)
    tmax = 60.0_wp
    t = [(tmax*(real(i, wp)/1000 - 1), i=0, 2000)]
    call undamped_eval(mo, t, th, om)
    call small_angle_eval(mo, t, ths, oms)
    call small_angle_bound(mo, tmax, dth, dom)
    call tc%check_true(maxval(abs(ths - th)) <= dth, 'small-angle theta error within its bound')
    call tc%check_true(maxval(abs(oms - om)) <= dom, 'small-angle omega error within its bound')
    call tc%check_true(dth <= 2*maxval(abs(ths - th)), 'small-angle bound tight (factor 2)')
    call tc%check_close(small_angle_phase_drift(mo), mo%m/4, 0.02_wp, 0.0_wp, 'phase drift ~ m/4')
    call small_angle_solve(t(1:3), 0.3_wp, 0.2_wp, 1.1_wp, ths(1:3), oms(1:3), st)
    call tc%check_true(status_ok(st) .and. ths(2) == ths(2), 'small_angle_solve ok')
    call undamped_init(mo, 0.0_wp, 3.0_wp, 1.0_wp, st)
    call small_angle_bound(mo, 1.0_wp, dth, dom)
    call tc%check_true(dth > huge(1.0_wp) .and. dom > huge(1.0_wp), 'no small-angle bound for rotation')
  end subroutine check_small_angle

  subroutine check_equilibria()
    real(wp) :: theta
    complex(wp) :: l1, l2
    integer :: kind, n
    type(status_t) :: st
    do n = -3, 4
      call equilibrium(n, 1.7_wp, theta, l1, l2, kind, st)
      call tc%check_close(theta, n*pi, eps, 0.0_wp, 'equilibrium angle n pi')
      if (modulo(n, 2) == 0) then
        call tc%check_true(kind == EQUILIBRIUM_CENTRE .and. l1 == cmplx(0.0_wp, 1.7_wp, wp) .and. l2 == -l1, &
                           'even n: centre, +-i w0')
      else
        call tc%check_true(kind == EQUILIBRIUM_SADDLE .and. l1 == cmplx(1.7_wp, 0.0_wp, wp) .and. l2 == -l1, &
                           'odd n: saddle, +-w0')
      end if
    end do
    call tc%check_true(equilibrium_type_name(EQUILIBRIUM_SADDLE) == 'saddle', 'type name')
    call equilibrium(1, -1.0_wp, theta, l1, l2, kind, st)
    call tc%check_true(st%code == PENDULA_ERR_DOMAIN .and. index(st%message, 'w0 =') == 1, 'equilibrium w0 <= 0')
  end subroutine check_equilibria

  subroutine check_bad_input()
    type(undamped_motion_t) :: mo
    type(status_t) :: st
    real(wp) :: nan, inf, th(2), om(2)
    ! ieee_value, not 0/0 or huge*2: the checked build traps invalid and overflow
    nan = ieee_value(nan, ieee_quiet_nan)
    inf = ieee_value(inf, ieee_positive_inf)
    call undamped_init(mo, nan, 0.0_wp, 1.0_wp, st)
    call tc%check_true(st%code == PENDULA_ERR_NONFINITE .and. index(st%message, 'theta0 =') == 1, &
                       'NaN theta0: '//trim(st%message))
    call undamped_init(mo, 0.0_wp, -inf, 1.0_wp, st)
    call tc%check_true(st%code == PENDULA_ERR_NONFINITE .and. index(st%message, 'omega0 =') == 1, &
                       'Inf omega0: '//trim(st%message))
    call undamped_init(mo, 0.0_wp, 0.0_wp, 0.0_wp, st)
    call tc%check_true(st%code == PENDULA_ERR_DOMAIN .and. index(st%message, 'w0 =') == 1, &
                       'w0 = 0: '//trim(st%message))
    call undamped_solve([1.0_wp, nan], 0.1_wp, 0.0_wp, 1.0_wp, th, om, st)
    call tc%check_true(st%code == PENDULA_ERR_NONFINITE .and. index(st%message, 't[1]') == 1, &
                       'NaN t: '//trim(st%message))
    call undamped_solve([1.0_wp, 2.0_wp, 3.0_wp], 0.1_wp, 0.0_wp, 1.0_wp, th, om, st)
    call tc%check_true(st%code == PENDULA_ERR_SIZE, 'size mismatch')
    call small_angle_solve([1.0_wp, 2.0_wp], 0.1_wp, 0.0_wp, -1.0_wp, th, om, st)
    call tc%check_true(st%code == PENDULA_ERR_DOMAIN .and. index(st%message, 'w0 =') == 1, 'small-angle w0 < 0')
  end subroutine check_bad_input

  !> States of every kind for the many-state kernels: random libration and
  !> rotation (theta0 up to +-20 rad), Omega0 = 0, |1 - m| from 1e-3 down to
  !> 1e-15 on both sides, the exact separatrix, the free rotor (|Omega0| = 1e150),
  !> huge theta0.
  subroutine many_states(th, om, w)
    real(wp), allocatable, intent(out) :: th(:), om(:), w(:)
    integer, parameter :: nr = 600
    real(wp) :: u(nr, 3), gap
    integer :: i
    call random_seed(put=[(7*i + 1, i=1, 64)])
    call random_number(u)
    th = [40*u(:, 1) - 20, 6.2_wp*u(1:100, 2) - 3.1_wp, 0.0_wp, 1.0_wp, -2.5_wp, 1.0e20_wp, -3.0e15_wp, &
          3.141592653589793_wp, 0.0_wp, 0.0_wp]
    om = [6*u(:, 2) - 3, [(0.0_wp, i=1, 100)], 2.0_wp, 0.0_wp, 1.0e151_wp, 0.3_wp, -0.7_wp, 0.0_wp, &
          -2.0_wp, 1.0_wp]
    w = [0.2_wp + 3*u(:, 3), [(1.3_wp, i=1, 100)], 1.0_wp, 1.0_wp, 0.5_wp, 1.2_wp, 2.0_wp, 1.0_wp, 1.0_wp, 0.5_wp]
    ! near the separatrix: Omega0 = 2 w0 cos(theta0/2) (1 +- gap)
    do i = 1, 100
      gap = 10.0_wp**(-3 - 12*u(i, 1))*merge(1, -1, mod(i, 2) == 0)
      om(i) = 2*w(i)*cos(0.5_wp*th(i) - 6.283185307179586_wp*anint(th(i)/6.283185307179586_wp))*(1 + gap)
    end do
  end subroutine many_states

  subroutine check_many_states()
    real(wp), allocatable :: th(:), om(:), w(:), per(:), amp(:), m(:), mc(:), t(:), ts(:), ths(:), oms(:), &
                             st0(:, :), thp(:)
    integer, allocatable :: reg(:)
    type(undamped_motion_t) :: mo
    type(status_t) :: st
    real(wp) :: x, y
    integer :: i, j, n, nbad, nrun
    call many_states(th, om, w)
    n = size(th)
    allocate (per(n), amp(n), m(n), mc(n), reg(n))
    call undamped_properties(th, om, w, st, period=per, amplitude=amp, m=m, mc=mc, regime=reg)
    call tc%check_true(st%code == PENDULA_OK, 'undamped_properties: '//trim(st%message))
    nbad = 0
    do i = 1, n
      call undamped_init(mo, th(i), om(i), w(i), st, plan=.false.)
      if (.not. (same(per(i), mo%period) .and. same(amp(i), mo%amplitude) .and. same(m(i), mo%m) &
                 .and. same(mc(i), mo%mc) .and. reg(i) == mo%regime)) nbad = nbad + 1
    end do
    call tc%check_true(nbad == 0, 'undamped_properties == undamped_init, bit for bit')
    call tc%check_true(count(reg == REGIME_SEPARATRIX) >= 3 .and. count(reg == REGIME_LIBRATION) > 100 .and. &
                       count(reg == REGIME_ROTATION) > 100, 'the states cover every regime')
    ! only what is asked: the period alone is the same
    call undamped_properties(th, om, w, st, period=amp)
    call tc%check_true(all(same(amp, per)), 'period alone == period with the others')

    ! undamped_states: every state once at one time (light motions), then a run of
    ! UNDAMPED_PLAN_MIN_TIMES copies of one state (a planned motion), times up to
    ! 1e15 s (whole periods taken out: the light motion gets its period on demand)
    nrun = UNDAMPED_PLAN_MIN_TIMES
    allocate (t(n))
    call random_number(t)
    t = 400*t - 200
    t(1:20) = t(1:20)*5.0e12_wp
    allocate (st0(3, n + nrun), ts(n + nrun), ths(n + nrun), oms(n + nrun))
    st0(:, 1:n) = transpose(reshape([th, om, w], [n, 3]))
    st0(:, n + 1:) = spread([-2.0_wp, 3.9_wp, 1.3_wp], 2, nrun)
    ts(1:n) = t
    ts(n + 1:) = [(-100 + 7.0_wp*i, i=1, nrun)]
    ts(n + 1) = 3.0e14_wp
    call undamped_states(ts, st0(1, :), st0(2, :), st0(3, :), ths, oms, st)
    call tc%check_true(st%code == PENDULA_OK, 'undamped_states: '//trim(st%message))
    nbad = 0
    do i = 1, n + nrun
      if (i <= n .or. i == n + 1) call undamped_init(mo, st0(1, i), st0(2, i), st0(3, i), st, plan=i > n)
      call undamped_eval(mo, ts(i), x, y)
      if (.not. (same(x, ths(i)) .and. same(y, oms(i)))) nbad = nbad + 1
    end do
    call tc%check_true(nbad == 0, 'undamped_states == undamped_init + undamped_eval, bit for bit')
    ! inputs of size 1 stand for every element
    call undamped_properties(th, [0.25_wp], [1.3_wp], st, period=per, regime=reg)
    call undamped_properties(th, spread(0.25_wp, 1, n), spread(1.3_wp, 1, n), st, period=amp, m=m)
    call tc%check_true(st%code == PENDULA_OK .and. all(same(per, amp)), 'undamped_properties: size-1 inputs')
    ! the period over amplitudes (Omega0 = 0, one w0: its own loop for |theta0| < pi,
    ! blocks with larger angles mixed in) is undamped_init's, bit for bit
    nbad = 0
    do j = 1, 2
      if (j == 1) thp = th
      if (j == 2) thp = pack(th, abs(th) < 3.14_wp)   ! whole blocks of the amplitude loop
      call undamped_properties(thp, [0.0_wp], [1.3_wp], st, period=per(1:size(thp)))
      do i = 1, size(thp)
        call undamped_init(mo, thp(i), 0.0_wp, 1.3_wp, st, plan=.false.)
        if (.not. same(per(i), mo%period)) nbad = nbad + 1
      end do
    end do
    call tc%check_true(nbad == 0 .and. size(thp) > 100 .and. count(abs(th) > 3.15_wp) > 100, &
                       'undamped_properties: period over amplitudes == undamped_init')
    call undamped_states([2.5_wp], th, om, [1.3_wp], ths(1:n), oms(1:n), st)
    call undamped_states(spread(2.5_wp, 1, n), th, om, spread(1.3_wp, 1, n), ts(1:n), t, st)
    call tc%check_true(st%code == PENDULA_OK .and. all(same(ths(1:n), ts(1:n))) .and. all(same(oms(1:n), t)), &
                       'undamped_states: size-1 inputs')
  end subroutine check_many_states

  !> Equal including the sign of zero and NaN == NaN.
  elemental logical function same(a, b)
    real(wp), intent(in) :: a, b
    same = transfer(a, 1_8) == transfer(b, 1_8)
  end function same

  subroutine check_many_states_bad_input()
    type(status_t) :: st
    real(wp) :: nan, per(4), th(4), om(4)
    integer :: reg(3)
    nan = ieee_value(nan, ieee_quiet_nan)
    call undamped_properties([0.1_wp, 0.2_wp, 0.3_wp, 0.4_wp], [0.0_wp, 0.0_wp, nan, 0.0_wp], &
                             [1.0_wp, 1.0_wp, 1.0_wp, -1.0_wp], st, period=per)
    call tc%check_true(st%code == PENDULA_ERR_NONFINITE .and. index(st%message, 'omega0 =') == 1 .and. &
                       all(per == 0), 'undamped_properties: first bad element named, outputs 0')
    call undamped_properties([0.1_wp, 0.2_wp, 0.3_wp, 0.4_wp], [0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp], &
                             [1.0_wp, 1.0_wp, 1.0_wp, -1.0_wp], st, period=per)
    call tc%check_true(st%code == PENDULA_ERR_DOMAIN .and. index(st%message, 'w0 =') == 1, &
                       'undamped_properties: w0 <= 0')
    call undamped_properties([0.1_wp, 0.2_wp, 0.3_wp, 0.4_wp], [0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp], &
                             [1.0_wp, 1.0_wp, 1.0_wp, 1.0_wp], st, regime=reg)
    call tc%check_true(st%code == PENDULA_ERR_SIZE, 'undamped_properties: output size')
    call undamped_states([0.0_wp, 1.0_wp, nan, 1.0_wp], [0.1_wp, 0.1_wp, 0.1_wp, 0.1_wp], &
                         [0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp], [1.0_wp, 1.0_wp, 1.0_wp, 1.0_wp], th, om, st)
    call tc%check_true(st%code == PENDULA_ERR_NONFINITE .and. index(st%message, 't =') == 1 .and. &
                       all(th == 0) .and. all(om == 0), 'undamped_states: NaN t named, outputs 0: '//trim(st%message))
    call undamped_states([0.0_wp, 1.0_wp, 1.0_wp, 1.0_wp], [0.1_wp, nan, 0.1_wp, 0.1_wp], &
                         [0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp], [1.0_wp, 1.0_wp, 1.0_wp, 1.0_wp], th, om, st)
    call tc%check_true(st%code == PENDULA_ERR_NONFINITE .and. index(st%message, 'theta0 =') == 1, &
                       'undamped_states: NaN theta0 named')
    call undamped_states([0.0_wp, 1.0_wp, 1.0_wp], [0.1_wp, 0.1_wp, 0.1_wp], &
                         [0.0_wp, 0.0_wp, 0.0_wp], [1.0_wp, 1.0_wp, 1.0_wp], th(1:3), om, st)
    call tc%check_true(st%code == PENDULA_ERR_SIZE, 'undamped_states: size mismatch')
    call undamped_properties([0.1_wp, 0.2_wp], [0.0_wp, 0.0_wp, 0.0_wp], [1.0_wp], st, period=per(1:3))
    call tc%check_true(st%code == PENDULA_ERR_SIZE, 'undamped_properties: inputs of sizes 2 and 3')
  end subroutine check_many_states_bad_input

end program test_undamped
