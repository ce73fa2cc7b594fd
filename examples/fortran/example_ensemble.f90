!> Example: many pendulums in one call (rk4_batch_solve, cvode_batch_solve).
!>
!> A map of the text's damped pendulum (w0**2 = 2 1/s**2, gamma = 0.1 1/s):
!> for a 9 x 25 grid of starts (theta0 in (-pi, pi), Omega0 in [0, 6] rad/s)
!> integrate to t = 30 s in one batch call and print how many times each
!> pendulum went over the top (the integer part of (theta(30) + pi) / 2 pi):
!> '.' librated only, digits count the turns.  Then the same batch with one
!> state given an unstable step, to show the per-state status: that state
!> fails alone and the others keep their answers.  Last, when this build has
!> CVODE, the same grid by cvode_batch_solve (one solver per thread, restarted
!> per state) with a tight budget of 600 steps per state: the states that need
!> more fail alone (ERR_MAXSTEPS) and the others keep their answers.
program example_ensemble
  use pendula
  use example_support, only: require
  implicit none
  integer, parameter :: n_th = 9, n_om = 25, n = n_th*n_om, nt = 601
  real(wp) :: t(nt), th0(n), om0(n), h(n), theta(nt, n), omega(nt, n)
  integer :: codes(n), i, j, k, turns, first
  integer(i8) :: steps(n)
  type(ode_stats_t) :: stats(n)
  type(status_t) :: st
  character(len=n_om) :: row

  t = [(0.05_wp*i, i=0, nt - 1)]
  do j = 1, n_th
    do i = 1, n_om
      k = (j - 1)*n_om + i
      th0(k) = -pi + 2*pi*(j - 0.5_wp)/n_th   ! cell centres, inside (-pi, pi)
      om0(k) = 6.0_wp*(i - 1)/(n_om - 1)
    end do
  end do
  h = 0.025_wp
  call rk4_batch_solve(t, th0, om0, [sqrt(2.0_wp)], [0.1_wp], h, theta, omega, codes, steps, st, threads=0)
  call require(st)
  write (*, '(a, i0, a, i0, a)') 'Turns over the top by t = 30 s (', n, ' states, ', sum(steps), ' RK4 steps)'
  write (*, '(a)') '  theta0 \ Omega0: 0 .. 6 rad/s'
  do j = 1, n_th
    do i = 1, n_om
      k = (j - 1)*n_om + i
      turns = int(abs(floor((theta(nt, k) + pi)/(2*pi))))
      row(i:i) = merge('.', achar(iachar('0') + min(turns, 9)), turns == 0)
    end do
    write (*, '(f8.3, 2x, a)') th0((j - 1)*n_om + 1), row
  end do

  ! One state with a step outside RK4's stability region: it fails alone.
  h(7) = 3.0_wp
  t = [(2.5_wp*i, i=0, nt - 1)]   ! substeps of 2.5 s for h = 3: beyond 2 sqrt(2)/w0 = 2 s
  call rk4_batch_solve(t(1:21), th0, om0, [sqrt(2.0_wp)], [0.1_wp], h, theta(1:21, :), omega(1:21, :), codes, &
                       steps, st, first_failed=first)
  write (*, '(/, a, i0, a, i0, a)') 'With h(7) = 3 s: ', count(codes /= PENDULA_OK), ' state failed (state ', first, &
    '); the others succeeded:'
  write (*, '(2x, a)') trim(st%message)
  if (first /= 7 .or. count(codes == PENDULA_OK) /= n - 1) error stop 'per-state status not as expected'

  if (.not. cvode_available()) then
    write (*, '(/, a)') 'This build has no CVODE: cvode_batch_solve is not shown.'
  else
    t = [(0.05_wp*i, i=0, nt - 1)]
    call cvode_batch_solve(t, th0, om0, [sqrt(2.0_wp)], [0.1_wp], [1e-8_wp], [1e-10_wp], PENDULA_CVODE_ADAMS, &
                           600_i8, theta, omega, codes, stats, st, threads=0, first_failed=first)
    write (*, '(/, a, i0, a, i0, a)') 'CVODE (Adams, at most 600 steps per state): ', count(codes == PENDULA_OK), &
      ' of ', n, ' states finished; the others ran out of steps:'
    write (*, '(2x, a)') trim(st%message)
    if (count(codes == PENDULA_OK) == 0 .or. all(codes == PENDULA_OK)) error stop 'CVODE per-state status not as expected'
  end if

end program example_ensemble
