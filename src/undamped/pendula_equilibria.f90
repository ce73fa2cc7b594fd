!> Equilibria of the undamped pendulum and their linearisation (text §1.1,
!> eqs 1.9-1.24): (theta, Omega) = (n pi, 0) for every integer n.  The
!> Jacobian [[0, 1], [-w0^2 cos(n pi), 0]] has eigenvalues lambda^2 = -w0^2 cos(n pi):
!> even n: lambda = +-i w0, a centre (the pendulum hangs; stable, not asymptotically);
!> odd n:  lambda = +-w0, a saddle (upright; unstable).
module pendula_equilibria
  use pendula_kinds, only: wp
  use pendula_format, only: code_text
  use pendula_status, only: status_t, check_positive, PENDULA_OK
  use pendula_constants, only: pi, pi_lo
  implicit none
  private
  public :: equilibrium_angle, equilibrium_type, equilibrium_eigenvalues, equilibrium, &
            equilibrium_type_name
  public :: EQUILIBRIUM_CENTRE, EQUILIBRIUM_SADDLE

  !> Even n: hanging, a centre (eigenvalues +-i w0).
  integer, parameter :: EQUILIBRIUM_CENTRE = 1
  !> Odd n: upright, a saddle (eigenvalues +-w0).
  integer, parameter :: EQUILIBRIUM_SADDLE = 2

contains

  !> theta = n pi [rad] of the n-th equilibrium, the double nearest n pi
  !> (pi carried in two doubles, so large |n| stays correctly rounded-ish).
  elemental real(wp) function equilibrium_angle(n) result(theta)
    integer, intent(in) :: n  !< equilibrium index: theta = n pi
    real(wp) :: x
    x = real(n, wp)
    theta = x*pi + x*pi_lo
  end function equilibrium_angle

  !> EQUILIBRIUM_CENTRE for even n, EQUILIBRIUM_SADDLE for odd n.
  elemental integer function equilibrium_type(n) result(kind)
    integer, intent(in) :: n  !< equilibrium index: theta = n pi
    if (modulo(n, 2) == 0) then
      kind = EQUILIBRIUM_CENTRE
    else
      kind = EQUILIBRIUM_SADDLE
    end if
  end function equilibrium_type

  !> Linearised eigenvalues [1/s] at the n-th equilibrium for w0 > 0 [1/s]:
  !> (+i w0, -i w0) for even n, (+w0, -w0) for odd n (exact).
  elemental subroutine equilibrium_eigenvalues(n, w0, lambda1, lambda2)
    integer, intent(in) :: n  !< equilibrium index: theta = n pi
    real(wp), intent(in) :: w0  !< small-angle angular frequency [1/s], finite, > 0
    complex(wp), intent(out) :: lambda1  !< first eigenvalue [1/s]
    complex(wp), intent(out) :: lambda2  !< second eigenvalue [1/s]
    if (modulo(n, 2) == 0) then
      lambda1 = cmplx(0.0_wp, w0, wp)
    else
      lambda1 = cmplx(w0, 0.0_wp, wp)
    end if
    lambda2 = -lambda1
  end subroutine equilibrium_eigenvalues

  !> Checked form: angle [rad], eigenvalues [1/s] and type of the n-th
  !> equilibrium; w0 finite and > 0 (status names it otherwise).
  pure subroutine equilibrium(n, w0, theta, lambda1, lambda2, kind, status)
    integer, intent(in) :: n  !< equilibrium index: theta = n pi
    real(wp), intent(in) :: w0  !< small-angle angular frequency [1/s], finite, > 0
    real(wp), intent(out) :: theta  !< equilibrium angle n pi [rad]
    complex(wp), intent(out) :: lambda1  !< first eigenvalue [1/s]
    complex(wp), intent(out) :: lambda2  !< second eigenvalue [1/s]
    integer, intent(out) :: kind  !< EQUILIBRIUM_CENTRE or EQUILIBRIUM_SADDLE
    type(status_t), intent(out) :: status
    !< error code and message naming the bad argument (PENDULA_OK on success)
    theta = equilibrium_angle(n)
    kind = equilibrium_type(n)
    lambda1 = 0
    lambda2 = 0
    call check_positive('w0', w0, status)
    if (status%code /= PENDULA_OK) return
    call equilibrium_eigenvalues(n, w0, lambda1, lambda2)
  end subroutine equilibrium

  !> 'centre' or 'saddle' for a type code ('unknown' otherwise).
  pure function equilibrium_type_name(kind) result(name)
    integer, intent(in) :: kind  !< EQUILIBRIUM_CENTRE or EQUILIBRIUM_SADDLE
    ! explicit length (not deferred): see pendula_format on gfortran's static lengths
    character(len=len(code_text(kind, [EQUILIBRIUM_CENTRE, EQUILIBRIUM_SADDLE], ['centre', 'saddle'], &
                                'unknown'))) :: name
    name = code_text(kind, [EQUILIBRIUM_CENTRE, EQUILIBRIUM_SADDLE], ['centre', 'saddle'], 'unknown')
  end function equilibrium_type_name

end module pendula_equilibria
