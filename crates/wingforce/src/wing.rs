//! One wing: geometry, kinematics and mount, prepared for fast force evaluation.
//!
//! Frames (MODEL.md section 1): the body frame is x forward, y left, z up. Each wing has a
//! stroke-plane frame with its origin at the hinge, obtained from the body frame by a rotation
//! about body y by the stroke-plane tilt (`body_from_stroke`); its z axis is the stroke-plane
//! normal, "lift" is along it. All per-step work happens in the stroke frame and the results
//! are rotated into the body frame once, at the end of [`Wing::evaluate`].

use nalgebra::{Matrix3, Rotation3, Vector3};
use serde::{Deserialize, Serialize};

use crate::added_mass::{self, AddedMassForm};
use crate::coefficients::{self, TranslationalModel, WakeCaptureModel, WakeCaptureParams};
use crate::inflow::InducedInflow;
use crate::kinematics::{Kinematics, StrokePhase, WingAngles};
use crate::planform::Geometry;
use crate::strips::{
    StripSums, StripVelocity, dickinson1999_sums, lee2016_sums, lee2016_sums_pair,
};

pub use crate::frame::WingFrame;

/// Which side of the body a wing is on. The right wing is the mirror image of the left in
/// the body's x-z plane.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Side {
    /// +y side.
    Left,
    /// -y side.
    Right,
}

impl Side {
    /// +1 for the left wing, -1 for the right.
    pub fn sign(self) -> f64 {
        match self {
            Side::Left => 1.0,
            Side::Right => -1.0,
        }
    }
}

/// Where and how a wing is attached to the body.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Mount {
    /// Which side.
    pub side: Side,
    /// Hinge position in the body frame, relative to the centre of mass, m.
    pub hinge_in_body_m: Vector3<f64>,
    /// Rotation about body y from the body frame to the stroke-plane frame, rad (positive
    /// tilts the stroke-plane normal forward: a hovering insect whose body is pitched up by
    /// this angle relative to a horizontal stroke plane).
    pub stroke_plane_tilt_rad: f64,
}

impl Mount {
    /// A fixed mount at the origin with the stroke plane on the body x-y plane (robofly).
    pub fn fixed(side: Side) -> Self {
        Self {
            side,
            hinge_in_body_m: Vector3::zeros(),
            stroke_plane_tilt_rad: 0.0,
        }
    }
}

/// Fluid properties.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Fluid {
    /// Density rho, kg/m^3.
    pub density_kg_m3: f64,
    /// Kinematic viscosity nu, m^2/s.
    pub kinematic_viscosity_m2_s: f64,
}

impl Fluid {
    /// Air at 20 C and 101.325 kPa: rho = 1.204 kg/m^3, nu = 1.516e-5 m^2/s
    /// (e.g. Engineering ToolBox / CRC Handbook tables of dry air).
    pub const AIR_20C: Fluid = Fluid {
        density_kg_m3: 1.204,
        kinematic_viscosity_m2_s: 1.516e-5,
    };
}

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

/// Linear and angular velocity of the body relative to the air, in the body frame.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct BodyMotion {
    /// Velocity of the centre of mass relative to the air, body frame, m/s.
    pub velocity_m_s: Vector3<f64>,
    /// Angular velocity, body frame, rad/s.
    pub angular_velocity_rad_s: Vector3<f64>,
}

/// The four aerodynamic terms.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Term {
    /// Quasi-steady translational lift and drag (delayed stall).
    Translational,
    /// Rotational circulation and pitch drag (Van Veen et al.).
    Rotational,
    /// Added mass (fluid accelerated with the wing).
    AddedMass,
    /// The seed paper's wake capture.
    WakeCapture,
}

impl Term {
    /// All terms, in the order of [`WingForces::terms`].
    pub const ALL: [Term; 4] = [
        Term::Translational,
        Term::Rotational,
        Term::AddedMass,
        Term::WakeCapture,
    ];

    /// Snake-case name used in CSV headers, JSON and logs.
    pub fn name(self) -> &'static str {
        match self {
            Term::Translational => "translational",
            Term::Rotational => "rotational",
            Term::AddedMass => "added_mass",
            Term::WakeCapture => "wake_capture",
        }
    }
}

/// Force and moment of one term, body frame.
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize, Deserialize)]
pub struct TermForce {
    /// Force on the wing, body frame, N.
    pub force_n: Vector3<f64>,
    /// Moment about the hinge, body frame, N m.
    pub moment_hinge_nm: Vector3<f64>,
    /// Lift coefficient on the reference scale (eq 11): force along the stroke-plane normal
    /// over 0.5 rho V_ref^2 S.
    pub c_l: f64,
    /// Drag coefficient on the reference scale (eq 12): force in the stroke plane against the
    /// wing's current stroke direction over 0.5 rho V_ref^2 S.
    pub c_d: f64,
}

impl TermForce {
    /// Moment about the centre of mass given the hinge position (body frame, from the CoM):
    /// `M_com = M_hinge + r_hinge x F`.
    pub fn moment_about_com_nm(&self, hinge_in_body_m: &Vector3<f64>) -> Vector3<f64> {
        self.moment_hinge_nm + hinge_in_body_m.cross(&self.force_n)
    }

    fn add(&mut self, other: &TermForce) {
        self.force_n += other.force_n;
        self.moment_hinge_nm += other.moment_hinge_nm;
        self.c_l += other.c_l;
        self.c_d += other.c_d;
    }
}

/// Everything one evaluation produces.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WingForces {
    /// Per term, in the order of [`Term::ALL`].
    pub terms: [TermForce; 4],
    /// Sum of the terms.
    pub total: TermForce,
    /// The kinematic state used.
    pub angles: WingAngles,
    /// Half stroke and t*.
    pub phase: StrokePhase,
}

impl WingForces {
    /// One term.
    pub fn term(&self, term: Term) -> &TermForce {
        &self.terms[term as usize]
    }
}

/// Strip data laid out for the hot loop.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct StripK {
    pub(crate) r_m: f64,
    pub(crate) half_rho_area: f64,
    pub(crate) x_cp_m: f64,
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

#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Cache {
    pub(crate) strips: Vec<StripK>,
    reynolds: f64,
    v_ref_m_s: f64,
    /// 0.5 rho V_ref^2 S, N.
    q_ref_s_n: f64,
    /// Lee: 2 K_l f, C_d0 f, 2 K_d f (f = f_AR f_Ro or 1).
    pub(crate) kl2: f64,
    pub(crate) cd0: f64,
    pub(crate) kd2: f64,
    wake: Option<WakeCaptureParams>,
    body_from_stroke: Matrix3<f64>,
    stroke_from_body: Matrix3<f64>,
    /// The hinge position in the stroke frame, m.
    hinge_s: Vector3<f64>,
    /// -(pi/4) rho.
    am_k: f64,
    /// The wing's velocity relative to the induced inflow's air, stroke frame, m/s: the air
    /// comes down through the stroke plane at w_i, so the wing moves up through it.
    inflow_s: Vector3<f64>,
}

impl Cache {
    /// Rotates a term from the stroke frame into the body frame.
    #[inline]
    fn to_body(&self, t: &mut TermForce) {
        t.force_n = self.body_from_stroke * t.force_n;
        t.moment_hinge_nm = self.body_from_stroke * t.moment_hinge_nm;
    }
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

impl Cache {
    fn empty() -> Self {
        Self {
            strips: Vec::new(),
            reynolds: 0.0,
            v_ref_m_s: 0.0,
            q_ref_s_n: 0.0,
            kl2: 0.0,
            cd0: 0.0,
            kd2: 0.0,
            wake: None,
            body_from_stroke: Matrix3::identity(),
            stroke_from_body: Matrix3::identity(),
            hinge_s: Vector3::zeros(),
            am_k: 0.0,
            inflow_s: Vector3::zeros(),
        }
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
        };
    }

    /// The induced downwash through the stroke plane at the current amplitude, m/s (zero
    /// without [`AeroOptions::induced_inflow`]).
    pub fn induced_downwash_m_s(&self) -> f64 {
        self.options.induced_inflow.map_or(0.0, |i| {
            i.downwash_m_s(
                self.fluid.density_kg_m3,
                self.kinematics.amplitude_rad,
                self.geometry.r_tip_m,
            )
        })
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
        self.refresh();
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
    pub fn set_reynolds(&mut self, re: f64) -> crate::Result<()> {
        crate::Validator::new("set_reynolds").positive("reynolds", re)?;
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

    /// Forces at time `t_s` for a wing whose phase is `t_s * f` (constant frequency).
    pub fn evaluate_at_time(&self, t_s: f64, body: &BodyMotion) -> WingForces {
        self.evaluate(t_s * self.kinematics.freq_hz, body)
    }

    /// Forces and moments of all four terms at wingbeat `phase` with the body moving as given.
    pub fn evaluate(&self, phase: f64, body: &BodyMotion) -> WingForces {
        self.evaluate_with(&self.kinematic_loads(phase), body)
    }

    /// Both wings of a mirror-symmetric pair (left, right) whose kinematics are identical:
    /// the angles are computed once and the right wing's frame is the mirror image of the
    /// left's. The caller guarantees identical kinematics (checked in debug builds).
    pub fn evaluate_mirrored_pair(
        left: &Wing,
        right: &Wing,
        phase: f64,
        body: &BodyMotion,
    ) -> [WingForces; 2] {
        Wing::evaluate_pair_with(
            left,
            right,
            &Wing::mirrored_kinematic_loads(left, right, phase),
            body,
        )
    }

    /// The evaluation proper, for given angles, stroke phase and frame (see [`Wing::evaluate`]).
    pub fn evaluate_in(
        &self,
        a: &WingAngles,
        sp: &StrokePhase,
        frame: &WingFrame,
        body: &BodyMotion,
    ) -> WingForces {
        self.evaluate_with(&self.kinematic_loads_in(a, sp, frame), body)
    }

    /// `forces` with its rotational, added-mass and wake-capture terms replaced by those of
    /// `k` and the total summed again (the translational term does not depend on the
    /// angular accelerations, so a dynamic wing that learns its accelerations after the
    /// strip loop keeps it).
    pub fn with_kinematic_terms(forces: &WingForces, k: &KinematicLoads) -> WingForces {
        let mut terms = k.terms;
        terms[0] = forces.terms[0];
        let mut total = TermForce::default();
        for t in &terms {
            total.add(t);
        }
        WingForces {
            terms,
            total,
            angles: k.angles,
            phase: k.phase,
        }
    }

    /// The part of the loads at wingbeat `phase` that the kinematics alone decide (see
    /// [`KinematicLoads`]).
    pub fn kinematic_loads(&self, phase: f64) -> KinematicLoads {
        let a = self.kinematics.angles(phase);
        let sp = self.kinematics.stroke_phase(phase);
        let frame = WingFrame::new(&a, self.mount.side);
        self.kinematic_loads_in(&a, &sp, &frame)
    }

    /// [`Wing::kinematic_loads`] of a mirror-symmetric pair (left, right) with identical
    /// kinematics: the angles once, the right frame as the mirror image of the left (checked
    /// in debug builds).
    pub fn mirrored_kinematic_loads(left: &Wing, right: &Wing, phase: f64) -> [KinematicLoads; 2] {
        debug_assert!(
            left.kinematics == right.kinematics
                && left.mount.side == Side::Left
                && right.mount.side == Side::Right
        );
        let a = left.kinematics.angles(phase);
        let sp = left.kinematics.stroke_phase(phase);
        let fl = WingFrame::new(&a, Side::Left);
        let fr = fl.mirrored();
        [
            left.kinematic_loads_in(&a, &sp, &fl),
            right.kinematic_loads_in(&a, &sp, &fr),
        ]
    }

    /// The rotational, added-mass and wake-capture terms for given angles, stroke phase and
    /// frame.
    #[inline(always)]
    pub fn kinematic_loads_in(
        &self,
        a: &WingAngles,
        sp: &StrokePhase,
        frame: &WingFrame,
    ) -> KinematicLoads {
        let c = &self.cache;
        let mut terms = [TermForce::default(); 4];

        // 2. Rotational (Van Veen et al., MODEL.md 4.2), normal to the wing, at R_g on the
        //    pitch axis. Stroke-pitch: lift side when the angle of attack rises; pitch-only:
        //    against the motion of the area farther from the pitch axis.
        if self.options.rotational {
            let g = &self.geometry;
            let rho = self.fluid.density_kg_m3;
            let td = a.theta_dot;
            let mag = self.options.c_rot
                * rho
                * (g.sqrt_sxx_syy_m4 * a.phi_dot.abs() * td - g.sx_absx_m4 * td * td.abs());
            let f = mag * frame.n;
            // The pitch-only part is a sum of strip forces C_rot rho x|x| theta_dot|theta_dot|
            // dS at their own chordwise stations x; applied on the pitch axis the force keeps
            // its lift and stroke-axis moment, and its moment about the pitch axis is added
            // from the same integrand: -C_rot rho S_|x|^3 theta_dot|theta_dot|, opposing the
            // rotation (the rotational damping that a passive-pitch hinge relies on, as in
            // Whitney & Wood 2010, J. Fluid Mech. 660:197). Prescribed kinematics only
            // report it; a dynamic pitch feels it.
            let damping = -self.options.c_rot * rho * g.s_absx3_m5 * td * td.abs();
            let m = (g.r_gyration_m * frame.e_span).cross(&f)
                + damping * frame.pitch_axis(self.mount.side);
            terms[1] = frame.term(f, m, c.q_ref_s_n, sp.downstroke);
        }

        // 3. Added mass in the chosen form (crate::added_mass); the span integrals are cached.
        let am = match self.options.added_mass {
            AddedMassForm::Impulse => Some(added_mass::impulse(
                frame,
                &self.geometry.added_mass,
                c.am_k,
                &c.inflow_s,
            )),
            AddedMassForm::Paper => {
                Some(added_mass::paper(frame, &self.geometry.added_mass, c.am_k))
            }
            AddedMassForm::Off => None,
        };
        if let Some(am) = am {
            terms[2] = frame.term(am.force_n, am.moment_nm, c.q_ref_s_n, sp.downstroke);
        }

        // 4. Wake capture (eq 23-24) on the reference scale, at R_g: lift along the stroke-plane
        //    normal, drag against the new half stroke's motion.
        if let Some(w) = &c.wake {
            let (cl, cd) = w.coefficients(sp.t_star);
            let dir = if sp.downstroke { 1.0 } else { -1.0 };
            let f = c.q_ref_s_n * (cl * Vector3::z() - cd * dir * frame.t);
            let m = (self.geometry.r_gyration_m * frame.e_span).cross(&f);
            terms[3] = frame.term(f, m, c.q_ref_s_n, sp.downstroke);
        }

        for t in &mut terms[1..] {
            c.to_body(t);
        }
        KinematicLoads {
            angles: *a,
            phase: *sp,
            frame: *frame,
            terms,
        }
    }

    /// The fluid impulse P of the wing's strips (MODEL.md 4.3), stroke frame, N s, at the
    /// wing's angles and rates in `frame` (the air moving steadily relative to the stroke
    /// frame, as the impulse form takes it): `Some` when the added mass is in the impulse
    /// form, whose force is -dP/dt.
    pub fn fluid_impulse_n_s(&self, frame: &WingFrame) -> Option<Vector3<f64>> {
        (self.options.added_mass == AddedMassForm::Impulse).then(|| {
            added_mass::fluid_impulse(
                frame,
                &self.geometry.added_mass,
                self.cache.am_k,
                &self.cache.inflow_s,
            )
        })
    }

    /// The impulse-form added-mass term over a step from `start` to `end` (the wing's
    /// frames there) of `dt_s`: the force -(P_end - P_start) / dt, so that a host which holds
    /// it over the step hands the body exactly the fluid's change of impulse, with the moment
    /// of `at_start` (the term evaluated at the step's start, body frame). `None` unless the
    /// added mass is in the impulse form.
    pub fn added_mass_over_step(
        &self,
        start: &WingFrame,
        end: &WingFrame,
        dt_s: f64,
        at_start: &TermForce,
        downstroke: bool,
    ) -> Option<TermForce> {
        let p0 = self.fluid_impulse_n_s(start)?;
        let p1 = self.fluid_impulse_n_s(end)?;
        let c = &self.cache;
        let moment_s = c.body_from_stroke.transpose() * at_start.moment_hinge_nm;
        let mut t = start.term(-(p1 - p0) / dt_s, moment_s, c.q_ref_s_n, downstroke);
        c.to_body(&mut t);
        Some(t)
    }

    /// All four terms: the translational one from the body's motion, the others from `k`
    /// (computed by [`Wing::kinematic_loads`] for this wing).
    #[inline]
    pub fn evaluate_with(&self, k: &KinematicLoads, body: &BodyMotion) -> WingForces {
        let u = self.strip_velocity(&k.frame, body);
        let sums = match self.options.translational {
            TranslationalModel::Lee2016 => lee2016_sums(&self.cache, &u),
            TranslationalModel::Dickinson1999 => dickinson1999_sums(&self.cache.strips, u),
        };
        self.finish(k, &sums)
    }

    /// Two wings at once, each at its own kinematic loads, for the same body motion. Wings
    /// with the same number of strips and the Lee et al. model (every vehicle's pair) have
    /// their strips evaluated side by side, two lanes at a time; the results are bit for
    /// bit those of [`Wing::evaluate_with`].
    pub fn evaluate_pair_with(
        left: &Wing,
        right: &Wing,
        k: &[KinematicLoads; 2],
        body: &BodyMotion,
    ) -> [WingForces; 2] {
        Self::evaluate_pair_each(left, right, k, [body, body])
    }

    /// As [`Wing::evaluate_pair_with`], each wing with its own body motion relative to its
    /// air (e.g. each in the wind at its own hinge); bit for bit [`Wing::evaluate_with`] of
    /// each.
    pub fn evaluate_pair_each(
        left: &Wing,
        right: &Wing,
        k: &[KinematicLoads; 2],
        body: [&BodyMotion; 2],
    ) -> [WingForces; 2] {
        let lee = TranslationalModel::Lee2016;
        if left.options.translational == lee
            && right.options.translational == lee
            && left.cache.strips.len() == right.cache.strips.len()
        {
            let u = [
                left.strip_velocity(&k[0].frame, body[0]),
                right.strip_velocity(&k[1].frame, body[1]),
            ];
            let [sl, sr] = lee2016_sums_pair([&left.cache, &right.cache], [&u[0], &u[1]]);
            [left.finish(&k[0], &sl), right.finish(&k[1], &sr)]
        } else {
            [
                left.evaluate_with(&k[0], body[0]),
                right.evaluate_with(&k[1], body[1]),
            ]
        }
    }

    /// The pitch-axis velocity relative to the air at radius r is linear in r:
    /// u(r) = v_hinge + r (omega_wing + omega_body) x e_span. Its (e_le, n) components as
    /// `StripVelocity`.
    #[inline(always)]
    fn strip_velocity(&self, frame: &WingFrame, body: &BodyMotion) -> StripVelocity {
        let c = &self.cache;
        let v_body_s = c.stroke_from_body * body.velocity_m_s;
        let w_body_s = c.stroke_from_body * body.angular_velocity_rad_s;
        let v_hinge_s = v_body_s + w_body_s.cross(&c.hinge_s) + c.inflow_s;
        let b = (frame.omega + w_body_s).cross(&frame.e_span);
        StripVelocity {
            a_le: v_hinge_s.dot(&frame.e_le),
            b_le: b.dot(&frame.e_le),
            a_n: v_hinge_s.dot(&frame.n),
            b_n: b.dot(&frame.n),
        }
    }

    /// The translational term from the strip sums, then the total.
    #[inline(always)]
    fn finish(&self, k: &KinematicLoads, sums: &StripSums) -> WingForces {
        let c = &self.cache;
        let frame = &k.frame;
        let f_tr = sums.f_le * frame.e_le + sums.f_n * frame.n;
        let m_tr = frame
            .e_span
            .cross(&(sums.rf_le * frame.e_le + sums.rf_n * frame.n))
            + frame.e_le.cross(&(sums.xf_n * frame.n));
        let mut terms = k.terms;
        terms[0] = frame.term(f_tr, m_tr, c.q_ref_s_n, k.phase.downstroke);
        c.to_body(&mut terms[0]);
        let mut total = TermForce::default();
        for t in &terms {
            total.add(t);
        }
        WingForces {
            terms,
            total,
            angles: k.angles,
            phase: k.phase,
        }
    }
}

/// What a wing's loads at one wingbeat phase owe to the kinematics alone: the angles, the
/// stroke phase, the wing's frame, and the rotational, added-mass and wake-capture terms.
/// Only the translational term depends on the body's motion, so a simulator whose steps
/// repeat every wingbeat can compute these once per step of the wingbeat and reuse them
/// with [`Wing::evaluate_with`] (the results are the same bit for bit).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct KinematicLoads {
    /// The kinematic state.
    pub angles: WingAngles,
    /// Half stroke and t*.
    pub phase: StrokePhase,
    /// The wing's unit vectors and rates, stroke frame.
    pub frame: WingFrame,
    /// In the order of [`Term::ALL`], body frame; the translational entry is zero.
    pub terms: [TermForce; 4],
}
