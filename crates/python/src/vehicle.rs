//! `flapwing.Vehicle` (a vehicle model: trim, stability, LQR design) and
//! `flapwing.HoverController`.

use nalgebra::DMatrix;
use numpy::{Complex64, PyArray1, PyArrayMethods};
use pyo3::exceptions::{PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::convert::{arg_int, describe, matrix, merge_record, model_text, real_array, record};
use crate::interrupt::{analysis, numpy_ready};
use crate::sim_err;
use crate::state::state_from_dict;
use flapsim::flight::FlightCondition;

/// The built-in vehicles, by name (flapsim's list).
pub const BUILTIN_VEHICLES: [&str; 6] = flapsim::BUILTIN_MODELS;

/// (name, TOML text) of every built-in vehicle.
pub fn builtin_pairs() -> Vec<(&'static str, &'static str)> {
    BUILTIN_VEHICLES
        .iter()
        .filter_map(|n| flapsim::builtin_model(n).map(|t| (*n, t)))
        .collect()
}

/// A vehicle model: body, two wings on their hinges, kinematics or actuators, controls.
#[pyclass(module = "flapwing", frozen)]
#[derive(Clone)]
pub struct Vehicle {
    pub(crate) vehicle: flapsim::Vehicle,
    pub(crate) toml: String,
    pub(crate) origin: String,
}

impl Vehicle {
    /// Loads a built-in name or a file.
    pub fn load(model: &str) -> PyResult<Self> {
        let (toml, origin) = model_text(model, &builtin_pairs())?;
        let vehicle = flapsim::Vehicle::from_toml(&toml, &origin).map_err(sim_err)?;
        Ok(Self {
            vehicle,
            toml,
            origin,
        })
    }

    /// A `Vehicle`, or a built-in name or model path, given as an argument (None: the fly).
    pub fn from_arg(vehicle: Option<&Bound<'_, PyAny>>) -> PyResult<Self> {
        match vehicle {
            None => Self::load("drosophila"),
            Some(obj) => match obj.cast::<Vehicle>() {
                Ok(v) => Ok(v.get().clone()),
                Err(_) => Self::load(&obj.extract::<String>().map_err(|_| {
                    PyValueError::new_err(format!(
                        "`vehicle` must be a flapwing.Vehicle or a model name/path, got {}",
                        crate::convert::describe(obj)
                    ))
                })?),
            },
        }
    }

    fn trim_value(&self) -> PyResult<flapsim::trim::Trim> {
        flapsim::trim::trim(&self.vehicle).map_err(sim_err)
    }

    /// The trim at a flight condition (hover when both are zero).
    fn trim_at(&self, condition: &FlightCondition) -> PyResult<flapsim::trim::Trim> {
        flapsim::trim::trim_at(&self.vehicle, self.vehicle.trim_lift, condition).map_err(sim_err)
    }
}

/// The flight condition of `speed_m_s` and `climb_m_s` (real numbers: a boolean, complex or
/// text value is a `TypeError`), or a `ValueError` naming them.
pub(crate) fn condition(
    speed_m_s: Option<&Bound<'_, PyAny>>,
    climb_m_s: Option<&Bound<'_, PyAny>>,
) -> PyResult<FlightCondition> {
    // A real number (a boolean, complex or text value is a TypeError); its range (finite,
    // allowed speeds) is FlightCondition's to check and name.
    let real = |name: &str, x: Option<&Bound<'_, PyAny>>| -> PyResult<f64> {
        let Some(x) = x else { return Ok(0.0) };
        real_array(name, x)?;
        x.extract::<f64>().map_err(|_| {
            PyTypeError::new_err(format!(
                "`{name}` must be a real number, got {}",
                describe(x)
            ))
        })
    };
    let (speed_m_s, climb_m_s) = (real("speed_m_s", speed_m_s)?, real("climb_m_s", climb_m_s)?);
    FlightCondition::new(speed_m_s, climb_m_s)
        .map_err(|e| PyValueError::new_err(format!("speed_m_s / climb_m_s: {e}")))
}

/// (Re, Im) pairs of modes as a complex numpy array.
fn eigenvalues<'py>(
    py: Python<'py>,
    modes: impl Iterator<Item = (f64, f64)>,
) -> Bound<'py, PyArray1<Complex64>> {
    PyArray1::from_vec(py, modes.map(|(r, i)| Complex64::new(r, i)).collect())
}

fn square(rows: &[Vec<f64>]) -> DMatrix<f64> {
    let n = rows.len();
    DMatrix::from_fn(n, n, |i, j| rows[i][j])
}

#[pymethods]
impl Vehicle {
    /// Loads a vehicle: a built-in name (`drosophila`, `bumblebee`, `robobee_kinematic`,
    /// `robobee`, `hummingbird`) or a model file path. A bad model raises `ValueError` with
    /// the file, field, value and what is allowed.
    #[new]
    #[pyo3(signature = (model = "drosophila"))]
    fn new(model: &str) -> PyResult<Self> {
        Self::load(model)
    }

    /// The model's name.
    #[getter]
    fn name(&self) -> &str {
        &self.vehicle.name
    }
    /// Where the model came from (a path or `<built-in NAME>`).
    #[getter]
    fn origin(&self) -> &str {
        &self.origin
    }
    /// The model file's text.
    #[getter]
    fn model_toml(&self) -> &str {
        &self.toml
    }
    /// The added-mass term's form: `"impulse"` (-dP/dt, MODEL.md 4.3), `"paper"` (eq 7-8)
    /// or `"off"`.
    #[getter]
    fn added_mass_form(&self) -> &'static str {
        self.vehicle.wings[0].options().added_mass.name()
    }
    /// The induced flow the wings meet (`[aero] inflow`): `"off"` (still air), `"frozen"`
    /// (the hover downwash held at the flight condition) or `"dynamic"` (each pair's wake
    /// answers its loads and the body).
    #[getter]
    fn inflow_model(&self) -> &'static str {
        self.vehicle.inflow_model().name()
    }
    /// Body mass, kg.
    #[getter]
    fn mass_kg(&self) -> f64 {
        self.vehicle.mass_kg
    }
    /// Inertia about the centre of mass, body frame, kg m^2 (3x3).
    #[getter]
    fn inertia_kg_m2<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, numpy::PyArray2<f64>>> {
        let i = &self.vehicle.inertia_kg_m2;
        matrix(py, &DMatrix::from_fn(3, 3, |r, c| i[(r, c)]))
    }
    /// Body length, m.
    #[getter]
    fn length_m(&self) -> f64 {
        self.vehicle.length_m
    }
    /// Weight m g, N.
    #[getter]
    fn weight_n(&self) -> f64 {
        self.vehicle.weight_n()
    }
    /// Gravity, m/s^2.
    #[getter]
    fn gravity_m_s2(&self) -> f64 {
        self.vehicle.gravity_m_s2
    }
    /// Wingbeat frequency with the current controls, Hz.
    #[getter]
    fn freq_hz(&self) -> f64 {
        self.vehicle.freq_hz()
    }
    /// Simulation steps per wingbeat.
    #[getter]
    fn steps_per_wingbeat(&self) -> usize {
        self.vehicle.sim.steps_per_wingbeat
    }
    /// Where in a step the wings' loads are taken (`[sim] load_sampling`): "step_mean"
    /// (second order, the default for prescribed wings), "midpoint" (second order, as
    /// before the step mean) or "step_start" (first order).
    #[getter]
    fn load_sampling(&self) -> &'static str {
        self.vehicle.load_sampling().name()
    }
    /// The fewest steps per wingbeat holding the accuracy the model file states
    /// (`[sim] accurate_steps_per_wingbeat`, from the error-cost frontier), or None.
    #[getter]
    fn accurate_steps_per_wingbeat(&self) -> Option<usize> {
        self.vehicle.sim.accurate_steps_per_wingbeat
    }
    /// A warning when the vehicle is stepped more coarsely than that bound, else None.
    #[getter]
    fn coarse_step_warning(&self) -> Option<String> {
        self.vehicle.coarse_step_warning()
    }
    /// True for an actuated vehicle (wings driven by actuators, passive pitch).
    #[getter]
    fn actuated(&self) -> bool {
        self.vehicle.actuation.is_some()
    }
    /// The names of the four control channels that trim, the LQR and the environments use.
    #[getter]
    fn control_channels(&self) -> Vec<&'static str> {
        self.vehicle.control_channels().to_vec()
    }
    /// The controls in force (offsets on the base kinematics or drive), as a dict.
    #[getter]
    fn controls<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        record(py, &self.vehicle.controls)
    }

    /// A copy with the controls' named fields replaced (`ValueError` for an unknown name or
    /// a value the model rejects).
    #[pyo3(signature = (**controls))]
    fn with_controls(&self, controls: Option<&Bound<'_, PyDict>>) -> PyResult<Self> {
        let c = merge_record(&self.vehicle.controls, controls, "controls")?;
        let mut v = self.clone();
        v.vehicle.apply_controls(&c).map_err(sim_err)?;
        Ok(v)
    }

    /// A copy whose wings meet another induced flow (`[aero] inflow`): `"off"` (still air),
    /// `"frozen"` (the hover downwash held at the flight condition) or `"dynamic"` (each
    /// pair's wake answers its loads and the body). `ValueError` for another name, or for a
    /// flow the vehicle cannot take (a frozen wake on actuated or four wings).
    fn with_inflow(&self, model: &str) -> PyResult<Self> {
        let m = wingforce::InflowModel::from_name(model).ok_or_else(|| {
            PyValueError::new_err(format!(
                "inflow `{model}` is not an induced-flow model; allowed: off, frozen, dynamic"
            ))
        })?;
        let mut v = self.clone();
        v.vehicle = v.vehicle.with_inflow_model(m).map_err(sim_err)?;
        Ok(v)
    }

    /// What the vehicle's trims vary to carry the weight (`[trim] lift_variable`):
    /// `"amplitude"`, `"angle_of_attack"` or `"frequency"`.
    #[getter]
    fn trim_lift(&self) -> &'static str {
        self.vehicle.trim_lift.name()
    }

    /// A copy whose trims (`trim`, `trimmed`, `stability`, `envelope`) carry the weight on
    /// `variable` (`[trim] lift_variable`): `"amplitude"`, `"angle_of_attack"` (both half
    /// strokes moved alike, amplitude and frequency held) or `"frequency"`. `ValueError` for
    /// another name, or for an actuated vehicle and anything but `"amplitude"` (its drive
    /// amplitude carries the weight).
    fn with_trim_lift(&self, variable: &str) -> PyResult<Self> {
        use flapsim::trim::LiftVariable;
        let lift = LiftVariable::from_name(variable).ok_or_else(|| {
            PyValueError::new_err(format!(
                "trim lift variable `{variable}` is not one of amplitude, angle_of_attack, frequency"
            ))
        })?;
        if self.vehicle.drive_controlled() && lift != LiftVariable::Amplitude {
            return Err(PyValueError::new_err(format!(
                "trim lift variable `{variable}` on the actuated `{}`: its drive amplitude carries the weight; allowed: amplitude",
                self.vehicle.name
            )));
        }
        let mut v = self.clone();
        v.vehicle.trim_lift = lift;
        Ok(v)
    }

    /// A copy whose initial state is `state` (a dict as returned by `Simulation.state`;
    /// missing keys keep the model's values).
    fn with_initial_state(&self, state: &Bound<'_, PyDict>) -> PyResult<Self> {
        let mut v = self.clone();
        let s0 = flapsim::State {
            position_m: v.vehicle.initial_position_m,
            world_from_body: v.vehicle.initial_attitude,
            velocity_m_s: v.vehicle.initial_velocity_m_s,
            angular_velocity_body_rad_s: v.vehicle.initial_angular_velocity_rad_s,
        };
        let s = state_from_dict(state, s0)?;
        v.vehicle.initial_position_m = s.position_m;
        v.vehicle.initial_attitude = s.world_from_body;
        v.vehicle.initial_velocity_m_s = s.velocity_m_s;
        v.vehicle.initial_angular_velocity_rad_s = s.angular_velocity_body_rad_s;
        Ok(v)
    }

    /// Trim (flapsim::trim) in hover or at a flight condition (forward speed `speed_m_s`,
    /// climb rate `climb_m_s`; flapsim::flight): condition, controls, body pitch and
    /// residuals, as a dict. Raises `AnalysisError` when no trim is found, `ValueError` for
    /// a bad condition.
    #[pyo3(signature = (speed_m_s = None, climb_m_s = None))]
    fn trim<'py>(
        &self,
        py: Python<'py>,
        speed_m_s: Option<&Bound<'py, PyAny>>,
        climb_m_s: Option<&Bound<'py, PyAny>>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let c = condition(speed_m_s, climb_m_s)?;
        let t = analysis(py, || self.trim_at(&c))??;
        record(py, &t)
    }

    /// The vehicle flying at its trim (controls applied, attitude at the trim pitch, and at
    /// a flight condition its velocity and the induced inflow frozen there).
    #[pyo3(signature = (speed_m_s = None, climb_m_s = None))]
    fn trimmed(
        &self,
        py: Python<'_>,
        speed_m_s: Option<&Bound<'_, PyAny>>,
        climb_m_s: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<Self> {
        let c = condition(speed_m_s, climb_m_s)?;
        let v = analysis(py, || -> PyResult<flapsim::Vehicle> {
            let t = self.trim_at(&c)?;
            let mut v = flapsim::trim::trimmed_vehicle(&self.vehicle, &t).map_err(sim_err)?;
            v.initial_attitude = t.attitude();
            Ok(v)
        })??;
        Ok(Self {
            vehicle: v,
            toml: self.toml.clone(),
            origin: self.origin.clone(),
        })
    }

    /// Hover stability (flapsim::stability::analyze): the averaged model's longitudinal and
    /// lateral system matrices `a_longitudinal`, `a_lateral` (numpy, with their state
    /// names), their eigenvalues (complex numpy) and modes with eigenvectors, the
    /// dimensional and non-dimensional derivatives, and with `floquet` the Floquet analysis
    /// of the time-periodic longitudinal motion: `floquet_monodromy` (the monodromy matrix
    /// Phi over one wingbeat, rows and columns `floquet_states`), `floquet_multipliers` (its
    /// eigenvalues mu), `floquet_exponents` (ln(mu) / T, so mu = exp(exponent T) with T =
    /// `floquet_period_s`) and `floquet_eigenvectors` (complex, column k the eigenvector of
    /// multiplier k: Phi v = mu v, unit norm, largest entry real and positive), and
    /// `floquet_warnings`: one string per state whose column of Phi is not to be trusted (its
    /// forward and backward differences disagree: the one-wingbeat map has a jump or a kink
    /// at the orbit; empty when it is smooth).
    /// `speed_m_s` and `climb_m_s` analyse about the trim at that flight condition.
    #[pyo3(signature = (floquet = true, speed_m_s = None, climb_m_s = None))]
    fn stability<'py>(
        &self,
        py: Python<'py>,
        floquet: bool,
        speed_m_s: Option<&Bound<'py, PyAny>>,
        climb_m_s: Option<&Bound<'py, PyAny>>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let c = condition(speed_m_s, climb_m_s)?;
        numpy_ready(py)?;
        let r = analysis(py, || {
            flapsim::stability::analyze_at(&self.vehicle, &c, floquet)
        })?
        .map_err(sim_err)?;
        let d = record(py, &r)?;
        let dict = d.cast::<PyDict>()?;
        dict.set_item("a_longitudinal", matrix(py, &square(&r.a_longitudinal))?)?;
        dict.set_item("a_lateral", matrix(py, &square(&r.a_lateral))?)?;
        let lon = square(&r.a_longitudinal).complex_eigenvalues();
        let lat = square(&r.a_lateral).complex_eigenvalues();
        dict.set_item(
            "eigenvalues_longitudinal",
            eigenvalues(py, lon.iter().map(|l| (l.re, l.im))),
        )?;
        dict.set_item(
            "eigenvalues_lateral",
            eigenvalues(py, lat.iter().map(|l| (l.re, l.im))),
        )?;
        dict.set_item(
            "floquet_multipliers",
            eigenvalues(py, r.floquet_longitudinal.iter().map(|m| m.multiplier)),
        )?;
        dict.set_item(
            "floquet_exponents",
            eigenvalues(py, r.floquet_longitudinal.iter().map(|m| m.exponent)),
        )?;
        dict.set_item(
            "floquet_monodromy",
            matrix(py, &square(&r.floquet_monodromy))?,
        )?;
        let n = r.floquet_states.len();
        let columns: Vec<Complex64> = (0..n)
            .flat_map(|i| {
                r.floquet_longitudinal
                    .iter()
                    .map(move |m| Complex64::new(m.eigenvector[i].0, m.eigenvector[i].1))
            })
            .collect();
        let vectors = PyArray1::from_vec(py, columns).reshape([n, r.floquet_longitudinal.len()])?;
        dict.set_item("floquet_eigenvectors", vectors)?;
        Ok(d)
    }

    /// Designs the per-wingbeat hover LQR (flapsim::control::HoverController) at the trim.
    /// `weights` overrides fields of flapsim's default LqrWeights (Bryson's rule maxima:
    /// each finite and > 0); `delay_wingbeats` (an integer >= 0, default 0) is the sensing
    /// delay the controller compensates.
    #[pyo3(signature = (delay_wingbeats = None, **weights))]
    fn lqr(
        &self,
        py: Python<'_>,
        delay_wingbeats: Option<&Bound<'_, PyAny>>,
        weights: Option<&Bound<'_, PyDict>>,
    ) -> PyResult<HoverController> {
        let delay = match delay_wingbeats {
            None => 0,
            Some(d) => arg_int("delay_wingbeats", d, 0, Some(u32::MAX as u64))? as usize,
        };
        let w = merge_record(
            &flapsim::control::LqrWeights::default(),
            weights,
            "LqrWeights",
        )?;
        let j = serde_json::to_value(w).map_err(|e| PyValueError::new_err(e.to_string()))?;
        if let Some(o) = j.as_object() {
            for (k, v) in o {
                let x = v.as_f64().unwrap_or(f64::NAN);
                // 1/x^2 is each weight: it must be finite and positive too.
                if !(x > 0.0 && (1.0 / (x * x)).is_finite()) {
                    return Err(PyValueError::new_err(format!(
                        "LqrWeights `{k}` is a largest allowed excursion (Bryson's rule): it \
                         must be finite and > 0 (and at least 1e-150), got {x}"
                    )));
                }
            }
        }
        let (t, c) = analysis(py, || -> PyResult<_> {
            let t = self.trim_value()?;
            let v = flapsim::trim::trimmed_vehicle(&self.vehicle, &t).map_err(sim_err)?;
            let c =
                flapsim::control::HoverController::design(&v, &t, &w, delay).map_err(sim_err)?;
            Ok((t, c))
        })??;
        if c.gain().iter().any(|x| !x.is_finite()) {
            return Err(PyValueError::new_err(
                "the LQR gain is not finite for these weights: make the LqrWeights fields \
                 less extreme",
            ));
        }
        Ok(HoverController {
            controller: c,
            trim: t,
            weights: w,
            drive: self.vehicle.drive_controlled(),
        })
    }

    fn __repr__(&self) -> String {
        format!(
            "Vehicle(name={:?}, origin={:?}, mass_kg={:e}, freq_hz={:.3}, actuated={})",
            self.vehicle.name,
            self.origin,
            self.vehicle.mass_kg,
            self.vehicle.freq_hz(),
            self.vehicle.actuation.is_some()
        )
    }
}

/// The per-wingbeat hover LQR with position integral: `update(state)` once per wingbeat
/// gives the controls for the next one.
#[pyclass(module = "flapwing")]
pub struct HoverController {
    pub(crate) controller: flapsim::control::HoverController,
    trim: flapsim::trim::Trim,
    weights: flapsim::control::LqrWeights,
    drive: bool,
}

#[pymethods]
impl HoverController {
    /// The gain K (4 controls x 15: 12 error states, then 3 position integrals); u = -K x.
    #[getter]
    fn gain<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, numpy::PyArray2<f64>>> {
        matrix(py, self.controller.gain())
    }
    /// The trim it was designed at, as a dict.
    #[getter]
    fn trim<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        record(py, &self.trim)
    }
    /// The weights used, as a dict.
    #[getter]
    fn weights<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        record(py, &self.weights)
    }
    /// The error state (position, velocity, attitude error, body rates; 12 numbers) of a
    /// state dict (keys missing from it are at the hover reference; an empty dict is a
    /// `ValueError`).
    fn error_state<'py>(
        &self,
        py: Python<'py>,
        state: &Bound<'py, PyDict>,
    ) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let s = self.measured(state)?;
        let x = self.controller.error_state(&s);
        Ok(PyArray1::from_slice(py, x.as_slice()))
    }
    /// Controls for the next wingbeat from the state measured now (a state dict; keys
    /// missing from it are at the hover reference, an empty dict is a `ValueError`), as a
    /// dict to pass to `Simulation.set_controls(**c)`.
    fn update<'py>(
        &mut self,
        py: Python<'py>,
        state: &Bound<'py, PyDict>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let s = self.measured(state)?;
        let c = self.controller.update(&s);
        record(py, &c)
    }
    /// The four control channels of the controls `update` would return for an error-free
    /// state, i.e. the trim's channels.
    #[getter]
    fn trim_channels<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        PyArray1::from_slice(py, &self.trim.controls.channels(self.drive))
    }
}

impl HoverController {
    /// The measured state of a state dict: at least one key (an empty dict measures nothing),
    /// the missing ones at the hover reference (position, trim velocity and attitude, no
    /// rotation), so that a partial state has the error of what it names only.
    fn measured(&self, state: &Bound<'_, PyDict>) -> PyResult<flapsim::State> {
        if state.is_empty() {
            return Err(PyValueError::new_err(
                "`state` is an empty dict: a measured state needs at least one of position_m, \
                 world_from_body_wxyz, velocity_m_s, angular_velocity_body_rad_s (the missing \
                 ones are taken at the hover reference)",
            ));
        }
        state_from_dict(state, self.controller.reference_state())
    }
}
