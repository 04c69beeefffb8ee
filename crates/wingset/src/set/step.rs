//! One step of the wing set: the loads on the body over [t_k, t_k + dt] from the body's
//! state at t_k.
//!
//! Prescribed wings: each wing's forces from its kinematics at the wingbeat phase of t_k and
//! the body's air-relative velocity and angular velocity at t_k (pairs of wings side by side,
//! [`Wing::evaluate_pair_with`]); a wing's mass, lumped on its pitch axis at the centroid
//! radius, reacts on the body with -m a. Actuated wings: each wing's dynamics advanced by the
//! step ([`DynamicWing::step`]) with its aerodynamic and inertial reaction. The air's velocity
//! is the uniform wind ([`WingSet::set_wind`]) or each wing's own wind at its hinge
//! ([`WingSet::set_wing_winds`]), each wing of a pair side by side at its own
//! ([`Wing::evaluate_pair_each`]). Sums are taken in
//! a fixed order (aerodynamic terms wing by wing, then the wings' inertia; actuated: wing by
//! wing), so a run is bit for bit reproducible.

use nalgebra::{Matrix3, UnitQuaternion, Vector3};
use wingforce::{BodyMotion, KinematicLoads, Term, Wing};

use super::body::{BodyLoad, State};
use super::output::{WingSetOutput, zero_forces};
use super::step_kinematics::StepKinematics;
use super::{StepMemory, WingSet};
use crate::actuated::ActuatedWingOutput;
use crate::controls::Controls;
use crate::error::{Error, Result};

/// The body's motion relative to air moving at `wind_world_m_s`, body frame.
fn air_motion(body: &State, wind_world_m_s: &Vector3<f64>) -> BodyMotion {
    let body_from_world = body.world_from_body.inverse();
    BodyMotion {
        velocity_m_s: body_from_world * (body.velocity_m_s - wind_world_m_s),
        angular_velocity_rad_s: body.angular_velocity_body_rad_s,
    }
}

/// Each wing's motion relative to its own air (per-wing winds), written into `out`.
fn wing_motions_into(body: &State, winds: &[Vector3<f64>], out: &mut Vec<BodyMotion>) {
    out.clear();
    out.extend(winds.iter().map(|w| air_motion(body, w)));
}

impl WingSet {
    /// The body's motion relative to the uniform wind's air, body frame.
    fn motion(&self, body: &State) -> BodyMotion {
        air_motion(body, &self.wind_world_m_s)
    }

    /// [`WingSet::step`] and [`WingSet::loads`]: adds the body's drag (when the host turned it on) to the output and
    /// checks that the loads are finite.
    /// The drag is taken at the `sampled` state ([`Self::sample_state`]); an overflow names
    /// the state the host `given`.
    fn finish(&self, given: &State, sampled: &State, out: &mut WingSetOutput) -> Result<()> {
        let drag = self.body_drag(sampled);
        out.body_drag = drag;
        out.total.add(drag.force_n, drag.moment_nm);
        if out.total.is_finite() {
            Ok(())
        } else {
            Err(self.overflow_error(given, &self.motion(given)))
        }
    }

    /// Advances the wings by one step from the body's state at t_k and returns the loads over
    /// the step (see the module documentation). Pending controls take effect at the first
    /// step of a wingbeat. A non-finite body state or wind is an error and changes nothing;
    /// so is, for prescribed wings, a finite one whose loads overflow (a speed through the
    /// air far beyond any flight, as wingforce's `Wing::evaluate` callers refuse it; an
    /// [`Error::Diverged`] that [`Error::is_load_overflow`] recognises): the step is not
    /// taken (an actuated set's wings are left as that step moved them).
    pub fn step(&mut self, body: &State) -> Result<&WingSetOutput> {
        self.check_input(body)?;
        let cycle = self.phase().floor() as i64;
        if (self.step == 0 || cycle != self.last_cycle)
            && let Some(c) = self.pending.take()
        {
            self.apply_controls(&c)?;
        }
        self.last_cycle = cycle;
        let sampled = self.sample_state(body);
        self.apply_inflow();
        if self.dynamic.is_none() {
            self.prescribed_step(&sampled);
        }
        // The output is taken out while the set fills it (an empty one in its place
        // allocates nothing) and put back whatever the outcome.
        let mut out = std::mem::take(&mut self.out);
        let r = match self.dynamic {
            Some(_) => self.actuated_into(body, &sampled, &mut out),
            None => Ok(()),
        }
        .and_then(|()| self.finish(body, &sampled, &mut out))
        .and_then(|()| self.advance_inflow(&sampled, &mut out));
        in_step_frame(&mut out, &self.wings, body, &sampled);
        self.out = out;
        r?;
        self.sampled = sampled;
        self.prev_body = Some(StepMemory {
            step: self.step,
            velocity_m_s: body.velocity_m_s,
            rates_rad_s: body.angular_velocity_body_rad_s,
            mid_rates_rad_s: sampled.angular_velocity_body_rad_s,
            world_from_body: self.attitude_estimate(body),
        });
        self.step += 1;
        Ok(&self.out)
    }

    /// The body's state at which the next step takes its loads ([`crate::LoadSampling`]):
    /// `body` (the state at t_k) for the step-start sampling and for the first step after a
    /// restart; for the second-order samplings the state at t_k + dt/2 predicted from the
    /// last step's: the velocity extrapolated by half its change over the last step, the body
    /// rates likewise (with the body's inertia known, the rate damping taken implicitly:
    /// module `rate_damping`), the position moved by the velocity over dt/2, and the attitude
    /// the set's own estimate ([`Self::attitude_estimate`]) turned by the body rates over dt/2.
    pub fn sample_state(&self, body: &State) -> State {
        let Some(prev) = self.previous() else {
            return *body;
        };
        let half = 0.5 * self.dt_s;
        let velocity_m_s = body.velocity_m_s + 0.5 * (body.velocity_m_s - prev.velocity_m_s);
        let rates = self.midpoint_rates(
            &body.angular_velocity_body_rad_s,
            &prev.rates_rad_s,
            &prev.mid_rates_rad_s,
        );
        State {
            position_m: body.position_m + half * body.velocity_m_s,
            world_from_body: self.attitude_estimate(body)
                * UnitQuaternion::from_scaled_axis(half * body.angular_velocity_body_rad_s),
            velocity_m_s,
            angular_velocity_body_rad_s: rates,
        }
    }

    /// The body state the last step took its loads at ([`Self::sample_state`] of the state
    /// it was given; a host that applies loads of its own there, such as the body's drag,
    /// reads it here instead of predicting it again).
    pub fn sampled_state(&self) -> &State {
        &self.sampled
    }

    /// The body-frame moment, N m, that a host adds to the last step's loads when its
    /// integrator takes the body's gyroscopic term at the step's start in the body frame
    /// (MuJoCo's free joint, whose bias force holds w_k x I w_k; a loop like
    /// `examples/python/wings_in_your_loop.py`): w_k x I w_k - w_m x I w_m, with w_k the body
    /// rates the step was given and w_m those it took its loads at. The host's update
    /// w_{k+1} = w_k + dt I^-1 (tau - w_k x I w_k) then becomes the midpoint rule of Euler's
    /// equations, I (w_{k+1} - w_k) / dt = tau_m - w_m x I w_m, second order as the loads are
    /// (with the start's term, a body turning about more than one principal axis is first
    /// order: measured in MuJoCo on the fly with a 1 deg left-right amplitude difference,
    /// 1.71x and 2.00x per halved step). flapsim's rapier hosts do the same for rapier's
    /// world-frame update (`flapsim::host::midpoint_torque_world`). `inertia_body_kg_m2`: the
    /// body's inertia about its centre of mass, body frame. Zero before the first step, after
    /// a restart and under the step-start sampling (w_m = w_k).
    pub fn gyroscopic_correction_nm(&self, inertia_body_kg_m2: &Matrix3<f64>) -> Vector3<f64> {
        match self.prev_body {
            Some(p) if p.step + 1 == self.step => {
                let gyro = |w: &Vector3<f64>| w.cross(&(inertia_body_kg_m2 * w));
                gyro(&p.rates_rad_s) - gyro(&p.mid_rates_rad_s)
            }
            _ => Vector3::zeros(),
        }
    }

    /// The last step's body state, when the midpoint prediction may use it (the step just
    /// before this one, not forgotten by a restart).
    pub(super) fn previous(&self) -> Option<StepMemory> {
        match (self.sampling, self.prev_body) {
            (s, Some(p)) if s.is_second_order() && p.step + 1 == self.step => Some(p),
            _ => None,
        }
    }

    /// The body's attitude at t_k as the set integrates it: the last estimate turned by the
    /// mean of the body rates at the two steps' starts (the trapezoidal rule, second order),
    /// or the host's attitude for the first step after a restart. A host's semi-implicit
    /// Euler turns the body by dt omega_{k+1} and carries a bias of dt/2 (omega(t) -
    /// omega(0)) in attitude (first order): the loads, taken in the estimate's frame, are
    /// handed back in the host's ([`in_step_frame`]), so the host applies them in the
    /// directions a second-order attitude gives (measured in a numpy host,
    /// `tests/python/test_second_order.py`: the velocity error then falls 4x per halved step,
    /// 2x without).
    fn attitude_estimate(&self, body: &State) -> UnitQuaternion<f64> {
        match self.previous() {
            Some(p) => {
                let mean_rates = 0.5 * (p.rates_rad_s + body.angular_velocity_body_rad_s);
                p.world_from_body * UnitQuaternion::from_scaled_axis(self.dt_s * mean_rates)
            }
            None => body.world_from_body,
        }
    }

    /// Sets the wings' inflow fields from their pairs' dynamic inflow for the coming step
    /// (module `inflow`); nothing when the wake does not answer.
    fn apply_inflow(&mut self) {
        if let Some(i) = &mut self.inflow {
            i.apply(&mut self.wings, self.sampling);
        }
    }

    /// Steps the pairs' dynamic inflow with the step's loads in `out` (taken at the
    /// `sampled` state, before they are turned into the host's frame) and records the states
    /// they were taken at.
    fn advance_inflow(&mut self, sampled: &State, out: &mut WingSetOutput) -> Result<()> {
        let motion = self.motion(sampled);
        let (step, t_s, dt_s) = (self.step, self.time_s(), self.dt_s);
        let Some(i) = &mut self.inflow else {
            return Ok(());
        };
        out.inflow.clear();
        out.inflow.extend(i.used());
        i.advance(&self.wings, &out.wings, &motion, dt_s)
            .map_err(|e| Error::Diverged {
                t_s,
                step,
                reason: e.reason(),
            })
    }

    /// The loads at a body state without advancing (an actuated set steps a copy of its
    /// wings: their accelerations come out of a step; a set whose wake answers sets a
    /// copy's inflow fields).
    pub fn loads(&self, body: &State) -> Result<WingSetOutput> {
        if self.inflow.is_some() {
            let mut copy = self.clone();
            copy.apply_inflow();
            let used = copy.inflow.take().map_or_else(Vec::new, |i| i.used());
            let mut out = copy.loads(body)?;
            out.inflow = used;
            return Ok(out);
        }
        self.check_input(body)?;
        let given = body;
        let body = &self.sample_state(body);
        let mut out = WingSetOutput::empty(self.wings.len());
        if self.dynamic.is_some() {
            let mut copy = self.clone();
            // A state the step would reject still gets its loads reported as far as known.
            let _ = copy.actuated_into(given, body, &mut out);
            self.finish(given, body, &mut out)?;
            in_step_frame(&mut out, &self.wings, given, body);
            return Ok(out);
        }
        let (cycles, table_phase, j) = self.sample_phase_parts();
        let n = self.wings.len();
        let cached = j.filter(|&j| self.table_gen.get(j) == Some(&self.generation));
        let kin: Vec<StepKinematics> = match cached {
            Some(j) => self.table[j * n..(j + 1) * n].to_vec(),
            None => self.step_kinematics(table_phase),
        };
        let mut motions = Vec::new();
        if let Some(w) = &self.wing_winds_world_m_s {
            wing_motions_into(body, w, &mut motions);
        }
        let sums = self.sums(body, cycles, table_phase, &motions);
        sums.loads_into(&kin, &mut out);
        self.finish(given, body, &mut out)?;
        in_step_frame(&mut out, &self.wings, given, body);
        Ok(out)
    }

    /// What the prescribed loads at a body state need besides the kinematic loads.
    fn sums<'a>(
        &'a self,
        body: &State,
        cycles: u64,
        table_phase: f64,
        wing_motions: &'a [BodyMotion],
    ) -> PrescribedLoads<'a> {
        PrescribedLoads {
            wings: &self.wings,
            wing_mass_kg: self.wing_mass_kg,
            still: self.still,
            motion: self.motion(body),
            wing_motions,
            cycles,
            table_phase,
            step: self.step,
            t_s: self.time_s(),
            controls: self.controls,
        }
    }

    /// Every wing's kinematic loads at a phase (mirror-symmetric pairs together), appended
    /// to `kin`.
    pub(super) fn kinematic_loads_extend(&self, phase: f64, kin: &mut Vec<KinematicLoads>) {
        let n = self.wings.len();
        let mut i = 0;
        while i < n {
            if i + 1 < n && self.mirrored_pair(i) {
                kin.extend(Wing::mirrored_kinematic_loads(
                    &self.wings[i],
                    &self.wings[i + 1],
                    phase,
                ));
                i += 2;
            } else {
                kin.push(self.wings[i].kinematic_loads(phase));
                i += 1;
            }
        }
    }

    /// A prescribed step: the kinematic loads from the wingbeat's table (filled the first
    /// time a step of the wingbeat comes round) or computed, then the sums, written straight
    /// into the set's output.
    fn prescribed_step(&mut self, body: &State) {
        let (cycles, table_phase, j) = self.sample_phase_parts();
        let n = self.wings.len();
        let fresh = match j {
            Some(j) if j < self.table_gen.len() => {
                if self.table_gen[j] != self.generation {
                    let kin = self.step_kinematics(table_phase);
                    self.table[j * n..(j + 1) * n].copy_from_slice(&kin);
                    self.table_gen[j] = self.generation;
                }
                None
            }
            _ => Some(self.step_kinematics(table_phase)),
        };
        match &self.wing_winds_world_m_s {
            Some(w) => wing_motions_into(body, w, &mut self.wing_motions),
            None => self.wing_motions.clear(),
        }
        let sums = PrescribedLoads {
            wings: &self.wings,
            wing_mass_kg: self.wing_mass_kg,
            still: self.still,
            motion: self.motion(body),
            wing_motions: &self.wing_motions,
            cycles,
            table_phase,
            step: self.step,
            t_s: self.time_s(),
            controls: self.controls,
        };
        let kin = match (&fresh, j) {
            (Some(k), _) => k.as_slice(),
            (None, Some(j)) => &self.table[j * n..(j + 1) * n],
            (None, None) => &[],
        };
        sums.loads_into(kin, &mut self.out);
    }
}

/// Expresses the loads of `out`, taken at the `sampled` state, in the body frame of the
/// state `body` the host gave (the frame in which it applies them): the body turns by dt/2
/// of its rates between the two, and the set's attitude estimate differs from the host's
/// by the host's first-order bias ([`WingSet::sample_state`]); a load held in the wrong
/// frame would point that much off. Each wing's forces turn with them, so that they still
/// sum to the total.
fn in_step_frame(out: &mut WingSetOutput, wings: &[Wing], body: &State, sampled: &State) {
    if sampled.world_from_body == body.world_from_body {
        return;
    }
    let rel = body.world_from_body.inverse() * sampled.world_from_body;
    let turn = |l: &mut BodyLoad| {
        l.force_n = rel * l.force_n;
        l.moment_nm = rel * l.moment_nm;
    };
    out.terms.iter_mut().for_each(turn);
    turn(&mut out.wing_inertia);
    turn(&mut out.body_drag);
    turn(&mut out.total);
    for (w, forces) in wings.iter().zip(&mut out.wings) {
        let hinge = &w.mount().hinge_in_body_m;
        for t in forces
            .terms
            .iter_mut()
            .chain(std::iter::once(&mut forces.total))
        {
            // The moment about the centre of mass turns with the force; the hinge stays
            // where it is in the body.
            let about_com = rel * t.moment_about_com_nm(hinge);
            t.force_n = rel * t.force_n;
            t.moment_hinge_nm = about_com - hinge.cross(&t.force_n);
        }
    }
}

/// The prescribed wings' loads at one body state (borrowing the set's wings while the
/// output is written).
struct PrescribedLoads<'a> {
    wings: &'a [Wing],
    wing_mass_kg: f64,
    still: bool,
    /// The body's motion relative to the uniform wind's air.
    motion: BodyMotion,
    /// Each wing's motion relative to its own air (per-wing winds), or empty: `motion`.
    wing_motions: &'a [BodyMotion],
    cycles: u64,
    table_phase: f64,
    step: u64,
    t_s: f64,
    controls: Controls,
}

impl PrescribedLoads<'_> {
    /// Wing i's motion relative to its air.
    fn motion_of(&self, i: usize) -> &BodyMotion {
        self.wing_motions.get(i).unwrap_or(&self.motion)
    }

    /// The loads of prescribed wings at a body state from their step kinematics.
    fn loads_into(&self, steps: &[StepKinematics], out: &mut WingSetOutput) {
        let (cycles, table_phase) = (self.cycles, self.table_phase);
        let n = self.wings.len();
        if out.wings.len() != n {
            out.wings.resize(n, zero_forces());
        }
        let mut i = 0;
        while i < n {
            match (
                steps[i..].first_chunk::<2>(),
                self.wings[i..].first_chunk::<2>(),
            ) {
                (Some([a, b]), Some([l, r])) => {
                    let f = Wing::evaluate_pair_each(
                        l,
                        r,
                        &[a.kin, b.kin],
                        [self.motion_of(i), self.motion_of(i + 1)],
                    );
                    out.wings[i..i + 2].copy_from_slice(&f);
                    i += 2;
                }
                _ => {
                    out.wings[i] = self.wings[i].evaluate_with(&steps[i].kin, self.motion_of(i));
                    i += 1;
                }
            }
        }
        if cycles > 0 {
            for w in &mut out.wings {
                w.phase.half_stroke += 2 * cycles as i64;
            }
        }
        let mut terms = [BodyLoad::default(); 4];
        let mut total = BodyLoad::default();
        if !self.still {
            for (w, f) in self.wings.iter().zip(&out.wings) {
                let hinge = &w.mount().hinge_in_body_m;
                for term in Term::ALL {
                    let t = f.term(term);
                    let m = t.moment_about_com_nm(hinge);
                    terms[term as usize].add(t.force_n, m);
                    total.add(t.force_n, m);
                }
            }
        }
        let mut wing_inertia = BodyLoad::default();
        if self.wing_mass_kg > 0.0 && !self.still {
            for st in steps {
                // Reaction of the wing's centre of mass accelerating with the kinematics
                // (step_kinematics).
                wing_inertia.add(st.inertia.force_n, st.inertia.moment_nm);
                total.add(st.inertia.force_n, st.inertia.moment_nm);
            }
        }
        out.step = self.step;
        out.t_s = self.t_s;
        out.phase = table_phase + cycles as f64;
        out.terms = terms;
        out.wing_inertia = wing_inertia;
        out.total = total;
        out.controls = self.controls;
        out.actuated.clear();
    }
}

impl WingSet {
    /// The loads of actuated wings, advancing their dynamics by one step from the body's
    /// state `given` at its start, whose midpoint is `body` ([`Self::sample_state`]). The
    /// inertial reaction of the wings and actuators is reported in `wing_inertia`, apart
    /// from the aerodynamic terms, and both enter `total`. Each wing is handed the body's
    /// motion at the step's start, its midpoint and its end, the end's extrapolated linearly
    /// from the other two (second order, as the midpoint's prediction is): a wing on
    /// inelastic stops under the split scheme takes each node's loads at its own time's
    /// motion (`wingset::actuated::StageLoads::Split`).
    fn actuated_into(
        &mut self,
        given: &State,
        body: &State,
        out: &mut WingSetOutput,
    ) -> Result<()> {
        let motion = self.motion(body);
        // The start in the set's own attitude (that of the midpoint's prediction, second
        // order), not the host's (first order: `attitude_estimate`).
        let given = &State {
            world_from_body: self.attitude_estimate(given),
            ..*given
        };
        let winds = self.wing_winds_world_m_s.as_deref();
        let wind = &self.wind_world_m_s;
        let (t_s, step, dt_s) = (self.time_s(), self.step, self.dt_s);
        let freq_hz = self.freq_hz();
        let Some(dynamic) = &mut self.dynamic else {
            return Ok(());
        };
        let n = self.wings.len();
        let mut terms = [BodyLoad::default(); 4];
        let mut total = BodyLoad::default();
        let mut wing_inertia = BodyLoad::default();
        if out.wings.len() != n || out.actuated.len() != n {
            out.wings.resize(n, zero_forces());
            out.actuated.resize(n, ActuatedWingOutput::default());
        }
        for i in 0..n {
            let (start_i, motion_i) = match winds {
                Some(w) => (air_motion(given, &w[i]), air_motion(body, &w[i])),
                None => (air_motion(given, wind), motion),
            };
            let end_i = BodyMotion {
                velocity_m_s: 2.0 * motion_i.velocity_m_s - start_i.velocity_m_s,
                angular_velocity_rad_s: 2.0 * motion_i.angular_velocity_rad_s
                    - start_i.angular_velocity_rad_s,
            };
            let s = dynamic[i]
                .step_moving(&mut self.wings[i], [&start_i, &motion_i, &end_i], dt_s)
                .map_err(|e| match e {
                    Error::Diverged { reason, .. } => Error::Diverged { t_s, step, reason },
                    e => e,
                })?;
            let hinge = self.wings[i].mount().hinge_in_body_m;
            if !self.still {
                for term in Term::ALL {
                    let t = s.forces.term(term);
                    let m = t.moment_about_com_nm(&hinge);
                    terms[term as usize].add(t.force_n, m);
                    total.add(t.force_n, m);
                }
                let m = s.inertial_moment_hinge_nm + hinge.cross(&s.inertial_force_n);
                wing_inertia.add(s.inertial_force_n, m);
                total.add(s.inertial_force_n, m);
            }
            out.wings[i] = s.forces;
            out.actuated[i] = s.output();
        }
        out.step = step;
        out.t_s = t_s;
        out.phase = (t_s + self.sampling.step_fraction() * dt_s) * freq_hz;
        out.terms = terms;
        out.wing_inertia = wing_inertia;
        out.total = total;
        out.controls = self.controls;
        Ok(())
    }
}
