!> K(m) in double-double for a block of points at once: pendula_elliptic_ke's compensated
!> AGM (k_double_double) stepped for every point of the block side by side, behind
!> k_double_double_block (pendula_elliptic_k_block), which the Jacobi array loops call
!> for their long arguments (beyond a few half periods they need K to ~1e-31).
!>
!> Why a file of its own, compiled several times: the AGM of one point is a chain of
!> dependent square roots; the block's points side by side fill the pipeline and
!> vectorise, so the speed is set by the vector width (it was ~30 % of the time of
!> undamped_states over distinct states at one time each in 0..100 s).  meson compiles
!> this file once per target (baseline x86-64 = SSE2, x86-64-v3 = AVX2, x86-64-v4 =
!> AVX-512; elsewhere only the portable build), each with its own module and entry name
!> given by the preprocessor (PENDULA_KDD_MODULE, PENDULA_KDD_ENTRY), and
!> pendula_kernel_path.c picks one at load time, as for the K and E block kernel
!> (pendula_elliptic_ke_lanes.F90).  The module uses no pendula module, so each variant is
!> a leaf of the build: pi/2 in double-double comes from the caller (pendula_constants).
!>
!> Bit-identity: pendula compiles everything with -ffp-contract=off and without
!> -ffast-math, and the AGM uses only +, -, *, / and sqrt (correctly rounded in every
!> instruction set), so every variant returns the same bits, those of the scalar
!> k_double_double (tests/fortran/test_elliptic.f90 compares them; test_kernel_paths.py
!> runs it on every path the machine has).
! meson defines the names per variant; a build that compiles the file once (fpm) gets the
! portable one, which pendula_kernel_path.c always has.
#ifndef PENDULA_KDD_MODULE
#define PENDULA_KDD_MODULE pendula_elliptic_k_lanes_baseline_m
#define PENDULA_KDD_ENTRY pendula_k_dd_block_baseline
#endif
module PENDULA_KDD_MODULE
  use, intrinsic :: iso_c_binding, only: c_int, c_double
  use, intrinsic :: iso_fortran_env, only: wp => real64
  implicit none
  private
  public :: PENDULA_KDD_ENTRY

contains

  !> K in double-double for nb points, mc = mch + mcl > 0 each: the compensated AGM of
  !> pendula_elliptic_ke's k_double_double, operation for operation (the same bits), with
  !> its steps taken for the whole block in turn, a point that has converged (t <= 2**-27)
  !> keeping its values by merge.  A point that needs no K passes mch = 1 (no step).
  pure subroutine PENDULA_KDD_ENTRY(nb, mch, mcl, hp, hp_lo, khi, klo) bind(C)
    integer(c_int), intent(in) :: nb  !< points, >= 0 (a few dozen: the work arrays live on the stack)
    real(c_double), intent(in) :: mch(nb)  !< 1 - m, high part, > 0 (1: no K wanted)
    real(c_double), intent(in) :: mcl(nb)  !< 1 - m, low part
    real(c_double), intent(in) :: hp  !< pi/2, high part
    real(c_double), intent(in) :: hp_lo  !< pi/2, low part
    real(c_double), intent(out) :: khi(nb)  !< K, high part
    real(c_double), intent(out) :: klo(nb)  !< K, low part
    real(wp), parameter :: tiny_mc = 2.0_wp**(-900), up = 2.0_wp**1000, down = 2.0_wp**(-500)
    real(wp), dimension(nb) :: ah, al, bh, bl, ah2, al2, bh2, bl2
    real(wp) :: x, xl, s, se, p, t, corr, nah, nal
    integer :: i, j, nlive
    do j = 1, nb
      ! b = sqrt(mc) with its residual; tiny mc is scaled so that the residual stays exact
      x = merge(mch(j)*up, mch(j), mch(j) < tiny_mc)
      xl = merge(mcl(j)*up, mcl(j), mch(j) < tiny_mc)
      bh(j) = sqrt(x)
      bl(j) = ((x - bh(j)*bh(j)) - sq_err(bh(j)) + xl)/(2*bh(j))
      bh(j) = merge(bh(j)*down, bh(j), mch(j) < tiny_mc)
      bl(j) = merge(bl(j)*down, bl(j), mch(j) < tiny_mc)
      ah(j) = 1; al(j) = 0
    end do
    ! steps in pairs, (ah, al, bh, bl) -> the second set -> back; a step where no point
    ! moved leaves both sets equal (up to 80 steps, as k_double_double)
    do i = 1, 40
      call agm_steps(int(nb), ah, al, bh, bl, ah2, al2, bh2, bl2, nlive)
      if (nlive == 0) exit
      call agm_steps(int(nb), ah2, al2, bh2, bl2, ah, al, bh, bl, nlive)
      if (nlive == 0) exit
    end do
    do j = 1, nb
      ! A = (a + b)/2 and the series in t (a - b is exact: a and b agree to 26 bits)
      s = ah(j) + bh(j)
      se = (ah(j) - (s - (s - ah(j)))) + (bh(j) - (s - ah(j)))
      t = ((ah(j) - bh(j)) + (al(j) - bl(j)))/s
      t = t*t
      corr = t*(0.25_wp + t*(5.0_wp/64))
      nah = 0.5_wp*s
      nal = 0.5_wp*((se + al(j)) + bl(j)) - nah*corr
      ! M = ah + al normalised, then K = (pi/2)/M with one correction of the quotient
      s = nah + nal
      nal = nal - (s - nah)
      nah = s
      x = hp/nah
      p = x*nah
      xl = (((hp - p) - prod_err(x, nah, p)) + (hp_lo - x*nal))/nah
      s = x + xl
      klo(j) = xl - (s - x)
      khi(j) = s
    end do
  end subroutine PENDULA_KDD_ENTRY

  !> One step of the block's compensated AGM, from (ah, al, bh, bl) into (ah2, al2, bh2,
  !> bl2), at each of nb points where t > 2**-27 still (the others copy their values);
  !> nlive counts the points stepped.  A real flag and separate outputs: the forms in
  !> which gcc vectorises the loop.
  pure subroutine agm_steps(nb, ah, al, bh, bl, ah2, al2, bh2, bl2, nlive)
    integer, intent(in) :: nb
    real(wp), intent(in) :: ah(nb), al(nb), bh(nb), bl(nb)
    real(wp), intent(out) :: ah2(nb), al2(nb), bh2(nb), bl2(nb)
    integer, intent(out) :: nlive
    real(wp) :: x, s, se, p, nah, nal, nbh, nbl, a, alo, b, blo, live
    integer :: j
    nlive = 0
    do j = 1, nb
      a = ah(j); alo = al(j); b = bh(j); blo = bl(j)
      live = merge(1.0_wp, 0.0_wp, abs(a - b) > 2.0_wp**(-26)*a)
      s = a + b
      se = (a - (s - (s - a))) + (b - (s - a))
      p = a*b
      x = (prod_err(a, b, p) + a*blo) + alo*b
      nah = 0.5_wp*s
      nal = 0.5_wp*((se + alo) + blo)
      nbh = sqrt(p)
      nbl = (((p - nbh*nbh) - sq_err(nbh)) + x)/(2*nbh)
      ah2(j) = merge(nah, a, live > 0); al2(j) = merge(nal, alo, live > 0)
      bh2(j) = merge(nbh, b, live > 0); bl2(j) = merge(nbl, blo, live > 0)
      nlive = nlive + merge(1, 0, live > 0)
    end do
  end subroutine agm_steps

  !> Exact error a*b - p of p = fl(a*b) (Dekker, as pendula_elliptic_ke's; no range scaling:
  !> the AGM's operands lie in (0, 2]).
  pure elemental real(wp) function prod_err(a, b, p) result(e)
    real(wp), intent(in) :: a, b, p
    real(wp), parameter :: split = 134217729.0_wp   ! 2**27 + 1 (Veltkamp)
    real(wp) :: ah, al, bh, bl
    ah = split*a; ah = ah - (ah - a); al = a - ah
    bh = split*b; bh = bh - (bh - b); bl = b - bh
    e = ((ah*bh - p) + ah*bl + al*bh) + al*bl
  end function prod_err

  !> Exact error s*s - fl(s*s) of a square.
  pure elemental real(wp) function sq_err(s) result(e)
    real(wp), intent(in) :: s
    e = prod_err(s, s, s*s)
  end function sq_err

end module PENDULA_KDD_MODULE
