//! One wing: geometry, kinematics and mount, prepared for fast force evaluation. Here the
//! wing, its builder, its settings and the cache it refreshes when they change; its
//! evaluation is in `evaluate`.
//!
//! Frames (MODEL.md section 1): the body frame is x forward, y left, z up. Each wing has a
//! stroke-plane frame with its origin at the hinge, obtained from the body frame by a rotation
//! about body y by the stroke-plane tilt (`body_from_stroke`); its z axis is the stroke-plane
//! normal, "lift" is along it. All per-step work happens in the stroke frame and the results
//! are rotated into the body frame once, at the end of [`Wing::evaluate`].

use nalgebra::{Matrix3, Rotation3, Vector3};

use crate::added_mass::AddedMassForm;
use crate::cache::{Cache, StripK};
use crate::coefficients::{self, TranslationalModel, WakeCaptureModel, WakeCaptureParams};
use crate::inflow::InducedInflow;
use crate::kinematics::Kinematics;
use crate::planform::Geometry;

pub use crate::forces::{KinematicLoads, StepKinematicLoads, WingForces};
pub use crate::frame::WingFrame;
pub use crate::mount::{BodyMotion, Fluid, Mount, Side};
pub use crate::terms::{Term, TermForce};

mod evaluate;
pub mod step_mean;

/// Which terms to compute and how.
#[derive(Debug, Clone, PartialEq)]
pub struct AeroOptions {
    /// Translational coefficient model.
    pub translational: TranslationalModel,
    /// Apply f_AR and f_Ro to the Lee et al. coefficients.
    pub ar_ro_corrections: bool,
    /// Include the rotational (Van Veen) term.
    pub rotational: bool,
    /// The added-mass term's form ([`AddedMassForm`]).
    pub added_mass: AddedMassForm,
    /// The wake-capture model, or `None` to switch the term off.
    pub wake_capture: Option<WakeCaptureModel>,
    /// Van Veen et al.'s rotational coefficient C_rot (2.08 +- 0.13).
    pub c_rot: f64,
    /// The induced inflow through the stroke plane (see [`crate::inflow`]), or `None` for
    /// still air (the default).
    pub induced_inflow: Option<InducedInflow>,
}

impl Default for AeroOptions {
    fn default() -> Self {
        Self {
            translational: TranslationalModel::Lee2016,
            ar_ro_corrections: true,
            rotational: true,
            added_mass: AddedMassForm::default(),
            wake_capture: Some(WakeCaptureModel::paper()),
            c_rot: 2.08,
            induced_inflow: None,
        }
    }
}

/// A wing ready to evaluate: everything that depends only on Re, the planform or the
/// kinematics parameters is computed here, once, not per step.
#[derive(Debug, Clone, PartialEq)]
pub struct Wing {
    geometry: Geometry,
    kinematics: Kinematics,
    mount: Mount,
    fluid: Fluid,
    options: AeroOptions,
    /// Measured stroke in place of the kinematics' own (dynamic wings).
    stroke_reference: Option<StrokeReference>,
    pub(crate) cache: Cache,
}

/// The stroke quantities that set Re and the wake-capture inputs, for a wing whose stroke is
/// an output of its dynamics rather than prescribed: measured from the motion the dynamics
/// produce (peak stroke rate, and dtau_A / dtau_D by the half-peak rule of
/// [`crate::kinematics::measure_acceleration_fractions`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StrokeReference {
    /// Peak |d phi / dt| over the wingbeat, rad/s.
    pub peak_stroke_rate_rad_s: f64,
    /// Acceleration fraction dtau_A.
    pub dtau_a: f64,
    /// Deceleration fraction dtau_D.
    pub dtau_d: f64,
}

/// Builds a [`Wing`] (see [`Wing::builder`]).
#[derive(Debug, Clone)]
pub struct WingBuilder {
    geometry: Geometry,
    kinematics: Kinematics,
    mount: Mount,
    fluid: Fluid,
    options: AeroOptions,
}

impl WingBuilder {
    /// Where the wing is attached (default: a fixed left mount at the origin).
    pub fn mount(mut self, mount: Mount) -> Self {
        self.mount = mount;
        self
    }
    /// The fluid (default: air at 20 C).
    pub fn fluid(mut self, fluid: Fluid) -> Self {
        self.fluid = fluid;
        self
    }
    /// Term switches and models (default: all four terms, Lee et al. translational).
    pub fn options(mut self, options: AeroOptions) -> Self {
        self.options = options;
        self
    }
    /// The prepared wing.
    pub fn build(self) -> Wing {
        let mut wing = Wing {
            geometry: self.geometry,
            kinematics: self.kinematics,
            mount: self.mount,
            fluid: self.fluid,
            options: self.options,
            stroke_reference: None,
            cache: Cache::empty(),
        };
        wing.refresh();
        wing
    }
}

impl Wing {
    /// Starts building a wing from its geometry and kinematics.
    pub fn builder(geometry: Geometry, kinematics: Kinematics) -> WingBuilder {
        WingBuilder {
            geometry,
            kinematics,
            mount: Mount::fixed(Side::Left),
            fluid: Fluid::AIR_20C,
            options: AeroOptions::default(),
        }
    }

    /// Recomputes the cached quantities after a change of kinematics, fluid or options.
    fn refresh(&mut self) {
        let g = &self.geometry;
        let rho = self.fluid.density_kg_m3;
        let v_ref = self.peak_stroke_rate_rad_s() * g.r_gyration_m;
        let re = v_ref * g.mean_chord_m / self.fluid.kinematic_viscosity_m2_s;
        let corr = if self.options.ar_ro_corrections
            && self.options.translational == TranslationalModel::Lee2016
        {
            coefficients::f_ar(g.aspect_ratio) * coefficients::f_ro(g.rossby)
        } else {
            1.0
        };
        let (kl, cd0, kd) = coefficients::lee2016_factors(re);
        let (da, dd) = match &self.stroke_reference {
            Some(r) => (r.dtau_a, r.dtau_d),
            None => self.kinematics.acceleration_fractions(),
        };
        let rot = Rotation3::from_axis_angle(&Vector3::y_axis(), self.mount.stroke_plane_tilt_rad);
        self.cache = Cache {
            strips: g
                .strips
                .iter()
                .map(|s| StripK {
                    r_m: s.r_m,
                    half_rho_area: 0.5 * rho * s.area_m2,
                    x_cp_m: s.x_cp_m,
                })
                .collect(),
            reynolds: re,
            v_ref_m_s: v_ref,
            q_ref_s_n: 0.5 * rho * v_ref * v_ref * g.area_m2,
            kl2: 2.0 * kl * corr,
            cd0: cd0 * corr,
            kd2: 2.0 * kd * corr,
            wake: self
                .options
                .wake_capture
                .as_ref()
                .map(|m| m.clamped(re, da, dd)),
            body_from_stroke: *rot.matrix(),
            stroke_from_body: *rot.inverse().matrix(),
            hinge_s: *rot.inverse().matrix() * self.mount.hinge_in_body_m,
            am_k: -0.25 * std::f64::consts::PI * rho,
            inflow_s: Vector3::z() * self.induced_downwash_m_s(),
            translational_inflow_s: Vector3::z() * self.induced_downwash_m_s(),
            inflow_gradient_per_s: nalgebra::Vector2::zeros(),
        };
    }

    /// The induced downwash through the stroke plane at the current amplitude, m/s (zero
    /// without [`AeroOptions::induced_inflow`]).
    /// In forward flight or climb ([`InducedInflow::flight_velocity_body_m_s`]) it is
    /// Glauert's ([`crate::inflow`]).
    pub fn induced_downwash_m_s(&self) -> f64 {
        self.options.induced_inflow.map_or(0.0, |i| {
            let normal_body =
                Rotation3::from_axis_angle(&Vector3::y_axis(), self.mount.stroke_plane_tilt_rad)
                    * Vector3::z();
            i.flight_downwash_m_s(
                self.fluid.density_kg_m3,
                self.kinematics.amplitude_rad,
                self.geometry.r_tip_m,
                &normal_body,
            )
        })
    }

    /// Sets the induced flow the translational term's strips meet (a dynamic inflow,
    /// [`crate::inflow::dynamic`], which the wing set holding this wing steps): the downwash
    /// at the hinge `at_hinge_m_s` and its gradient over the stroke plane `gradient_per_s`
    /// ((d w / d x, d w / d y), stroke frame, 1/s), so a strip at radius r meets
    /// w = at_hinge + gradient . (r e_span). The added mass keeps the wing's own
    /// [`AeroOptions::induced_inflow`] (the dynamic inflow's start), whose contribution to a
    /// periodic fluid impulse has zero cycle mean (MODEL.md 4.3). Changing the kinematics,
    /// fluid or options resets the field to that inflow.
    pub fn set_inflow_field(&mut self, at_hinge_m_s: f64, gradient_per_s: nalgebra::Vector2<f64>) {
        self.cache.translational_inflow_s = Vector3::z() * at_hinge_m_s;
        self.cache.inflow_gradient_per_s = gradient_per_s;
    }

    /// Takes `other`'s dynamic-inflow field ([`Self::set_inflow_field`]), exactly: a host
    /// that puts a wing back to an earlier state whose kinematics are its own (a wing set's
    /// `restore_state`) copies what changes from step to step, not the whole wing.
    pub fn copy_inflow_field_from(&mut self, other: &Wing) {
        self.cache.translational_inflow_s = other.cache.translational_inflow_s;
        self.cache.inflow_gradient_per_s = other.cache.inflow_gradient_per_s;
    }

    /// The dynamic-inflow field in use ([`Self::set_inflow_field`]): the downwash at the
    /// hinge as a stroke-frame vector, m/s, and its gradient over the stroke plane, 1/s.
    pub fn inflow_field(&self) -> (Vector3<f64>, nalgebra::Vector2<f64>) {
        (
            self.cache.translational_inflow_s,
            self.cache.inflow_gradient_per_s,
        )
    }

    /// The hinge's position in the stroke frame (the stroke plane through the hinge), m.
    pub fn hinge_in_stroke_m(&self) -> Vector3<f64> {
        self.cache.hinge_s
    }

    /// Replaces the kinematics (a controller does this between wingbeats).
    pub fn set_kinematics(&mut self, kinematics: Kinematics) {
        self.kinematics = kinematics;
        self.refresh();
    }

    /// Sets (or, with `None`, clears) a measured stroke that replaces the kinematics' own
    /// peak stroke rate and acceleration fractions in Re, V_ref and the wake-capture inputs
    /// (a dynamic wing's stroke is an output; see [`StrokeReference`]).
    pub fn set_stroke_reference(&mut self, reference: Option<StrokeReference>) {
        self.stroke_reference = reference;
        // The measured stroke moves Re and the wake-capture inputs, not the air: a dynamic
        // inflow's field ([`Self::set_inflow_field`]) stays as its wing set set it.
        let field = (
            self.cache.translational_inflow_s,
            self.cache.inflow_gradient_per_s,
        );
        self.refresh();
        if self.options.induced_inflow.is_some_and(|i| i.dynamic) {
            (
                self.cache.translational_inflow_s,
                self.cache.inflow_gradient_per_s,
            ) = field;
        }
    }

    /// The measured stroke in use, if any.
    pub fn stroke_reference(&self) -> Option<&StrokeReference> {
        self.stroke_reference.as_ref()
    }

    /// Peak stroke rate that sets V_ref: the measured one when set, else the kinematics'.
    fn peak_stroke_rate_rad_s(&self) -> f64 {
        match &self.stroke_reference {
            Some(r) => r.peak_stroke_rate_rad_s,
            None => self.kinematics.peak_stroke_rate_rad_s(),
        }
    }

    /// Replaces the fluid.
    pub fn set_fluid(&mut self, fluid: Fluid) {
        self.fluid = fluid;
        self.refresh();
    }

    /// Sets the kinematic viscosity so that the paper's Re = V_ref c_bar / nu equals `re`
    /// (finite and > 0; anything else is refused with an error naming `--re`/`reynolds`).
    pub fn set_reynolds(&mut self, re: f64) -> crate::error::Result<()> {
        crate::error::Validator::new("set_reynolds").positive("reynolds", re)?;
        let v_ref = self.peak_stroke_rate_rad_s() * self.geometry.r_gyration_m;
        self.fluid.kinematic_viscosity_m2_s = v_ref * self.geometry.mean_chord_m / re;
        self.refresh();
        Ok(())
    }

    /// Replaces the options.
    pub fn set_options(&mut self, options: AeroOptions) {
        self.options = options;
        self.refresh();
    }

    /// The planform's derived quantities.
    pub fn geometry(&self) -> &Geometry {
        &self.geometry
    }
    /// The kinematics.
    pub fn kinematics(&self) -> &Kinematics {
        &self.kinematics
    }
    /// The mount.
    pub fn mount(&self) -> &Mount {
        &self.mount
    }
    /// The fluid.
    pub fn fluid(&self) -> &Fluid {
        &self.fluid
    }
    /// The options.
    pub fn options(&self) -> &AeroOptions {
        &self.options
    }
    /// Reynolds number Re = V_ref c_bar / nu (the seed paper's definition: V_ref is the peak
    /// stroke speed at the radius of gyration, c_bar the mean chord).
    pub fn reynolds(&self) -> f64 {
        self.cache.reynolds
    }
    /// Reference speed V_ref = peak stroke rate times R_g, m/s.
    pub fn v_ref_m_s(&self) -> f64 {
        self.cache.v_ref_m_s
    }
    /// Reference force 0.5 rho V_ref^2 S, N.
    pub fn reference_force_n(&self) -> f64 {
        self.cache.q_ref_s_n
    }
    /// The wake-capture parameters in use (clamped to the fitted range; flags say which
    /// inputs were), or `None` when the term is off.
    pub fn wake_capture(&self) -> Option<&WakeCaptureParams> {
        self.cache.wake.as_ref()
    }
    /// Rotation from the stroke-plane frame to the body frame.
    pub fn body_from_stroke(&self) -> &Matrix3<f64> {
        &self.cache.body_from_stroke
    }
}
