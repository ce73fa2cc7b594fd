!> Numeric helpers shared by the concerns: one root finder on a
!> sign-changing bracket.
!>
!> The root finder works by reverse communication (no procedure argument: an
!> internal procedure passed as one would need an executable-stack trampoline
!> in gfortran).  The caller evaluates f at br%c until br%done:
!>
!>     call bracket_start(br, a, b, fa, fb, ROOT_ILLINOIS, 200, atol, rtol)
!>     do while (.not. br%done)
!>       call bracket_update(br, f(br%c))
!>     end do
!>     x = br%root
!>
!> Two step rules: ROOT_BISECT halves the bracket (the root is the last point
!> evaluated, an endpoint of the final bracket); ROOT_ILLINOIS takes the regula
!> falsi point with the Illinois halving of the retained end's value (bisection
!> when that point falls outside the open bracket), and the root is the end of
!> the final bracket with the smaller |f|.  Either stops when f(c) = 0, when
!> b - a <= max(atol, rtol |b|), or after maxit evaluations.
module pendula_numeric
  use pendula_kinds, only: wp
  implicit none
  private
  public :: bracket_t, bracket_start, bracket_update, ROOT_BISECT, ROOT_ILLINOIS

  !> Step rules of the bracketing root finder.
  integer, parameter :: ROOT_BISECT = 1, ROOT_ILLINOIS = 2

  !> State of a bracketing root search: the bracket [a, b] with f(a), f(b) of
  !> opposite signs (or f(b) = 0), the next point c to evaluate, and the root
  !> once done.
  type :: bracket_t
    real(wp) :: a = 0, b = 0, fa = 0, fb = 0
    real(wp) :: c = 0                !< next point at which the caller evaluates f
    real(wp) :: root = 0             !< the answer, once done
    real(wp) :: atol = 0, rtol = 0
    integer :: method = ROOT_BISECT, maxit = 100, evals = 0, side = 0
    logical :: done = .false.
  end type bracket_t

contains

  !> Start a root search on [a, b] (a < b) with f(a) = fa, f(b) = fb of
  !> opposite signs or fb = 0 (then the root is b at once).  method: ROOT_*;
  !> maxit: most evaluations; atol, rtol >= 0: stop when b - a <= max(atol,
  !> rtol |b|).  The caller checks the bracket: this helper trusts it.
  pure subroutine bracket_start(br, a, b, fa, fb, method, maxit, atol, rtol)
    type(bracket_t), intent(out) :: br
    !< bracket state (current interval, next point br%c, br%root and br%done when finished)
    real(wp), intent(in) :: a  !< left end of the bracket
    real(wp), intent(in) :: b  !< right end of the bracket, > a
    real(wp), intent(in) :: fa  !< f(a)
    real(wp), intent(in) :: fb  !< f(b), sign opposite to fa or 0
    real(wp), intent(in) :: atol  !< absolute width tolerance, >= 0 (same units as a, b)
    real(wp), intent(in) :: rtol  !< relative width tolerance, >= 0
    integer, intent(in) :: method  !< ROOT_BISECT or ROOT_ILLINOIS
    integer, intent(in) :: maxit  !< most function evaluations
    br = bracket_t(a=a, b=b, fa=fa, fb=fb, root=b, atol=atol, rtol=rtol, method=method, maxit=maxit, &
                   done=fb == 0)
    if (.not. br%done) call next_point(br)
  end subroutine bracket_start

  !> Take f(br%c) = fc: shrink the bracket, and either set br%root and
  !> br%done or the next br%c.
  pure subroutine bracket_update(br, fc)
    type(bracket_t), intent(inout) :: br
    !< bracket state (current interval, next point br%c, br%root and br%done when finished)
    real(wp), intent(in) :: fc  !< f(br%c), the value at the point last asked for
    logical :: illinois
    br%evals = br%evals + 1
    if (fc == 0) then
      br%root = br%c
      br%done = .true.
      return
    end if
    illinois = br%method == ROOT_ILLINOIS
    if (sign(1.0_wp, fc) == sign(1.0_wp, br%fa)) then
      br%a = br%c
      br%fa = fc
      if (illinois .and. br%side == -1) br%fb = br%fb/2
      br%side = -1
    else
      br%b = br%c
      br%fb = fc
      if (illinois .and. br%side == 1) br%fa = br%fa/2
      br%side = 1
    end if
    if (br%b - br%a <= max(br%atol, br%rtol*abs(br%b)) .or. br%evals >= br%maxit) then
      br%done = .true.
      if (illinois) then
        br%root = merge(br%a, br%b, abs(br%fa) < abs(br%fb))
      else
        br%root = br%c
      end if
      return
    end if
    call next_point(br)
  end subroutine bracket_update

  pure subroutine next_point(br)
    type(bracket_t), intent(inout) :: br
    real(wp) :: c
    if (br%method == ROOT_ILLINOIS) then
      c = (br%a*br%fb - br%b*br%fa)/(br%fb - br%fa)
      if (.not. (c > br%a .and. c < br%b)) c = 0.5_wp*(br%a + br%b)
    else
      c = 0.5_wp*(br%a + br%b)
    end if
    br%c = c
  end subroutine next_point

end module pendula_numeric
