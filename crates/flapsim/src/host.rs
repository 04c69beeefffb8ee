//! The wing set on a body in your own rapier world.
//!
//! [`RapierWings`] attaches a [`WingSet`] to any [`RigidBodyHandle`] of the user's
//! [`RigidBodySet`]. Before each step of the user's `PhysicsPipeline` (with the wing set's
//! time step as `IntegrationParameters::dt`), [`RapierWings::apply`] reads the body's state,
//! steps the wings, and sets the body's user force and torque to the wings' loads (rapier keeps
//! user forces until reset); after it, [`RapierWings::after_step`] moves the pose to the
//! trapezoidal rule under a second-order load sampling, so that the body follows flapsim's own
//! `Simulation` to round-off (`flapsim/tests/rapier_host.rs`). The world may hold anything
//! else: ground, obstacles, other vehicles with their own wing sets.
//!
//! Frames: the wing set's body frame is the rapier body's local frame, its origin the
//! vehicle's centre of mass. A body whose rapier centre of mass is elsewhere (colliders with
//! density) gets the moment transferred to it and the origin's velocity read off the rigid
//! motion, so the loads stay the model's. glam meets nalgebra only in [`crate::frames`].

use nalgebra::Vector3;
use rapier3d_f64::prelude::*;

use crate::error::{Error, Result};
use crate::frames::{from_glam, matrix_from_glam, quat_from_glam, quat_to_glam, to_glam};
use crate::model::Vehicle;
use crate::wings::{FromVehicle, State, WingSet, WingSetOutput};

/// A rigid-body builder for a vehicle: dynamic, its mass and inertia about its centre of
/// mass at the body origin, its initial pose and velocities, never asleep. Add colliders
/// with zero density so that they leave the mass properties to the model.
pub fn vehicle_body(vehicle: &Vehicle) -> RigidBodyBuilder {
    let i = &vehicle.inertia_kg_m2;
    let inertia = Matrix::from_cols_array(&[
        i[(0, 0)],
        i[(1, 0)],
        i[(2, 0)],
        i[(0, 1)],
        i[(1, 1)],
        i[(2, 1)],
        i[(0, 2)],
        i[(1, 2)],
        i[(2, 2)],
    ]);
    // parry's `with_inertia_matrix` diagonalizes the tensor, and for some tensors its
    // principal frame comes out wrong: a diagonal [4.3e-13, 8.1e-14, 3.53e-13] pitched
    // exactly as [8.1e-14, 4.3e-13, 3.53e-13], and the hummingbird's tensor (with its Ixz)
    // with any Iyy above its Ixx pitched as one whose Iyy is its Ixx (both found by
    // flapwing-identify's inertia fits). Its result is kept where it reproduces the tensor
    // (so runs of models it got right stay bit for bit those of earlier versions and their
    // logs); a diagonal tensor it gets wrong is given as its own principal frame, any other
    // as nalgebra's symmetric eigen-decomposition.
    let parry = MassProperties::with_inertia_matrix(Vector::ZERO, vehicle.mass_kg, inertia);
    let props = if reproduces(&parry, &inertia) {
        parry
    } else if i[(0, 2)] == 0.0 && i[(2, 0)] == 0.0 {
        MassProperties::new(
            Vector::ZERO,
            vehicle.mass_kg,
            Vector::new(i[(0, 0)], i[(1, 1)], i[(2, 2)]),
        )
    } else {
        let (moments, body_from_principal) = principal_axes(i);
        MassProperties::with_principal_inertia_frame(
            Vector::ZERO,
            vehicle.mass_kg,
            to_glam(&moments),
            quat_to_glam(&body_from_principal),
        )
    };
    let q = quat_to_glam(&vehicle.initial_attitude);
    RigidBodyBuilder::dynamic()
        .pose(Pose::from_parts(to_glam(&vehicle.initial_position_m), q))
        .additional_mass_properties(props)
        .can_sleep(false)
        .allow_fast_rotation(true)
        .linvel(to_glam(&vehicle.initial_velocity_m_s))
        .angvel(to_glam(
            &(vehicle.initial_attitude * vehicle.initial_angular_velocity_rad_s),
        ))
}

/// The principal moments of the inertia tensor `i` (body axes) and the rotation from its
/// principal axes to the body's (a proper rotation: a reflected eigenvector is flipped).
fn principal_axes(i: &nalgebra::Matrix3<f64>) -> (Vector3<f64>, nalgebra::UnitQuaternion<f64>) {
    let eig = nalgebra::SymmetricEigen::new(*i);
    let mut axes = eig.eigenvectors;
    if axes.determinant() < 0.0 {
        axes.column_mut(2).neg_mut();
    }
    let rotation = nalgebra::Rotation3::from_matrix_unchecked(axes);
    (
        eig.eigenvalues,
        nalgebra::UnitQuaternion::from_rotation_matrix(&rotation),
    )
}

/// True when two inertia tensors agree to 1e-9 of the larger one's largest entry (the
/// tolerance of [`reproduces`]).
fn same_tensor(a: &nalgebra::Matrix3<f64>, b: &nalgebra::Matrix3<f64>) -> bool {
    let scale = a.amax().max(b.amax());
    (a - b).amax() <= 1e-9 * scale
}

/// True when mass properties' principal moments in their principal frame give back the
/// inertia tensor `inertia` (to 1e-9 of its largest entry).
fn reproduces(props: &MassProperties, inertia: &Matrix) -> bool {
    let r = Matrix::from_quat(props.principal_inertia_local_frame);
    let back = r * Matrix::from_diagonal(props.principal_inertia()) * r.transpose();
    let a = back.to_cols_array();
    let b = inertia.to_cols_array();
    let scale = b.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    a.iter().zip(&b).all(|(x, y)| (x - y).abs() <= 1e-9 * scale)
}

/// The state of a rapier body in the wing set's terms: the body origin's position and
/// velocity (world), its attitude, its angular velocity in the body frame.
pub fn body_state(rb: &RigidBody) -> State {
    let q = quat_from_glam(rb.rotation());
    let origin = from_glam(rb.translation());
    let w_world = from_glam(rb.angvel());
    // rapier's linear velocity is its centre of mass's.
    let mut velocity_m_s = from_glam(rb.linvel());
    if let Some(arm) = origin_from_com_world(rb) {
        velocity_m_s += w_world.cross(&arm);
    }
    State {
        position_m: origin,
        world_from_body: q,
        velocity_m_s,
        angular_velocity_body_rad_s: q.inverse() * w_world,
    }
}

/// The world torque to hand rapier for a step whose loads represent it (a second-order load
/// sampling, `wingset::sampling`), so that the body's angular velocity is second order too.
///
/// rapier updates the angular velocity as w_{k+1} = w_k + dt I_w(t_k)^-1 tau, with the world
/// inertia I_w = R I R^T at the step's start and its own explicit gyroscopic correction at the
/// step's start. Euler's equations in the world frame, dw/dt = R I^-1 (tau_b - w_b x I w_b),
/// need both at the step's midpoint: with the start's, a body turning about more than one axis
/// is first order (measured on the fly with a 1 deg left-right amplitude difference: 1.83x and
/// 1.97x per halved step over 10 wingbeats; with this torque and rapier's gyroscopic term off,
/// 3.99x and 4.00x: `flapsim/tests/second_order.rs`). A turn about a principal axis alone
/// (the symmetric flights) was second order already. So rapier is handed
/// tau' = I_w(t_k) R_mid I^-1 (tau_b,mid - w_mid x I w_mid), with the body's midpoint attitude
/// R_mid and rates w_mid the wing set took its loads at ([`WingSet::sampled_state`]):
/// `moment_world` the loads' moment (world), `start` the attitude at the step's start,
/// `inertia_kg_m2` the body's inertia about its centre of mass, body frame. The body's own
/// gyroscopic forces must be off (`RigidBody::enable_gyroscopic_forces(false)`).
pub fn midpoint_torque_world(
    moment_world: &Vector3<f64>,
    start: &nalgebra::UnitQuaternion<f64>,
    mid: &State,
    inertia_kg_m2: &nalgebra::Matrix3<f64>,
) -> Vector3<f64> {
    let (q_mid, w) = (mid.world_from_body, mid.angular_velocity_body_rad_s);
    let Some(i_inv) = inertia_kg_m2.try_inverse() else {
        return *moment_world;
    };
    let tau_b = q_mid.inverse() * moment_world;
    let alpha_world = q_mid * (i_inv * (tau_b - w.cross(&(inertia_kg_m2 * w))));
    let r = start.to_rotation_matrix();
    let torque = r * (inertia_kg_m2 * (r.inverse() * alpha_world));
    // A body spinning past any bound overflows w x I w: hand rapier the loads' moment, so
    // that the run's own check names the bound it broke at the next step.
    match torque.iter().all(|x| x.is_finite()) {
        true => torque,
        false => *moment_world,
    }
}

/// Moves the pose rapier integrated over a step from `before` (the body's state at the
/// step's start) to the trapezoidal rule's (second-order stepping, `wingset::sampling`).
/// rapier's semi-implicit Euler moves the body by dt v_{k+1} (in `substeps` sub-steps of h:
/// by h v at each one's end); with the wings' loads the step's means, v_{k+1} is second-order
/// accurate, and the pose x_k + dt (v_k + v_{k+1})/2 then is too, where dt v_{k+1} leaves a
/// bias of dt/2 (v(t) - v(0)) in position and attitude (first order, measured: the fly's hover
/// excursion error fell only 3.9x from 100 to 400 steps per wingbeat without this, 0.09% at
/// 100). With a constant load the pose leads the trapezoidal rule's by h/2 (v_{k+1} - v_k);
/// likewise the attitude is turned back by h/2 (omega_{k+1} - omega_k), world frame.
pub(crate) fn trapezoid_pose(rb: &mut RigidBody, before: &State, dt_s: f64, substeps: usize) {
    let after = body_state(rb);
    let half = 0.5 * dt_s / substeps.max(1) as f64;
    let w0 = before.world_from_body * before.angular_velocity_body_rad_s;
    let w1 = after.world_from_body * after.angular_velocity_body_rad_s;
    let position_m = after.position_m - half * (after.velocity_m_s - before.velocity_m_s);
    let world_from_body =
        nalgebra::UnitQuaternion::from_scaled_axis(-half * (w1 - w0)) * after.world_from_body;
    rb.set_position(
        Pose::from_parts(to_glam(&position_m), quat_to_glam(&world_from_body)),
        false,
    );
}

/// The body origin relative to rapier's centre of mass, world frame, or `None` where they
/// coincide (every body [`vehicle_body`] builds). Taken from the local centre of mass and the
/// pose, not `RigidBody::center_of_mass`, which rapier updates only when it steps.
fn origin_from_com_world(rb: &RigidBody) -> Option<Vector3<f64>> {
    let local_com = from_glam(rb.local_center_of_mass());
    (local_com != Vector3::zeros()).then(|| quat_from_glam(rb.rotation()) * -local_com)
}

/// A wing set attached to a body of the user's rapier world (see the module documentation).
#[derive(Debug, Clone)]
pub struct RapierWings {
    body: RigidBodyHandle,
    wings: WingSet,
    /// The body's state the last [`RapierWings::apply`] read (the step's start), for
    /// [`RapierWings::after_step`].
    start: Option<State>,
}

impl RapierWings {
    /// Attaches `wings` to `body`, which must be in `bodies` and dynamic. Under a
    /// second-order sampling the host moves the body by the trapezoidal rule
    /// ([`RapierWings::after_step`]), so the wings share a stop strike's impulse between
    /// steps for that pose (wingset's `actuated::StrikeShare::TrapezoidalPose`), unless the
    /// vehicle they were built from names its own rule (a replay's, [`crate::SimSpec`]'s
    /// `strike_share`).
    pub fn attach(
        bodies: &RigidBodySet,
        body: RigidBodyHandle,
        mut wings: WingSet,
    ) -> Result<Self> {
        let named = wings.vehicle().and_then(|v| v.sim.strike_share);
        match named {
            Some(share) => wings.set_strike_share(share),
            None if wings.load_sampling().is_second_order() => {
                wings.set_strike_share(wingset::actuated::StrikeShare::TrapezoidalPose)
            }
            None => {}
        }
        match bodies.get(body) {
            None => Err(Error::Input(format!(
                "rapier host: body handle {:?} is not in the rigid-body set; allowed: a handle returned by RigidBodySet::insert that was not removed",
                body.into_raw_parts()
            ))),
            Some(rb) if !rb.is_dynamic() => Err(Error::Input(format!(
                "rapier host: body handle {:?} is {:?}; allowed: a dynamic body (the wings push it)",
                body.into_raw_parts(),
                rb.body_type()
            ))),
            Some(_) => Ok(Self {
                body,
                wings,
                start: None,
            }),
        }
    }

    /// The body the wings push.
    pub fn body(&self) -> RigidBodyHandle {
        self.body
    }
    /// The wing set.
    pub fn wings(&self) -> &WingSet {
        &self.wings
    }
    /// The wing set, to set controls, wind or kinematics.
    pub fn wings_mut(&mut self) -> &mut WingSet {
        &mut self.wings
    }

    /// Steps the wings from the body's state now and sets the body's user force and torque
    /// to their loads (replacing the body's user force: add your own after this call). Call
    /// once before every pipeline step, with `IntegrationParameters::dt` equal to the wing
    /// set's [`WingSet::dt_s`].
    pub fn apply(&mut self, bodies: &mut RigidBodySet) -> Result<&WingSetOutput> {
        let Some(rb) = bodies.get_mut(self.body) else {
            return Err(Error::Input(format!(
                "rapier host: body handle {:?} is no longer in the rigid-body set (removed?)",
                self.body.into_raw_parts()
            )));
        };
        let state = body_state(rb);
        self.start = None;
        self.wings.step(&state)?;
        self.start = Some(state);
        let out = self.wings.output();
        let q = state.world_from_body;
        let force_world = q * out.total.force_n;
        // Moment about the body origin (the model's CoM) moved to rapier's centre of mass.
        let mut moment_world: Vector3<f64> = q * out.total.moment_nm;
        if let Some(arm) = origin_from_com_world(rb) {
            moment_world += arm.cross(&force_world);
        }
        // Under a second-order sampling the angular velocity is advanced by the midpoint
        // rule ([`midpoint_torque_world`]), the body's own gyroscopic forces off.
        let torque_world = if self.wings.load_sampling().is_second_order() {
            rb.enable_gyroscopic_forces(false);
            let body = matrix_from_glam(
                &rb.mass_properties()
                    .local_mprops
                    .reconstruct_inertia_matrix(),
            );
            // The model's tensor where the body carries it (a `vehicle_body`: rapier keeps it
            // as principal moments in a frame that gives it back to 1e-9, `reproduces`), or
            // before rapier has computed the body's mass properties (its first pipeline step
            // comes after this call: they read zero), as flapsim's `Simulation` takes it;
            // else the body's own.
            let inertia = match crate::wings::FromVehicle::vehicle(&self.wings) {
                Some(v)
                    if body == nalgebra::Matrix3::zeros()
                        || same_tensor(&v.inertia_kg_m2, &body) =>
                {
                    v.inertia_kg_m2
                }
                _ => body,
            };
            midpoint_torque_world(&moment_world, &q, self.wings.sampled_state(), &inertia)
        } else {
            moment_world
        };
        rb.reset_forces(false);
        rb.reset_torques(false);
        rb.add_force(to_glam(&force_world), false);
        rb.add_torque(to_glam(&torque_world), false);
        Ok(self.wings.output())
    }

    /// Call after the pipeline step that followed [`RapierWings::apply`]: under a second-order
    /// load sampling it moves the pose rapier integrated to the trapezoidal rule's, as flapsim's
    /// own `Simulation` does (`trapezoid_pose` in this module); without it the pose stays
    /// first order (it lags by dt/2 (v - v_0)). `params`: the pipeline's integration
    /// parameters (its solver iterations are rapier's sub-steps). Nothing under the
    /// step-start sampling, or when no `apply` came before.
    pub fn after_step(
        &mut self,
        bodies: &mut RigidBodySet,
        params: &IntegrationParameters,
    ) -> Result<()> {
        let Some(before) = self.start.take() else {
            return Ok(());
        };
        if !self.wings.load_sampling().is_second_order() {
            return Ok(());
        }
        let Some(rb) = bodies.get_mut(self.body) else {
            return Err(Error::Input(format!(
                "rapier host: body handle {:?} is no longer in the rigid-body set (removed?)",
                self.body.into_raw_parts()
            )));
        };
        trapezoid_pose(rb, &before, self.wings.dt_s(), params.num_solver_iterations);
        Ok(())
    }
}
