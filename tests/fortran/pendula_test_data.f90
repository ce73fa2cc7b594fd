!> Reference values shared by several Fortran test programs (test code, not library).
module pendula_test_data
  use pendula_kinds, only: wp
  implicit none
  private
  public :: text_w0, text_ref_theta, text_ref_omega

  !> The text's section 2.2 pendulum: w0 = sqrt(g/l), g = 9.8 m/s^2, l = 4.9 m [1/s].
  real(wp), parameter :: text_w0 = sqrt(9.8_wp/4.9_wp)

  !> mpmath.odefun, 30 digits (tests/data/integrators_reference.csv): theta [rad]
  !> and Omega [rad/s] of the text's scene (theta0 = 0, Omega0 = 2 rad/s) at
  !> t = 10, 20, 30 s for b = 0.01 (gamma = 0.1 1/s, column 1) and b = 0.05
  !> (gamma = 0.5 1/s, column 2).
  real(wp), parameter :: text_ref_theta(3, 2) = reshape([ &
                                            0.2400126145763811213858_wp, 0.5344712913225421240946_wp, 0.1179274468147600127087_wp, &
                               0.1000924483346291624116_wp, 0.007455571654278061090688_wp, -0.0004083907732093957465404_wp], [3, 2])
  real(wp), parameter :: text_ref_omega(3, 2) = reshape([ &
                                            1.184454667053134559653_wp, 0.1191161960216510483342_wp, -0.4375926992513724250281_wp, &
                              0.07323844044153948735306_wp, -0.01125299113151889803706_wp, -0.0008961503710664712388837_wp], [3, 2])
end module pendula_test_data
