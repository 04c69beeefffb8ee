//! `flapwing.Simulation`: one vehicle on rapier3d-f64, stepped one step or many steps per
//! call (the GIL released while Rust runs), with state, loads, controls, wind, a run summary
//! and an optional MCAP log.

use numpy::{PyArrayMethods, PyUntypedArrayMethods};
use pyo3::exceptions::{PyFileExistsError, PyRuntimeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::PyDict;

use flapsim::{Mode, StepOutput};

use crate::convert::{
    arg_int, arg_vec3, merge_record, output_cap, record, scalar, shaped, try_vec, vec3, vector,
};
use crate::interrupt::Signals;
pub use crate::state::{state_dict, state_from_dict};
use crate::vehicle::Vehicle;
use crate::{log_err, sim_err};

/// "free", "tethered" or "longitudinal".
pub fn parse_mode(mode: &str) -> PyResult<Mode> {
    match mode {
        "free" => Ok(Mode::Free),
        "tethered" => Ok(Mode::Tethered),
        "longitudinal" => Ok(Mode::LONGITUDINAL),
        other => Err(PyValueError::new_err(format!(
            "mode must be \"free\", \"tethered\" or \"longitudinal\", got {other:?}"
        ))),
    }
}

fn load_dict<'py>(py: Python<'py>, l: &flapsim::BodyLoad) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("force_n", vec3(py, &l.force_n))?;
    d.set_item("moment_nm", vec3(py, &l.moment_nm))?;
    Ok(d)
}

const TERM_NAMES: [&str; 4] = ["translational", "rotational", "added_mass", "wake_capture"];

/// What one step applied: time, phase, the state at its start, the loads per term, the wings'
/// inertial reaction and the total (body frame, about the CoM), and the controls.
pub fn step_dict<'py>(py: Python<'py>, o: &StepOutput) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("step", o.step)?;
    d.set_item("t_s", o.t_s)?;
    d.set_item("phase", o.phase)?;
    d.set_item("state", state_dict(py, &o.state)?)?;
    let terms = PyDict::new(py);
    for (n, l) in TERM_NAMES.iter().zip(&o.terms) {
        terms.set_item(*n, load_dict(py, l)?)?;
    }
    d.set_item("terms", terms)?;
    d.set_item("wing_inertia", load_dict(py, &o.wing_inertia)?)?;
    d.set_item("total", load_dict(py, &o.total)?)?;
    d.set_item("controls", record(py, &o.controls)?)?;
    Ok(d)
}

/// Per-step arrays of a multi-step run.
#[derive(Default)]
pub struct Trace {
    t_s: Vec<f64>,
    phase: Vec<f64>,
    position_m: Vec<f64>,
    quat_wxyz: Vec<f64>,
    velocity_m_s: Vec<f64>,
    omega: Vec<f64>,
    force_n: Vec<f64>,
    moment_nm: Vec<f64>,
    term_force_n: Vec<f64>,
    term_moment_nm: Vec<f64>,
}

impl Trace {
    /// Room for `n` steps, or `MemoryError` (`name`: the argument asking for them).
    fn with_capacity(name: &str, n: usize) -> PyResult<Self> {
        let v = |k: usize| try_vec::<f64>(name, k.saturating_mul(n));
        Ok(Self {
            t_s: v(1)?,
            phase: v(1)?,
            position_m: v(3)?,
            quat_wxyz: v(4)?,
            velocity_m_s: v(3)?,
            omega: v(3)?,
            force_n: v(3)?,
            moment_nm: v(3)?,
            term_force_n: v(12)?,
            term_moment_nm: v(12)?,
        })
    }

    fn push(&mut self, o: &StepOutput) {
        let s = &o.state;
        self.t_s.push(o.t_s);
        self.phase.push(o.phase);
        self.position_m.extend_from_slice(s.position_m.as_slice());
        let q = &s.world_from_body;
        self.quat_wxyz.extend_from_slice(&[q.w, q.i, q.j, q.k]);
        self.velocity_m_s
            .extend_from_slice(s.velocity_m_s.as_slice());
        self.omega
            .extend_from_slice(s.angular_velocity_body_rad_s.as_slice());
        self.force_n.extend_from_slice(o.total.force_n.as_slice());
        self.moment_nm
            .extend_from_slice(o.total.moment_nm.as_slice());
        for t in &o.terms {
            self.term_force_n.extend_from_slice(t.force_n.as_slice());
            self.term_moment_nm
                .extend_from_slice(t.moment_nm.as_slice());
        }
    }

    fn into_dict(self, py: Python<'_>) -> PyResult<Bound<'_, PyDict>> {
        let n = self.t_s.len();
        let d = PyDict::new(py);
        d.set_item("t_s", shaped(py, self.t_s, &[n])?)?;
        d.set_item("phase", shaped(py, self.phase, &[n])?)?;
        d.set_item("position_m", shaped(py, self.position_m, &[n, 3])?)?;
        d.set_item("world_from_body_wxyz", shaped(py, self.quat_wxyz, &[n, 4])?)?;
        d.set_item("velocity_m_s", shaped(py, self.velocity_m_s, &[n, 3])?)?;
        d.set_item(
            "angular_velocity_body_rad_s",
            shaped(py, self.omega, &[n, 3])?,
        )?;
        d.set_item("force_n", shaped(py, self.force_n, &[n, 3])?)?;
        d.set_item("moment_nm", shaped(py, self.moment_nm, &[n, 3])?)?;
        d.set_item("term_force_n", shaped(py, self.term_force_n, &[n, 4, 3])?)?;
        d.set_item(
            "term_moment_nm",
            shaped(py, self.term_moment_nm, &[n, 4, 3])?,
        )?;
        d.set_item("terms", TERM_NAMES.to_vec())?;
        Ok(d)
    }
}

/// Bytes of a [`Trace`] per step: 45 float64.
const BYTES_PER_STEP: u64 = 8 * (1 + 1 + 3 + 4 + 3 + 3 + 3 + 3 + 12 + 12);

/// Steps `sim` `n` times, feeding the summary (and the log and the trace when given), while
/// `keep_going` says so.
pub fn run_steps(
    sim: &mut flapsim::Simulation,
    summary: &mut flapsim::SummaryBuilder,
    mut log: Option<&mut flightlog::Recorder>,
    mut trace: Option<&mut Trace>,
    n: u64,
    keep_going: &mut dyn FnMut() -> bool,
) -> PyResult<()> {
    let dt = sim.dt_s();
    for _ in 0..n {
        if !keep_going() {
            return Ok(());
        }
        // A copy: the log takes every wing's forces from the wing set beside it.
        let out = match sim.step() {
            Ok(o) => *o,
            Err(e) => {
                if let Some(rec) = log.as_deref_mut() {
                    let _ = rec.event(sim.time_s(), flightlog::Level::Error, &e.to_string());
                }
                return Err(sim_err(e));
            }
        };
        summary.observe(&out, dt);
        if let Some(t) = trace.as_deref_mut() {
            t.push(&out);
        }
        if let Some(rec) = log.as_deref_mut() {
            rec.record_wings(&out, sim.wing_set().output())
                .map_err(log_err)?;
        }
    }
    Ok(())
}

/// One vehicle's simulation.
#[pyclass(module = "flapwing")]
pub struct Simulation {
    sim: flapsim::Simulation,
    summary: flapsim::SummaryBuilder,
    vehicle: Vehicle,
    log: Option<flightlog::Recorder>,
}

#[pymethods]
impl Simulation {
    /// A simulation of `vehicle` (a `Vehicle`, or a built-in name or model path) in `mode`
    /// ("free", "tethered" or "longitudinal"), from the vehicle's initial state at t = 0.
    /// With `mcap`, every step is logged to that MCAP file at `log_rate_hz` (None: every
    /// step; else finite and > 0) until `close_log()`; the file reads back with
    /// `flapwing.read_log`. An existing `mcap` file is refused (`FileExistsError`) unless
    /// `force=True` (the CLI's `--force`).
    #[new]
    #[pyo3(signature = (vehicle = None, mode = "free", mcap = None, log_rate_hz = Some(2000.0), *, force = false))]
    fn new(
        vehicle: Option<&Bound<'_, PyAny>>,
        mode: &str,
        mcap: Option<std::path::PathBuf>,
        #[pyo3(from_py_with = log_rate)] log_rate_hz: Option<f64>,
        force: bool,
    ) -> PyResult<Self> {
        let v = Vehicle::from_arg(vehicle)?;
        if let Some(path) = &mcap {
            if path.is_dir() {
                return Err(PyValueError::new_err(format!(
                    "`mcap` {} is a directory; give a file name",
                    path.display()
                )));
            }
            if path.exists() && !force {
                return Err(PyFileExistsError::new_err(format!(
                    "`mcap`: refusing to overwrite the existing log `{}` (pass force=True to \
                     replace it)",
                    path.display()
                )));
            }
        }
        let mode_v = parse_mode(mode)?;
        let log = match mcap {
            None => None,
            Some(path) => {
                let settings = flightlog::SimSettings::new(mode_v, 0.0, log_rate_hz, [0.0; 3]);
                let info = flightlog::RunInfo::new(
                    "python",
                    format!("flapwing.Simulation({:?}, mode={mode:?})", v.origin),
                    v.toml.clone(),
                    v.origin.clone(),
                    settings.to_json(),
                );
                let opts = flightlog::LogOptions {
                    mcap: Some(path),
                    log_rate_hz,
                    // A vehicle whose wake answers logs its pairs' inflow (`/inflow`), as
                    // `flapwing simulate` does.
                    inflow: v.vehicle.inflow_model() == wingforce::InflowModel::Dynamic,
                    ..flightlog::LogOptions::default()
                };
                Some(flightlog::Recorder::create(&opts, &info, &v.vehicle).map_err(log_err)?)
            }
        };
        let mut sim = flapsim::Simulation::new(v.vehicle.clone(), mode_v);
        // The model's `[wind]`, as `flapwing simulate` flies it (reference point: the start).
        if let Some(w) = &v.vehicle.wind {
            let field = flapsim::Wind::from_spec(w, &v.origin, v.vehicle.initial_position_m)
                .map_err(sim_err)?;
            sim.set_wind_model(Some(field));
        }
        Ok(Self {
            sim,
            summary: flapsim::SummaryBuilder::new(v.vehicle.weight_n()),
            vehicle: v,
            log,
        })
    }

    /// The vehicle simulated (as built; the controls in force are `controls`).
    #[getter]
    fn vehicle(&self) -> Vehicle {
        self.vehicle.clone()
    }
    /// "free", "tethered" or "longitudinal".
    #[getter]
    fn mode(&self) -> &'static str {
        flightlog::mode_name(self.sim.mode())
    }
    /// Step length, s.
    #[getter]
    fn dt_s(&self) -> f64 {
        self.sim.dt_s()
    }
    /// Steps taken.
    #[getter]
    fn steps(&self) -> u64 {
        self.sim.steps()
    }
    /// Simulated time, s.
    #[getter]
    fn time_s(&self) -> f64 {
        self.sim.time_s()
    }
    /// Wingbeat phase now, cycles.
    #[getter]
    fn phase(&self) -> f64 {
        self.sim.phase()
    }
    /// Steps per wingbeat.
    #[getter]
    fn steps_per_wingbeat(&self) -> usize {
        self.sim.vehicle().sim.steps_per_wingbeat
    }
    /// The body state now: position_m, world_from_body_wxyz, velocity_m_s (world),
    /// angular_velocity_body_rad_s, euler_rad (roll, pitch, yaw).
    #[getter]
    fn state<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        state_dict(py, &self.sim.state())
    }
    /// Overwrites the body state (keys of `state`; missing ones keep their values).
    #[pyo3(signature = (**state))]
    fn set_state(&mut self, state: Option<&Bound<'_, PyDict>>) -> PyResult<()> {
        if let Some(d) = state {
            let s = state_from_dict(d, self.sim.state())?;
            self.sim.set_state(&s);
        }
        Ok(())
    }
    /// The controls in force, as a dict.
    #[getter]
    fn controls<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        record(py, &self.sim.vehicle().controls)
    }
    /// Sets the named control fields (the rest keep their values); they take effect at the
    /// start of the next wingbeat.
    #[pyo3(signature = (**controls))]
    fn set_controls(&mut self, controls: Option<&Bound<'_, PyDict>>) -> PyResult<()> {
        let c = merge_record(&self.sim.vehicle().controls, controls, "controls")?;
        check_controls(&self.sim, &c)?;
        self.sim.set_controls(c);
        Ok(())
    }
    /// Sets the four control channels (`Vehicle.control_channels`) to `values`, from the
    /// next wingbeat on.
    fn set_control_channels(&mut self, values: &Bound<'_, PyAny>) -> PyResult<()> {
        let u = crate::convert::real_array("values", values)?;
        if u.shape() != [4] {
            return Err(PyValueError::new_err(format!(
                "`values` must have shape (4,) (the channels {}), got shape {}",
                self.sim.vehicle().control_channels().join(", "),
                crate::convert::shape_str(u.shape())
            )));
        }
        let u = vector("values", values, Some(4))?;
        let v = self.sim.vehicle();
        let drive = v.drive_controlled();
        let now = v.controls.channels(drive);
        let delta: Vec<f64> = u.iter().zip(now).map(|(a, b)| a - b).collect();
        let c = v.controls.with_channels(drive, &delta);
        check_controls(&self.sim, &c)?;
        self.sim.set_controls(c);
        Ok(())
    }
    /// Uniform wind, world frame, m/s.
    fn set_wind(&mut self, wind_world_m_s: &Bound<'_, PyAny>) -> PyResult<()> {
        let w = arg_vec3("wind_world_m_s", Some(wind_world_m_s))?;
        self.sim.set_wind(w);
        Ok(())
    }
    /// A wind field evaluated at each wing's hinge every step, in the form of a model's
    /// `[wind]` table as a dict (`steady_world_m_s`, `turbulence` = {`intensity_m_s`,
    /// `length_scale_m`, `seed`, ...}, `gusts` = [{`amplitude_m_s`, `direction_world`,
    /// `start_s`, `duration_s` or `length_m`}], ...; crates/flapsim/README.md), reference
    /// point the vehicle's start; it adds to `set_wind`'s uniform wind. `None` removes it
    /// (a simulation of a model with a `[wind]` table starts in that field). A bad table is
    /// a `ValueError` naming the field, the value and what is allowed; nothing changes then.
    #[pyo3(signature = (wind))]
    fn set_wind_model(&mut self, wind: Option<&Bound<'_, PyDict>>) -> PyResult<()> {
        let Some(d) = wind else {
            self.sim.set_wind_model(None);
            return Ok(());
        };
        let json: String = d
            .py()
            .import("json")?
            .call_method1("dumps", (d,))?
            .extract()?;
        let spec = wind_spec(&json)?;
        let origin = format!("{} (set_wind_model)", self.vehicle.origin);
        let field =
            flapsim::Wind::from_spec(&spec, &origin, self.vehicle.vehicle.initial_position_m)
                .map_err(sim_err)?;
        self.sim.set_wind_model(Some(field));
        Ok(())
    }

    /// Each wing's wind at its hinge at the last step, world frame, m/s: an (n_wings, 3)
    /// array (0 rows before the first step or without a wind field).
    #[getter]
    fn wing_winds_m_s<'py>(&self, py: Python<'py>) -> Bound<'py, numpy::PyArray2<f64>> {
        let w = self.sim.wing_winds_m_s();
        let flat: Vec<f64> = w.iter().flat_map(|v| [v.x, v.y, v.z]).collect();
        numpy::PyArray1::from_vec(py, flat)
            .reshape([w.len(), 3])
            .expect("n x 3 elements")
    }

    /// The loads at the current state without stepping (a dict like `step()`'s).
    fn loads<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        step_dict(py, &self.sim.loads())
    }
    /// Advances one step; returns what was applied during it (state at its start, loads).
    /// Raises `DivergedError` when the run leaves the meaningful region.
    fn step<'py>(&mut self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let dt = self.sim.dt_s();
        let out = match self.sim.step() {
            Ok(o) => *o,
            Err(e) => return Err(sim_err(e)),
        };
        self.summary.observe(&out, dt);
        if let Some(rec) = &mut self.log {
            rec.record_wings(&out, self.sim.wing_set().output())
                .map_err(log_err)?;
        }
        step_dict(py, &out)
    }
    /// Advances `steps` steps in one call with the GIL released (Ctrl-C raises
    /// KeyboardInterrupt within about 50 ms, the steps taken so far kept). With `record`,
    /// returns the per-step arrays (t_s, phase, position_m (n,3), world_from_body_wxyz
    /// (n,4), velocity_m_s, angular_velocity_body_rad_s, force_n, moment_nm, term_force_n
    /// (n,4,3), term_moment_nm), 360 bytes a step, at most 1 GiB a call (2982616 steps:
    /// run longer in chunks or with `record=False`); else None.
    #[pyo3(signature = (steps, record = true))]
    fn run<'py>(
        &mut self,
        py: Python<'py>,
        steps: &Bound<'py, PyAny>,
        record: bool,
    ) -> PyResult<Option<Bound<'py, PyDict>>> {
        let n = arg_int("steps", steps, 0, None)?;
        self.run_n(py, n, record, "steps", 1)
    }
    /// Advances whole wingbeats (`wingbeats` x steps_per_wingbeat steps); see `run`.
    #[pyo3(signature = (wingbeats, record = true))]
    fn run_wingbeats<'py>(
        &mut self,
        py: Python<'py>,
        wingbeats: &Bound<'py, PyAny>,
        record: bool,
    ) -> PyResult<Option<Bound<'py, PyDict>>> {
        let per = self.sim.vehicle().sim.steps_per_wingbeat as u64;
        let max = u64::MAX / per.max(1);
        let w = arg_int("wingbeats", wingbeats, 0, Some(max))?;
        self.run_n(py, w.saturating_mul(per), record, "wingbeats", per)
    }
    /// The run summary so far: cycle-mean loads per term over complete wingbeats, lift over
    /// weight, final pose, drift and largest excursion.
    fn summary<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        record(py, &self.summary.finish(self.sim.state()))
    }
    /// Finishes the MCAP log (if any) and returns its statistics; later steps are not
    /// logged. Also done when the simulation is garbage-collected, without error reports.
    fn close_log<'py>(&mut self, py: Python<'py>) -> PyResult<Option<Bound<'py, PyAny>>> {
        match self.log.take() {
            None => Ok(None),
            Some(rec) => {
                let stats = py.detach(|| rec.finish()).map_err(log_err)?;
                let d = PyDict::new(py);
                d.set_item("steps_seen", stats.steps_seen)?;
                d.set_item("samples", stats.samples)?;
                d.set_item("events", stats.events)?;
                d.set_item("mcap_messages", stats.mcap_messages)?;
                d.set_item("mcap_bytes", stats.mcap_bytes)?;
                Ok(Some(d.into_any()))
            }
        }
    }
    fn __repr__(&self) -> String {
        format!(
            "Simulation(vehicle={:?}, mode={:?}, t_s={:.6}, steps={})",
            self.vehicle.vehicle.name,
            flightlog::mode_name(self.sim.mode()),
            self.sim.time_s(),
            self.sim.steps()
        )
    }
}

impl Simulation {
    /// `n` steps (`name` counts them in units of `per` steps, for messages).
    fn run_n<'py>(
        &mut self,
        py: Python<'py>,
        n: u64,
        record: bool,
        name: &str,
        per: u64,
    ) -> PyResult<Option<Bound<'py, PyDict>>> {
        if record {
            output_cap(
                name,
                n / per.max(1),
                BYTES_PER_STEP.saturating_mul(per),
                ": run in chunks, or pass record=False",
            )?;
        }
        let mut trace = if record {
            Some(Trace::with_capacity(name, n as usize)?)
        } else {
            None
        };
        let (sim, summary, log) = (&mut self.sim, &mut self.summary, self.log.as_mut());
        let mut sig = Signals::new();
        let t = trace.as_mut();
        py.detach(|| run_steps(sim, summary, log, t, n, &mut || sig.keep_going()))?;
        sig.result()?;
        trace.map(|t| t.into_dict(py)).transpose()
    }
}

/// `log_rate_hz`: None (every step) or a finite rate > 0.
fn log_rate(obj: &Bound<'_, PyAny>) -> PyResult<Option<f64>> {
    if obj.is_none() {
        return Ok(None);
    }
    let r = scalar("log_rate_hz", obj)?;
    if r <= 0.0 {
        return Err(PyValueError::new_err(format!(
            "`log_rate_hz` must be > 0 (or None: every step), got {r}"
        )));
    }
    Ok(Some(r))
}

/// Controls the model would reject raise now, not at the next wingbeat's step.
fn check_controls(sim: &flapsim::Simulation, c: &flapsim::Controls) -> PyResult<()> {
    let mut v = sim.vehicle().clone();
    v.apply_controls(c).map_err(sim_err)?;
    if !v.freq_hz().is_finite() || v.freq_hz() <= 0.0 {
        return Err(PyRuntimeError::new_err(
            "the wingbeat frequency must stay positive",
        ));
    }
    Ok(())
}

/// A `[wind]` table from its JSON form; an error names the table's field that is wrong (each
/// field is tried alone once the whole fails: serde_json's message gives only a column).
fn wind_spec(json: &str) -> PyResult<flapsim::WindSpec> {
    let bad = |field: &str, e: serde_json::Error| {
        PyValueError::new_err(format!("set_wind_model: [wind].{field}: {e}"))
    };
    let value: serde_json::Value = serde_json::from_str(json).map_err(|e| bad("(table)", e))?;
    match serde_json::from_value::<flapsim::WindSpec>(value.clone()) {
        Ok(spec) => Ok(spec),
        Err(whole) => {
            if let Some(obj) = value.as_object() {
                for (k, v) in obj {
                    let alone = serde_json::json!({ k.clone(): v.clone() });
                    if let Err(e) = serde_json::from_value::<flapsim::WindSpec>(alone) {
                        return Err(bad(k, e));
                    }
                }
            }
            Err(bad("(table)", whole))
        }
    }
}
