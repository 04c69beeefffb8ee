//! `flapwing.HoverTask` and `flapwing.VecHoverTask`: flapsim's control tasks
//! (flapsim::task), one or many stepped in Rust threads per call; the Gymnasium
//! environments in `python/flapwing/envs.py` wrap them.

use numpy::{PyArray1, PyReadonlyArray1, PyReadonlyArray2};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use rayon::prelude::*;

use flapsim::randomize::Randomization;
use flapsim::task::{Task, TaskSpec, TaskStep};

use crate::convert::{merge_record, model_text, record, shaped};
use crate::sim_err;

/// "hover" or "recover", with fields overridden by `overrides`.
fn task_spec(kind: &str, overrides: Option<&Bound<'_, PyDict>>) -> PyResult<TaskSpec> {
    let base = match kind {
        "hover" => TaskSpec::hover(),
        "recover" => TaskSpec::recover(),
        other => {
            return Err(PyValueError::new_err(format!(
                "task must be \"hover\" or \"recover\", got {other:?}"
            )));
        }
    };
    let Some(o) = overrides else {
        return Ok(base);
    };
    // action_wingbeats is an integer: merge it apart from the float fields.
    let mut spec = base;
    let rest = PyDict::new(o.py());
    for (k, v) in o.iter() {
        if k.extract::<String>()? == "action_wingbeats" {
            let n: i64 = v.extract()?;
            if n < 1 {
                return Err(PyValueError::new_err(format!(
                    "action_wingbeats must be at least 1, got {n}"
                )));
            }
            spec.action_wingbeats = n as usize;
        } else {
            rest.set_item(k, v)?;
        }
    }
    let mut j = merge_record(&spec, Some(&rest), "task")?;
    j.action_wingbeats = spec.action_wingbeats;
    Ok(j)
}

fn load_randomization(path: Option<&str>) -> PyResult<Option<Randomization>> {
    let Some(p) = path else { return Ok(None) };
    let text = std::fs::read_to_string(p).map_err(|e| {
        pyo3::exceptions::PyOSError::new_err(format!("cannot read randomisation file {p}: {e}"))
    })?;
    Ok(Some(Randomization::from_toml(&text, p).map_err(sim_err)?))
}

fn new_task(
    model: &str,
    task: &str,
    randomize: Option<&str>,
    overrides: Option<&Bound<'_, PyDict>>,
) -> PyResult<Task> {
    let (text, origin) = model_text(model, &crate::vehicle::builtin_pairs())?;
    let spec = task_spec(task, overrides)?;
    let r = load_randomization(randomize)?;
    Task::new(&text, &origin, spec, r).map_err(sim_err)
}

fn draws_dict<'py>(py: Python<'py>, t: &Task) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    for (k, v) in t.draws() {
        d.set_item(k, v)?;
    }
    Ok(d)
}

/// One task: `reset(seed)` and `step(action)`.
#[pyclass(module = "flapwing")]
pub struct HoverTask {
    task: Task,
}

#[pymethods]
impl HoverTask {
    /// A task ("hover" or "recover") for `model` (built-in name or file; it needs a
    /// `[sensors]` table); `randomize` is a randomisation file (flapsim::randomize);
    /// keyword arguments override TaskSpec fields (duration_s, action_wingbeats,
    /// disturbance_deg, disturbance_body_lengths_s, max_position_body_lengths,
    /// max_attitude_deg).
    #[new]
    #[pyo3(signature = (model = "drosophila", task = "hover", randomize = None, **spec))]
    fn new(
        model: &str,
        task: &str,
        randomize: Option<&str>,
        spec: Option<&Bound<'_, PyDict>>,
    ) -> PyResult<Self> {
        Ok(Self {
            task: new_task(model, task, randomize, spec)?,
        })
    }
    /// The task's settings.
    #[getter]
    fn spec<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        record(py, self.task.spec())
    }
    /// Largest action magnitude per channel.
    #[getter]
    fn action_limit<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        PyArray1::from_slice(py, &self.task.action_limit())
    }
    /// Length of an observation.
    #[getter]
    fn observation_len(&self) -> usize {
        self.task.observation_len()
    }
    /// The control channels' names.
    #[getter]
    fn control_channels(&self) -> Vec<&'static str> {
        self.task.vehicle().control_channels().to_vec()
    }
    /// Simulation steps per action.
    #[getter]
    fn steps_per_action(&self) -> u64 {
        self.task.steps_per_action()
    }
    /// Simulated time, s.
    #[getter]
    fn time_s(&self) -> f64 {
        self.task.simulation().time_s()
    }
    /// The true body state (for diagnostics; not part of the observation).
    #[getter]
    fn state<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        crate::sim::state_dict(py, &self.task.simulation().state())
    }
    /// This episode's trim, as a dict.
    #[getter]
    fn trim<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        record(py, self.task.trim())
    }
    /// This episode's randomised parameters {model path: drawn scale factor}.
    #[getter]
    fn draws<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        draws_dict(py, &self.task)
    }
    /// Starts an episode from `seed`; returns the first observation.
    fn reset<'py>(&mut self, py: Python<'py>, seed: u64) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let task = &mut self.task;
        let o = py.detach(|| task.reset(seed)).map_err(sim_err)?;
        Ok(PyArray1::from_vec(py, o))
    }
    /// Applies an action; returns (observation, reward, terminated, truncated, reason).
    fn step<'py>(
        &mut self,
        py: Python<'py>,
        action: PyReadonlyArray1<'py, f64>,
    ) -> PyResult<(Bound<'py, PyArray1<f64>>, f64, bool, bool, Option<String>)> {
        let a = action.as_slice()?.to_vec();
        let task = &mut self.task;
        let s: TaskStep = py.detach(|| task.step(&a)).map_err(value_err)?;
        Ok((
            PyArray1::from_vec(py, s.observation),
            s.reward,
            s.terminated,
            s.truncated,
            s.reason,
        ))
    }
}

/// A bad action is the caller's argument: ValueError.
fn value_err(e: flapsim::Error) -> PyErr {
    match e {
        flapsim::Error::Analysis(m) => PyValueError::new_err(m),
        e => sim_err(e),
    }
}

/// Many tasks stepped together, in parallel Rust threads (rayon), one call per action.
#[pyclass(module = "flapwing")]
pub struct VecHoverTask {
    tasks: Vec<Task>,
}

#[pymethods]
impl VecHoverTask {
    /// `num` copies of the task of `HoverTask(model, task, randomize, **spec)`.
    #[new]
    #[pyo3(signature = (num, model = "drosophila", task = "hover", randomize = None, **spec))]
    fn new(
        num: usize,
        model: &str,
        task: &str,
        randomize: Option<&str>,
        spec: Option<&Bound<'_, PyDict>>,
    ) -> PyResult<Self> {
        if num == 0 {
            return Err(PyValueError::new_err("num must be at least 1, got 0"));
        }
        let first = new_task(model, task, randomize, spec)?;
        let (text, origin) = model_text(model, &crate::vehicle::builtin_pairs())?;
        let spec_v = *first.spec();
        let r = load_randomization(randomize)?;
        let mut tasks = vec![first];
        for _ in 1..num {
            tasks.push(Task::new(&text, &origin, spec_v, r.clone()).map_err(sim_err)?);
        }
        Ok(Self { tasks })
    }
    /// Number of tasks.
    fn __len__(&self) -> usize {
        self.tasks.len()
    }
    /// Length of an observation.
    #[getter]
    fn observation_len(&self) -> usize {
        self.tasks[0].observation_len()
    }
    /// Largest action magnitude per channel.
    #[getter]
    fn action_limit<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        PyArray1::from_slice(py, &self.tasks[0].action_limit())
    }
    /// Resets every task, task i from seeds[i]; returns observations (num, obs_len).
    fn reset<'py>(&mut self, py: Python<'py>, seeds: Vec<u64>) -> PyResult<Bound<'py, PyAny>> {
        if seeds.len() != self.tasks.len() {
            return Err(PyValueError::new_err(format!(
                "{} seeds for {} tasks",
                seeds.len(),
                self.tasks.len()
            )));
        }
        let tasks = &mut self.tasks;
        let obs: Vec<Vec<f64>> = py
            .detach(|| {
                tasks
                    .par_iter_mut()
                    .zip(seeds.par_iter())
                    .map(|(t, s)| t.reset(*s))
                    .collect::<flapsim::Result<Vec<_>>>()
            })
            .map_err(sim_err)?;
        let n = obs.len();
        let m = obs.first().map_or(0, Vec::len);
        shaped(py, obs.concat(), &[n, m])
    }
    /// Steps task i with actions[i] (shape (num, 4)), in parallel; returns observations
    /// (num, obs_len), rewards, terminated and truncated (num,). With `reset_seeds`, task i
    /// is instead reset from reset_seeds[i] when that is not None (Gymnasium's next-step
    /// autoreset: its first observation, reward 0, not terminated, not truncated).
    #[pyo3(signature = (actions, reset_seeds = None))]
    fn step<'py>(
        &mut self,
        py: Python<'py>,
        actions: PyReadonlyArray2<'py, f64>,
        reset_seeds: Option<Vec<Option<u64>>>,
    ) -> PyResult<(
        Bound<'py, PyAny>,
        Bound<'py, PyAny>,
        Bound<'py, PyAny>,
        Bound<'py, PyAny>,
    )> {
        let a = actions.as_array();
        let n = self.tasks.len();
        if a.shape() != [n, 4] {
            return Err(PyValueError::new_err(format!(
                "actions must have shape ({n}, 4), got {:?}",
                a.shape()
            )));
        }
        let resets = reset_seeds.unwrap_or_else(|| vec![None; n]);
        if resets.len() != n {
            return Err(PyValueError::new_err(format!(
                "{} reset seeds for {n} tasks",
                resets.len()
            )));
        }
        let rows: Vec<Vec<f64>> = a.outer_iter().map(|r| r.to_vec()).collect();
        let tasks = &mut self.tasks;
        let out: Vec<TaskStep> = py
            .detach(|| {
                tasks
                    .par_iter_mut()
                    .zip(rows.par_iter().zip(resets.par_iter()))
                    .map(|(t, (a, r))| match r {
                        Some(seed) => t.reset(*seed).map(|observation| TaskStep {
                            observation,
                            reward: 0.0,
                            terminated: false,
                            truncated: false,
                            reason: None,
                        }),
                        None => t.step(a),
                    })
                    .collect::<flapsim::Result<Vec<_>>>()
            })
            .map_err(value_err)?;
        let m = out.first().map_or(0, |s| s.observation.len());
        let obs: Vec<f64> = out.iter().flat_map(|s| s.observation.clone()).collect();
        let rew: Vec<f64> = out.iter().map(|s| s.reward).collect();
        let term: Vec<bool> = out.iter().map(|s| s.terminated).collect();
        let trunc: Vec<bool> = out.iter().map(|s| s.truncated).collect();
        Ok((
            shaped(py, obs, &[n, m])?,
            shaped(py, rew, &[n])?,
            PyArray1::from_vec(py, term).into_any(),
            PyArray1::from_vec(py, trunc).into_any(),
        ))
    }
    /// Resets task `i` from `seed`; returns its observation.
    fn reset_one<'py>(
        &mut self,
        py: Python<'py>,
        i: usize,
        seed: u64,
    ) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let n = self.tasks.len();
        let t = self
            .tasks
            .get_mut(i)
            .ok_or_else(|| PyValueError::new_err(format!("task index {i} out of 0..{n}")))?;
        let o = py.detach(|| t.reset(seed)).map_err(sim_err)?;
        Ok(PyArray1::from_vec(py, o))
    }
    /// Task `i`'s randomised parameters this episode.
    fn draws<'py>(&self, py: Python<'py>, i: usize) -> PyResult<Bound<'py, PyDict>> {
        let t = self
            .tasks
            .get(i)
            .ok_or_else(|| PyValueError::new_err(format!("task index {i} out of range")))?;
        draws_dict(py, t)
    }
}
