//! `flapwing.WingSet`: the wings as a force element for a Python host (PyBullet, Isaac, your
//! own integrator): give it the body's state each step, apply the wrench it returns.

use flapsim::FromVehicle;
use nalgebra::{Quaternion, UnitQuaternion, Vector3};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::convert::{arg_vec3, finite, merge_record, record, vec3, vector};
use crate::sim_err;
use crate::vehicle::Vehicle;

/// The wings of a vehicle model as a force element: `step(...)` takes the body's state at
/// t_k and returns the force and moment (about the centre of mass, body frame) to apply over
/// [t_k, t_k + dt_s]; the host integrates the body with that step. The returned total
/// includes the body's parasite drag (the model's `[body] drag_area_m2`, also reported on its
/// own as `body_drag`), as the C ABI's does: the host applies the total and nothing else.
#[pyclass(module = "flapwing")]
pub struct WingSet {
    set: flapsim::WingSet,
}

fn load_dict<'py>(py: Python<'py>, l: &flapsim::BodyLoad) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("force_body_n", vec3(py, &l.force_n))?;
    d.set_item("moment_body_nm", vec3(py, &l.moment_nm))?;
    Ok(d)
}

#[pymethods]
impl WingSet {
    /// The wings of `vehicle` (a `Vehicle`, a built-in name or a model path; default the
    /// fly) stepped by `dt_s` (None: the model's own step, 1 / (f steps_per_wingbeat);
    /// else finite, > 0 and at most 1/10 of the wingbeat period, or a ValueError).
    #[new]
    #[pyo3(signature = (vehicle = None, dt_s = None))]
    fn new(vehicle: Option<&Bound<'_, PyAny>>, dt_s: Option<f64>) -> PyResult<Self> {
        let v = Vehicle::from_arg(vehicle)?;
        let set = match dt_s {
            None => flapsim::WingSet::from_vehicle_sized(&v.vehicle),
            Some(dt) => flapsim::WingSet::from_vehicle(&v.vehicle, dt),
        }
        .and_then(|mut s| {
            s.set_body_drag_area_m2(v.vehicle.body_drag_area_m2)?;
            Ok(s)
        })
        .map_err(sim_err)?;
        Ok(Self { set })
    }

    /// The host's step, s.
    #[getter]
    fn dt_s(&self) -> f64 {
        self.set.dt_s()
    }
    /// Time of the next step, s.
    #[getter]
    fn time_s(&self) -> f64 {
        self.set.time_s()
    }
    /// Wingbeat phase now, cycles.
    #[getter]
    fn phase(&self) -> f64 {
        self.set.phase()
    }
    /// Steps taken.
    #[getter]
    fn steps(&self) -> u64 {
        self.set.steps()
    }
    /// Number of wings.
    fn __len__(&self) -> usize {
        self.set.len()
    }
    /// Where in a step the loads are taken (the model's `[sim] load_sampling`): "step_start",
    /// or "step_mean" and "midpoint" (second order: the body's state at the step's midpoint
    /// is predicted from the last two states `step` was given).
    #[getter]
    fn load_sampling(&self) -> &'static str {
        self.set.load_sampling().name()
    }
    /// Forgets the states earlier steps were given: call it after moving the body by hand
    /// (a reset, a disturbance), so that a second-order set does not predict from a state the
    /// body has left. Nothing to forget for "step_start".
    fn restart_motion(&mut self) {
        self.set.restart_motion();
    }
    /// A copy in the state this set is in now, which steps as this one would from here, bit
    /// for bit (`copy.copy`, `copy.deepcopy`).
    fn __copy__(&self) -> Self {
        Self {
            set: self.set.clone(),
        }
    }
    fn __deepcopy__(&self, _memo: &Bound<'_, PyAny>) -> Self {
        self.__copy__()
    }
    /// Copies this set's state into `saved`, a copy of it (`copy.copy`, made once), for
    /// `restore_state`: cheaper than a copy per step (no table of kinematic loads, no
    /// allocation). ValueError if `saved` is not a copy of this set; itself: nothing to do.
    fn save_state(slf: &Bound<'_, Self>, saved: &Bound<'_, WingSet>) -> PyResult<()> {
        if slf.is(saved) {
            return Ok(()); // its own state already
        }
        let me = slf.borrow();
        me.set
            .save_state(&mut saved.borrow_mut().set)
            .map_err(sim_err)
    }
    /// Puts back the state saved in `saved` (`save_state`): the steps that follow repeat
    /// those that followed the save, bit for bit (a host that steps back: finite differences,
    /// rollouts). ValueError if `saved` is not a copy of this set.
    fn restore_state(slf: &Bound<'_, Self>, saved: &Bound<'_, WingSet>) -> PyResult<()> {
        if slf.is(saved) {
            return Ok(());
        }
        let from = saved.borrow();
        slf.borrow_mut()
            .set
            .restore_state(&from.set)
            .map_err(sim_err)
    }
    /// After a step: the body-frame moment, N m, to add to it when your integrator takes the
    /// body's gyroscopic term w x I w at the step's start in the body frame (a semi-implicit
    /// Euler loop such as examples/python/wings_in_your_loop.py; MuJoCo's free joint): the
    /// start's term less the one at the rates the wings took their loads at, so that the
    /// rates' update is the midpoint rule of Euler's equations, second order as the loads
    /// are. Zeros before the first step, after `restart_motion` and for "step_start".
    /// `inertia_body_kg_m2`: 3 x 3, about the centre of mass, body frame.
    fn gyroscopic_correction_nm(&self, inertia_body_kg_m2: [[f64; 3]; 3]) -> PyResult<[f64; 3]> {
        let flat: Vec<f64> = inertia_body_kg_m2.iter().flatten().copied().collect();
        finite("inertia_body_kg_m2", &flat)?;
        let i = nalgebra::Matrix3::from_row_slice(&flat);
        Ok(self.set.gyroscopic_correction_nm(&i).into())
    }
    /// Each wing pair's dynamic inflow states `(w0, w_x, w_y)`, m/s: the mean induced
    /// velocity through the pair's disc and the extra downwash at its front and left edges
    /// (`[aero] inflow = "dynamic"`; an empty list otherwise).
    #[getter]
    fn inflow_states(&self) -> Vec<[f64; 3]> {
        self.set
            .inflow_states()
            .iter()
            .map(|s| s.to_array())
            .collect()
    }
    /// Replaces each pair's dynamic inflow states (one `(w0, w_x, w_y)` per pair, m/s).
    /// ValueError for a set whose wake does not answer, a wrong count or a non-finite value.
    fn set_inflow_states(&mut self, states: Vec<[f64; 3]>) -> PyResult<()> {
        let states: Vec<_> = states
            .into_iter()
            .map(wingforce::inflow::InflowState::from_array)
            .collect();
        self.set.set_inflow_states(&states).map_err(sim_err)
    }
    /// The controls in force (a dict of SI fields).
    #[getter]
    fn controls<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        record(py, &self.set.controls())
    }
    /// Sets the named control fields (the rest keep their values) from the next wingbeat on.
    #[pyo3(signature = (**controls))]
    fn set_controls(&mut self, controls: Option<&Bound<'_, PyDict>>) -> PyResult<()> {
        let c = merge_record(&self.set.controls(), controls, "controls")?;
        if let Some(v) = self.set.vehicle() {
            // Refused now, not at the wingbeat boundary.
            v.clone().apply_controls(&c).map_err(sim_err)?;
        }
        self.set.set_controls(c).map_err(sim_err)
    }
    /// Uniform wind, world frame, m/s.
    fn set_wind(&mut self, wind_world_m_s: &Bound<'_, PyAny>) -> PyResult<()> {
        let w = arg_vec3("wind_world_m_s", Some(wind_world_m_s))?;
        finite("wind_world_m_s", w.as_slice())?;
        self.set.set_wind(w);
        Ok(())
    }

    /// One step from the body's state at t_k: `position_m` (world), `world_from_body_wxyz`
    /// (a unit quaternion), `velocity_m_s` (the CoM's, world) and
    /// `angular_velocity_body_rad_s`. Returns a dict: `force_body_n`, `moment_body_nm` (the
    /// total about the CoM, body frame), `terms` (each term's load), `wing_inertia`,
    /// `body_drag`, `wing_forces_body_n` (one row per wing), `t_s` and `phase`. A state or
    /// wind whose loads overflow (a speed through the air far beyond flight) is a ValueError
    /// naming the velocities, and the step is not taken.
    #[pyo3(signature = (position_m, world_from_body_wxyz, velocity_m_s, angular_velocity_body_rad_s))]
    fn step<'py>(
        &mut self,
        py: Python<'py>,
        position_m: &Bound<'py, PyAny>,
        world_from_body_wxyz: &Bound<'py, PyAny>,
        velocity_m_s: &Bound<'py, PyAny>,
        angular_velocity_body_rad_s: &Bound<'py, PyAny>,
    ) -> PyResult<Bound<'py, PyDict>> {
        let v3 = |name: &str, o: &Bound<'py, PyAny>| vector(name, o, Some(3));
        let state = body_state([
            &v3("position_m", position_m)?,
            &vector("world_from_body_wxyz", world_from_body_wxyz, Some(4))?,
            &v3("velocity_m_s", velocity_m_s)?,
            &v3("angular_velocity_body_rad_s", angular_velocity_body_rad_s)?,
        ])?;
        let out = self.set.step(&state).map_err(step_err)?;
        let d = load_dict(py, &out.total)?;
        let terms = PyDict::new(py);
        for term in wingforce::Term::ALL {
            terms.set_item(term.name(), load_dict(py, &out.terms[term as usize])?)?;
        }
        d.set_item("terms", terms)?;
        d.set_item("wing_inertia", load_dict(py, &out.wing_inertia)?)?;
        d.set_item("body_drag", load_dict(py, &out.body_drag)?)?;
        let rows: Vec<Vec<f64>> = out
            .wings
            .iter()
            .map(|w| w.total.force_n.iter().copied().collect())
            .collect();
        d.set_item("wing_forces_body_n", numpy::PyArray2::from_vec2(py, &rows)?)?;
        d.set_item("t_s", out.t_s)?;
        d.set_item("phase", out.phase)?;
        Ok(d)
    }

    /// The lean step for a host's inner loop: the body's state as one float64 array of 13
    /// (position_m 3, world_from_body_wxyz 4, velocity_m_s 3, angular_velocity_body_rad_s 3)
    /// and the wrench written into `out`, a float64 array of 6 (force_body_n 3 then
    /// moment_body_nm 3, the same total `step` returns), with nothing else built. Checks as
    /// `step`: each value finite, the quaternion a unit one within 1e-6, and a load overflow
    /// a ValueError with the step not taken.
    #[pyo3(signature = (state, out))]
    fn step_wrench(
        &mut self,
        state: numpy::PyReadonlyArray1<'_, f64>,
        mut out: numpy::PyReadwriteArray1<'_, f64>,
    ) -> PyResult<()> {
        let x = state.as_slice().map_err(|_| {
            PyValueError::new_err("`state` must be a contiguous float64 array of 13")
        })?;
        if x.len() != 13 {
            return Err(PyValueError::new_err(format!(
                "`state` has {} values; allowed 13: position_m (3), world_from_body_wxyz (4), velocity_m_s (3), angular_velocity_body_rad_s (3)",
                x.len()
            )));
        }
        let o = out.as_slice_mut().map_err(|_| {
            PyValueError::new_err("`out` must be a contiguous, writable float64 array of 6")
        })?;
        if o.len() != 6 {
            return Err(PyValueError::new_err(format!(
                "`out` has {} values; allowed 6: force_body_n (3) then moment_body_nm (3)",
                o.len()
            )));
        }
        let state = body_state([&x[0..3], &x[3..7], &x[7..10], &x[10..13]])?;
        let total = self.set.step(&state).map_err(step_err)?.total;
        o[..3].copy_from_slice(total.force_n.as_slice());
        o[3..].copy_from_slice(total.moment_nm.as_slice());
        Ok(())
    }
}

/// The argument names of a body state's parts, in order.
const STATE_PARTS: [&str; 4] = [
    "position_m",
    "world_from_body_wxyz",
    "velocity_m_s",
    "angular_velocity_body_rad_s",
];

/// A body state from its parts (position, quaternion w x y z, velocity, body rates): each
/// finite, the quaternion a unit one within 1e-6, or a ValueError naming the part.
fn body_state(parts: [&[f64]; 4]) -> PyResult<flapsim::State> {
    for (name, p) in STATE_PARTS.iter().zip(parts) {
        finite(name, p)?;
    }
    let [p, q, v, w] = parts;
    let norm = q.iter().map(|x| x * x).sum::<f64>().sqrt();
    if (norm - 1.0).abs() > 1e-6 {
        return Err(PyValueError::new_err(format!(
            "`world_from_body_wxyz` must be a unit quaternion (w, x, y, z), got norm {norm}; allowed: |q| within 1e-6 of 1"
        )));
    }
    Ok(flapsim::State {
        position_m: Vector3::from_column_slice(p),
        world_from_body: UnitQuaternion::new_normalize(Quaternion::new(q[0], q[1], q[2], q[3])),
        velocity_m_s: Vector3::from_column_slice(v),
        angular_velocity_body_rad_s: Vector3::from_column_slice(w),
    })
}

/// A wing-set step's error: a load overflow is the caller's state or wind, a bad argument.
fn step_err(e: flapsim::Error) -> PyErr {
    match e.is_load_overflow() {
        true => PyValueError::new_err(format!("wing set: {}", e.reason())),
        false => sim_err(e),
    }
}
