!> Umbrella module: `use pendula` gives the whole public Fortran API.
module pendula
  use pendula_kinds
  use pendula_status
  use pendula_control, only: CONTROL_SIZE, CONTROL_CANCEL, CONTROL_PROGRESS
  use pendula_physics
  ! <concern modules: one `use` line each, kept in architecture order>
  use pendula_elliptic
  use pendula_undamped
  use pendula_small_angle
  use pendula_equilibria
  use pendula_linear_damped
  use pendula_integrators
  use pendula_scene
  implicit none
  public
end module pendula
