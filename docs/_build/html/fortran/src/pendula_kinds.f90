!> Working precision for the whole library: every real in pendula is real(wp).
module pendula_kinds
  use, intrinsic :: iso_fortran_env, only: real64, int64
  implicit none
  private
  public :: wp, i8

  !> Double precision (IEEE binary64); the single kind used for all reals.
  integer, parameter :: wp = real64
  !> 64-bit integers, for counters that can exceed 2**31 (steps of very long runs).
  integer, parameter :: i8 = int64
end module pendula_kinds
