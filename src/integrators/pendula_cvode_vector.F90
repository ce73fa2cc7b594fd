!> Vector operations for CVODE's two-component state (theta, Omega), specialised
!> for length 2, installed into the operations table of a SUNDIALS serial
!> N_Vector.
!>
!> Why: for N = 2 CVODE's time goes into the generic serial vector kernels, not
!> into the pendulum.  Each N_VLinearSum_Serial call costs ~125 instructions
!> (case analysis and a call to a static kernel, all unoptimised: Debian's
!> SUNDIALS 6.4.1 is compiled without optimisation) to do 2 multiply-adds,
!> and cvPredict alone makes q(q+1)/2 of them per step; the
!> fused operations (N_VLinearCombination in CVodeGetDky, N_VScaleAddMulti) are
!> disabled in a new serial vector, so SUNDIALS falls back to loops of
!> N_VScale/N_VLinearSum.  The kernels here work on the two numbers directly.
!>
!> The vector stays a serial vector (same ID, content struct and data layout,
!> clone/destroy/array-pointer operations untouched), so the dense matrix and
!> linear solver, which read the data array, keep working; only the arithmetic
!> entries of the table are replaced.  CVODE clones its work vectors from the
!> state vector (N_VClone copies the table), so every vector it makes gets
!> these kernels too.
!>
!> Results are bit-for-bit those of the serial kernels on the same data: each
!> kernel evaluates the same expressions in the same order, including the
!> special cases of N_VLinearSum_Serial that are not plain a*x + b*y
!> (a == b: a*(x + y); a == -b: a*(x - y), when neither is +-1), and the
!> fused operations follow SUNDIALS' fallback loops (what CVODE ran before:
!> a new serial vector has its fused operations disabled).  gfortran without -march
!> does not contract a*x + b*y into an FMA, nor does the Debian SUNDIALS build,
!> so the roundings agree.  tests/fortran/test_cvode_vector.f90 checks this
!> against the serial library.
!>
!> Compiled only with SUNDIALS (PENDULA_WITH_SUNDIALS); empty otherwise, so that
!> fpm, which compiles every file under src/, builds without SUNDIALS too.
#ifdef PENDULA_WITH_SUNDIALS
module pendula_cvode_vector
  use, intrinsic :: iso_c_binding
  use fsundials_nvector_mod, only: N_Vector, N_Vector_Ops, FN_VGetVectorID, SUNDIALS_NVEC_SERIAL
  implicit none
  private
  public :: specialise_pair_ops, pair_t, pair_of

  !> The content of a serial N_Vector (nvector_serial.h, sunindextype = int64
  !> in this SUNDIALS build): length, ownership flag, data pointer.
  type, bind(C) :: serial_content_t
    integer(c_int64_t) :: length
    integer(c_int) :: own_data
    type(c_ptr) :: data
  end type serial_content_t

  !> The data of a length-2 vector, reached by one scalar pointer (no array
  !> descriptor to build in each kernel).
  type, bind(C) :: pair_t
    real(c_double) :: v(2)
  end type pair_t

contains

  !> Replace the arithmetic operations of the serial vector y, which must have
  !> length 2, by the length-2 kernels of this module; do it before CVodeInit
  !> so that every vector CVODE clones from y inherits them.  ok is false (and
  !> y untouched) when y is not a serial vector of length 2 or has no table.
  subroutine specialise_pair_ops(y, ok)
    ! inout: the operations table y points to is rewritten (and the SUNDIALS
    ! wrapper FN_VGetVectorID takes inout).
    type(N_Vector), intent(inout) :: y  !< serial SUNDIALS vector of length 2
    logical, intent(out) :: ok  !< whether the kernels were installed
    type(serial_content_t), pointer :: content
    type(N_Vector_Ops), pointer :: ops
    ok = .false.
    if (.not. (c_associated(y%content) .and. c_associated(y%ops))) return
    if (FN_VGetVectorID(y) /= SUNDIALS_NVEC_SERIAL) return
    call c_f_pointer(y%content, content)
    if (content%length /= 2 .or. .not. c_associated(content%data)) return
    call c_f_pointer(y%ops, ops)
    ops%nvlinearsum = c_funloc(linear_sum)
    ops%nvconst = c_funloc(const)
    ops%nvprod = c_funloc(prod)
    ops%nvdiv = c_funloc(div)
    ops%nvscale = c_funloc(scale)
    ops%nvabs = c_funloc(abs_)
    ops%nvinv = c_funloc(inv)
    ops%nvaddconst = c_funloc(add_const)
    ops%nvdotprod = c_funloc(dot_prod)
    ops%nvmaxnorm = c_funloc(max_norm)
    ops%nvwrmsnorm = c_funloc(wrms_norm)
    ops%nvmin = c_funloc(min_)
    ops%nvwsqrsumlocal = c_funloc(wsqr_sum)
    ops%nvlinearcombination = c_funloc(linear_combination)
    ops%nvscaleaddmulti = c_funloc(scale_add_multi)
    ops%nvscalevectorarray = c_funloc(scale_vector_array)
    ops%nvlinearsumvectorarray = c_funloc(linear_sum_vector_array)
    ok = .true.
  end subroutine specialise_pair_ops

  ! Every kernel loads its inputs before it stores: SUNDIALS passes the same
  ! vector as input and output (z == x, z == y) all the time.
  !
  ! bind(C, name=''): C calling convention without a global C name.  With the
  ! default name (the procedure's), a library loaded before ours that
  ! exports the same name takes the reference: in Python, c_funloc(div)
  ! returned libc's div(), so N_VDiv (CVODE's initial-step bound) did not
  ! run our kernel at all.

  !> The two numbers of the serial length-2 vector x, as p%v(1:2): for the
  !> right-hand side, where FN_VGetArrayPointer would go through the SUNDIALS
  !> wrapper and build an array descriptor on every call.
  function pair_of(x) result(p)
    type(N_Vector), intent(in) :: x  !< serial SUNDIALS vector of length 2
    type(pair_t), pointer :: p
    p => pair(x)
  end function pair_of

  ! pair is private so that gfortran inlines it into the kernels (a public
  ! procedure stays an out-of-line call there).

  !> The two numbers of vector x.
  function pair(x) result(p)
    type(N_Vector), intent(in) :: x
    type(pair_t), pointer :: p
    type(serial_content_t), pointer :: content
    call c_f_pointer(x%content, content)
    call c_f_pointer(content%data, p)
  end function pair

  !> The two numbers of the vector whose address is x (an N_Vector* array element).
  function pair_at(x) result(p)
    type(c_ptr), intent(in) :: x
    type(pair_t), pointer :: p
    type(N_Vector), pointer :: vec
    call c_f_pointer(x, vec)
    p => pair(vec)
  end function pair_at

  !> z = a x + b y, with N_VLinearSum_Serial's roundings.  Its cases in its
  !> order: a or b = +-1 (axpy, sum, difference: the same roundings and signs
  !> of zero as the plain formula, since (+-1) x is exact and x - y is
  !> x + (-y)); then a == b and a == -b, which factor out a; else the plain
  !> formula.
  subroutine linear_sum(a, x, b, y, z) bind(C, name='')
    real(c_double), value :: a, b
    type(N_Vector), intent(in) :: x, y, z
    real(c_double) :: x1, x2, y1, y2
    type(pair_t), pointer :: pz
    associate (px => pair(x), py => pair(y))
      x1 = px%v(1); x2 = px%v(2); y1 = py%v(1); y2 = py%v(2)
    end associate
    pz => pair(z)
    if (abs(a) == 1 .or. abs(b) == 1) then
      pz%v(1) = a*x1 + b*y1
      pz%v(2) = a*x2 + b*y2
    else if (a == b) then
      pz%v(1) = a*(x1 + y1)
      pz%v(2) = a*(x2 + y2)
    else if (a == -b) then
      pz%v(1) = a*(x1 - y1)
      pz%v(2) = a*(x2 - y2)
    else
      pz%v(1) = a*x1 + b*y1
      pz%v(2) = a*x2 + b*y2
    end if
  end subroutine linear_sum

  !> z = c
  subroutine const(c, z) bind(C, name='')
    real(c_double), value :: c
    type(N_Vector), intent(in) :: z
    type(pair_t), pointer :: pz
    pz => pair(z)
    pz%v = c
  end subroutine const

  !> z = x y (componentwise)
  subroutine prod(x, y, z) bind(C, name='')
    type(N_Vector), intent(in) :: x, y, z
    real(c_double) :: r(2)
    type(pair_t), pointer :: pz
    associate (px => pair(x), py => pair(y))
      r = px%v*py%v
    end associate
    pz => pair(z)
    pz%v = r
  end subroutine prod

  !> z = x / y (componentwise)
  subroutine div(x, y, z) bind(C, name='')
    type(N_Vector), intent(in) :: x, y, z
    real(c_double) :: r(2)
    type(pair_t), pointer :: pz
    associate (px => pair(x), py => pair(y))
      r = px%v/py%v
    end associate
    pz => pair(z)
    pz%v = r
  end subroutine div

  !> z = c x  (the serial special cases c = +-1 round the same)
  subroutine scale(c, x, z) bind(C, name='')
    real(c_double), value :: c
    type(N_Vector), intent(in) :: x, z
    real(c_double) :: r(2)
    type(pair_t), pointer :: pz
    associate (px => pair(x))
      r = c*px%v
    end associate
    pz => pair(z)
    pz%v = r
  end subroutine scale

  !> z = |x|
  subroutine abs_(x, z) bind(C, name='')
    type(N_Vector), intent(in) :: x, z
    real(c_double) :: r(2)
    type(pair_t), pointer :: pz
    associate (px => pair(x))
      r = abs(px%v)
    end associate
    pz => pair(z)
    pz%v = r
  end subroutine abs_

  !> z = 1 / x
  subroutine inv(x, z) bind(C, name='')
    type(N_Vector), intent(in) :: x, z
    real(c_double) :: r(2)
    type(pair_t), pointer :: pz
    associate (px => pair(x))
      r = 1/px%v
    end associate
    pz => pair(z)
    pz%v = r
  end subroutine inv

  !> z = x + b
  subroutine add_const(x, b, z) bind(C, name='')
    type(N_Vector), intent(in) :: x, z
    real(c_double), value :: b
    real(c_double) :: r(2)
    type(pair_t), pointer :: pz
    associate (px => pair(x))
      r = px%v + b
    end associate
    pz => pair(z)
    pz%v = r
  end subroutine add_const

  !> sum of x y, summed from 0 in index order as the serial kernel does
  real(c_double) function dot_prod(x, y) result(s) bind(C, name='')
    type(N_Vector), intent(in) :: x, y
    associate (px => pair(x), py => pair(y))
      s = (0 + px%v(1)*py%v(1)) + px%v(2)*py%v(2)
    end associate
  end function dot_prod

  !> max |x|, starting from 0 with a strict > (a NaN is skipped, as in the
  !> serial kernel)
  real(c_double) function max_norm(x) result(m) bind(C, name='')
    type(N_Vector), intent(in) :: x
    integer :: i
    associate (px => pair(x))
      m = 0
      do i = 1, 2
        if (abs(px%v(i)) > m) m = abs(px%v(i))
      end do
    end associate
  end function max_norm

  !> sum of (x w)**2, the local part of the weighted norms
  real(c_double) function wsqr_sum(x, w) result(s) bind(C, name='')
    type(N_Vector), intent(in) :: x, w
    real(c_double) :: p1, p2
    associate (px => pair(x), pw => pair(w))
      p1 = px%v(1)*pw%v(1)
      p2 = px%v(2)*pw%v(2)
    end associate
    s = (0 + p1*p1) + p2*p2
  end function wsqr_sum

  !> sqrt(sum of (x w)**2 / 2): CVODE's error norm (SUNRsqrt: 0 for a sum <= 0)
  real(c_double) function wrms_norm(x, w) result(s) bind(C, name='')
    type(N_Vector), intent(in) :: x, w
    s = wsqr_sum(x, w)/2
    if (s <= 0) then
      s = 0
    else
      s = sqrt(s)
    end if
  end function wrms_norm

  !> min x (first component, then a strict <)
  real(c_double) function min_(x) result(m) bind(C, name='')
    type(N_Vector), intent(in) :: x
    associate (px => pair(x))
      m = px%v(1)
      if (px%v(2) < m) m = px%v(2)
    end associate
  end function min_

  !> z = sum_i c(i) x_i, as SUNDIALS' fallback computes it (z = c(1) x_1, then
  !> z = z + c(i) x_i in order); z may be x_1.  Used by CVodeGetDky for every
  !> output.
  integer(c_int) function linear_combination(nvec, c, x, z) result(ierr) bind(C, name='')
    integer(c_int), value :: nvec
    real(c_double), intent(in) :: c(*)
    type(c_ptr), intent(in) :: x(*)
    type(N_Vector), intent(in) :: z
    real(c_double) :: r1, r2
    integer :: i
    type(pair_t), pointer :: pz, px
    ierr = -1
    if (nvec < 1) return
    px => pair_at(x(1))
    r1 = c(1)*px%v(1)
    r2 = c(1)*px%v(2)
    do i = 2, nvec
      px => pair_at(x(i))
      r1 = r1 + c(i)*px%v(1)
      r2 = r2 + c(i)*px%v(2)
    end do
    pz => pair(z)
    pz%v(1) = r1
    pz%v(2) = r2
    ierr = 0
  end function linear_combination

  !> z_i = a(i) x + y_i for i = 1..nvec (SUNDIALS' fallback: N_VLinearSum with
  !> b = 1, which rounds as a x + y); z_i may be y_i.
  integer(c_int) function scale_add_multi(nvec, a, x, y, z) result(ierr) bind(C, name='')
    integer(c_int), value :: nvec
    real(c_double), intent(in) :: a(*)
    type(N_Vector), intent(in) :: x
    type(c_ptr), intent(in) :: y(*), z(*)
    real(c_double) :: x1, x2, y1, y2
    integer :: i
    type(pair_t), pointer :: py, pz
    ierr = -1
    if (nvec < 1) return
    associate (px => pair(x))
      x1 = px%v(1); x2 = px%v(2)
    end associate
    do i = 1, nvec
      py => pair_at(y(i))
      y1 = py%v(1); y2 = py%v(2)
      pz => pair_at(z(i))
      pz%v(1) = a(i)*x1 + y1
      pz%v(2) = a(i)*x2 + y2
    end do
    ierr = 0
  end function scale_add_multi

  !> z_i = c(i) x_i for i = 1..nvec (cvRescale after a step-size change)
  integer(c_int) function scale_vector_array(nvec, c, x, z) result(ierr) bind(C, name='')
    integer(c_int), value :: nvec
    real(c_double), intent(in) :: c(*)
    type(c_ptr), intent(in) :: x(*), z(*)
    real(c_double) :: r(2)
    integer :: i
    type(pair_t), pointer :: px, pz
    ierr = -1
    if (nvec < 1) return
    do i = 1, nvec
      px => pair_at(x(i))
      r = c(i)*px%v
      pz => pair_at(z(i))
      pz%v = r
    end do
    ierr = 0
  end function scale_vector_array

  !> z_i = a x_i + b y_i for i = 1..nvec, each as linear_sum
  integer(c_int) function linear_sum_vector_array(nvec, a, x, b, y, z) result(ierr) bind(C, name='')
    integer(c_int), value :: nvec
    real(c_double), value :: a, b
    type(c_ptr), intent(in) :: x(*), y(*), z(*)
    integer :: i
    type(N_Vector), pointer :: vx, vy, vz
    ierr = -1
    if (nvec < 1) return
    do i = 1, nvec
      call c_f_pointer(x(i), vx)
      call c_f_pointer(y(i), vy)
      call c_f_pointer(z(i), vz)
      call linear_sum(a, vx, b, vy, vz)
    end do
    ierr = 0
  end function linear_sum_vector_array

end module pendula_cvode_vector
#endif
