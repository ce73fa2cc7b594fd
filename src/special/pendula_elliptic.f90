!> Complete and incomplete elliptic integrals of the first and second kind and
!> the Jacobi elliptic functions, for every real parameter m = k**2.
!>
!> Conventions follow DLMF ch. 19 and 22 (and scipy.special): parameter m = k**2,
!> F(phi|m) = int_0^phi dt / sqrt(1 - m sin^2 t), K(m) = F(pi/2|m), E(m) likewise.
!> Every function has a complement form taking mc = 1 - m directly (suffix c),
!> because near the separatrix (m -> 1) forming 1 - m loses every digit.
!>
!> Domain errors in the elemental functions give a quiet NaN (never stop/print):
!> K, E need m <= 1 (mc >= 0); F needs m sin^2(phi) <= 1; NaN in gives NaN out.
!>
!> Algorithms (own implementations from the papers):
!>  * K, E: degree-12 polynomials (Chebyshev interpolants at 40 digits) on 17 intervals
!>    of m in [0, 0.85) and, for mc <= 0.15, the logarithmic form K = P(mc) - ln(mc) Q(mc),
!>    E = Pe(mc) - ln(mc) mc Qe1(mc) (structure of DLMF 19.12.1), exact as mc -> 0 down
!>    to the smallest subnormal.  m < 0 by the imaginary-modulus transformation
!>    (DLMF 19.7.5).  Measured <= 2.4 ulps.  K in double-double (for the period
!>    reductions) by the AGM in double-double arithmetic (DLMF 19.8.5).
!>  * F: Carlson's R_F by duplication (DLMF 19.36.1, Carlson 1995), any real phi by
!>    F(phi + n pi) = F(phi) + 2 n K with n*pi subtracted in double-double.
!>  * sn, cn, dn: Maclaurin series at u/2^N followed by N duplications, first on the
!>    complements 1 - cn, 1 - dn and then on cn, dn written without cancellation
!>    (cn(2u) = (cn^2 dn^2 - mc sn^2)/D, dn(2u) = (mc + m cn^4)/D,
!>    D = cn^2 + sn^2 dn^2), after the idea of Fukushima's conditional duplication
!>    (Numer. Math. 2012); the complement steps run on fractions without division.
!>    u is reduced modulo 2K with K and 1 - m in double-double and [K/2, K] is mapped
!>    to [0, K/2] by u -> K - u (DLMF 22.4.3), which keeps cn and dn relatively
!>    accurate when mc is tiny.  m < 0 by DLMF 22.6.12 (imaginary modulus), m > 1 by
!>    DLMF 22.6.11 (reciprocal modulus).  am = 2 atan(sn/(1 + cn)) by a polynomial.
!>  * Plans (one m, many u): Taylor polynomials of degree 8 of sn, cn, dn, am about a
!>    1/32 grid of [0, K] from the ODEs (DLMF 22.13): a table look-up and four short
!>    polynomials per point, no division.
!>
!> Measured against mpmath at the exact double inputs (tests/python/test_elliptic.py):
!> sn, cn, dn, am within 3.1 eps times the condition number in every region
!> (m < 0 to -1e10, 1 - m down to 5e-324, m > 1, |u| to 1e6); K, E within 2.4 ulps,
!> F within 3.4 ulps.
module pendula_elliptic
  use, intrinsic :: ieee_arithmetic, only: ieee_value, ieee_quiet_nan, ieee_positive_inf, &
      ieee_is_nan, ieee_is_finite
  use pendula_kinds, only: wp
  use pendula_status, only: status_t, set_error, PENDULA_ERR_SIZE
  implicit none
  private

  public :: ellipk, ellipkc, ellipe, ellipec, ellipf, ellipfc, ellipk_array, ellipe_array
  public :: ellipj, ellipjc, ellipj_array, ellipjc_array
  public :: ellipj_plan_t, ellipj_plan, ellipj_planc, ellipj_eval, ellipj_eval_array

  real(wp), parameter :: pi = 3.141592653589793115997963468544185_wp
  real(wp), parameter :: pi_lo = 1.2246467991473532e-16_wp      ! pi - pi(double)
  real(wp), parameter :: pi_lo2 = -2.9947698097183397e-33_wp   ! pi - pi(double) - pi_lo
  real(wp), parameter :: half_pi = 0.5_wp * pi, half_pi_lo = 0.5_wp * pi_lo
  real(wp), parameter :: eps = epsilon(1.0_wp)
  !> Largest argument fed to the Maclaurin series (truncation < eps/8 for every m in [0,1]).
  real(wp), parameter :: wmax = 0.1_wp
  !> Switch from complement (1-cn, 1-dn) to direct duplication once 1 - cn exceeds this.
  real(wp), parameter :: xswitch = 0.25_wp
  !> Tabulated plans: Taylor polynomials of degree ntay about a grid of step 1/32 in the core
  !> argument; |delta| <= 1/64 and the nearest singularity is >= K' >= pi/2 away, so the
  !> truncation is below ~ (1/64 / (pi/2))**9 ~ 1e-18 relative.
  integer, parameter :: ntay = 8
  real(wp), parameter :: tab_step = 0.03125_wp, tab_inv_step = 32.0_wp
  !> Largest core K a plan tabulates (the core K is at most 374, at mc = 5e-324).
  real(wp), parameter :: khi_tab_max = 400.0_wp

  ! Maclaurin coefficients, js(j,k): coefficient of m^j w^(2k+1) in sn;
  ! jc(j,k): of m^j w^(2k+2) in 1 - cn; jd(j,k): of m^(j+1) w^(2k+2) in 1 - dn.
  ! Generated exactly by tests/python/gen_elliptic_coeffs.py.
  real(wp), parameter :: js(0:6, 0:6) = reshape([ &
      1.00000000000000000e+00_wp, 0.00000000000000000e+00_wp, 0.00000000000000000e+00_wp, &
      0.00000000000000000e+00_wp, 0.00000000000000000e+00_wp, 0.00000000000000000e+00_wp, &
      0.00000000000000000e+00_wp, -1.66666666666666657e-01_wp, -1.66666666666666657e-01_wp, &
      0.00000000000000000e+00_wp, 0.00000000000000000e+00_wp, 0.00000000000000000e+00_wp, &
      0.00000000000000000e+00_wp, 0.00000000000000000e+00_wp, 8.33333333333333322e-03_wp, &
      1.16666666666666669e-01_wp, 8.33333333333333322e-03_wp, 0.00000000000000000e+00_wp, &
      0.00000000000000000e+00_wp, 0.00000000000000000e+00_wp, 0.00000000000000000e+00_wp, &
      -1.98412698412698413e-04_wp, -2.67857142857142842e-02_wp, -2.67857142857142842e-02_wp, &
      -1.98412698412698413e-04_wp, 0.00000000000000000e+00_wp, 0.00000000000000000e+00_wp, &
      0.00000000000000000e+00_wp, 2.75573192239858925e-06_wp, 3.38403880070546744e-03_wp, &
      1.50958994708994716e-02_wp, 3.38403880070546744e-03_wp, 2.75573192239858925e-06_wp, &
      0.00000000000000000e+00_wp, 0.00000000000000000e+00_wp, -2.50521083854417202e-08_wp, &
      -2.77301787718454409e-04_wp, -4.15429092512425817e-03_wp, -4.15429092512425817e-03_wp, &
      -2.77301787718454409e-04_wp, -2.50521083854417202e-08_wp, 0.00000000000000000e+00_wp, &
      1.60590438368216133e-10_wp, 1.60015524598857930e-05_wp, 7.21749797270630636e-04_wp, &
      2.11662501593057155e-03_wp, 7.21749797270630636e-04_wp, 1.60015524598857930e-05_wp, &
      1.60590438368216133e-10_wp], [7, 7])
  real(wp), parameter :: jc(0:6, 0:6) = reshape([ &
      5.00000000000000000e-01_wp, 0.00000000000000000e+00_wp, 0.00000000000000000e+00_wp, &
      0.00000000000000000e+00_wp, 0.00000000000000000e+00_wp, 0.00000000000000000e+00_wp, &
      0.00000000000000000e+00_wp, -4.16666666666666644e-02_wp, -1.66666666666666657e-01_wp, &
      0.00000000000000000e+00_wp, 0.00000000000000000e+00_wp, 0.00000000000000000e+00_wp, &
      0.00000000000000000e+00_wp, 0.00000000000000000e+00_wp, 1.38888888888888894e-03_wp, &
      6.11111111111111091e-02_wp, 2.22222222222222231e-02_wp, 0.00000000000000000e+00_wp, &
      0.00000000000000000e+00_wp, 0.00000000000000000e+00_wp, 0.00000000000000000e+00_wp, &
      -2.48015873015873016e-05_wp, -1.01190476190476195e-02_wp, -2.26190476190476185e-02_wp, &
      -1.58730158730158730e-03_wp, 0.00000000000000000e+00_wp, 0.00000000000000000e+00_wp, &
      0.00000000000000000e+00_wp, 2.75573192239858883e-07_wp, 1.01631393298059970e-03_wp, &
      8.47883597883597809e-03_wp, 4.35626102292768942e-03_wp, 7.05467372134038740e-05_wp, &
      0.00000000000000000e+00_wp, 0.00000000000000000e+00_wp, -2.08767569878681002e-09_wp, &
      -6.93358853081075301e-05_wp, -1.81761397039174812e-03_wp, -3.21201432312543441e-03_wp, &
      -5.41392763614985829e-04_wp, -2.13777991555769346e-06_wp, 0.00000000000000000e+00_wp, &
      1.14707455977297245e-11_wp, 3.42897292302054208e-06_wp, 2.63196900101662034e-04_wp, &
      1.22648662331202021e-03_wp, 7.45700507605269523e-04_wp, 4.79590955781431980e-05_wp, &
      4.69841739683009516e-08_wp], [7, 7])
  real(wp), parameter :: jd(0:6, 0:6) = reshape([ &
      5.00000000000000000e-01_wp, 0.00000000000000000e+00_wp, 0.00000000000000000e+00_wp, &
      0.00000000000000000e+00_wp, 0.00000000000000000e+00_wp, 0.00000000000000000e+00_wp, &
      0.00000000000000000e+00_wp, -1.66666666666666657e-01_wp, -4.16666666666666644e-02_wp, &
      0.00000000000000000e+00_wp, 0.00000000000000000e+00_wp, 0.00000000000000000e+00_wp, &
      0.00000000000000000e+00_wp, 0.00000000000000000e+00_wp, 2.22222222222222231e-02_wp, &
      6.11111111111111091e-02_wp, 1.38888888888888894e-03_wp, 0.00000000000000000e+00_wp, &
      0.00000000000000000e+00_wp, 0.00000000000000000e+00_wp, 0.00000000000000000e+00_wp, &
      -1.58730158730158730e-03_wp, -2.26190476190476185e-02_wp, -1.01190476190476195e-02_wp, &
      -2.48015873015873016e-05_wp, 0.00000000000000000e+00_wp, 0.00000000000000000e+00_wp, &
      0.00000000000000000e+00_wp, 7.05467372134038740e-05_wp, 4.35626102292768942e-03_wp, &
      8.47883597883597809e-03_wp, 1.01631393298059970e-03_wp, 2.75573192239858883e-07_wp, &
      0.00000000000000000e+00_wp, 0.00000000000000000e+00_wp, -2.13777991555769346e-06_wp, &
      -5.41392763614985829e-04_wp, -3.21201432312543441e-03_wp, -1.81761397039174812e-03_wp, &
      -6.93358853081075301e-05_wp, -2.08767569878681002e-09_wp, 0.00000000000000000e+00_wp, &
      4.69841739683009516e-08_wp, 4.79590955781431980e-05_wp, 7.45700507605269523e-04_wp, &
      1.22648662331202021e-03_wp, 2.63196900101662034e-04_wp, 3.42897292302054208e-06_wp, &
      1.14707455977297245e-11_wp], [7, 7])

  ! K and E: piecewise polynomials in y = m - (i + 1/2)/20 on [i/20, (i+1)/20), i = 0..16,
  ! and for mc <= 0.15 the logarithmic form K = P(mc) - ln(mc) Q(mc),
  ! E = Pe(mc) - ln(mc) mc Qe1(mc) in powers of mc (columns P, Q, Pe, Qe1 of kepoly1).
  ! Chebyshev interpolants of degree 12 at 40 digits, made by
  ! tests/python/gen_elliptic_coeffs.py --ke; truncation < 0.1 ulp.
  real(wp), parameter :: kpoly(0:12, 0:16) = reshape([ &
      1.58075430577932385e+00_wp, 4.04038895713874746e-01_wp, 2.32853856751793487e-01_wp, &
      1.65763143243780831e-01_wp, 1.30125572527805655e-01_wp, 1.08081645771623325e-01_wp, &
      9.31333423752087053e-02_wp, 8.23535779159631220e-02_wp, 7.42305237077258429e-02_wp, &
      6.79047122956733945e-02_wp, 6.28517992698109929e-02_wp, 5.88402247712737705e-02_wp, &
      5.54236677939679220e-02_wp, 1.60155995418273100e+00_wp, 4.28636129422623913e-01_wp, &
      2.59814620082540082e-01_wp, 1.94742541550192244e-01_wp, 1.61034153341627406e-01_wp, &
      1.40923710662130747e-01_wp, 1.27958079806564623e-01_wp, 1.19236381168391956e-01_wp, &
      1.13264761645175516e-01_wp, 1.09197713840972738e-01_wp, 1.06523162486596323e-01_wp, &
      1.05125797510438726e-01_wp, 1.04365975665784788e-01_wp, 1.62366669262102725e+00_wp, &
      4.56163335146506477e-01_wp, 2.91630499636008955e-01_wp, 2.30820579309124252e-01_wp, &
      2.01639399915022610e-01_wp, 1.86459107454377160e-01_wp, 1.78922539736111941e-01_wp, &
      1.76213208861540238e-01_wp, 1.76921123873487907e-01_wp, 1.80289062281446311e-01_wp, &
      1.85901344996051265e-01_wp, 1.93973325689529907e-01_wp, 2.03559239830868682e-01_wp, &
      1.64723410965519035e+00_wp, 4.87164541928064410e-01_wp, 3.29529264625301188e-01_wp, &
      2.76299141486132105e-01_wp, 2.55819870830741480e-01_wp, 2.50783662879744296e-01_wp, &
      2.55149867249780116e-01_wp, 2.66452098146653937e-01_wp, 2.83683682944951054e-01_wp, &
      3.06559084084430777e-01_wp, 3.35219694806786206e-01_wp, 3.71041327157025425e-01_wp, &
      4.12943285245900904e-01_wp, 1.67245237875652708e+00_wp, 5.22325968313588684e-01_wp, &
      3.75150715746689623e-01_wp, 3.34434269116231753e-01_wp, 3.29387020927819907e-01_wp, &
      3.43573910396739346e-01_wp, 3.71984880445575872e-01_wp, 4.13423473115500262e-01_wp, &
      4.68468880940952737e-01_wp, 5.38824767101441338e-01_wp, 6.27136806492021748e-01_wp, &
      7.39111941662619176e-01_wp, 8.75579458055204207e-01_wp, 1.69955053043560844e+00_wp, &
      5.62525472922093206e-01_wp, 4.30723936787360984e-01_wp, 4.09930389013550667e-01_wp, &
      4.31267096934639993e-01_wp, 4.80633020059062555e-01_wp, 5.56077281046085559e-01_wp, &
      6.60480300491271488e-01_wp, 7.99881285464649316e-01_wp, 9.83307502784933951e-01_wp, &
      1.22324651333878687e+00_wp, 1.54155580341239284e+00_wp, 1.95196983079809994e+00_wp, &
      1.72880771007748391e+00_wp, 6.08904118104327874e-01_wp, 4.99340139448105458e-01_wp, &
      5.09749721183202387e-01_wp, 5.75560968593949451e-01_wp, 6.88613711764127778e-01_wp, &
      8.55421027324469785e-01_wp, 1.09100636235712023e+00_wp, 1.41886686348715108e+00_wp, &
      1.87314542649868621e+00_wp, 2.50250849001975872e+00_wp, 3.38866832907088211e+00_wp, &
      4.60831222433467591e+00_wp, 1.76056881177195446e+00_wp, 6.62972287443292174e-01_wp, &
      5.85384812975286661e-01_wp, 6.44482015126841667e-01_wp, 7.85269527843608484e-01_wp, &
      1.01414966910306936e+00_wp, 1.36010986764910125e+00_wp, 1.87296901914341318e+00_wp, &
      2.63015403798572089e+00_wp, 3.74942711323233846e+00_wp, 5.40924788003747548e+00_wp, &
      7.91484119741429115e+00_wp, 1.16236796910679239e+01_wp, 1.79526669611037581e+00_wp, &
      7.26771483728822942e-01_wp, 6.95244913490067673e-01_wp, 8.30751161327066834e-01_wp, &
      1.09932366292289352e+00_wp, 1.54236827318969638e+00_wp, 2.24755984990841995e+00_wp, &
      3.36327535114710630e+00_wp, 5.13257805774680875e+00_wp, 7.95169469352918146e+00_wp, &
      1.24677156764617134e+01_wp, 1.98429589086713207e+01_wp, 3.16727081536090402e+01_wp, &
      1.83345461720171254e+00_wp, 8.03129086801636416e-01_wp, 8.38510676612223338e-01_wp, &
      1.09563128486632544e+00_wp, 1.58651884733051229e+00_wp, 2.43654499481865594e+00_wp, &
      3.88722812560172803e+00_wp, 6.36911101604642660e+00_wp, 1.06431127109143180e+01_wp, &
      1.80562402055321805e+01_wp, 3.10030881678485457e+01_wp, 5.40927422326562208e+01_wp, &
      9.45566666537396543e+01_wp, 1.87585504547517590e+00_wp, 8.96074849265164231e-01_wp, &
      1.03011028337253574e+00_wp, 1.48517324479273816e+00_wp, 2.37477601712117314e+00_wp, &
      4.02871038838626383e+00_wp, 7.10109972682330515e+00_wp, 1.28559945173105845e+01_wp, &
      2.37392523518656127e+01_wp, 4.45055885574849768e+01_wp, 8.44497850452181069e+01_wp, &
      1.63062745591044830e+02_wp, 3.15021865488850040e+02_wp, 1.92343593364636001e+00_wp, &
      1.01155284869382345e+00_wp, 1.29430569967399189e+00_wp, 2.08189417177529812e+00_wp, &
      3.71695405110288668e+00_wp, 7.04325183130661436e+00_wp, 1.38694648114247840e+01_wp, &
      2.80553885093972291e+01_wp, 5.78876162856587655e+01_wp, 1.21271035976848353e+02_wp, &
      2.57149171206428548e+02_wp, 5.55941111942961243e+02_wp, 1.20029696156189470e+03_wp, &
      1.97753525023561139e+00_wp, 1.15870568752577907e+00_wp, 1.67266183347274189e+00_wp, &
      3.04337751495530995e+00_wp, 6.15172830857053121e+00_wp, 1.32028347276176596e+01_wp, &
      2.94528306176016272e+01_wp, 6.75008308963199113e+01_wp, 1.57810852025620477e+02_wp, &
      3.74609689164109682e+02_wp, 9.00124596724053504e+02_wp, 2.21127727491948099e+03_wp, &
      5.41045608613945114e+03_wp, 2.04007570550447737e+00_wp, 1.35234940024789863e+00_wp, &
      2.24123354179574719e+00_wp, 4.69554652161274788e+00_wp, 1.09396699636492958e+01_wp, &
      2.70729565003358239e+01_wp, 6.96549570443080199e+01_wp, 1.84138908135312192e+02_wp, &
      4.96614174206537712e+02_wp, 1.35991223392965730e+03_wp, 3.76980304399587931e+03_wp, &
      1.07285727672158828e+04_wp, 3.02872904044447969e+04_wp, 2.11396129062346061e+00_wp, &
      1.61815963046188993e+00_wp, 3.15150384041057263e+00_wp, 7.78563517766854751e+00_wp, &
      2.14122137814627891e+01_wp, 6.25810582630272805e+01_wp, 1.90200080885136430e+02_wp, &
      5.94037571503421077e+02_wp, 1.89292332866542574e+03_wp, 6.12424055554659935e+03_wp, &
      2.00606392614753531e+04_wp, 6.79092149621340068e+04_wp, 2.26563792370638053e+05_wp, &
      2.20387814328396114e+00_wp, 2.00480010454742397e+00_wp, 4.74153288407762563e+00_wp, &
      1.42816464327792456e+01_wp, 4.79468245486594284e+01_wp, 1.71149023905568981e+02_wp, &
      6.35454674675949946e+02_wp, 2.42489245760662288e+03_wp, 9.44177112098183716e+03_wp, &
      3.73191620850117979e+04_wp, 1.49384336911351362e+05_wp, 6.25185190487240674e+05_wp, &
      2.54940868046983425e+06_wp, 2.31812262171251060e+00_wp, 2.61692015029118030e+00_wp, &
      7.89793507573107778e+00_wp, 3.05023971568490708e+01_wp, 1.31486936565004243e+02_wp, &
      6.02984733290128361e+02_wp, 2.87702445613246391e+03_wp, 1.41106864421028149e+04_wp, &
      7.06223251582986559e+04_wp, 3.58535623692539288e+05_wp, 1.84489315516957128e+06_wp, &
      1.01593439104575440e+07_wp, 5.32747136714732945e+07_wp], [13, 17])
  real(wp), parameter :: epoly(0:12, 0:16) = reshape([ &
      1.56093234430089201e+00_wp, -3.96439229568634033e-01_wp, -7.59966614524074102e-02_wp, &
      -3.24258159638082591e-02_wp, -1.81703171236977101e-02_wp, -1.17334106476865759e-02_wp, &
      -8.26983314149262391e-03_wp, -6.18622234062924953e-03_wp, -4.83171868202055248e-03_wp, &
      -3.89942666571040011e-03_wp, -3.22897120122667483e-03_wp, -2.73392959860655101e-03_wp, &
      -2.35110816653906788e-03_wp, 1.54091622057641531e+00_wp, -4.04291557375438371e-01_wp, &
      -8.11485734906183531e-02_wp, -3.63753324681889076e-02_wp, -2.14431320154128517e-02_wp, &
      -1.45763056449828461e-02_wp, -1.08188442858803639e-02_wp, -8.52456444219493181e-03_wp, &
      -7.01420282524297615e-03_wp, -5.96423033402289707e-03_wp, -5.20390048381188380e-03_wp, &
      -4.64367785619397132e-03_wp, -4.20828981316552584e-03_wp, 1.52049408560669730e+00_wp, &
      -4.12690428057320480e-01_wp, -8.69458141783720495e-02_wp, -4.10574094678570617e-02_wp, &
      -2.55335319698389573e-02_wp, -1.83237409009191013e-02_wp, -1.43636262307466588e-02_wp, &
      -1.19558006890199651e-02_wp, -1.03938999218205364e-02_wp, -9.33893244341154824e-03_wp, &
      -8.61092741968493870e-03_wp, -8.12220096151951287e-03_wp, -7.77936958439189464e-03_wp, &
      1.49963690194726063e+00_wp, -4.21706307736942010e-01_wp, -9.35117631301748548e-02_wp, &
      -4.66609287950253415e-02_wp, -3.07103553650038483e-02_wp, -2.33413618718352339e-02_wp, &
      -1.93863838253613106e-02_wp, -1.71018959972382700e-02_wp, -1.57598035902796751e-02_wp, &
      -1.50116038640700170e-02_wp, -1.46748711737940841e-02_wp, -1.46798719046681604e-02_wp, &
      -1.49086567307630917e-02_wp, 1.47831177498567268e+00_wp, -4.31423563935232346e-01_wp, &
      -1.01002671531507077e-01_wp, -5.34390378904951030e-02_wp, -3.73550442576423419e-02_wp, &
      -3.01785382774735836e-02_wp, -2.66544688516844146e-02_wp, -2.50113406788208918e-02_wp, &
      -2.45211233331914212e-02_wp, -2.48523014638029824e-02_wp, -2.58524800369258137e-02_wp, &
      -2.75289517660673513e-02_wp, -2.97541593511984094e-02_wp, 1.45648116689350071e+00_wp, &
      -4.41944297349286697e-01_wp, -1.09619250520733194e-01_wp, -6.17370819546432664e-02_wp, &
      -4.60204451092428718e-02_wp, -3.96814476981520378e-02_wp, -3.74242396290491025e-02_wp, &
      -3.75092585178403506e-02_wp, -3.92863497883689725e-02_wp, -4.25425182729481169e-02_wp, &
      -4.72883490500929093e-02_wp, -5.38288888380629438e-02_wp, -6.21762782744360934e-02_wp, &
      1.43410188612057543e+00_wp, -4.53393575318320696e-01_wp, -1.19623494450774734e-01_wp, &
      -7.20357210747595983e-02_wp, -5.75273522343862920e-02_wp, -5.31906162932875501e-02_wp, &
      -5.38200423397341074e-02_wp, -5.78902334185811135e-02_wp, -6.50833319565688045e-02_wp, &
      -7.56607319849835758e-02_wp, -9.02947813366106605e-02_wp, -1.10407608522362061e-01_wp, &
      -1.36939371952042671e-01_wp, 1.41112376709651466e+00_wp, -4.65926726233919675e-01_wp, &
      -1.31363707472915009e-01_wp, -8.50194180251296200e-02_wp, -7.31283083337311429e-02_wp, &
      -7.28990318686168620e-02_wp, -7.95685293970364999e-02_wp, -9.23535325035651639e-02_wp, &
      -1.12062181979900324e-01_wp, -1.40624687026318140e-01_wp, -1.81175442806924825e-01_wp, &
      -2.39299776608431408e-01_wp, -3.20464208458678346e-01_wp, 1.38748791293592832e+00_wp, &
      -4.79739744911114763e-01_wp, -1.45312787539828320e-01_wp, -1.01688843478659863e-01_wp, &
      -9.47961599805197674e-02_wp, -1.02529539543225093e-01_wp, -1.21490670059617167e-01_wp, &
      -1.53136551843100183e-01_wp, -2.01838259307589890e-01_wp, -2.75162054547672064e-01_wp, &
      -3.85172290571559106e-01_wp, -5.53160871537694221e-01_wp, -8.04977422965665657e-01_wp, &
      1.36312430607321522e+00_wp, -4.95084538029997245e-01_wp, -1.62128709879810096e-01_wp, &
      -1.23552472622032672e-01_wp, -1.25754979409516077e-01_wp, -1.48680840307803402e-01_wp, &
      -1.92704812642001067e-01_wp, -2.65785744455027451e-01_wp, -3.83407406967217035e-01_wp, &
      -5.72158280516752216e-01_wp, -8.76803132772014271e-01_wp, -1.37984877211207291e+00_wp, &
      -2.19864106015055993e+00_wp, 1.33794847767170921e+00_wp, -5.12291969336635011e-01_wp, &
      -1.82753752346918652e-01_wp, -1.52967944867231809e-01_wp, -1.71507981061089360e-01_wp, &
      -2.23660980892720629e-01_wp, -3.19962152443171999e-01_wp, -4.87281102301406643e-01_wp, &
      -7.76350002614385359e-01_wp, -1.27976974499144736e+00_wp, -2.16664733445601421e+00_wp, &
      -3.77163368623004169e+00_wp, -6.64049143515985829e+00_wp, 1.31185672659880903e+00_wp, &
      -5.31808006128305033e-01_wp, -2.08584714158921047e-01_wp, -1.93783060057168138e-01_wp, &
      -2.41951928584660997e-01_wp, -3.51876617562083438e-01_wp, -5.61791633828711556e-01_wp, &
      -9.55249323799283734e-01_wp, -1.69968984777064636e+00_wp, -3.12961578625868864e+00_wp, &
      -5.91902722371519108e+00_wp, -1.15299409327483726e+01_wp, -2.26822611898527811e+01_wp, &
      1.28471900986606324e+00_wp, -5.54252992295638625e-01_wp, -2.41781078092056206e-01_wp, &
      -2.52618293119087955e-01_wp, -3.56057209871957103e-01_wp, -5.85492454292482756e-01_wp, &
      -1.05778701864668312e+00_wp, -2.03624851189485634e+00_wp, -4.10295966831643355e+00_wp, &
      -8.55669322189360848e+00_wp, -1.83321785042885104e+01_wp, -4.05482249281622842e+01_wp, &
      -9.03809991827313581e+01_wp, 1.25636790364772066e+00_wp, -5.80524297671671685e-01_wp, &
      -2.85861149102306256e-01_wp, -3.41641998639226563e-01_wp, -5.53210468225198593e-01_wp, &
      -1.04699210151587541e+00_wp, -2.17901575212930787e+00_wp, -4.83447515677445505e+00_wp, &
      -1.12306211334016481e+01_wp, -2.70068062813099203e+01_wp, -6.67286789999309775e+01_wp, &
      -1.70817549568528364e+02_wp, -4.39221736281851406e+02_wp, 1.22658050756813020e+00_wp, &
      -6.11986746934710668e-01_wp, -3.46956166733510152e-01_wp, -4.85203526485139980e-01_wp, &
      -9.24071990558289702e-01_wp, -2.06120135735010734e+00_wp, -5.06094782709296087e+00_wp, &
      -1.32541583046441378e+01_wp, -3.63563200503708117e+01_wp, -1.03249051299467965e+02_wp, &
      -3.01335449095107606e+02_wp, -9.16270279001219819e+02_wp, -2.78383983137929044e+03_wp, &
      1.19504661869980588e+00_wp, -6.50859048118809791e-01_wp, -4.36755179493101831e-01_wp, &
      -7.37906956043470008e-01_wp, -1.70840510524140110e+00_wp, -4.64361144909189072e+00_wp, &
      -1.39093033905135215e+01_wp, -4.44657109678517841e+01_wp, -1.48938343996559837e+02_wp, &
      -5.16526579216126265e+02_wp, -1.84149029564060629e+03_wp, -6.90686935155662013e+03_wp, &
      -2.56457537170931246e+04_wp, 1.16130715219628278e+00_wp, -7.01100284555289166e-01_wp, &
      -5.80551474465435646e-01_wp, -1.24369306109487954e+00_wp, -3.67938361358051891e+00_wp, &
      -1.28159090248955714e+01_wp, -4.92567242354122641e+01_wp, -2.02183069044833360e+02_wp, &
      -8.69866136443476876e+02_wp, -3.87383276068080477e+03_wp, -1.77461377577397434e+04_wp, &
      -8.72042654019117617e+04_wp, -4.16379075189365656e+05_wp], [13, 17])
  real(wp), parameter :: kepoly1(0:12, 0:3) = reshape([ &
      1.38629436111989057e+00_wp, 9.65735902799726570e-02_wp, 3.08851445324856942e-02_wp, &
      1.49376003696237245e-02_wp, 8.76631220909213776e-03_wp, 5.75488714837959006e-03_wp, &
      4.06467397818785058e-03_wp, 3.02225024249489806e-03_wp, 2.33902897085205104e-03_wp, &
      1.82365327645570030e-03_wp, 1.71689971337648660e-03_wp, 5.04289799850565876e-04_wp, &
      2.56028841308320780e-03_wp, 5.00000000000000000e-01_wp, 1.24999999999999958e-01_wp, &
      7.03125000000152794e-02_wp, 4.88281249977679105e-02_wp, 3.73840333721913304e-02_wp, &
      3.02810592935986722e-02_wp, 2.54447262111105847e-02_wp, 2.19352025614617113e-02_wp, &
      1.93374020940255895e-02_wp, 1.67141459048814750e-02_wp, 1.83832734856337193e-02_wp, &
      3.61587723642193670e-03_wp, 3.37689143450084980e-02_wp, 1.00000000000000000e+00_wp, &
      4.43147180559945286e-01_wp, 5.68051927099806481e-02_wp, 2.18313704435678241e-02_wp, &
      1.15445214301415633e-02_wp, 7.14199973609708303e-03_wp, 4.85475995437578255e-03_wp, &
      3.51436879636958521e-03_wp, 2.66640678408386778e-03_wp, 2.04931591980090158e-03_wp, &
      1.89835082137982942e-03_wp, 5.69548697922875650e-04_wp, 2.77384511870585769e-03_wp, &
      2.50000000000000000e-01_wp, 9.37499999999999584e-02_wp, 5.85937500000147660e-02_wp, &
      4.27246093728425938e-02_wp, 3.36456300462195587e-02_wp, 2.77576373069522153e-02_wp, &
      2.36272540557896475e-02_wp, 2.05641309672642512e-02_wp, 1.82643039795682971e-02_wp, &
      1.58705036572104261e-02_wp, 1.75811415006300181e-02_wp, 3.38361490522440548e-03_wp, &
      3.25575758460640574e-02_wp], [13, 4])


  ! atan(w) = w + w t P(t), t = w**2 <= tan(pi/8)**2: P of degree 10 (Chebyshev interpolant,
  ! tests/python/gen_elliptic_coeffs.py --atan); atan on [-1, 1] within 1.2 ulps.
  real(wp), parameter :: atpoly(0:10) = [ &
      -3.33333333333333315e-01_wp, 1.99999999999955214e-01_wp, -1.42857142846665425e-01_wp, &
      1.11111110152563614e-01_wp, -9.09090457812390257e-02_wp, 7.69218319082608654e-02_wp, &
      -6.66451144738194751e-02_wp, 5.85814891280221003e-02_wp, -5.08544973794025981e-02_wp, &
      3.92316582955871893e-02_wp, -1.91768871190622602e-02_wp]

  real(wp), parameter :: tan_pi8 = 0.41421356237309503_wp

  !> Parameter-dependent constants of sn, cn, dn at one m (no table; cheap to build).
  type :: jpar_t
    integer :: kind = -1        ! -1 NaN/invalid, 0: 0<=m<1, 1: m==1, 2: m>1, 3: m<0
    real(wp) :: m = 0, mc = 1   ! core parameter in [0,1] and its complement
    real(wp) :: mcl = 0         ! low part of mc (double-double), for K in extra precision
    real(wp) :: khi = 0, klo = 0! K of the core parameter, double-double
    real(wp) :: uscale = 1      ! u is multiplied by this before the core
    real(wp) :: uscale_lo = 0   ! ... in double-double, so large u keeps its digits
    real(wp) :: oscale = 1      ! sn scale (m>1: 1/k, m<0: 1/sqrt(1-m))
    real(wp) :: cs(0:6) = 0, cc(0:6) = 0, cd(0:6) = 0  ! series coefficients at m
  end type jpar_t

  !> m-dependent work for many evaluations of sn, cn, dn at one parameter: the
  !> modulus transformation, K in double-double and a table of Taylor polynomials.
  type :: ellipj_plan_t
    private
    type(jpar_t) :: par
    integer :: ntab = -1
    !> Taylor coefficients of sn, cn, dn, am about t_j = j*tab_step, j = 0..ntab (core argument)
    real(wp), allocatable :: tab(:, :, :)
  end type ellipj_plan_t

contains

  ! ------------------------------------------------------------------ helpers
  pure elemental real(wp) function qnan()
    qnan = ieee_value(1.0_wp, ieee_quiet_nan)
  end function qnan

  !> Exact product a*b = p + e (Dekker/Veltkamp, no fma needed) whenever p is finite and
  !> the error term does not underflow.  The Veltkamp split overflows above 2**996 (split*a,
  !> and the 26-bit head of a double near huge() rounds up to 2**1024): there the big factor
  !> is scaled by 2**-28 first, which scales p and e exactly.  Without this the split gave
  !> Inf - Inf = NaN for |m| >= 1.3e300, the cause of the old crash in the plan set-up.
  pure elemental subroutine two_prod(a, b, p, e)
    real(wp), intent(in) :: a, b
    real(wp), intent(out) :: p, e
    real(wp), parameter :: big = 2.0_wp**996
    real(wp) :: ps
    p = a * b
    if (abs(a) <= big .and. abs(b) <= big) then
      e = prod_err(a, b, p)
    else if (abs(p) <= huge(p)) then      ! one factor big (both big would overflow p)
      if (abs(a) > big) then
        ps = scale(a, -28) * b
        e = scale(prod_err(scale(a, -28), b, ps), 28)
      else
        ps = a * scale(b, -28)
        e = scale(prod_err(a, scale(b, -28), ps), 28)
      end if
    else
      e = 0                               ! p = +-Inf or NaN: no error term
    end if
  end subroutine two_prod

  !> Error a*b - p of the rounded product p = fl(a*b), |a|, |b| <= 2**996 (Dekker).
  pure elemental real(wp) function prod_err(a, b, p) result(e)
    real(wp), intent(in) :: a, b, p
    real(wp) :: ah, al, bh, bl
    call two_prod_split(a, ah, al)
    call two_prod_split(b, bh, bl)
    e = ((ah * bh - p) + ah * bl + al * bh) + al * bl
  end function prod_err

  !> Veltkamp split a = hi + lo, each with at most 26 significant bits (|a| <= 2**996, where
  !> split*a cannot overflow).
  pure elemental subroutine two_prod_split(a, hi, lo)
    real(wp), intent(in) :: a
    real(wp), intent(out) :: hi, lo
    real(wp), parameter :: split = 134217729.0_wp   ! 2**27 + 1
    real(wp) :: t
    t = split * a
    hi = t - (t - a)
    lo = a - hi
  end subroutine two_prod_split

  pure elemental subroutine two_sum(a, b, s, e)
    real(wp), intent(in) :: a, b
    real(wp), intent(out) :: s, e
    real(wp) :: bb
    s = a + b
    bb = s - a
    e = (a - (s - bb)) + (b - bb)
  end subroutine two_sum

  pure subroutine dd_add(ah, al, bh, bl, ch, cl)
    real(wp), intent(in) :: ah, al, bh, bl
    real(wp), intent(out) :: ch, cl
    real(wp) :: s, e, t, f, f2
    call two_sum(ah, bh, s, e)
    call two_sum(al, bl, t, f)
    e = e + t
    call two_sum(s, e, t, f2)
    e = f2 + f
    call two_sum(t, e, ch, cl)
  end subroutine dd_add

  pure subroutine dd_mul(ah, al, bh, bl, ch, cl)
    real(wp), intent(in) :: ah, al, bh, bl
    real(wp), intent(out) :: ch, cl
    real(wp) :: p, e
    call two_prod(ah, bh, p, e)
    e = e + (ah * bl + al * bh)
    call two_sum(p, e, ch, cl)
  end subroutine dd_mul

  pure subroutine dd_div(ah, al, bh, bl, ch, cl)
    real(wp), intent(in) :: ah, al, bh, bl
    real(wp), intent(out) :: ch, cl
    real(wp) :: q1, q2, ph, pl, rh, rl
    q1 = ah / bh
    call dd_mul(q1, 0.0_wp, bh, bl, ph, pl)
    call dd_add(ah, al, -ph, -pl, rh, rl)
    q2 = rh / bh
    call two_sum(q1, q2, ch, cl)
  end subroutine dd_div

  pure subroutine dd_sqrt(ah, al, ch, cl)
    real(wp), intent(in) :: ah, al
    real(wp), intent(out) :: ch, cl
    real(wp) :: s, p, e, r, xh, xl
    integer :: sh
    if (ah <= 0) then
      ch = 0; cl = 0
      return
    end if
    ! above 2**1000, s*s may round to +Inf: work on a / 2**100 and scale the root back
    sh = 0
    if (ah > 2.0_wp**1000) sh = 50
    xh = scale(ah, -2 * sh); xl = scale(al, -2 * sh)
    s = sqrt(xh)
    call two_prod(s, s, p, e)
    r = ((xh - p) - e + xl) / (2 * s)
    call two_sum(s, r, ch, cl)
    ch = scale(ch, sh); cl = scale(cl, sh)
  end subroutine dd_sqrt

  !> K(m) in double-double from mc = 1 - m = mch + mcl > 0 given in double-double (any
  !> mc > 0, also mc > 1 for m < 0): K = (pi/2) / AGM(1, sqrt(mc)) (DLMF 19.8.5).
  pure subroutine kdd(mch, mcl, khi, klo)
    real(wp), intent(in) :: mch, mcl
    real(wp), intent(out) :: khi, klo
    real(wp) :: ah, al, bh, bl, th, tl, ph, pl
    integer :: i, sh
    ! sqrt(mc) in double-double; scale tiny mc so the residual stays exact
    sh = 0
    if (mch < 2.0_wp**(-900)) then
      call dd_sqrt(scale(mch, 1000), scale(mcl, 1000), bh, bl)
      bh = scale(bh, -500); bl = scale(bl, -500)
    else
      call dd_sqrt(mch, mcl, bh, bl)
    end if
    ah = 1; al = 0
    do i = 1, 80
      call dd_add(ah, al, -bh, -bl, th, tl)
      if (abs(th) <= 1.0e-33_wp * ah) exit
      call dd_add(ah, al, bh, bl, th, tl)
      call dd_mul(ah, al, bh, bl, ph, pl)
      ah = 0.5_wp * th; al = 0.5_wp * tl
      call dd_sqrt(ph, pl, bh, bl)
    end do
    call dd_div(half_pi, half_pi_lo, ah, al, khi, klo)
  end subroutine kdd

  !> Horner evaluation of a degree-12 polynomial.
  pure real(wp) function hor12(p, y) result(r)
    real(wp), intent(in) :: p(0:12), y
    real(wp) :: y2, y4
    ! Estrin's scheme: a short dependency chain, the same accuracy for these small |y|
    y2 = y * y
    y4 = y2 * y2
    r = ((p(0) + p(1) * y) + (p(2) + p(3) * y) * y2) + ((p(4) + p(5) * y) + (p(6) + p(7) * y) * y2) * y4 &
        + (((p(8) + p(9) * y) + (p(10) + p(11) * y) * y2) + p(12) * y4) * (y4 * y4)
  end function hor12

  !> Index i in 0..16 of the interval [i/20, (i+1)/20) holding m, for ANY m (NaN gives 0:
  !> the polynomial then returns NaN); the test comes before int() so that no
  !> out-of-range or NaN value is ever converted.
  pure elemental integer function interval20(m) result(i)
    real(wp), intent(in) :: m
    real(wp) :: t
    t = m * 20
    if (t >= 0 .and. t < 16) then
      i = int(t)
    else if (t >= 16) then
      i = 16
    else
      i = 0
    end if
  end function interval20

  !> K(m) for 0 <= m < 1 given m and mc = 1 - m (mc accurate when m > 0.85).
  pure elemental real(wp) function kpair(m, mc) result(k)
    real(wp), intent(in) :: m, mc
    integer :: i
    if (mc <= 0.15_wp) then
      k = hor12(kepoly1(:, 0), mc) - log(mc) * hor12(kepoly1(:, 1), mc)
    else
      i = interval20(m)
      k = hor12(kpoly(:, i), m - (0.025_wp + 0.05_wp * i))
    end if
  end function kpair

  !> E(m) for 0 <= m < 1 given m and mc = 1 - m (mc accurate when m > 0.85).
  pure elemental real(wp) function epair(m, mc) result(e)
    real(wp), intent(in) :: m, mc
    integer :: i
    if (mc <= 0.15_wp) then
      e = hor12(kepoly1(:, 2), mc) - log(mc) * mc * hor12(kepoly1(:, 3), mc)
    else
      i = interval20(m)
      e = hor12(epoly(:, i), m - (0.025_wp + 0.05_wp * i))
    end if
  end function epair

  ! ------------------------------------------------------- complete integrals
  !> Complete elliptic integral of the first kind K(m), m = k**2 <= 1.
  !> K(1) = +Inf, K(-Inf) = 0; NaN for m > 1 or NaN.  Accuracy: <= 2.4 ulps measured.
  elemental real(wp) function ellipk(m) result(k)
    real(wp), intent(in) :: m
    if (ieee_is_nan(m)) then     ! before any ordered comparison (quiet under -ffpe-trap)
      k = m
    else if (m >= 0 .and. m < 1) then
      k = kpair(m, 1 - m)
    else if (m < 0) then
      k = kfun(1 - m)
    else if (m == 1) then
      k = ieee_value(1.0_wp, ieee_positive_inf)
    else
      k = qnan()
    end if
  end function ellipk

  !> K as a function of the complementary parameter mc = 1 - m >= 0 (mc = 0 gives +Inf,
  !> NaN for mc < 0).  Exact to a few ulps down to the smallest subnormal mc.
  elemental real(wp) function ellipkc(mc) result(k)
    real(wp), intent(in) :: mc
    if (ieee_is_nan(mc)) then
      k = mc
    else if (mc > 0) then
      k = kfun(mc)
    else if (mc == 0) then
      k = ieee_value(1.0_wp, ieee_positive_inf)
    else
      k = qnan()
    end if
  end function ellipkc

  !> K from mc = 1 - m > 0 alone (m < 0 when mc > 1, by DLMF 19.7.5).
  pure elemental real(wp) function kfun(mc) result(k)
    real(wp), intent(in) :: mc
    if (mc <= 1) then
      k = kpair(1 - mc, mc)
    else if (mc > huge(1.0_wp)) then   ! m = -Inf
      k = 0
    else
      ! imaginary modulus: K(m) = K(mu)/sqrt(1-m), mu = -m/(1-m), 1 - mu = 1/(1-m)
      k = kpair((mc - 1) / mc, 1 / mc) / sqrt(mc)
    end if
  end function kfun

  !> ellipk over a rank-1 array (k of the size of m): the same numbers as the
  !> elemental function, with the polynomial evaluation inlined in one loop.
  !> A size mismatch sets status (PENDULA_ERR_SIZE) and k = NaN; nothing else is written.
  pure subroutine ellipk_array(m, k, status)
    real(wp), intent(in) :: m(:)
    real(wp), intent(out) :: k(:)
    type(status_t), intent(out) :: status
    integer :: i
    if (size(k) /= size(m)) then
      k = qnan()
      call set_error(status, PENDULA_ERR_SIZE, 'ellipk_array: k must have the size of m')
      return
    end if
    do i = 1, size(m)
      if (ieee_is_nan(m(i))) then
        k(i) = m(i)
      else if (m(i) >= 0 .and. m(i) < 1) then
        k(i) = kpair(m(i), 1 - m(i))
      else
        k(i) = ellipk(m(i))
      end if
    end do
  end subroutine ellipk_array

  !> ellipe over a rank-1 array (same numbers as the elemental function); e must have
  !> the size of m (status PENDULA_ERR_SIZE and e = NaN otherwise).
  pure subroutine ellipe_array(m, e, status)
    real(wp), intent(in) :: m(:)
    real(wp), intent(out) :: e(:)
    type(status_t), intent(out) :: status
    integer :: i
    if (size(e) /= size(m)) then
      e = qnan()
      call set_error(status, PENDULA_ERR_SIZE, 'ellipe_array: e must have the size of m')
      return
    end if
    do i = 1, size(m)
      if (ieee_is_nan(m(i))) then
        e(i) = m(i)
      else if (m(i) >= 0 .and. m(i) < 1) then
        e(i) = epair(m(i), 1 - m(i))
      else
        e(i) = ellipe(m(i))
      end if
    end do
  end subroutine ellipe_array

  !> Complete elliptic integral of the second kind E(m), m <= 1 (E(1) = 1,
  !> E(-Inf) = +Inf); NaN for m > 1 or NaN.  A few ulps.
  elemental real(wp) function ellipe(m) result(e)
    real(wp), intent(in) :: m
    if (ieee_is_nan(m)) then
      e = m
    else if (m <= 1) then
      e = efun(m, 1 - m)
    else
      e = qnan()
    end if
  end function ellipe

  !> E as a function of mc = 1 - m >= 0 (mc = 0 gives 1); NaN for mc < 0 or NaN.
  elemental real(wp) function ellipec(mc) result(e)
    real(wp), intent(in) :: mc
    if (ieee_is_nan(mc)) then
      e = mc
    else if (mc >= 0) then
      e = efun(1 - mc, mc)
    else
      e = qnan()
    end if
  end function ellipec

  !> E(m) given both m and mc = 1 - m (mc accurate), m <= 1.
  pure elemental real(wp) function efun(m, mc) result(e)
    real(wp), intent(in) :: m, mc
    real(wp) :: mu, muc, r
    if (mc == 0) then
      e = 1
    else if (m >= 0) then
      e = efun01(m, mc)
    else if (.not. ieee_is_finite(mc)) then
      e = mc
    else
      ! imaginary modulus: E(m) = sqrt(1-m) E(-m/(1-m)) (DLMF 19.7.5)
      r = sqrt(mc)
      muc = 1 / mc
      mu = -m / mc
      e = r * efun01(mu, muc)
    end if
  end function efun

  pure elemental real(wp) function efun01(m, mc) result(e)
    real(wp), intent(in) :: m, mc
    e = epair(m, mc)
  end function efun01

  ! ------------------------------------------------------- incomplete integral
  !> Carlson's symmetric integral R_F(x, y, z), x, y, z >= 0, at most one zero
  !> (DLMF 19.36.1 with the 7th-order series of Carlson 1995).
  pure elemental real(wp) function carlson_rf(x0, y0, z0) result(rf)
    real(wp), intent(in) :: x0, y0, z0
    real(wp) :: x, y, z, a, lam, sx, sy, sz, dx, dy, dz, e2, e3, f
    integer :: i
    x = x0; y = y0; z = z0
    f = 1
    ! the series below is exact through degree 7 in the deviations, so stopping at
    ! |dev| <= 5e-3 leaves a truncation ~ (5e-3)**8 ~ 4e-19 (Carlson 1995, DLMF 19.36.1)
    do i = 1, 200
      a = (x + y + z) * (1.0_wp / 3)
      dx = (a - x); dy = (a - y); dz = (a - z)
      if (max(abs(dx), abs(dy), abs(dz)) <= 5.0e-3_wp * a) exit
      sx = sqrt(x); sy = sqrt(y); sz = sqrt(z)
      lam = sx * (sy + sz) + sy * sz
      x = 0.25_wp * (x + lam); y = 0.25_wp * (y + lam); z = 0.25_wp * (z + lam)
    end do
    dx = dx / a; dy = dy / a; dz = -(dx + dy)
    e2 = dx * dy - dz * dz
    e3 = dx * dy * dz
    rf = (1 - e2 / 10 + e3 / 14 + e2 * e2 / 24 - 3 * e2 * e3 / 44 - 5 * e2**3 / 208 &
         + 3 * e3 * e3 / 104 + e2 * e2 * e3 / 16) / sqrt(a)
  end function carlson_rf

  !> (rh, rl) = (xh + xl) - n pi as a double-double, pi in three parts (pi, pi_lo, pi_lo2);
  !> n*pi and n*pi_lo are exact products, so the residue is right to ~1e-32 |r| + n 1e-49.
  pure subroutine sub_npi(xh, xl, n, rh, rl)
    real(wp), intent(in) :: xh, xl, n
    real(wp), intent(out) :: rh, rl
    real(wp) :: p, e, q, f, a, b, t1, t2
    call two_prod(n, pi, p, e)
    call two_prod(n, pi_lo, q, f)
    call two_sum(xh, -p, a, t1)         ! exact (Sterbenz) when n pi is within 2x of x
    call two_sum(a, -q, b, t2)
    call two_sum(b, (((t1 + t2) - e) - f) + (xl - n * pi_lo2), rh, rl)
  end subroutine sub_npi

  !> Reduce phi to r = rh + rl in [-pi/2, pi/2] with phi = (n1 + n2) pi + r exactly up
  !> to double-double rounding.  The rounded quotient anint(phi/pi) misses by one when
  !> phi is the double nearest an odd multiple of pi/2 (fl(pi/2)/fl(pi) = 0.5 exactly
  !> rounds up) and by many when |phi| > 2**53 pi (n not representable); further
  !> multiples, decided on the double-double residue, correct both (one step, or up to
  !> ~20 for |phi| near huge(), where each step removes ~52 bits).
  pure elemental subroutine reduce_pi(phi, n1, n2, rh, rl)
    real(wp), intent(in) :: phi
    real(wp), intent(out) :: n1, n2, rh, rl
    real(wp) :: q, xh, xl
    integer :: i
    n1 = anint(phi / pi)
    if (abs(phi) > 2.0_wp**1022) n1 = anint(0.5_wp * (phi / pi))   ! n1*pi must not overflow
    n2 = 0
    if (n1 == 0) then
      rh = phi; rl = 0
    else
      call sub_npi(phi, 0.0_wp, n1, rh, rl)
    end if
    do i = 1, 40
      if (abs(rh) < 1.5_wp) exit                   ! cheap screen: pi/2 = 1.5708
      if (half_pi_minus(rh, rl) >= 0) exit
      q = anint(rh / pi)
      if (q == 0) q = sign(1.0_wp, rh)
      xh = rh; xl = rl
      call sub_npi(xh, xl, q, rh, rl)
      n2 = n2 + q
    end do
  end subroutine reduce_pi

  !> pi/2 - |rh + rl| for a double-double; exact first difference for |rh| >= pi/4.
  pure elemental real(wp) function half_pi_minus(rh, rl) result(w)
    real(wp), intent(in) :: rh, rl
    w = (half_pi - abs(rh)) + (half_pi_lo - sign(1.0_wp, rh) * rl)
  end function half_pi_minus

  !> Incomplete elliptic integral of the first kind F(phi|m) for any real phi (rad)
  !> and any real m with m sin^2(phi) <= 1 (including m > 1; there, like K, the
  !> quasi-period uses Re K(m) = K(1/m)/sqrt(m)); NaN outside or for NaN input.
  !> F(phi + n pi) = F(phi) + 2 n K(m).  A few ulps (Carlson R_F).
  elemental real(wp) function ellipf(phi, m) result(f)
    real(wp), intent(in) :: phi, m
    f = ffun(phi, m, 1 - m, .false.)
  end function ellipf

  !> F(phi|m) with the complementary parameter mc = 1 - m (accurate near m = 1).
  elemental real(wp) function ellipfc(phi, mc) result(f)
    real(wp), intent(in) :: phi, mc
    f = ffun(phi, 1 - mc, mc, .true.)
  end function ellipfc

  pure elemental real(wp) function ffun(phi, m, mc, usemc) result(f)
    real(wp), intent(in) :: phi, m, mc
    logical, intent(in) :: usemc
    real(wp) :: n1, n2, rh, rl, s, c, w, d2, kh, kl, p, e, p2, e2, t, ps
    type(jpar_t) :: par
    if (ieee_is_nan(phi) .or. ieee_is_nan(m) .or. ieee_is_nan(mc)) then
      f = qnan(); return
    end if
    if (.not. ieee_is_finite(phi)) then
      if (m <= 1 .and. (mc > 0 .or. .not. usemc .and. m < 1)) then
        f = phi           ! F grows linearly in phi without bound
      else
        f = qnan()
      end if
      return
    end if
    call reduce_pi(phi, n1, n2, rh, rl)
    ! sin and cos of the double-double residue; near +-pi/2 cos r = sin(pi/2 - |r|) from
    ! the exact difference, so cos keeps its relative accuracy down to the 6e-17 of fl(pi/2)
    if (abs(rh) <= 0.79_wp) then
      s = sin(rh); c = cos(rh)
      s = s + c * rl
    else
      w = half_pi_minus(rh, rl)
      s = sign(cos(w), rh); c = sin(w)
    end if
    ! 1 - m sin^2 = cos^2 + mc sin^2: no cancellation near m = 1 (mc = 1 - m is exact for
    ! m in [0.5, 2], and for other m the sum does not cancel or cancels as 1 - m sin^2 does)
    d2 = c * c + mc * (s * s)
    if (d2 < 0 .or. ieee_is_nan(d2)) then
      f = qnan(); return
    end if
    if (d2 == 0 .and. c == 0) then
      f = sign(ieee_value(1.0_wp, ieee_positive_inf), s)
    else if (s == 0) then
      f = rh
    else
      f = s * carlson_rf(c * c, d2, 1.0_wp)
    end if
    if (n1 /= 0 .or. n2 /= 0) then
      ! F + 2 n K with K in double-double: the sum may cancel (phi in (-pi, -pi/2) etc.)
      par = make_par(m, mc, usemc, .true.)
      if (par%kind == 1) then
        if (n1 + n2 /= 0) f = f + sign(ieee_value(1.0_wp, ieee_positive_inf), n1 + n2)
      else if (par%kind < 0) then
        f = qnan()
      else
        kh = par%khi; kl = par%klo
        if (par%kind /= 0) then
          ! Re K(m) = K(core)/k for m > 1 (DLMF 19.7.3); K(m) = K(mu)/sqrt(1-m) for m < 0
          call dd_div(par%khi, par%klo, par%uscale, par%uscale_lo, kh, kl)
        end if
        if (abs(n1 + n2) >= 0.5_wp * (huge(kh) / kh)) then
          ! |F| = 2 |n| K + O(K) > huge (|phi| near huge): +-Inf, the rounded value, formed
          ! without an overflowing operation (the checked build traps overflow)
          f = sign(ieee_value(1.0_wp, ieee_positive_inf), n1 + n2)
          return
        end if
        call two_prod(2 * n1, kh, p, e)
        e = e + 2 * n1 * kl
        if (n2 /= 0) then
          call two_prod(2 * n2, kh, p2, e2)
          call two_sum(p, p2, ps, t)
          p = ps
          e = e + (t + (e2 + 2 * n2 * kl))
        end if
        f = p + (f + e)
      end if
    end if
  end function ffun

  ! ------------------------------------------------------- Jacobi functions
  !> Series coefficients of sn, 1 - cn, 1 - dn in w^2 at parameter m (Horner in m).
  pure subroutine series_coeffs(m, cs, cc, cd)
    real(wp), intent(in) :: m
    real(wp), intent(out) :: cs(0:6), cc(0:6), cd(0:6)
    ! unrolled Horner in m of the generated tables js, jc, jd (same numbers)
    cs(0) = 1.00000000000000000e+00_wp
    cc(0) = 5.00000000000000000e-01_wp
    cd(0) = m * 5.00000000000000000e-01_wp
    cs(1) = (-1.66666666666666657e-01_wp + m * (-1.66666666666666657e-01_wp))
    cc(1) = (-4.16666666666666644e-02_wp + m * (-1.66666666666666657e-01_wp))
    cd(1) = m * (-1.66666666666666657e-01_wp + m * (-4.16666666666666644e-02_wp))
    cs(2) = (8.33333333333333322e-03_wp + m * (1.16666666666666669e-01_wp + m * 8.33333333333333322e-03_wp))
    cc(2) = (1.38888888888888894e-03_wp + m * (6.11111111111111091e-02_wp + m * 2.22222222222222231e-02_wp))
    cd(2) = m * (2.22222222222222231e-02_wp + m * (6.11111111111111091e-02_wp + &
        m * 1.38888888888888894e-03_wp))
    cs(3) = (-1.98412698412698413e-04_wp + m * (-2.67857142857142842e-02_wp + &
        m * (-2.67857142857142842e-02_wp + m * (-1.98412698412698413e-04_wp))))
    cc(3) = (-2.48015873015873016e-05_wp + m * (-1.01190476190476195e-02_wp + &
        m * (-2.26190476190476185e-02_wp + m * (-1.58730158730158730e-03_wp))))
    cd(3) = m * (-1.58730158730158730e-03_wp + m * (-2.26190476190476185e-02_wp + &
        m * (-1.01190476190476195e-02_wp + m * (-2.48015873015873016e-05_wp))))
    cs(4) = (2.75573192239858925e-06_wp + m * (3.38403880070546744e-03_wp + &
        m * (1.50958994708994716e-02_wp + m * (3.38403880070546744e-03_wp + m * 2.75573192239858925e-06_wp))))
    cc(4) = (2.75573192239858883e-07_wp + m * (1.01631393298059970e-03_wp + &
        m * (8.47883597883597809e-03_wp + m * (4.35626102292768942e-03_wp + m * 7.05467372134038740e-05_wp))))
    cd(4) = m * (7.05467372134038740e-05_wp + m * (4.35626102292768942e-03_wp + &
        m * (8.47883597883597809e-03_wp + m * (1.01631393298059970e-03_wp + m * 2.75573192239858883e-07_wp))))
    cs(5) = (-2.50521083854417202e-08_wp + m * (-2.77301787718454409e-04_wp + &
        m * (-4.15429092512425817e-03_wp + m * (-4.15429092512425817e-03_wp + &
        m * (-2.77301787718454409e-04_wp + m * (-2.50521083854417202e-08_wp))))))
    cc(5) = (-2.08767569878681002e-09_wp + m * (-6.93358853081075301e-05_wp + &
        m * (-1.81761397039174812e-03_wp + m * (-3.21201432312543441e-03_wp + &
        m * (-5.41392763614985829e-04_wp + m * (-2.13777991555769346e-06_wp))))))
    cd(5) = m * (-2.13777991555769346e-06_wp + m * (-5.41392763614985829e-04_wp + &
        m * (-3.21201432312543441e-03_wp + m * (-1.81761397039174812e-03_wp + &
        m * (-6.93358853081075301e-05_wp + m * (-2.08767569878681002e-09_wp))))))
    cs(6) = (1.60590438368216133e-10_wp + m * (1.60015524598857930e-05_wp + &
        m * (7.21749797270630636e-04_wp + m * (2.11662501593057155e-03_wp + &
        m * (7.21749797270630636e-04_wp + m * (1.60015524598857930e-05_wp + &
        m * 1.60590438368216133e-10_wp))))))
    cc(6) = (1.14707455977297245e-11_wp + m * (3.42897292302054208e-06_wp + &
        m * (2.63196900101662034e-04_wp + m * (1.22648662331202021e-03_wp + &
        m * (7.45700507605269523e-04_wp + m * (4.79590955781431980e-05_wp + &
        m * 4.69841739683009516e-08_wp))))))
    cd(6) = m * (4.69841739683009516e-08_wp + m * (4.79590955781431980e-05_wp + &
        m * (7.45700507605269523e-04_wp + m * (1.22648662331202021e-03_wp + &
        m * (2.63196900101662034e-04_wp + m * (3.42897292302054208e-06_wp + &
        m * 1.14707455977297245e-11_wp))))))
  end subroutine series_coeffs

  !> sn, cn, dn at 0 <= v <= K(m)/2 for 0 <= m <= 1 (mc = 1 - m accurate).
  pure subroutine jcore(v, m, mc, cs, cc, cd, s, c, d)
    real(wp), intent(in) :: v, m, mc, cs(0:6), cc(0:6), cd(0:6)
    real(wp), intent(out) :: s, c, d
    real(wp) :: w, w2, w4, x, y, s2, den, r, c2, d2, q
    integer :: n, i
    n = 0
    w = v
    do while (w > wmax)
      w = 0.5_wp * w
      n = n + 1
    end do
    w2 = w * w
    w4 = w2 * w2
    ! Estrin's scheme (short dependency chains); terms fall by >= 400x each
    s = w * (((cs(0) + cs(1) * w2) + (cs(2) + cs(3) * w2) * w4) + ((cs(4) + cs(5) * w2) + cs(6) * w4) * (w4 * w4))
    x = w2 * (((cc(0) + cc(1) * w2) + (cc(2) + cc(3) * w2) * w4) + ((cc(4) + cc(5) * w2) + cc(6) * w4) * (w4 * w4))
    y = w2 * (((cd(0) + cd(1) * w2) + (cd(2) + cd(3) * w2) * w4) + ((cd(4) + cd(5) * w2) + cd(6) * w4) * (w4 * w4))
    i = 0
    ! duplication on the complements x = 1 - cn, y = 1 - dn (no cancellation for small u),
    ! kept as fractions x = xq/q, y = yq/q, s = sq/q so that the steps need no division:
    ! with c = q - xq, d = q - yq (times 1/q),
    !   xq' = 2 sq^2 d^2, yq' = 2 m sq^2 c^2, sq' = 2 sq q c d, q' = c^2 q^2 + sq^2 d^2.
    ! Here cn >= 3/4, so 1 - m sn^4 >= 0.8 and q' >= 0.8 q^4: at most 4 steps keep q >= 1e-8.
    if (n > 0 .and. x < xswitch) then
      q = 1
      do while (i < n)
        c = q - x; d = q - y
        s2 = s * s
        c2 = c * c; d2 = d * d
        x = 2 * s2 * d2
        y = 2 * m * s2 * c2
        s = 2 * s * q * c * d
        q = c2 * (q * q) + s2 * d2
        i = i + 1
        if (x >= xswitch * q) exit
      end do
      r = 1 / q
      x = x * r; y = y * r; s = s * r
    end if
    c = 1 - x; d = 1 - y
    ! direct duplication, cancellation-free forms for 0 <= m <= 1
    do while (i < n)
      s2 = s * s
      c2 = c * c; d2 = d * d
      den = c2 + s2 * d2
      r = 1 / den
      s = 2 * r * s * c * d
      c = r * (c2 * d2 - mc * s2)
      d = r * (mc + m * (c2 * c2))
      i = i + 1
    end do
  end subroutine jcore

  !> cd = cn/dn without the cancellation of two nearly equal small numbers when m -> 1:
  !> dn^2 - cn^2 = mc sn^2, so cd = 1 - mc sn^2 / (dn (dn + cn)) (cn >= 0 here).
  pure elemental real(wp) function cd_ratio(s, c, d, mc) result(cd)
    real(wp), intent(in) :: s, c, d, mc
    real(wp) :: t
    t = mc * (s * s) / (d * (d + c))
    if (t <= 0.5_wp) then
      cd = 1 - t
    else
      cd = c / d
    end if
  end function cd_ratio

  !> Plan for sn, cn, dn at one parameter m (all real m; NaN m gives NaN results).
  !> Does the m-dependent work once: the transformation to a core parameter in [0,1],
  !> K in double-double for the period reduction, the series coefficients.
  pure function ellipj_plan(m) result(plan)
    real(wp), intent(in) :: m
    type(ellipj_plan_t) :: plan
    plan = make_plan(m, 1 - m, .false.)
  end function ellipj_plan

  !> Plan from the complementary parameter mc = 1 - m (mc >= 0, accurate near m = 1).
  pure function ellipj_planc(mc) result(plan)
    real(wp), intent(in) :: mc
    type(ellipj_plan_t) :: plan
    plan = make_plan(1 - mc, mc, .true.)
  end function ellipj_planc

  pure function make_par(m, mc, usemc, full) result(plan)
    real(wp), intent(in) :: m, mc
    logical, intent(in) :: usemc, full
    type(jpar_t) :: plan
    real(wp) :: mm, wh, wl, ah, al, qh, ql
    if (ieee_is_nan(m) .or. ieee_is_nan(mc)) then
      plan%kind = -1
      return
    end if
    if ((usemc .and. mc == 0) .or. (.not. usemc .and. m == 1)) then
      plan%kind = 1
      plan%m = 1; plan%mc = 0
      return
    end if
    ! w = 1 - m exactly, as a double-double
    if (usemc) then
      wh = mc; wl = 0
    else
      call two_sum(1.0_wp, -m, wh, wl)
    end if
    if (.not. ieee_is_finite(wh)) then
      plan%kind = -1
      return
    end if
    if (wh > 0 .and. wh <= 1) then
      plan%kind = 0
      mm = m
      plan%mc = wh; plan%mcl = wl
      plan%uscale = 1; plan%uscale_lo = 0
    else if (wh < 0) then
      ! reciprocal modulus (DLMF 22.6.11): core parameter 1/m, u scaled by k = sqrt(m)
      plan%kind = 2
      call two_sum(1.0_wp, -wh, ah, al)         ! m = 1 - w
      al = al - wl
      mm = 1 / ah
      call dd_div(-wh, -wl, ah, al, qh, ql)     ! core mc = (m - 1)/m
      plan%mc = qh; plan%mcl = ql
      call dd_sqrt(ah, al, qh, ql)
      plan%uscale = qh; plan%uscale_lo = ql
      plan%oscale = 1 / qh
    else
      ! imaginary modulus (DLMF 22.6.12): core mu = -m/(1-m), mc = 1/(1-m), u scaled by sqrt(1-m)
      plan%kind = 3
      mm = -m / wh
      if (usemc) mm = (mc - 1) / mc
      call dd_div(1.0_wp, 0.0_wp, wh, wl, qh, ql)
      plan%mc = qh; plan%mcl = ql
      call dd_sqrt(wh, wl, qh, ql)
      plan%uscale = qh; plan%uscale_lo = ql
      plan%oscale = 1 / qh
    end if
    plan%m = mm
    if (full) then
      call kdd(plan%mc, plan%mcl, plan%khi, plan%klo)
    else if (plan%kind == 0) then
      plan%khi = kpair(mm, plan%mc); plan%klo = 0
    else
      plan%khi = kfun(plan%mc); plan%klo = 0
    end if
    call series_coeffs(mm, plan%cs, plan%cc, plan%cd)
  end function make_par

  pure function make_plan(m, mc, usemc) result(plan)
    real(wp), intent(in) :: m, mc
    logical, intent(in) :: usemc
    type(ellipj_plan_t) :: plan
    integer :: j
    plan%par = make_par(m, mc, usemc, .true.)
    ! K of a core parameter in [0, 1) lies in [pi/2, 374] (374 at the smallest subnormal
    ! mc); anything else (never seen, but NaN would size the table from garbage) gets
    ! no table and the direct evaluation
    if ((plan%par%kind == 0 .or. plan%par%kind >= 2) .and. &
        plan%par%khi >= 1 .and. plan%par%khi <= khi_tab_max) then
      plan%ntab = ceiling(plan%par%khi * tab_inv_step) + 1
      allocate(plan%tab(0:ntay, 4, 0:plan%ntab))
      do j = 0, plan%ntab
        call taylor_at(plan%par, j * tab_step, plan%tab(:, :, j))
      end do
    end if
  end function make_plan

  !> Evaluate sn, cn, dn (and optionally am, rad) at u with a plan (see ellipj).
  !> With a tabulated plan (the default) a point costs one table look-up and four
  !> short polynomials, no division and no transcendental call.
  elemental subroutine ellipj_eval(plan, u, sn, cn, dn, am)
    type(ellipj_plan_t), intent(in) :: plan
    real(wp), intent(in) :: u
    real(wp), intent(out) :: sn, cn, dn
    real(wp), intent(out), optional :: am
    real(wp) :: a
    if (allocated(plan%tab)) then
      call eval_plan(plan%par, u, .true., present(am), sn, cn, dn, a, plan%tab, plan%ntab)
    else
      call eval_plan(plan%par, u, .true., present(am), sn, cn, dn, a)
    end if
    if (present(am)) am = a
  end subroutine ellipj_eval

  !> ellipj_eval over rank-1 arrays (sn, cn, dn and the optional am of the size of u):
  !> the same numbers as the elemental form, with the table look-up inlined in one loop.
  !> A size mismatch sets status (PENDULA_ERR_SIZE) and the outputs to NaN.
  pure subroutine ellipj_eval_array(plan, u, sn, cn, dn, status, am)
    type(ellipj_plan_t), intent(in) :: plan
    real(wp), intent(in) :: u(:)
    real(wp), intent(out) :: sn(:), cn(:), dn(:)
    type(status_t), intent(out) :: status
    real(wp), intent(out), optional :: am(:)
    real(wp) :: a
    integer :: i
    logical :: bad
    call outputs_mismatch('ellipj_eval_array', size(u), sn, cn, dn, status, bad, am)
    if (bad) return
    if (allocated(plan%tab)) then
      if (present(am)) then
        call tab_loop(plan%par, plan%tab, plan%ntab, size(u), u, .true., sn, cn, dn, am)
      else
        call tab_loop(plan%par, plan%tab, plan%ntab, size(u), u, .false., sn, cn, dn, sn)
      end if
    else
      do i = 1, size(u)
        call eval_plan(plan%par, u(i), .true., present(am), sn(i), cn(i), dn(i), a)
        if (present(am)) am(i) = a
      end do
    end if
  end subroutine ellipj_eval_array

  !> The loop of ellipj_eval_array for tabulated plans.  Points the fast reduction
  !> cannot take (NaN, Inf, n >= 2**26 half periods) go through eval_plan.
  pure subroutine tab_loop(par, tab, ntab, n, u, want_am, sn, cn, dn, am)
    type(jpar_t), intent(in) :: par
    integer, intent(in) :: ntab, n
    real(wp), intent(in) :: tab(0:ntay, 4, 0:ntab), u(n)
    logical, intent(in) :: want_am
    real(wp), intent(out) :: sn(n), cn(n), dn(n)
    real(wp), intent(inout) :: am(*)
    real(wp) :: c1, c2, c3, inv2k, vmax, v, vl, q, r, t, del, fs, fc, fd, fa, a
    integer :: i, j, parity
    logical :: big
    call two_prod_split(2 * par%khi, c1, c2)
    c3 = 2 * par%klo
    inv2k = 1 / (2 * par%khi)
    vmax = 2.0_wp**25 * (2 * par%khi)
    do i = 1, n
      v = abs(u(i)) * par%uscale
      big = ieee_is_nan(v)
      if (.not. big) big = v >= vmax
      if (big) then
        call eval_plan(par, u(i), .true., want_am, sn(i), cn(i), dn(i), a, tab, ntab)
        if (want_am) am(i) = a
        cycle
      end if
      vl = 0
      if (par%kind /= 0) then
        call two_prod(abs(u(i)), par%uscale, v, vl)
        vl = vl + abs(u(i)) * par%uscale_lo
      end if
      q = anint(v * inv2k)
      r = (((v - q * c1) - q * c2) + vl) - q * c3
      t = abs(r)
      j = tab_index(t, ntab)
      del = t - j * tab_step
      fs = sign(horner(tab(:, 1, j), del), r)
      fc = horner(tab(:, 2, j), del)
      fd = horner(tab(:, 3, j), del)
      parity = iand(int(q), 1)
      if (par%kind == 2) then
        if (parity /= 0) then
          fs = -fs; fd = -fd
        end if
      else if (parity /= 0) then
        fs = -fs; fc = -fc
      end if
      if (u(i) < 0) fs = -fs
      sn(i) = fs; cn(i) = fc; dn(i) = fd
      if (want_am) then
        fa = sign(horner(tab(:, 4, j), del), r)
        if (par%kind == 2) then
          if (parity /= 0) fa = -fa
        else
          fa = fa + q * pi
        end if
        if (u(i) < 0) fa = -fa
        am(i) = fa
      end if
    end do
  end subroutine tab_loop

  !> Amplitude atan2(sn, cn) for normalized sn**2 + cn**2 = 1 and cn >= 0 (always the case
  !> on the core interval [0, K]): am = 2 atan(sn/(1 + cn)) by the half-angle identity,
  !> atan by a polynomial; no libm call (glibc atan2 dominated the cost).
  pure elemental real(wp) function am_of(s, c) result(am)
    real(wp), intent(in) :: s, c
    real(wp) :: as, c1, w, t, t2, t4, p, base
    logical :: big
    ! x = |s|/(1 + c) in [0, 1]; above tan(pi/8) use atan x = pi/4 + atan((x - 1)/(x + 1)),
    ! formed directly from s and c with a single division
    as = abs(s)
    c1 = 1 + c
    big = as > tan_pi8 * c1      ! merge, not a branch: the test is unpredictable
    w = merge(as - c1, as, big) / merge(as + c1, c1, big)
    base = merge(0.25_wp * pi, 0.0_wp, big)
    t = w * w
    t2 = t * t
    t4 = t2 * t2
    p = ((atpoly(0) + atpoly(1) * t) + (atpoly(2) + atpoly(3) * t) * t2) &
        + ((atpoly(4) + atpoly(5) * t) + (atpoly(6) + atpoly(7) * t) * t2) * t4 &
        + ((atpoly(8) + atpoly(9) * t) + atpoly(10) * t2) * (t4 * t4)
    am = sign(2 * (base + (w + w * t * p)), s)
  end function am_of

  !> Core functions at 0 <= t <= K (+ one table step): s, c, d of the core parameter.
  pure subroutine core_at(plan, t, s, c, d)
    type(jpar_t), intent(in) :: plan
    real(wp), intent(in) :: t
    real(wp), intent(out) :: s, c, d
    call core_at2(plan%m, plan%mc, plan%khi, plan%klo, plan%cs, plan%cc, plan%cd, t, s, c, d)
  end subroutine core_at

  pure subroutine core_at2(m, mc, khi, klo, cs, cc, cd, t, s, c, d)
    real(wp), intent(in) :: m, mc, khi, klo, cs(0:6), cc(0:6), cd(0:6), t
    real(wp), intent(out) :: s, c, d
    real(wp) :: w, rd, sq
    if (t > 0.5_wp * khi) then
      ! sn(K - w) = cd(w), cn(K - w) = sqrt(mc) sd(w), dn(K - w) = sqrt(mc) nd(w) (DLMF 22.4.3)
      w = (khi - t) + klo
      call jcore(abs(w), m, mc, cs, cc, cd, s, c, d)
      if (w < 0) s = -s
      ! one division: rd = 1/(d (d + c)) gives 1/d = rd (d + c) and the cancellation-free
      ! cd = 1 - mc s^2 rd (see cd_ratio)
      rd = 1 / (d * (d + c))
      sq = sqrt(mc)
      w = mc * (s * s) * rd
      if (w <= 0.5_wp) then
        w = 1 - w
      else
        w = c * (d + c) * rd
      end if
      rd = rd * (d + c)
      c = sq * s * rd
      d = sq * rd
      s = w
    else
      call jcore(t, m, mc, cs, cc, cd, s, c, d)
    end if
  end subroutine core_at2

  !> The final sn, cn, dn, am of the caller's parameter at core argument t >= 0
  !> (no half-period shift), from the core values by the modulus transformations.
  pure subroutine final_at(plan, t, want_am, fs, fc, fd, fa)
    type(jpar_t), intent(in) :: plan
    real(wp), intent(in) :: t
    logical, intent(in) :: want_am
    real(wp), intent(out) :: fs, fc, fd, fa
    real(wp) :: s, c, d
    call core_at(plan, t, s, c, d)
    call finalize(plan, s, c, d, want_am, fs, fc, fd, fa)
  end subroutine final_at

  !> The modulus transformations from core s, c, d to the caller's sn, cn, dn, am.
  pure subroutine finalize(plan, s, c, d, want_am, fs, fc, fd, fa)
    type(jpar_t), intent(in) :: plan
    real(wp), intent(in) :: s, c, d
    logical, intent(in) :: want_am
    real(wp), intent(out) :: fs, fc, fd, fa
    fa = 0
    select case (plan%kind)
    case (2)   ! m > 1 (DLMF 22.6.11): sn = sn'/k, cn = dn', dn = cn'; am on the asin branch
      fs = s * plan%oscale; fc = d; fd = c
    case (3)   ! m < 0 (DLMF 22.6.12): sn = k1' sd', cn = cd', dn = nd'
      fs = plan%oscale * s / d
      fc = cd_ratio(s, c, d, plan%mc)
      fd = 1 / d
    case default
      fs = s; fc = c; fd = d
    end select
    if (want_am) fa = am_of(fs, fc)
  end subroutine finalize

  !> Taylor coefficients (degree ntay) of the final sn, cn, dn, am about t, from the
  !> ODEs sn' = cn dn, cn' = -sn dn, dn' = -m sn cn of the core (DLMF 22.13).
  pure subroutine taylor_at(plan, t, tab)
    type(jpar_t), intent(in) :: plan
    real(wp), intent(in) :: t
    real(wp), intent(out) :: tab(0:ntay, 4)
    real(wp) :: s(0:ntay), c(0:ntay), d(0:ntay), r(0:ntay), fs, fc, fd, fa, acc1, acc2, acc3
    integer :: k, i
    call core_at(plan, t, s(0), c(0), d(0))
    do k = 0, ntay - 1
      acc1 = 0; acc2 = 0; acc3 = 0
      do i = 0, k
        acc1 = acc1 + c(i) * d(k - i)
        acc2 = acc2 + s(i) * d(k - i)
        acc3 = acc3 + s(i) * c(k - i)
      end do
      s(k + 1) = acc1 / (k + 1)
      c(k + 1) = -acc2 / (k + 1)
      d(k + 1) = -plan%m * acc3 / (k + 1)
    end do
    call finalize(plan, s(0), c(0), d(0), .true., fs, fc, fd, fa)
    select case (plan%kind)
    case (2)
      tab(:, 1) = plan%oscale * s
      tab(:, 2) = d
      tab(:, 3) = c
      tab(1:, 4) = plan%oscale * c(0:ntay-1) / [(real(k, wp), k = 1, ntay)]
    case (3)
      r(0) = 1 / d(0)
      do k = 1, ntay
        acc1 = 0
        do i = 1, k
          acc1 = acc1 + d(i) * r(k - i)
        end do
        r(k) = -acc1 * r(0)
      end do
      do k = 0, ntay
        acc1 = 0; acc2 = 0
        do i = 0, k
          acc1 = acc1 + s(i) * r(k - i)
          acc2 = acc2 + c(i) * r(k - i)
        end do
        tab(k, 1) = plan%oscale * acc1
        tab(k, 2) = acc2
      end do
      tab(:, 3) = r
      tab(1:, 4) = plan%oscale * r(0:ntay-1) / [(real(k, wp), k = 1, ntay)]
    case default
      tab(:, 1) = s
      tab(:, 2) = c
      tab(:, 3) = d
      tab(1:, 4) = d(0:ntay-1) / [(real(k, wp), k = 1, ntay)]
    end select
    ! the values themselves from the accurate path (cancellation-free cd etc.)
    tab(0, 1) = fs; tab(0, 2) = fc; tab(0, 3) = fd; tab(0, 4) = fa
  end subroutine taylor_at

  pure subroutine eval_plan(plan, u, exact_k, want_am, sn, cn, dn, am, tab, ntab)
    type(jpar_t), intent(in) :: plan
    real(wp), intent(in), optional :: tab(0:, :, 0:)
    integer, intent(in), optional :: ntab
    real(wp), intent(in) :: u
    logical, intent(in) :: exact_k, want_am
    real(wp), intent(out) :: sn, cn, dn, am
    real(wp) :: v, vl, n, khi, klo, p, e, r, t, ex, fs, fc, fd, fa, del
    integer :: j, parity
    if (plan%kind < 0 .or. ieee_is_nan(u)) then
      sn = qnan(); cn = sn; dn = sn; am = sn
      return
    end if
    if (plan%kind == 1) then
      ! m = 1: sn = tanh, cn = dn = sech, am = gd(u)
      sn = tanh(u)
      if (abs(u) < 20) then
        cn = 1 / cosh(u)
      else
        ex = exp(-abs(u))      ! sech without overflow, subnormal tail kept
        cn = 2 * ex / (1 + ex * ex)
      end if
      dn = cn
      am = 0
      if (want_am) am = am_of(sn, cn)
      return
    end if
    if (.not. ieee_is_finite(u)) then
      sn = qnan(); cn = sn; dn = sn; am = sn
      return
    end if
    v = abs(u) * plan%uscale
    khi = plan%khi; klo = plan%klo
    n = 0
    parity = 0
    r = v
    if (.not. v <= huge(v)) then
      ! |u| sqrt(|m|) or |u| sqrt(1 - m) overflows (|m| > ~1e300, |u| > ~1e150): the
      ! phase u mod 2K is far below the resolution of u (the condition number is ~ |u|
      ! sqrt|m| there), so any point of the period is within eps*cond; take r = 0
      r = 0
    else if (v > khi) then
      ! u * scale and n * 2K both in extra precision: large u keeps its digits
      vl = 0
      if (plan%kind /= 0) then
        call two_prod(abs(u), plan%uscale, v, vl)
        vl = vl + abs(u) * plan%uscale_lo
      end if
      n = anint(v / (2 * khi))
      if (.not. exact_k .and. n > 4) then
        call kdd(plan%mc, plan%mcl, khi, klo)
        n = anint(v / (2 * khi))
      end if
      if (n < 2.0_wp**26) then
        ! Cody-Waite: 2K = c1 + c2 + 2 klo with c1, c2 of 26 bits, so n*c1, n*c2 are exact
        call two_prod_split(2 * khi, p, e)
        r = (((v - n * p) - n * e) + vl) - n * (2 * klo)
      else
        call two_prod(n, 2 * khi, p, e)
        r = (((v - p) - e) + vl) - n * (2 * klo)
      end if
      if (n < 1.0e15_wp) then
        parity = int(mod(int(n, kind=8), 2_8))
      else
        parity = merge(1, 0, mod(n, 2.0_wp) /= 0)
      end if
    end if
    if (.not. (abs(r) <= 1.5_wp * khi)) then
      ! only when n*2K outruns the double-double K (|u| > ~1e15 K): the phase is then
      ! below the resolution of u itself (error within eps*cond); keep r in range
      r = modulo(r, 2 * khi)
      if (r > khi) r = r - 2 * khi
      if (.not. (abs(r) <= 1.5_wp * khi)) r = 0
    end if
    t = abs(r)
    if (present(tab)) then
      j = tab_index(t, ntab)
      del = t - j * tab_step
      fs = horner(tab(:, 1, j), del)
      fc = horner(tab(:, 2, j), del)
      fd = horner(tab(:, 3, j), del)
      fa = 0
      if (want_am) fa = horner(tab(:, 4, j), del)
    else
      call final_at(plan, t, want_am, fs, fc, fd, fa)
    end if
    fs = sign(fs, r)
    fa = sign(fa, r)
    if (parity /= 0) then
      select case (plan%kind)
      case (2)
        fs = -fs; fd = -fd; fa = -fa
      case default
        fs = -fs; fc = -fc
      end select
    end if
    if (plan%kind /= 2) fa = fa + n * pi
    if (u < 0) then
      fs = -fs
      fa = -fa
    end if
    sn = fs; cn = fc; dn = fd; am = fa
  end subroutine eval_plan

  !> Table row 0..ntab nearest to the core argument t >= 0; t beyond the table or NaN
  !> gives ntab (the compare comes before int(), so no NaN or huge value is converted).
  pure elemental integer function tab_index(t, ntab) result(j)
    real(wp), intent(in) :: t
    integer, intent(in) :: ntab
    real(wp) :: x
    x = t * tab_inv_step + 0.5_wp
    if (x >= 0 .and. x < ntab) then
      j = int(x)
    else if (x >= 0) then
      j = ntab
    else
      j = 0
    end if
  end function tab_index

  !> True (with status set and every output NaN) when sn, cn, dn or am (if present) does
  !> not have n elements: the array routines check before writing anything.
  pure subroutine outputs_mismatch(name, n, sn, cn, dn, status, bad, am)
    character(len=*), intent(in) :: name
    integer, intent(in) :: n
    real(wp), intent(inout) :: sn(:), cn(:), dn(:)
    type(status_t), intent(inout) :: status
    logical, intent(out) :: bad
    real(wp), intent(inout), optional :: am(:)
    bad = size(sn) /= n .or. size(cn) /= n .or. size(dn) /= n
    if (present(am)) bad = bad .or. size(am) /= n
    if (.not. bad) return
    sn = qnan(); cn = qnan(); dn = qnan()
    if (present(am)) am = qnan()
    call set_error(status, PENDULA_ERR_SIZE, name // ': sn, cn, dn and am must have the size of u')
  end subroutine outputs_mismatch

  pure real(wp) function horner(p, x) result(y)
    real(wp), intent(in) :: p(0:ntay), x
    real(wp) :: x2, x4
    ! Estrin's scheme for degree ntay = 8
    x2 = x * x
    x4 = x2 * x2
    y = ((p(0) + p(1) * x) + (p(2) + p(3) * x) * x2) + ((p(4) + p(5) * x) + (p(6) + p(7) * x) * x2) * x4 &
        + p(8) * (x4 * x4)
  end function horner

  !> Jacobi elliptic functions sn(u|m), cn(u|m), dn(u|m) and the amplitude am(u|m)
  !> (rad, optional) for all real u and all real m (m = k**2; m < 0 and m > 1 by the
  !> modulus transformations; for m > 1 am = asin-branch atan2(sn, cn)).  NaN in gives
  !> NaN out.  Accuracy: a few eps times the condition number; u is reduced
  !> modulo 2K with K in double-double, so large |u| does not lose u*eps.
  elemental subroutine ellipj(u, m, sn, cn, dn, am)
    real(wp), intent(in) :: u, m
    real(wp), intent(out) :: sn, cn, dn
    real(wp), intent(out), optional :: am
    real(wp) :: a
    call eval_plan(make_par(m, 1 - m, .false., .false.), u, .false., present(am), sn, cn, dn, a)
    if (present(am)) am = a
  end subroutine ellipj

  !> ellipj over rank-1 arrays u, m (and outputs) of one size: the same numbers as the
  !> elemental form, in one loop inside this module.  A size mismatch sets status
  !> (PENDULA_ERR_SIZE) and the outputs to NaN.
  pure subroutine ellipj_array(u, m, sn, cn, dn, status, am)
    real(wp), intent(in) :: u(:), m(:)
    real(wp), intent(out) :: sn(:), cn(:), dn(:)
    type(status_t), intent(out) :: status
    real(wp), intent(out), optional :: am(:)
    real(wp) :: a
    integer :: i
    logical :: bad
    logical :: done
    call outputs_mismatch('ellipj_array', size(u), sn, cn, dn, status, bad, am)
    if (bad) return
    if (size(m) /= size(u)) then
      sn = qnan(); cn = qnan(); dn = qnan()
      if (present(am)) am = qnan()
      call set_error(status, PENDULA_ERR_SIZE, 'ellipj_array: m must have the size of u')
      return
    end if
    do i = 1, size(u)
      done = .false.
      if (.not. (ieee_is_nan(m(i)) .or. ieee_is_nan(u(i)))) then
        if (m(i) >= 0 .and. m(i) < 1) call jac01(u(i), m(i), present(am), sn(i), cn(i), dn(i), a, done)
      end if
      if (.not. done) call eval_plan(make_par(m(i), 1 - m(i), .false., .false.), u(i), .false., &
          present(am), sn(i), cn(i), dn(i), a)
      if (present(am)) am(i) = a
    end do
  end subroutine ellipj_array

  !> ellipj for 0 <= m < 1 and |u| < 9 K (the common case) with all work inline; the same
  !> steps as make_par + eval_plan.  done = .false. leaves the point to the general path.
  pure subroutine jac01(u, m, want_am, sn, cn, dn, am, done)
    real(wp), intent(in) :: u, m
    logical, intent(in) :: want_am
    real(wp), intent(out) :: sn, cn, dn, am
    logical, intent(out) :: done
    real(wp) :: mc, k, v, n, r, t, c1, c2, s, c, d, ps, su, cs(0:6), cc(0:6), cd(0:6)
    mc = 1 - m
    k = kpair(m, mc)
    v = abs(u)
    ! no branch on v > K: n = 0 leaves r = v exactly (random u makes that test unpredictable)
    n = anint(v / (2 * k))
    if (.not. n <= 4) then
      done = .false.
      sn = 0; cn = 0; dn = 0; am = 0
      return
    end if
    call two_prod_split(2 * k, c1, c2)
    r = (v - n * c1) - n * c2
    t = abs(r)
    call series_coeffs(m, cs, cc, cd)
    call core_at2(m, mc, k, 0.0_wp, cs, cc, cd, t, s, c, d)
    ! signs by merge (blends, not branches): the parity of n and the sign of u are random
    ps = merge(-1.0_wp, 1.0_wp, iand(int(n), 1) /= 0)
    su = merge(-1.0_wp, 1.0_wp, u < 0)
    am = 0
    if (want_am) am = (sign(am_of(s, c), r) + n * pi) * su
    sn = sign(s, r) * (ps * su); cn = c * ps; dn = d
    done = .true.
  end subroutine jac01

  !> ellipjc over rank-1 arrays (same numbers as the elemental form); sizes as ellipj_array.
  pure subroutine ellipjc_array(u, mc, sn, cn, dn, status, am)
    real(wp), intent(in) :: u(:), mc(:)
    real(wp), intent(out) :: sn(:), cn(:), dn(:)
    type(status_t), intent(out) :: status
    real(wp), intent(out), optional :: am(:)
    real(wp) :: a
    integer :: i
    logical :: bad
    call outputs_mismatch('ellipjc_array', size(u), sn, cn, dn, status, bad, am)
    if (bad) return
    if (size(mc) /= size(u)) then
      sn = qnan(); cn = qnan(); dn = qnan()
      if (present(am)) am = qnan()
      call set_error(status, PENDULA_ERR_SIZE, 'ellipjc_array: mc must have the size of u')
      return
    end if
    do i = 1, size(u)
      call eval_plan(make_par(1 - mc(i), mc(i), .true., .false.), u(i), .false., present(am), &
          sn(i), cn(i), dn(i), a)
      if (present(am)) am(i) = a
    end do
  end subroutine ellipjc_array

  !> Jacobi functions with the complementary parameter mc = 1 - m (any real mc;
  !> accurate near m = 1 including the smallest subnormal mc; mc = 0 gives tanh/sech).
  elemental subroutine ellipjc(u, mc, sn, cn, dn, am)
    real(wp), intent(in) :: u, mc
    real(wp), intent(out) :: sn, cn, dn
    real(wp), intent(out), optional :: am
    real(wp) :: a
    call eval_plan(make_par(1 - mc, mc, .true., .false.), u, .false., present(am), sn, cn, dn, a)
    if (present(am)) am = a
  end subroutine ellipjc

end module pendula_elliptic
