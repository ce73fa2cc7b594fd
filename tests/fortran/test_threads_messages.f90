!> Messages built by several threads at once equal the serial ones.
!>
!> Why: gfortran 12 keeps the length of a `character(len=:), allocatable`
!> function result in a static variable at each call site, so two threads at
!> the same site race on it and get garbled or truncated texts (Python users
!> call the library from threads).  The library therefore returns explicit
!> lengths; this program runs the message paths (the formatters, a check's
!> message, the code names, a scene solve's reason) in an OpenMP loop and
!> compares every text with the one built serially.  With the deferred-length
!> results it found hundreds of wrong texts per run; it is built only when
!> OpenMP is found.
program test_threads_messages
  use pendula
  use pendula_format, only: format_sci, format_fixed, format_general, format_short, format_int
  use pendula_scene_codes, only: scene_model_list, scene_want_list
  use pendula_status, only: check_positive
  use pendula_testing, only: checker_t, quick_mode
  implicit none
  integer, parameter :: N = 4000, REPEATS = 12, TEXT = 1600, THREADS = 4
  type(checker_t) :: t
  character(len=TEXT), allocatable :: serial(:)
  real(wp) :: x(N)
  integer :: i, r, bad, first_bad, rounds

  ! values of every magnitude and sign, zeros and subnormals among them
  do i = 1, N
    x(i) = (-1.0_wp)**i*(1.0_wp + mod(i*7919, 1000)/997.0_wp)*10.0_wp**(mod(i*37, 600) - 300)
  end do
  x(1) = 0
  x(2) = -0.0_wp
  x(3) = 4.9e-324_wp
  x(4) = huge(1.0_wp)

  allocate (serial(N))
  do i = 1, N
    serial(i) = texts(i)
  end do
  call t%check_true(index(serial(5), 'w0 = ') > 0 .and. len_trim(serial(4)) > 300, &
                    'serial texts carry the messages and the 309-digit fixed form')

  ! one round under PENDULA_TEST_QUICK (the memcheck and checked legs, where
  ! threads are serialised and a round costs ~10 s): they look for memory
  ! errors, which one round exercises
  rounds = merge(1, REPEATS, quick_mode())
  bad = 0
  first_bad = 0
  do r = 1, rounds
    !$omp parallel do num_threads(THREADS) schedule(dynamic, 16) reduction(+:bad) reduction(max:first_bad)
    do i = 1, N
      if (texts(i) /= serial(i)) then
        bad = bad + 1
        first_bad = max(first_bad, i)
      end if
    end do
    !$omp end parallel do
  end do
  call t%check_true(bad == 0, 'texts built in '//format_int(THREADS)//' threads equal the serial ones: '// &
                    format_int(bad)//' of '//format_int(N*rounds)//' differ (e.g. item '//format_int(first_bad)//')')
  call t%report('test_threads_messages')

contains

  ! Every message path for item i, joined into one text.
  function texts(i) result(s)
    integer, intent(in) :: i
    character(len=TEXT) :: s
    type(status_t) :: st
    type(scene_t) :: sc
    type(scene_result_t) :: res
    integer :: k
    k = mod(i, 17)
    st = status_t()
    call check_positive('w0', -abs(x(i)), st)
    s = format_sci(x(i), k + 1)//'|'//format_fixed(x(i), k)//'|'//format_general(x(i), 15)//'|'// &
        format_short(x(i))//'|'//format_int(i*104729 - N)//'|'//trim(st%message)//'|'// &
        code_name(mod(i, 12) - 1)//'|'//scene_model_name(mod(i, 8) - 1)//'|'// &
        scene_want_name(mod(i, 8))//'|'//scene_model_list(mod(i, 3))//'|'//scene_want_list()
    if (mod(i, 50) == 0) then
      ! a solve's reason (closed forms, quick), with an error estimate in it
      call scene_init(sc, 0.1_wp*mod(i, 30), 0.0_wp, [1.0_wp], 1.0_wp, 0.0_wp, 1.0e-9_wp, SCENE_WANT_FINAL, st)
      call scene_solve(sc, res, st)
      s = trim(s)//'|'//trim(res%reason)//'|'//trim(st%message)
    end if
  end function texts

end program test_threads_messages
