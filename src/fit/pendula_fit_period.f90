!> Weighted least-squares fit of the small-angle angular frequency w0 to
!> measured (amplitude, period) pairs with the exact period of the swing,
!> T = 4 K(m) / w0 with m = sin(theta0/2)**2 (text eq. 1.53).
!>
!> For exact amplitudes the model T_i = f_i u, f_i = 4 K(m_i), is linear in
!> u = 1/w0 and the weighted fit is closed form:
!>   u = sum(f_i T_i / s_i**2) / sum(f_i**2 / s_i**2),  var(u) = 1 / sum(f_i**2 / s_i**2).
!> Amplitude errors sigma_theta0_i enter through the effective variance
!> s_i**2 = sigma_period_i**2 + (u f'_i sigma_theta0_i)**2 (Orear, Am. J. Phys. 50
!> (1982) 912), which depends on u: the closed form is iterated to a fixed point.
!> f'_i = df/dtheta0 = 4 dK/dm sin(theta0)/2 with dK/dm = (E - (1-m) K) / (2 m (1-m))
!> (DLMF 19.4.1).
module pendula_fit_period
  use pendula_kinds, only: wp
  use pendula_constants, only: pi
  use pendula_format, only: format_general, format_int
  use pendula_status, only: status_t, set_error, check_size, check_same_size, check_all_finite, &
                            PENDULA_OK, PENDULA_ERR_DOMAIN, PENDULA_ERR_SOLVER
  use pendula_elliptic, only: ellipkm1, ellipem1
  implicit none
  private
  public :: period_fit_t, fit_period, period_factor, FIT_PERIOD_MAX_ITER

  !> Most effective-variance iterations; they converge linearly at a rate of
  !> about the amplitude terms' share of the variance, so 200 is generous.
  integer, parameter :: FIT_PERIOD_MAX_ITER = 200

  !> Result of fit_period.
  type :: period_fit_t
    real(wp) :: w0 = 0  !< fitted small-angle angular frequency [1/s]
    real(wp) :: se_w0 = 0  !< its standard error from the given uncertainties [1/s]
    real(wp) :: se_w0_scatter = 0  !< its standard error scaled by sqrt(chi2/dof) (uncertainties unknown) [1/s]
    real(wp) :: chi2 = 0  !< chi-square of the fit with the effective variances
    integer :: dof = 0  !< degrees of freedom, n - 1
    integer :: iterations = 0  !< effective-variance iterations (1 when sigma_theta0 is all zero)
    real(wp) :: w0_small_angle = 0  !< the w0 the small-angle model T = 2 pi / w0 fits [1/s]
  end type period_fit_t

contains

  !> f = w0 T = 4 K(sin(theta0/2)**2) and its derivative df/dtheta0, for
  !> |theta0| < pi [rad].  Accurate to a few ulps (K and E through their
  !> complementary-parameter forms, which keep full precision near pi).
  elemental subroutine period_factor(theta0, f, dfdtheta)
    real(wp), intent(in) :: theta0  !< amplitude [rad], |theta0| < pi
    real(wp), intent(out) :: f  !< 4 K(m), m = sin(theta0/2)**2
    real(wp), intent(out) :: dfdtheta  !< d f / d theta0 [1/rad]
    real(wp) :: m, mc, k, e
    m = sin(theta0/2)**2
    mc = cos(theta0/2)**2
    k = ellipkm1(mc)
    e = ellipem1(mc)
    f = 4*k
    if (m < 1.0e-6_wp) then
      ! dK/dm = pi/8 (1 + 9 m / 8 + ...) (DLMF 19.5.1): the closed form cancels here.
      dfdtheta = 4*(pi/8)*(1 + 9*m/8)*sin(theta0)/2
    else
      dfdtheta = 4*(e - mc*k)/(2*m*mc)*sin(theta0)/2
    end if
  end subroutine period_factor

  !> Fit w0 [1/s] to periods period(i) [s] measured at amplitudes theta0(i)
  !> [rad] with standard uncertainties sigma_period(i) [s] (> 0) and
  !> sigma_theta0(i) [rad] (>= 0).  Closed form when every sigma_theta0 is 0,
  !> else iterated effective variance (relative change of w0 below 4 eps).
  !> Errors: sizes differ or n = 0, non-finite data, |theta0| >= pi (a
  !> rotation has no swing period), period <= 0, sigma_period <= 0,
  !> sigma_theta0 < 0; no convergence (PENDULA_ERR_SOLVER).
  pure subroutine fit_period(theta0, period, sigma_period, sigma_theta0, fit, status)
    real(wp), intent(in) :: theta0(:)  !< amplitudes [rad], |theta0| < pi
    real(wp), intent(in) :: period(:)  !< measured periods [s], > 0
    real(wp), intent(in) :: sigma_period(:)  !< their standard uncertainties [s], > 0
    real(wp), intent(in) :: sigma_theta0(:)  !< amplitude uncertainties [rad], >= 0
    type(period_fit_t), intent(out) :: fit  !< estimate, standard errors, chi-square
    type(status_t), intent(out) :: status
    !< error code and message naming the bad argument (PENDULA_OK on success)
    real(wp), dimension(size(theta0)) :: f, df, w, s2
    real(wp) :: u, u_new, sw, s0
    integer :: i, n, it

    n = size(theta0)
    call check_size('theta0', n, 1, status)
    call check_same_size('period', size(period), 'theta0', n, status)
    call check_same_size('sigma_period', size(sigma_period), 'theta0', n, status)
    call check_same_size('sigma_theta0', size(sigma_theta0), 'theta0', n, status)
    if (status%code /= PENDULA_OK) return
    call check_all_finite('theta0', theta0, status)
    call check_all_finite('period', period, status)
    call check_all_finite('sigma_period', sigma_period, status)
    call check_all_finite('sigma_theta0', sigma_theta0, status)
    if (status%code /= PENDULA_OK) return
    do i = 1, n
      if (.not. abs(theta0(i)) < pi) then
        call bad(status, 'theta0', i, theta0(i), 'an amplitude must satisfy |theta0| < pi rad: '// &
                 'a pendulum that goes over the top rotates and has no swing period')
      else if (.not. period(i) > 0) then
        call bad(status, 'period', i, period(i), 'periods must be > 0 s')
      else if (.not. sigma_period(i) > 0) then
        call bad(status, 'sigma_period', i, sigma_period(i), 'period uncertainties must be > 0 s')
      else if (sigma_theta0(i) < 0) then
        call bad(status, 'sigma_theta0', i, sigma_theta0(i), 'amplitude uncertainties must be >= 0 rad')
      end if
      if (status%code /= PENDULA_OK) return
    end do

    call period_factor(theta0, f, df)
    ! Uncertainties in units of the smallest one: the weights 1/s**2 stay
    ! finite for any positive sigma (a subnormal sigma_period would overflow them).
    s0 = minval(sigma_period)
    ! Small-angle model: f = 2 pi for every point.
    w = (s0/sigma_period)**2
    fit%w0_small_angle = sum(w*2*pi)/sum(w*period)
    s2 = (sigma_period/s0)**2
    u = sum(f*period/s2)/sum(f**2/s2)
    it = 1
    if (any(sigma_theta0 > 0)) then
      do it = 1, FIT_PERIOD_MAX_ITER
        s2 = (sigma_period/s0)**2 + (u*df*(sigma_theta0/s0))**2
        u_new = sum(f*period/s2)/sum(f**2/s2)
        if (abs(u_new - u) <= 4*epsilon(u)*u) then
          u = u_new
          exit
        end if
        u = u_new
      end do
      if (it > FIT_PERIOD_MAX_ITER) then
        call set_error(status, PENDULA_ERR_SOLVER, 'the effective-variance iteration did not converge in '// &
                       format_int(FIT_PERIOD_MAX_ITER)//' steps: are sigma_theta0 much larger than the amplitudes?')
        return
      end if
      s2 = (sigma_period/s0)**2 + (u*df*(sigma_theta0/s0))**2
    end if
    sw = sum(f**2/s2)
    fit%iterations = min(it, FIT_PERIOD_MAX_ITER)
    fit%w0 = 1/u
    ! var(u) = s0**2 / sw, and w0 = 1/u: se(w0) = se(u) / u**2.
    fit%se_w0 = s0*sqrt(1/sw)/u**2
    fit%chi2 = sum(((period - f*u)/s0)**2/s2)
    fit%dof = n - 1
    if (n > 1) then
      fit%se_w0_scatter = fit%se_w0*sqrt(fit%chi2/fit%dof)
    else
      fit%se_w0_scatter = 0
    end if
  end subroutine fit_period

  pure subroutine bad(status, name, i, x, why)
    type(status_t), intent(inout) :: status
    character(len=*), intent(in) :: name, why
    integer, intent(in) :: i
    real(wp), intent(in) :: x
    call set_error(status, PENDULA_ERR_DOMAIN, name//'['//format_int(i - 1)//'] = '// &
                   format_general(x, 17)//': '//why)
  end subroutine bad

end module pendula_fit_period
