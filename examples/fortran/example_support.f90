!> What the Fortran example programs share.
module example_support
  use pendula, only: status_t, PENDULA_OK
  implicit none
  private
  public :: require

contains

  !> Stop the example (error stop 1) with the library's message when a call failed:
  !> an example shows results, and has nothing sensible to do after an error.
  subroutine require(status)
    type(status_t), intent(in) :: status
    if (status%code /= PENDULA_OK) then
      write (*, '(a)') 'error: '//trim(status%message)
      error stop 1
    end if
  end subroutine require

end module example_support
