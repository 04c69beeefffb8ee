//! `flapwing.HoverTask` and `flapwing.VecHoverTask`: flapsim's control tasks
//! (flapsim::task), one or many stepped in Rust threads per call; the Gymnasium
//! environments in `python/flapwing/envs.py` wrap them.

use std::sync::atomic::Ordering;

use numpy::{PyArray1, PyArrayMethods, PyUntypedArrayMethods};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use rayon::prelude::*;

use flapsim::randomize::Randomization;
use flapsim::task::{Observation, Task, TaskSpec, TaskStep};

use crate::convert::{
    arg_int, finite, float_array, int_list, merge_record, model_text, record, shape_str, shaped,
};
use crate::interrupt::{Signals, analysis, watch_token};
use crate::sim_err;

/// The most tasks a `VecHoverTask` holds (each is a trimmed simulation with sensors, built in
/// parallel at construction): more is a `ValueError` naming `num`.
pub const MAX_TASKS: u64 = 4096;

/// The most wingbeats one action may last (`action_wingbeats`).
pub const MAX_ACTION_WINGBEATS: u64 = 1_000_000;

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
        let key: String = k.extract()?;
        if key == "action_wingbeats" {
            let n = arg_int("action_wingbeats", &v, 1, Some(MAX_ACTION_WINGBEATS))?;
            spec.action_wingbeats = n as usize;
        } else if key == "observe" {
            spec.observe = match v.extract::<String>().as_deref() {
                Ok("sensors") => Observation::Sensors,
                Ok("estimate") => Observation::Estimate,
                _ => {
                    return Err(PyValueError::new_err(format!(
                        "task.observe = {}; allowed: \"sensors\" or \"estimate\"",
                        v.repr()?
                    )));
                }
            };
        } else {
            rest.set_item(k, v)?;
        }
    }
    let mut j = merge_record(&spec, Some(&rest), "task")?;
    j.action_wingbeats = spec.action_wingbeats;
    j.observe = spec.observe;
    Ok(j)
}

fn load_randomization(path: Option<&str>) -> PyResult<Option<Randomization>> {
    let Some(p) = path else { return Ok(None) };
    // Bounded as model files are (a regular file of at most 1 MiB: a FIFO would block).
    let text = flapsim::model::read_bounded_text(std::path::Path::new(p), "randomisation file")
        .map_err(|e| pyo3::exceptions::PyOSError::new_err(format!("`randomize`: {e}")))?;
    Ok(Some(Randomization::from_toml(&text, p).map_err(sim_err)?))
}

/// A task built with the GIL released and Ctrl-C honoured (its trim runs under a
/// `flapsim::cancel` token: seconds for an actuated vehicle).
fn new_task(
    py: Python<'_>,
    model: &str,
    task: &str,
    randomize: Option<&str>,
    overrides: Option<&Bound<'_, PyDict>>,
) -> PyResult<Task> {
    let (text, origin) = model_text(model, &crate::vehicle::builtin_pairs())?;
    let spec = task_spec(task, overrides)?;
    let r = load_randomization(randomize)?;
    analysis(py, || Task::new(&text, &origin, spec, r))?.map_err(sim_err)
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
        py: Python<'_>,
        model: &str,
        task: &str,
        randomize: Option<&str>,
        spec: Option<&Bound<'_, PyDict>>,
    ) -> PyResult<Self> {
        Ok(Self {
            task: new_task(py, model, task, randomize, spec)?,
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
        crate::state::state_dict(py, &self.task.simulation().state())
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
    /// Starts an episode from `seed` (an integer from 0 to 2^64 - 1); returns the first
    /// observation.
    fn reset<'py>(
        &mut self,
        py: Python<'py>,
        seed: &Bound<'py, PyAny>,
    ) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let seed = arg_int("seed", seed, 0, None)?;
        let task = &mut self.task;
        let o = analysis(py, || task.reset(seed))?.map_err(sim_err)?;
        Ok(PyArray1::from_vec(py, o))
    }
    /// Applies an action (array-like of shape (4,), finite, within +-action_limit); returns
    /// (observation, reward, terminated, truncated, reason). Ctrl-C raises KeyboardInterrupt
    /// and ends the episode.
    fn step<'py>(
        &mut self,
        py: Python<'py>,
        action: &Bound<'py, PyAny>,
    ) -> PyResult<(Bound<'py, PyArray1<f64>>, f64, bool, bool, Option<String>)> {
        let a = actions_array("action", action, 1, &self.task)?;
        let task = &mut self.task;
        let mut sig = Signals::new();
        let s = py
            .detach(|| task.step_interruptible(&a, &mut || sig.keep_going()))
            .map_err(value_err)?;
        sig.result()?;
        let s = s.ok_or_else(|| PyValueError::new_err("the action was interrupted"))?;
        Ok((
            PyArray1::from_vec(py, s.observation),
            s.reward,
            s.terminated,
            s.truncated,
            s.reason,
        ))
    }
}

/// Actions for `n` tasks as a flat vector: `obj` must be an array-like of shape (4,) (`n` 1,
/// a single task) or exactly (n, 4), finite and within +-action_limit, refused naming
/// `name`, the index and the value otherwise (never reshaped).
fn actions_array(name: &str, obj: &Bound<'_, PyAny>, n: usize, task: &Task) -> PyResult<Vec<f64>> {
    let a = float_array(name, obj)?;
    let channels = task.vehicle().control_channels().join(", ");
    let (want, ok) = if name == "action" {
        ("(4,)".to_owned(), a.shape() == [4])
    } else {
        (format!("({n}, 4)"), a.shape() == [n, 4])
    };
    if !ok {
        return Err(PyValueError::new_err(format!(
            "`{name}` must have shape {want} (channels {channels}), got shape {}",
            shape_str(a.shape())
        )));
    }
    let v = a.readonly().as_slice()?.to_vec();
    finite(name, &v)?;
    let lim = task.action_limit();
    for (k, x) in v.iter().enumerate() {
        let (i, j) = (k / 4, k % 4);
        if x.abs() > lim[j] {
            let at = if name == "action" {
                format!("{name}[{j}]")
            } else {
                format!("{name}[{i}, {j}]")
            };
            return Err(PyValueError::new_err(format!(
                "`{at}` ({}) = {x} is outside the allowed +-{}",
                task.vehicle().control_channels()[j],
                lim[j]
            )));
        }
    }
    Ok(v)
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
    /// `num` copies (1 to 4096, `MAX_TASKS`) of the task of `HoverTask(model, task,
    /// randomize, **spec)`, built in parallel Rust threads with the GIL released (Ctrl-C
    /// honoured).
    #[new]
    #[pyo3(signature = (num, model = "drosophila", task = "hover", randomize = None, **spec))]
    fn new(
        py: Python<'_>,
        num: &Bound<'_, PyAny>,
        model: &str,
        task: &str,
        randomize: Option<&str>,
        spec: Option<&Bound<'_, PyDict>>,
    ) -> PyResult<Self> {
        let num = arg_int("num", num, 1, Some(MAX_TASKS))? as usize;
        let first = new_task(py, model, task, randomize, spec)?;
        let (text, origin) = model_text(model, &crate::vehicle::builtin_pairs())?;
        let spec_v = *first.spec();
        let r = load_randomization(randomize)?;
        let rest = watch_token(py, |stop| {
            (1..num)
                .into_par_iter()
                .map(|_| {
                    if stop.load(Ordering::Relaxed) {
                        return Ok(None);
                    }
                    flapsim::cancel::with_cancel(stop.clone(), || {
                        Task::new(&text, &origin, spec_v, r.clone()).map(Some)
                    })
                })
                .collect::<flapsim::Result<Vec<Option<Task>>>>()
        })?
        .map_err(sim_err)?;
        let mut tasks = vec![first];
        tasks.extend(rest.into_iter().flatten());
        if tasks.len() != num {
            return Err(PyValueError::new_err("building the tasks was interrupted"));
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
    /// Resets every task, task i from seeds[i] (integers from 0 to 2^64 - 1); returns
    /// observations (num, obs_len).
    fn reset<'py>(
        &mut self,
        py: Python<'py>,
        seeds: &Bound<'py, PyAny>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let seeds: Vec<u64> = int_list("seeds", seeds, 0, None, false)?
            .into_iter()
            .flatten()
            .collect();
        if seeds.len() != self.tasks.len() {
            return Err(PyValueError::new_err(format!(
                "`seeds` must have one seed per task ({}), got {}",
                self.tasks.len(),
                seeds.len()
            )));
        }
        let tasks = &mut self.tasks;
        let obs: Vec<Vec<f64>> = watch_token(py, |stop| {
            tasks
                .par_iter_mut()
                .zip(seeds.par_iter())
                .map(|(t, s)| flapsim::cancel::with_cancel(stop.clone(), || t.reset(*s)))
                .collect::<flapsim::Result<Vec<_>>>()
        })?
        .map_err(sim_err)?;
        let n = obs.len();
        let m = obs.first().map_or(0, Vec::len);
        shaped(py, obs.concat(), &[n, m])
    }
    /// Steps task i with actions[i] (an array-like of shape exactly (num, 4), finite, within
    /// +-action_limit; never reshaped), in parallel; returns observations (num, obs_len),
    /// rewards, terminated and truncated (num,). With `reset_seeds` (num integers or None),
    /// task i is instead reset from reset_seeds[i] when that is not None (Gymnasium's
    /// next-step autoreset: its first observation, reward 0, not terminated, not
    /// truncated). Ctrl-C raises KeyboardInterrupt and ends the interrupted episodes.
    #[pyo3(signature = (actions, reset_seeds = None))]
    fn step<'py>(
        &mut self,
        py: Python<'py>,
        actions: &Bound<'py, PyAny>,
        reset_seeds: Option<&Bound<'py, PyAny>>,
    ) -> PyResult<(
        Bound<'py, PyAny>,
        Bound<'py, PyAny>,
        Bound<'py, PyAny>,
        Bound<'py, PyAny>,
    )> {
        let n = self.tasks.len();
        let resets = match reset_seeds {
            None => vec![None; n],
            Some(r) => int_list("reset_seeds", r, 0, None, true)?,
        };
        if resets.len() != n {
            return Err(PyValueError::new_err(format!(
                "`reset_seeds` must have one entry per task ({n}), got {}",
                resets.len()
            )));
        }
        let flat = actions_array("actions", actions, n, &self.tasks[0])?;
        let rows: Vec<&[f64]> = flat.chunks(4).collect();
        let tasks = &mut self.tasks;
        let out: Vec<Option<TaskStep>> = watch_token(py, |stop| {
            tasks
                .par_iter_mut()
                .zip(rows.par_iter().zip(resets.par_iter()))
                .map(|(t, (a, r))| match r {
                    Some(seed) => flapsim::cancel::with_cancel(stop.clone(), || t.reset(*seed))
                        .map(|observation| {
                            Some(TaskStep {
                                observation,
                                reward: 0.0,
                                terminated: false,
                                truncated: false,
                                reason: None,
                            })
                        }),
                    None => t.step_interruptible(a, &mut || !stop.load(Ordering::Relaxed)),
                })
                .collect::<flapsim::Result<Vec<_>>>()
        })?
        .map_err(value_err)?;
        let out: Vec<TaskStep> = out
            .into_iter()
            .collect::<Option<Vec<_>>>()
            .ok_or_else(|| PyValueError::new_err("the step was interrupted"))?;
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
    /// Resets task `i` (0 to num - 1) from `seed`; returns its observation.
    fn reset_one<'py>(
        &mut self,
        py: Python<'py>,
        i: &Bound<'py, PyAny>,
        seed: &Bound<'py, PyAny>,
    ) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let n = self.tasks.len();
        let i = arg_int("i", i, 0, Some(n as u64 - 1))? as usize;
        let seed = arg_int("seed", seed, 0, None)?;
        let t = self
            .tasks
            .get_mut(i)
            .ok_or_else(|| PyValueError::new_err(format!("task index {i} out of 0..{n}")))?;
        let o = analysis(py, || t.reset(seed))?.map_err(sim_err)?;
        Ok(PyArray1::from_vec(py, o))
    }
    /// Task `i`'s randomised parameters this episode.
    fn draws<'py>(&self, py: Python<'py>, i: &Bound<'py, PyAny>) -> PyResult<Bound<'py, PyDict>> {
        let i = arg_int("i", i, 0, Some(self.tasks.len() as u64 - 1))? as usize;
        let t = self
            .tasks
            .get(i)
            .ok_or_else(|| PyValueError::new_err(format!("task index {i} out of range")))?;
        draws_dict(py, t)
    }
}
