!> The Taylor series of the nonlinear damped pendulum (text eq. 2.2)
!>   theta' = Omega,  Omega' = -gamma Omega - w0**2 sin(theta)
!> by automatic differentiation: normalised coefficients x(k) = theta^(k)/k!,
!> v(k) = Omega^(k)/k! from the product recurrences of s = sin(theta),
!> c = cos(theta) (s' = c theta', c' = -s theta'; Jorba & Zou, Exp. Math. 14
!> (2005) 99, section 3), the order and step that a per-step tolerance asks
!> for (their eqs. 3-5: step from the last two coefficients; the order from
!> this code's own cost per step, see taylor_order), and the phase shear that
!> the error estimate of pendula_taylor propagates.
!>
!> A forcing term F cos(Omega_d t + phi) enters as one more series f(k) added
!> to the Omega recurrence (`v(k+1) = (-gamma v(k) - w0**2 s(k) + f(k))/(k+1)`,
!> f by the same sin/cos recurrences of a linear argument); the driver and the
!> step choice need no change.
module pendula_taylor_series
  use pendula_kinds, only: wp
  implicit none
  private
  public :: TAYLOR_MAX_ORDER, taylor_coefficients, taylor_coefficients_driven, taylor_drive_series, taylor_order, &
            taylor_step, taylor_shear

  !> Largest order the integrator uses (per-step tolerance >= e**(-78) ~ 1e-34):
  !> the coefficient arrays are fixed-size locals, no allocation per call.
  integer, parameter :: TAYLOR_MAX_ORDER = 40

  ! 1/k, so that the recurrences multiply instead of dividing (a literal list:
  ! an implied-do would need a module variable)
  real(wp), parameter :: INV(TAYLOR_MAX_ORDER + 1) = 1.0_wp/real([ &
                                                                 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, &
                                                                 15, 16, 17, 18, 19, 20, 21, 22, 23, 24, 25, 26, 27, 28, &
                                                                 29, 30, 31, 32, 33, 34, 35, 36, 37, 38, 39, 40, 41], wp)

contains

  !> Normalised Taylor coefficients x(0:p+1), v(0:p+1) [rad s**-k, rad s**-(k+1)]
  !> of theta and Omega about a state (xh + xl, vh): xh, xl is the angle as a
  !> double-double (xl only corrects sin and cos), vh the angular velocity,
  !> w0sq = w0**2 [1/s**2], gamma [1/s].  Cost 2 p**2 multiplications.  The
  !> terms of order p + 1 measure the truncation of the order-p polynomial.
  !> Accuracy: each coefficient to a few ulps of the sums of absolute terms.
  pure subroutine taylor_coefficients(xh, xl, vh, w0sq, gamma, p, x, v, s0abs, sn, cs)
    real(wp), intent(in) :: xh  !< angle, high part [rad]
    real(wp), intent(in) :: xl  !< angle, low part [rad] (|xl| <= ulp(xh)/2)
    real(wp), intent(in) :: vh  !< angular velocity [rad/s]
    real(wp), intent(in) :: w0sq  !< w0**2 [1/s**2]
    real(wp), intent(in) :: gamma  !< damping rate [1/s]
    integer, intent(in) :: p  !< order, 1..TAYLOR_MAX_ORDER - 1
    real(wp), intent(out) :: x(0:TAYLOR_MAX_ORDER)  !< theta coefficients, x(0:p+1) set
    real(wp), intent(out) :: v(0:TAYLOR_MAX_ORDER)  !< Omega coefficients, v(0:p+1) set
    real(wp), intent(out) :: s0abs  !< abs(gamma vh) + w0sq abs(sin theta): size of v(1)'s terms
    real(wp), intent(out) :: sn  !< sin(theta)
    real(wp), intent(out) :: cs  !< cos(theta)
    ! cs2(1, k) = c(k), cs2(2, k) = s(k) side by side: the sums for s(k) (over
    ! c) and c(k) (over s) share every v(j-1) and run as one two-lane vector
    ! operation; each lane's arithmetic is the scalar sum's, term by term.
    real(wp) :: cs2(2, 0:TAYLOR_MAX_ORDER), a1(2), a2(2), sh, ch
    integer :: k, j, l
    sh = sin(xh)
    ch = cos(xh)
    cs2(2, 0) = sh + ch*xl
    cs2(1, 0) = ch - sh*xl
    sn = cs2(2, 0)
    cs = cs2(1, 0)
    x(0) = xh
    v(0) = vh
    x(1) = vh
    v(1) = -gamma*vh - w0sq*sn
    s0abs = abs(gamma*vh) + w0sq*abs(sn)
    ! k x(k) = v(k-1), so s(k) = (1/k) sum_j v(j-1) c(k-j) (and c likewise).
    ! The chain from one order to the next runs through the newest c(k-1),
    ! s(k-1) only (the j = 1 term): the older terms j = 2..k (two partial sums)
    ! are summed first, off that chain, and the newest term added last, so a
    ! step costs ~ p latencies of one multiply-add, not p sums of length k.
    do k = 1, p
      a1 = 0
      a2 = 0
      do j = 2, k - 1, 2
        ! (the two lanes in one SSE2 register: -O2 does not do it by itself)
        !$omp simd
        do l = 1, 2
          a1(l) = a1(l) + v(j - 1)*cs2(l, k - j)
          a2(l) = a2(l) + v(j)*cs2(l, k - j - 1)
        end do
      end do
      if (mod(k, 2) == 0) a1 = a1 + v(k - 1)*cs2(:, 0)
      a1 = ((a1 + a2) + v(0)*cs2(:, k - 1))*INV(k)
      cs2(2, k) = a1(1)
      cs2(1, k) = -a1(2)
      x(k + 1) = v(k)*INV(k + 1)
      v(k + 1) = (-gamma*v(k) - w0sq*a1(1))*INV(k + 1)
    end do
  end subroutine taylor_coefficients

  !> The series of cos(psi0 + Omega tau) in tau [s], dc(k) = Omega**k
  !> cos(psi0 + k pi/2)/k!, k = 0..p+1, by the two-term recurrence with its
  !> sine: dc(k) = -Omega ds(k-1)/k, ds(k) = Omega dc(k-1)/k.  cos0, sin0 are
  !> cos(psi0) and sin(psi0); omega_d the drive frequency [rad/s].
  pure subroutine taylor_drive_series(cos0, sin0, omega_d, p, dc)
    real(wp), intent(in) :: cos0  !< cos of the drive phase at the step's start
    real(wp), intent(in) :: sin0  !< sin of the drive phase at the step's start
    real(wp), intent(in) :: omega_d  !< drive frequency Omega [rad/s]
    integer, intent(in) :: p  !< order, 1..TAYLOR_MAX_ORDER - 1
    real(wp), intent(out) :: dc(0:TAYLOR_MAX_ORDER)  !< coefficients of cos, dc(0:p+1) set
    real(wp) :: ds, dn
    integer :: k
    dc(0) = cos0
    ds = sin0
    do k = 1, p + 1
      dn = -omega_d*ds*INV(k)
      ds = omega_d*dc(k - 1)*INV(k)
      dc(k) = dn
    end do
  end subroutine taylor_drive_series

  !> taylor_coefficients for the driven pendulum theta'' = -gamma theta' -
  !> (w0**2 + pivot c(t)) sin(theta) + torque c(t), c(t) = cos(Omega t + phi)
  !> with the series dc (taylor_drive_series) about the step's start:
  !> kind 1 (torque) adds amp dc(k) to the Omega recurrence, kind 2 (pivot)
  !> subtracts amp (dc * s)(k), the product series of dc and sin(theta)
  !> (amp = F [rad/s**2] or (a/l) Omega**2 [1/s**2]).  s0abs also counts the
  !> drive's terms.  Cost ~2 p**2 (torque) or ~2.5 p**2 (pivot) multiplications.
  pure subroutine taylor_coefficients_driven(xh, xl, vh, w0sq, gamma, kind, amp, dc, p, x, v, s0abs, sn, cs)
    real(wp), intent(in) :: xh  !< angle, high part [rad]
    real(wp), intent(in) :: xl  !< angle, low part [rad] (|xl| <= ulp(xh)/2)
    real(wp), intent(in) :: vh  !< angular velocity [rad/s]
    real(wp), intent(in) :: w0sq  !< w0**2 [1/s**2]
    real(wp), intent(in) :: gamma  !< damping rate [1/s]
    integer, intent(in) :: kind  !< 1: torque, 2: pivot (pendula_drive's DRIVE_TORQUE, DRIVE_PIVOT)
    real(wp), intent(in) :: amp  !< F [rad/s**2] (torque) or (a/l) Omega**2 [1/s**2] (pivot)
    real(wp), intent(in) :: dc(0:TAYLOR_MAX_ORDER)  !< series of the drive's cosine (taylor_drive_series)
    integer, intent(in) :: p  !< order, 1..TAYLOR_MAX_ORDER - 1
    real(wp), intent(out) :: x(0:TAYLOR_MAX_ORDER)  !< theta coefficients, x(0:p+1) set
    real(wp), intent(out) :: v(0:TAYLOR_MAX_ORDER)  !< Omega coefficients, v(0:p+1) set
    real(wp), intent(out) :: s0abs  !< size of v(1)'s terms [rad/s**2]
    real(wp), intent(out) :: sn  !< sin(theta)
    real(wp), intent(out) :: cs  !< cos(theta)
    real(wp) :: ss(0:TAYLOR_MAX_ORDER), cc(0:TAYLOR_MAX_ORDER), b, d, f, sh, ch
    integer :: k, j
    sh = sin(xh)
    ch = cos(xh)
    ss(0) = sh + ch*xl
    cc(0) = ch - sh*xl
    sn = ss(0)
    cs = cc(0)
    x(0) = xh
    v(0) = vh
    x(1) = vh
    if (kind == 2) then
      v(1) = -gamma*vh - (w0sq + amp*dc(0))*sn
      s0abs = abs(gamma*vh) + (w0sq + abs(amp*dc(0)))*abs(sn)
    else
      v(1) = -gamma*vh - w0sq*sn + amp*dc(0)
      s0abs = abs(gamma*vh) + w0sq*abs(sn) + abs(amp*dc(0))
    end if
    do k = 1, p
      b = 0
      d = 0
      do j = 1, k
        b = b + v(j - 1)*cc(k - j)
        d = d + v(j - 1)*ss(k - j)
      end do
      ss(k) = b*INV(k)
      cc(k) = -d*INV(k)
      if (kind == 2) then
        f = 0
        do j = 0, k
          f = f + dc(j)*ss(k - j)
        end do
        f = -amp*f
      else
        f = amp*dc(k)
      end if
      x(k + 1) = v(k)*INV(k + 1)
      v(k + 1) = (-gamma*v(k) - w0sq*ss(k) + f)*INV(k + 1)
    end do
  end subroutine taylor_coefficients_driven

  !> Order p = ceil(0.8 ln(1/eps)) + 2 for a per-step tolerance eps in (0, 1),
  !> between 4 and TAYLOR_MAX_ORDER - 1: the order that minimises the work per
  !> unit time, (c0 + p + q p**2) eps**(-1/p), for this implementation's cost of
  !> a step (measured: a base of c0 ~ 6 orders' work for the step, its sin and
  !> cos and its dense output, q ~ 0.02 for the sums that grow as p**2; the
  !> minimum is flat within 2 % over +-3 orders).  Jorba & Zou's
  !> ceil(ln(1/eps)/2) + 1 (their eq. 7) is the minimum for a cost ~ p**2,
  !> which the latency-bound recurrences here are not.  The ratio of the
  !> step to the radius of convergence is then eps**(1/p) ~ e**(-1.25).
  !> short_steps: Jorba & Zou's order instead (steps ~ e**(-2) of the radius,
  !> ~2x more of them): for a rounding-limited window, whose accumulated
  !> rounding grows like the square root of the step.
  pure integer function taylor_order(eps, short_steps) result(p)
    real(wp), intent(in) :: eps  !< per-step absolute tolerance, > 0
    logical, intent(in) :: short_steps  !< the order for short steps (rounding-limited windows)
    if (short_steps) then
      p = ceiling(-log(eps)/2) + 1
    else
      p = ceiling(-0.8_wp*log(eps)) + 2
    end if
    p = max(4, min(TAYLOR_MAX_ORDER - 1, p))
  end function taylor_order

  !> Step |h| [s] at which the last two terms of the series, in the norm
  !> max(|theta|, |Omega|/w0), are each at most eps: min over j = p-1, p of
  !> (eps/|c_j|)**(1/j) (Jorba & Zou, eqs. 3-5; at taylor_order's order
  !> ~ rho e**(-1.25), rho the radius of convergence).  The truncated tail is
  !> then ~0.3 eps when the coefficients decay geometrically.  h_cap [s] bounds the answer (zero
  !> coefficients allow any step).
  pure real(wp) function taylor_step(x, v, p, inv_w0, eps, h_cap) result(h)
    real(wp), intent(in) :: x(0:TAYLOR_MAX_ORDER)  !< theta coefficients
    real(wp), intent(in) :: v(0:TAYLOR_MAX_ORDER)  !< Omega coefficients
    integer, intent(in) :: p  !< order
    real(wp), intent(in) :: inv_w0  !< 1/w0 [s]
    real(wp), intent(in) :: eps  !< per-step tolerance, > 0
    real(wp), intent(in) :: h_cap  !< largest step wanted [s], > 0
    real(wp) :: n1, n2, l1, l2
    h = h_cap
    n1 = max(abs(x(p - 1)), abs(v(p - 1))*inv_w0)
    n2 = max(abs(x(p)), abs(v(p))*inv_w0)
    if (n1 <= 0 .and. n2 <= 0) return
    l1 = huge(1.0_wp)
    l2 = huge(1.0_wp)
    if (n1 > 0) l1 = log(eps/n1)/(p - 1)
    if (n2 > 0) l2 = log(eps/n2)/p
    h = min(h, exp(min(l1, l2, 700.0_wp)))
  end function taylor_step

  !> Phase shear of the undamped pendulum at the scaled energy
  !> e = u**2/2 + 1 - cos(x) (u = Omega/w0, time tau = w0 t): the rate
  !> [per unit tau] at which an error delta of the state (max norm, theta in
  !> rad, Omega/w0) turns into a growing position error through the energy
  !> dependence of the frequency nu(e):  G = max|d state/d phase| *
  !> |d ln nu/d e| * max|de/d state|.  For a libration (m = e/2 < 1)
  !> nu = pi/(2 K(m)); for a rotation one turn takes 2 K(1/m)/sqrt(m).  G -> 0
  !> for small swings (the harmonic oscillator does not shear), G -> 1 for fast
  !> rotations (a free rotor: delta u tau), and G -> infinity at the separatrix
  !> (where the caller's exponential bound takes over).  K and E by the AGM.
  pure real(wp) function taylor_shear(e) result(g)
    real(wp), intent(in) :: e  !< scaled energy, >= 0
    real(wp) :: m, mu, kk_over, q, pp
    m = e/2
    if (m <= 0) then
      g = 0
    else if (.not. m <= 1.0e300_wp) then
      g = 1   ! the free rotor's limit (also for e = +inf)
    else if (m < 1) then
      ! d ln nu/dm = -K'(m)/K(m); max |d state/d phase| = 2 sqrt(m) (u at the
      ! bottom; |sin| is smaller); max |de/d state| <= |sin x| + |u|.
      kk_over = dlogk(m)
      q = 2*sqrt(m)
      pp = min(1.0_wp, 2*sqrt(m*(1 - m))) + q
      g = 0.5_wp*q*pp*kk_over
    else if (m > 1) then
      mu = 1/m
      ! nu = pi sqrt(m)/K(1/m): d ln nu/dm = 1/(2m) + K'(mu)/K(mu) / m**2
      kk_over = dlogk(mu)
      q = 2*sqrt(m)
      pp = 1 + q
      g = 0.5_wp*q*pp*(0.5_wp/m + kk_over/m**2)
    else
      g = huge(1.0_wp)
    end if
  end function taylor_shear

  ! K'(m)/K(m) = (E/K - (1 - m))/(2 m (1 - m)), 0 < m < 1, by the AGM:
  ! E/K = 1 - m/2 - sum_{n>=1} 2**(n-1) c_n**2, so the numerator is
  ! m/2 - sum (no cancellation for small m).
  pure real(wp) function dlogk(m) result(r)
    real(wp), intent(in) :: m
    real(wp) :: a, b, c, an, tw, acc
    integer :: it
    r = 0.25_wp   ! the limit m -> 0
    if (m < 1.0e-300_wp) return
    a = 1
    b = sqrt(1 - m)
    tw = 1
    acc = 0
    do it = 1, 40
      c = (a - b)/2
      an = (a + b)/2
      b = sqrt(a*b)
      a = an
      acc = acc + tw*c*c
      tw = 2*tw
      if (abs(c) <= 1.0e-6_wp*a) exit   ! the next term is ~c**2: 1e-12 relative
    end do
    r = (m/2 - acc)/(2*m*(1 - m))
    r = max(r, 0.25_wp)   ! its minimum, at m -> 0; guards rounding in the numerator
  end function dlogk

end module pendula_taylor_series
