!> Nanoseconds per call of pendula_format's number texts for a few typical
!> values (a benchmark that prints numbers, not a test).  Built with the tests
!> (tests/meson.build); run it from a build directory:
!>
!>     build/dev/tests/bench_format
program bench_format
  use pendula_kinds, only: wp, i8
  use pendula_format, only: format_sci, format_fixed, format_general, format_short
  implicit none
  real(wp), parameter :: values(*) = [1.0e-10_wp, 3.7_wp, 2.2e20_wp, 5.0e-324_wp]
  character(len=*), parameter :: forms(*) = [character(len=20) :: 'format_sci(x, 4)', &
      'format_sci(x, 17)', 'format_fixed(x, 6)', 'format_general(x, 6)', 'format_short(x)']
  integer :: i, f
  integer(i8) :: check

  check = 0
  print '(a)', 'ns of processor time per call (best of 5 runs of 20000 calls)'
  print '(a22, 4(a12))', 'form \ x', '1e-10', '3.7', '2.2e+20', '5e-324'
  do f = 1, size(forms)
    write (*, '(a22)', advance='no') forms(f)
    do i = 1, size(values)
      write (*, '(f12.1)', advance='no') ns_per_call(f, values(i))
    end do
    write (*, *)
  end do
  print '(a, i0)', 'checksum ', check

contains

  ! Best-of-five mean processor time per call of form f on x, in nanoseconds
  ! (processor time, not wall time: the machine may be shared).
  real(wp) function ns_per_call(f, x) result(best)
    integer, intent(in) :: f
    real(wp), intent(in) :: x
    integer, parameter :: calls = 20000
    real(wp) :: t0, t1
    integer :: run, j
    real(wp) :: xj
    character(len=64) :: text
    best = huge(best)
    do run = 1, 5
      call cpu_time(t0)
      do j = 1, calls
        xj = x * (1 + epsilon(x) * mod(j, 3))   ! keeps the call inside the loop
        select case (f)
        case (1)
          text = format_sci(xj, 4)
        case (2)
          text = format_sci(xj, 17)
        case (3)
          text = format_fixed(xj, 6)
        case (4)
          text = format_general(xj, 6)
        case default
          text = format_short(xj)
        end select
        check = check + len_trim(text) + iachar(text(2:2))
      end do
      call cpu_time(t1)
      best = min(best, (t1 - t0) / calls * 1.0e9_wp)
    end do
  end function ns_per_call

end program bench_format
