!> The length-2 N_Vector kernels of pendula_cvode_vector against the SUNDIALS
!> serial vector: the same data go into plain serial vectors and into serial
!> vectors with the specialised table, the same generic N_V* call runs on
!> both, and the results must agree bit for bit (CVODE's trajectory is then
!> unchanged by the kernels).  The plain vectors run what CVODE ran before:
!> the serial kernels, and SUNDIALS' fallback loops for the fused and array
!> operations (disabled in a new serial vector).  Coefficients include the
!> special cases of N_VLinearSum_Serial (+-1, 0, a == b, a == -b), data
!> include cancellations (signs of zero), outputs alias inputs as CVODE
!> does.  Also: clones inherit the table; a vector of another length is
!> refused.  Built only with SUNDIALS.
program test_cvode_vector
  use, intrinsic :: iso_c_binding
  use pendula_kinds, only: wp
  use pendula_testing, only: checker_t
  use fsundials_context_mod, only: FSUNContext_Create, FSUNContext_Free
  use fsundials_nvector_mod, only: N_Vector, N_Vector_Ops, FN_VGetArrayPointer, FN_VDestroy, FN_VClone, &
                                   FN_VLinearSum, FN_VConst, FN_VProd, FN_VDiv, FN_VScale, FN_VAbs, FN_VInv, FN_VAddConst, &
                                   FN_VDotProd, FN_VMaxNorm, FN_VWrmsNorm, FN_VMin, FN_VWSqrSumLocal, FN_VLinearCombination, &
                                   FN_VScaleAddMulti, FN_VScaleVectorArray, FN_VLinearSumVectorArray
  use fnvector_serial_mod, only: FN_VNew_Serial
  use pendula_cvode_vector, only: specialise_pair_ops
  implicit none

  !> A pointer to one N_Vector (Fortran has no arrays of pointers).
  type :: vec_ref
    type(N_Vector), pointer :: p => null()
  end type vec_ref

  integer, parameter :: NV = 5
  ! Coefficients: N_VLinearSum_Serial's special cases and ordinary values.
  real(wp), parameter :: coefs(10) = [1.0_wp, -1.0_wp, 0.0_wp, -0.0_wp, 2.5_wp, -2.5_wp, &
                                      0.3_wp, -0.3_wp, 1.7_wp, 1.0_wp/3]
  ! Data sets (rows: vector 1..NV, columns: component); set 2 repeats values
  ! and their negatives so that sums and differences cancel to zeros.
  real(wp), parameter :: data(2, NV, 3) = reshape([ &
                                   0.3_wp, -1.7_wp, 2.5_wp, 1.0_wp/3, -4.0e4_wp, 1.0e-3_wp, 7.1e-2_wp, -3.0e3_wp, 0.9_wp, 0.25_wp, &
                                                  1.0_wp/3, -2.0_wp/7, 1.0_wp/3, 2.0_wp/7, -1.0_wp/3, 2.0_wp/7, 0.1_wp, -0.1_wp, &
                                                  2.0_wp/7, 1.0_wp/3, &
                                      1.0e-5_wp, 3.0e4_wp, -7.0_wp, 7.0_wp, 1.25_wp, -1.0e-4_wp, 6.0_wp, 6.0_wp, -0.7_wp, 0.7_wp], &
                                                  [2, NV, 3])

  type(checker_t) :: tc
  type(c_ptr) :: ctx
  type(vec_ref) :: plain(NV), pair(NV)
  integer(c_int) :: ierr
  integer :: k
  logical :: ok

  ierr = FSUNContext_Create(c_null_ptr, ctx)
  call tc%check_true(ierr == 0, 'SUNContext_Create')
  do k = 1, NV
    plain(k)%p => FN_VNew_Serial(2_c_int64_t, ctx)
    pair(k)%p => FN_VNew_Serial(2_c_int64_t, ctx)
    call specialise_pair_ops(pair(k)%p, ok)
    call tc%check_true(ok, 'specialise_pair_ops accepts a serial vector of length 2')
  end do

  do k = 1, size(data, 3)
    call test_linear_sum(k)
    call test_unary_binary(k)
    call test_reductions(k)
    call test_fused(k)
  end do
  call test_clone_and_refusal()

  do k = 1, NV
    call FN_VDestroy(plain(k)%p)
    call FN_VDestroy(pair(k)%p)
  end do
  ierr = FSUNContext_Free(ctx)
  call tc%report('test_cvode_vector')

contains

  !> Put data set `set` into every vector of both families.
  subroutine load(set)
    integer, intent(in) :: set
    integer :: j
    real(c_double), pointer :: d(:)
    do j = 1, NV
      d => FN_VGetArrayPointer(plain(j)%p)
      d(1:2) = data(:, j, set)
      d => FN_VGetArrayPointer(pair(j)%p)
      d(1:2) = data(:, j, set)
    end do
  end subroutine load

  !> Vector k of both families holds the same bits.
  logical function same(k)
    integer, intent(in) :: k
    real(c_double), pointer :: a(:), b(:)
    a => FN_VGetArrayPointer(plain(k)%p)
    b => FN_VGetArrayPointer(pair(k)%p)
    same = all(transfer(a(1:2), 0_c_int64_t, 2) == transfer(b(1:2), 0_c_int64_t, 2))
  end function same

  logical function same_real(a, b)
    real(c_double), intent(in) :: a, b
    same_real = transfer(a, 0_c_int64_t) == transfer(b, 0_c_int64_t)
  end function same_real

  character(len=64) function label(what, set, a, b)
    character(len=*), intent(in) :: what
    integer, intent(in) :: set
    real(wp), intent(in) :: a, b
    write (label, '(a, " set ", i0, " a=", g0.4, " b=", g0.4)') what, set, a, b
  end function label

  !> z = a x + b y for every pair of coefficients, with z distinct, z == x
  !> and z == y (x == y too), against N_VLinearSum_Serial.
  subroutine test_linear_sum(set)
    integer, intent(in) :: set
    integer :: i, j, mode
    logical :: all_same, ok
    do mode = 1, 4
      all_same = .true.
      do i = 1, size(coefs)
        do j = 1, size(coefs)
          call load(set)
          select case (mode)
          case (1)
            call FN_VLinearSum(coefs(i), plain(1)%p, coefs(j), plain(2)%p, plain(3)%p)
            call FN_VLinearSum(coefs(i), pair(1)%p, coefs(j), pair(2)%p, pair(3)%p)
            ok = same(3)
          case (2)
            call FN_VLinearSum(coefs(i), plain(1)%p, coefs(j), plain(2)%p, plain(1)%p)
            call FN_VLinearSum(coefs(i), pair(1)%p, coefs(j), pair(2)%p, pair(1)%p)
            ok = same(1)
          case (3)
            call FN_VLinearSum(coefs(i), plain(1)%p, coefs(j), plain(2)%p, plain(2)%p)
            call FN_VLinearSum(coefs(i), pair(1)%p, coefs(j), pair(2)%p, pair(2)%p)
            ok = same(2)
          case default
            call FN_VLinearSum(coefs(i), plain(4)%p, coefs(j), plain(4)%p, plain(3)%p)
            call FN_VLinearSum(coefs(i), pair(4)%p, coefs(j), pair(4)%p, pair(3)%p)
            ok = same(3)
          end select
          if (.not. ok) then
            call tc%check_true(.false., label('N_VLinearSum mode '//achar(48 + mode), set, coefs(i), coefs(j)))
            all_same = .false.
          end if
        end do
      end do
      if (all_same) call tc%check_true(.true., 'N_VLinearSum')
    end do
  end subroutine test_linear_sum

  !> N_VConst, N_VProd, N_VDiv, N_VScale, N_VAbs, N_VInv, N_VAddConst, out of
  !> place and in place.
  subroutine test_unary_binary(set)
    integer, intent(in) :: set
    integer :: i, z
    do z = 1, 3, 2          ! in place (z = x = vector 1) and out of place (z = 3)
      do i = 1, size(coefs)
        call load(set)
        call FN_VScale(coefs(i), plain(1)%p, plain(z)%p)
        call FN_VScale(coefs(i), pair(1)%p, pair(z)%p)
        call tc%check_true(same(z), label('N_VScale', set, coefs(i), real(z, wp)))
        call load(set)
        call FN_VAddConst(plain(1)%p, coefs(i), plain(z)%p)
        call FN_VAddConst(pair(1)%p, coefs(i), pair(z)%p)
        call tc%check_true(same(z), label('N_VAddConst', set, coefs(i), real(z, wp)))
        call FN_VConst(coefs(i), plain(z)%p)
        call FN_VConst(coefs(i), pair(z)%p)
        call tc%check_true(same(z), label('N_VConst', set, coefs(i), real(z, wp)))
      end do
      call load(set)
      call FN_VProd(plain(1)%p, plain(2)%p, plain(z)%p)
      call FN_VProd(pair(1)%p, pair(2)%p, pair(z)%p)
      call tc%check_true(same(z), label('N_VProd', set, 0.0_wp, real(z, wp)))
      call load(set)
      call FN_VDiv(plain(1)%p, plain(2)%p, plain(z)%p)
      call FN_VDiv(pair(1)%p, pair(2)%p, pair(z)%p)
      call tc%check_true(same(z), label('N_VDiv', set, 0.0_wp, real(z, wp)))
      call load(set)
      call FN_VAbs(plain(1)%p, plain(z)%p)
      call FN_VAbs(pair(1)%p, pair(z)%p)
      call tc%check_true(same(z), label('N_VAbs', set, 0.0_wp, real(z, wp)))
      call load(set)
      call FN_VInv(plain(1)%p, plain(z)%p)
      call FN_VInv(pair(1)%p, pair(z)%p)
      call tc%check_true(same(z), label('N_VInv', set, 0.0_wp, real(z, wp)))
    end do
  end subroutine test_unary_binary

  !> N_VDotProd, N_VMaxNorm, N_VWrmsNorm, N_VMin, N_VWSqrSumLocal.
  subroutine test_reductions(set)
    integer, intent(in) :: set
    integer :: i, j
    call load(set)
    do i = 1, NV
      call tc%check_true(same_real(FN_VMaxNorm(plain(i)%p), FN_VMaxNorm(pair(i)%p)), &
                         label('N_VMaxNorm', set, real(i, wp), 0.0_wp))
      call tc%check_true(same_real(FN_VMin(plain(i)%p), FN_VMin(pair(i)%p)), &
                         label('N_VMin', set, real(i, wp), 0.0_wp))
      do j = 1, NV
        call tc%check_true(same_real(FN_VDotProd(plain(i)%p, plain(j)%p), FN_VDotProd(pair(i)%p, pair(j)%p)), &
                           label('N_VDotProd', set, real(i, wp), real(j, wp)))
        call tc%check_true(same_real(FN_VWrmsNorm(plain(i)%p, plain(j)%p), FN_VWrmsNorm(pair(i)%p, pair(j)%p)), &
                           label('N_VWrmsNorm', set, real(i, wp), real(j, wp)))
        call tc%check_true(same_real(FN_VWSqrSumLocal(plain(i)%p, plain(j)%p), &
                                   FN_VWSqrSumLocal(pair(i)%p, pair(j)%p)), label('N_VWSqrSumLocal', set, real(i, wp), real(j, wp)))
      end do
    end do
  end subroutine test_reductions

  !> N_VLinearCombination (z distinct and z = X(1), as in cvRestore-like
  !> uses), N_VScaleAddMulti (Z = Y, as CVODE calls it, and Z distinct),
  !> N_VScaleVectorArray and N_VLinearSumVectorArray, for 1..4 vectors.
  subroutine test_fused(set)
    integer, intent(in) :: set
    type(c_ptr), target :: xp(NV), yp(NV), zp(NV), xs(NV), ys(NV), zs(NV)
    real(c_double), target :: c(NV)
    integer :: n, i, shift
    do shift = 0, 2
      c = [(coefs(1 + mod(i + 3*shift, size(coefs))), i=1, NV)]
      do n = 1, 4
        ! linear combination of vectors 1..n into vector 5, then into vector 1
        call load(set)
        call fill(xp, plain, [(i, i=1, n)]); call fill(xs, pair, [(i, i=1, n)])
        ierr = FN_VLinearCombination(int(n, c_int), c, c_loc(xp), plain(5)%p)
        ierr = FN_VLinearCombination(int(n, c_int), c, c_loc(xs), pair(5)%p)
        call tc%check_true(same(5), label('N_VLinearCombination', set, real(n, wp), real(shift, wp)))
        call load(set)
        ierr = FN_VLinearCombination(int(n, c_int), c, c_loc(xp), plain(1)%p)
        ierr = FN_VLinearCombination(int(n, c_int), c, c_loc(xs), pair(1)%p)
        call tc%check_true(same(1), label('N_VLinearCombination z=X1', set, real(n, wp), real(shift, wp)))
        if (n > 2) cycle
        ! scale-add-multi: x = vector 5, Y = vectors 1..n, Z = Y or vectors 3..
        call load(set)
        call fill(yp, plain, [(i, i=1, n)]); call fill(ys, pair, [(i, i=1, n)])
        ierr = FN_VScaleAddMulti(int(n, c_int), c, plain(5)%p, c_loc(yp), c_loc(yp))
        ierr = FN_VScaleAddMulti(int(n, c_int), c, pair(5)%p, c_loc(ys), c_loc(ys))
        call tc%check_true(all([(same(i), i=1, n)]), label('N_VScaleAddMulti Z=Y', set, real(n, wp), &
                                                           real(shift, wp)))
        call load(set)
        call fill(zp, plain, [(2 + i, i=1, n)]); call fill(zs, pair, [(2 + i, i=1, n)])
        ierr = FN_VScaleAddMulti(int(n, c_int), c, plain(5)%p, c_loc(yp), c_loc(zp))
        ierr = FN_VScaleAddMulti(int(n, c_int), c, pair(5)%p, c_loc(ys), c_loc(zs))
        call tc%check_true(all([(same(2 + i), i=1, n)]), label('N_VScaleAddMulti', set, real(n, wp), &
                                                               real(shift, wp)))
        ! vector arrays: X = 1..n, Y = 3..; Z = X (in place) for the scaling
        call load(set)
        ierr = FN_VScaleVectorArray(int(n, c_int), c, c_loc(yp), c_loc(yp))
        ierr = FN_VScaleVectorArray(int(n, c_int), c, c_loc(ys), c_loc(ys))
        call tc%check_true(all([(same(i), i=1, n)]), label('N_VScaleVectorArray', set, real(n, wp), &
                                                           real(shift, wp)))
        call load(set)
        ierr = FN_VLinearSumVectorArray(int(n, c_int), c(1), c_loc(yp), c(2), c_loc(zp), c_loc(zp))
        ierr = FN_VLinearSumVectorArray(int(n, c_int), c(1), c_loc(ys), c(2), c_loc(zs), c_loc(zs))
        call tc%check_true(all([(same(2 + i), i=1, n)]), label('N_VLinearSumVectorArray', set, c(1), c(2)))
      end do
    end do
  end subroutine test_fused

  !> The N_Vector* array of the vectors idx of one family.
  subroutine fill(ptrs, family, idx)
    type(c_ptr), intent(out) :: ptrs(:)
    type(vec_ref), intent(in) :: family(:)
    integer, intent(in) :: idx(:)
    integer :: i
    ptrs = c_null_ptr
    do i = 1, size(idx)
      ptrs(i) = c_loc(family(idx(i))%p)
    end do
  end subroutine fill

  !> A clone has the specialised table (CVODE's work vectors are clones);
  !> a length-3 serial vector is refused and keeps its own table.
  subroutine test_clone_and_refusal()
    type(N_Vector), pointer :: clone, three
    type(N_Vector_Ops), pointer :: ops_pair, ops_clone, ops_three, ops_plain
    logical :: accepted
    clone => FN_VClone(pair(1)%p)
    call c_f_pointer(pair(1)%p%ops, ops_pair)
    call c_f_pointer(clone%ops, ops_clone)
    call c_f_pointer(plain(1)%p%ops, ops_plain)
    call tc%check_true(c_associated(ops_clone%nvlinearsum, ops_pair%nvlinearsum) .and. &
                       c_associated(ops_clone%nvlinearcombination, ops_pair%nvlinearcombination) .and. &
                       .not. c_associated(ops_clone%nvlinearsum, ops_plain%nvlinearsum), 'a clone inherits the kernels')
    call FN_VDestroy(clone)
    three => FN_VNew_Serial(3_c_int64_t, ctx)
    call specialise_pair_ops(three, accepted)
    call tc%check_true(.not. accepted, 'specialise_pair_ops refuses a vector of length 3')
    call c_f_pointer(three%ops, ops_three)
    call tc%check_true(c_associated(ops_three%nvlinearsum, ops_plain%nvlinearsum) .and. &
                       .not. c_associated(ops_three%nvlinearcombination), 'a refused vector keeps the serial table')
    call FN_VDestroy(three)
  end subroutine test_clone_and_refusal

end program test_cvode_vector
