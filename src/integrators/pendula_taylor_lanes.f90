!> The batch Taylor integrator's block kernel: TAYLOR_LANES states advance
!> side by side, each with its own order, step sizes and place in the output
!> grid.  Only the Taylor series, which costs ~2 p**2 operations a step and
!> is a chain of dependent sums for one state, are formed for the block at
!> once (taylor_series_lanes, compiled per instruction set and chosen at run
!> time by pendula_dispatch: one SIMD lane per state); each state then takes
!> its step through taylor_walk_step, the scalar integrator's own step, so
!> that its results are bit-identical to taylor_solve's.  A lane whose state
!> is done takes the next state of the list at once (no lane idles while
!> states remain), and the series go up to the largest order in the block
!> (a lane of lower order ignores the extra terms, which do not change its
!> own).
module pendula_taylor_lanes
  use, intrinsic :: iso_c_binding, only: c_int
  use pendula_kinds, only: wp, i8
  use pendula_dispatch, only: taylor_series_lanes
  use pendula_status, only: status_t, PENDULA_OK, PENDULA_ERR_CANCELLED
  use pendula_control, only: CONTROL_SIZE, cancel_requested, add_progress
  use pendula_ode, only: at => batch_index
  use pendula_batch_support, only: failed_output
  use pendula_taylor_series, only: TAYLOR_MAX_ORDER
  use pendula_taylor_walk, only: taylor_walk_t, taylor_walk_step
  use pendula_taylor, only: taylor_check, taylor_start, taylor_outcome
  implicit none
  private
  public :: taylor_lanes_run, taylor_lanes_list, TAYLOR_LANES

  include 'pendula_taylor_lanes.inc'

contains

  !> Integrate the states list(1:m) of a batch (taylor_batch_solve's
  !> arguments, without a drive) over the shared grid t [s]: theta(:, k),
  !> omega(:, k), err(:, k), steps(k), order(k) and codes(k) of each state k
  !> of the list, as taylor_solve would give them.  control (optional): cancel
  !> flag, looked at before a state starts and when it ends (a state running
  !> then is cancelled), and progress (finished states).
  subroutine taylor_lanes_run(t, list, theta0, omega0, w0, gamma, tol, budget, theta, omega, err, codes, steps, order, &
                              control)
    real(wp), intent(in) :: t(:)  !< shared output times [s], checked
    integer, intent(in) :: list(:)  !< the states to integrate (indices into theta0)
    real(wp), intent(in) :: theta0(:)  !< initial angles [rad]
    real(wp), intent(in) :: omega0(:)  !< initial angular velocities [rad/s], n elements or one
    real(wp), intent(in) :: w0(:)  !< angular frequencies [1/s], n elements or one
    real(wp), intent(in) :: gamma(:)  !< damping rates [1/s], n elements or one
    real(wp), intent(in) :: tol(:)  !< absolute accuracies [rad], n elements or one
    integer(i8), intent(in) :: budget  !< step budget per state
    real(wp), intent(inout) :: theta(:, :)  !< angles [rad], one column per state
    real(wp), intent(inout) :: omega(:, :)  !< angular velocities [rad/s]
    real(wp), intent(inout) :: err(:, :)  !< error estimates [rad]
    integer, intent(inout) :: codes(:)  !< status code of each state
    integer(i8), intent(inout) :: steps(:)  !< steps of each state
    integer, intent(inout) :: order(:)  !< series order of each state
    integer(i8), intent(inout), volatile, optional :: control(CONTROL_SIZE)  !< optional cancel flag and progress
    integer, parameter :: NL = TAYLOR_LANES
    type(taylor_walk_t) :: w(NL)
    real(wp) :: cc(NL, 0:TAYLOR_MAX_ORDER), ss(NL, 0:TAYLOR_MAX_ORDER), xx(NL, 0:TAYLOR_MAX_ORDER), vv(NL, 0:TAYLOR_MAX_ORDER)
    real(wp) :: w0sq(NL), gam(NL), x(0:TAYLOR_MAX_ORDER), v(0:TAYLOR_MAX_ORDER), sh, ch, ev1(1), ev2(1), ev3(1)
    integer :: state(NL), next, l, pmax, q, evk(1), nev
    logical :: done, trunc
    state = 0
    next = 1
    do l = 1, NL
      call fill(l)
    end do
    do while (any(state > 0))
      ! the series of every busy lane (an idle lane's are zeros)
      pmax = 1
      do l = 1, NL
        if (state(l) == 0) then
          cc(l, 0) = 1
          ss(l, 0) = 0
          xx(l, 0:1) = 0
          vv(l, 0:1) = 0
          w0sq(l) = 0
          gam(l) = 0
          cycle
        end if
        associate (wl => w(l))
          pmax = max(pmax, wl%p)
          ! taylor_coefficients' first terms, operation for operation
          sh = sin(wl%xh)
          ch = cos(wl%xh)
          ss(l, 0) = sh + ch*wl%xl
          cc(l, 0) = ch - sh*wl%xl
          wl%sn = ss(l, 0)
          wl%cs = cc(l, 0)
          xx(l, 0) = wl%xh
          vv(l, 0) = wl%vh
          xx(l, 1) = wl%vh
          vv(l, 1) = -wl%gamma*wl%vh - wl%w0sq*wl%sn
          wl%s0abs = abs(wl%gamma*wl%vh) + wl%w0sq*abs(wl%sn)
          w0sq(l) = wl%w0sq
          gam(l) = wl%gamma
        end associate
      end do
      call taylor_series_lanes(int(pmax, c_int), int(TAYLOR_MAX_ORDER, c_int), w0sq, gam, cc, ss, xx, vv)
      ! each busy lane's step, by the scalar integrator's code
      do l = 1, NL
        if (state(l) == 0) cycle
        q = w(l)%p + 1
        x(0:q) = xx(l, 0:q)
        v(0:q) = vv(l, 0:q)
        call taylor_walk_step(w(l), t, x, v, .false., budget, theta(:, state(l)), omega(:, state(l)), err(:, state(l)), &
                              ev1, evk, ev2, ev3, nev, trunc, done)
        if (done) then
          call finish(l)
          call fill(l)
        end if
      end do
    end do

  contains

    ! Give lane ll the next state of the list that needs steps (the others,
    ! refused or done at their start, are finished on the way).
    subroutine fill(ll)
      integer, intent(in) :: ll
      integer :: k
      type(status_t) :: sk
      state(ll) = 0
      do while (next <= size(list))
        k = list(next)
        next = next + 1
        ! (a state that runs writes every output, or its failure NaNs them)
        steps(k) = 0
        order(k) = 0
        sk%code = PENDULA_OK
        if (present(control)) then
          if (cancel_requested(control)) sk%code = PENDULA_ERR_CANCELLED
        end if
        if (sk%code == PENDULA_OK) call taylor_check(t(1:1), theta0(k), omega0(at(omega0, k)), w0(at(w0, k)), &
                                                     gamma(at(gamma, k)), tol(at(tol, k)), budget, sk)
        codes(k) = sk%code
        if (sk%code /= PENDULA_OK) then
          theta(:, k) = failed_output()
          omega(:, k) = failed_output()
          err(:, k) = failed_output()
          cycle
        end if
        call taylor_start(t, theta0(k), omega0(at(omega0, k)), w0(at(w0, k)), gamma(at(gamma, k)), tol(at(tol, k)), &
                          budget, theta(:, k), omega(:, k), err(:, k), w(ll))
        order(k) = w(ll)%p
        state(ll) = k
        if (size(t) > 1 .and. w(ll)%outcome == PENDULA_OK) return
        call finish(ll)
        state(ll) = 0
      end do
    end subroutine fill

    ! The end of lane ll's state: its code, the cancel flag, the progress.
    subroutine finish(ll)
      integer, intent(in) :: ll
      integer :: k, outcome
      type(status_t) :: sk
      k = state(ll)
      outcome = w(ll)%outcome
      steps(k) = w(ll)%steps
      if (present(control)) then
        if (cancel_requested(control)) outcome = PENDULA_ERR_CANCELLED
        call add_progress(control, 1_i8)
      end if
      call taylor_outcome(outcome, w(ll)%t_fail, budget, sk)
      codes(k) = sk%code
      ! a failed state's outputs are NaN: the batch writes them (nan_failed)
      if (sk%code /= PENDULA_OK) steps(k) = 0
    end subroutine finish

  end subroutine taylor_lanes_run

  !> The states 1..n in the order the blocks should take them: by series
  !> order (stable counting sort), so that a block's lanes mostly share their
  !> order and the series, formed up to the block's largest order, waste
  !> little.  States that taylor_check refuses come first.  Arguments as
  !> taylor_lanes_run's; keys is work space.
  subroutine taylor_lanes_list(t, theta0, omega0, w0, gamma, tol, budget, keys, list)
    real(wp), intent(in) :: t(:)  !< shared output times [s], checked
    real(wp), intent(in) :: theta0(:)  !< initial angles [rad], n = size(theta0)
    real(wp), intent(in) :: omega0(:)  !< initial angular velocities [rad/s], n elements or one
    real(wp), intent(in) :: w0(:)  !< angular frequencies [1/s], n elements or one
    real(wp), intent(in) :: gamma(:)  !< damping rates [1/s], n elements or one
    real(wp), intent(in) :: tol(:)  !< absolute accuracies [rad], n elements or one
    integer(i8), intent(in) :: budget  !< step budget per state
    integer, intent(out) :: keys(:)  !< work space: each state's order (0: refused), n elements
    integer, intent(out) :: list(:)  !< the n state indices, in block order
    integer :: k, slot(0:TAYLOR_MAX_ORDER)
    real(wp) :: a(1), b(1), c(1)
    type(taylor_walk_t) :: w
    type(status_t) :: sk
    slot = 0
    do k = 1, size(theta0)
      call taylor_check(t(1:1), theta0(k), omega0(at(omega0, k)), w0(at(w0, k)), gamma(at(gamma, k)), &
                        tol(at(tol, k)), budget, sk)
      keys(k) = 0
      if (sk%code == PENDULA_OK) then
        call taylor_start(t, theta0(k), omega0(at(omega0, k)), w0(at(w0, k)), gamma(at(gamma, k)), tol(at(tol, k)), &
                          budget, a, b, c, w)
        keys(k) = w%p
      end if
      slot(keys(k)) = slot(keys(k)) + 1
    end do
    ! slot(key): the first place of the states of that order
    do k = TAYLOR_MAX_ORDER, 1, -1
      slot(k) = slot(k - 1)
    end do
    slot(0) = 1
    do k = 1, TAYLOR_MAX_ORDER
      slot(k) = slot(k) + slot(k - 1)
    end do
    do k = 1, size(theta0)
      list(slot(keys(k))) = k
      slot(keys(k)) = slot(keys(k)) + 1
    end do
  end subroutine taylor_lanes_list

end module pendula_taylor_lanes
