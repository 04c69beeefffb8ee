//! Flight conditions beyond hover: forward flight and climb.
//!
//! A [`FlightCondition`] is the body's steady velocity through still air, world frame: a
//! forward speed U along world x (the vehicle flies nose first, no sideslip: a left-right
//! symmetric vehicle trims in its plane of symmetry) and a climb rate W along world z (up).
//! Hover is U = W = 0. At a condition three things change from hover:
//!
//! - The wings see the body's velocity: the cycle-averaged loads are taken at the frozen
//!   state with that velocity ([`crate::averaged::FrozenState`]).
//! - The body feels parasite drag, 0.5 rho |V| V C_D S against its velocity V, at the centre
//!   of mass, with C_D S the model's `[body] drag_area_m2` (0: none).
//! - The induced inflow (`[aero] induced_inflow`) follows Glauert's momentum theory
//!   ([`wingforce::inflow`]): the wake shed at the condition, frozen there like the hover
//!   downwash, for the force the wings must carry (weight plus body drag).
//!
//! Power ([`Power`]) is what the wings' drive spends against the air: the cycle mean of
//! P(t) = - sum over wings of M_hinge(t) . omega_wing(t) (the aerodynamic moment about each
//! hinge and the wing's angular velocity relative to the body). In steady flight it includes
//! the body's parasite power: the wings push the body against its drag and the drive pays.

pub mod condition;
pub mod point;
pub mod power;

pub use condition::FlightCondition;
pub use point::{LimitMargin, TrimPoint, limit_margin, stroke_plane_angle_rad, trim_point};
pub use power::{Power, cycle_power, power_at, wing_power_w};
