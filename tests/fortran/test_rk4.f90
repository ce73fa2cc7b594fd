program test_rk4
  use pendula_testing, only: checker_t
  implicit none
  type(checker_t) :: t
  call t%check_true(.true., 'placeholder')
  call t%report('test_rk4')
end program test_rk4
