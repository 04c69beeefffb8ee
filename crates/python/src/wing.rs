//! `flapwing.Wing`: one wing's four force terms at a phase, or over many phases in one call.

use numpy::{PyArray1, PyArrayMethods, PyUntypedArrayMethods};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use wingforce::{BodyMotion, Term, WingForces, WingModelSpec};

use crate::convert::{
    arg_int, arg_vec3, contiguous, finite, model_text, output_cap, real_array, scalar, shape_str,
    shaped, try_vec, vec3,
};
use crate::interrupt::Signals;
use crate::{sim_err, wing_err};

/// Bytes of output arrays per phase of `evaluate_many` / `evaluate_cycle`: five terms of
/// force (3), moment (3), c_l and c_d, four angles and the phase, as float64.
const BYTES_PER_PHASE: u64 = 8 * (5 * 8 + 4 + 1);

/// The built-in wing model (the seed paper's robotic fruit-fly wing, run V3).
const ROBOFLY_TOML: &str = include_str!("../../../models/robofly.toml");

/// One wing with its kinematics, fluid and aerodynamic options.
#[pyclass(module = "flapwing", frozen)]
pub struct Wing {
    pub(crate) wing: wingforce::Wing,
    origin: String,
}

fn side_index(side: &str) -> PyResult<usize> {
    match side {
        "left" => Ok(0),
        "right" => Ok(1),
        other => Err(PyValueError::new_err(format!(
            "side must be \"left\" or \"right\", got {other:?}"
        ))),
    }
}

fn motion(
    velocity_m_s: Option<&Bound<'_, PyAny>>,
    angular_velocity_rad_s: Option<&Bound<'_, PyAny>>,
) -> PyResult<BodyMotion> {
    Ok(BodyMotion {
        velocity_m_s: arg_vec3("velocity_m_s", velocity_m_s)?,
        angular_velocity_rad_s: arg_vec3("angular_velocity_rad_s", angular_velocity_rad_s)?,
    })
}

/// Every number of `f` is finite.
fn all_finite(f: &WingForces) -> bool {
    let term_ok = |t: &wingforce::TermForce| {
        t.force_n.iter().all(|x| x.is_finite())
            && t.moment_hinge_nm.iter().all(|x| x.is_finite())
            && t.c_l.is_finite()
            && t.c_d.is_finite()
    };
    f.terms.iter().all(term_ok)
        && term_ok(&f.total)
        && [f.angles.phi, f.angles.theta, f.angles.eta, f.phase.t_star]
            .iter()
            .all(|x| x.is_finite())
}

/// The `ValueError` of forces that overflowed.
fn not_finite(phase: f64, m: &BodyMotion) -> PyErr {
    let v = &m.velocity_m_s;
    let w = &m.angular_velocity_rad_s;
    PyValueError::new_err(format!(
        "the forces at phase {phase} are not finite for velocity_m_s = [{}, {}, {}] and \
         angular_velocity_rad_s = [{}, {}, {}]: `velocity_m_s` and `angular_velocity_rad_s` \
         must be small enough for the forces (which grow with their square) to stay finite",
        v.x, v.y, v.z, w.x, w.y, w.z
    ))
}

/// The forces at every phase, the GIL released, Ctrl-C honoured; an overflow is a
/// `ValueError` ([`not_finite`]).
fn evaluate_all(
    py: Python<'_>,
    wing: &wingforce::Wing,
    phases: &[f64],
    m: &BodyMotion,
    name: &str,
) -> PyResult<Vec<WingForces>> {
    let mut out = try_vec::<WingForces>(name, phases.len())?;
    let mut sig = Signals::new();
    let bad = py.detach(|| {
        for &x in phases {
            if !sig.keep_going() {
                return None;
            }
            let f = wing.evaluate(x, m);
            if !all_finite(&f) {
                return Some(x);
            }
            out.push(f);
        }
        None
    });
    sig.result()?;
    match bad {
        Some(x) => Err(not_finite(x, m)),
        None => Ok(out),
    }
}

const KEYS: [&str; 5] = [
    "translational",
    "rotational",
    "added_mass",
    "wake_capture",
    "total",
];

fn term_of(f: &WingForces, i: usize) -> &wingforce::TermForce {
    if i < 4 {
        f.term(Term::ALL[i])
    } else {
        &f.total
    }
}

/// Stacks `forces` into {term: {force_n (n,3), moment_hinge_nm (n,3), c_l (n,), c_d (n,)}}
/// plus the angles; `single` drops the leading axis.
fn forces_dict<'py>(
    py: Python<'py>,
    forces: &[WingForces],
    single: bool,
) -> PyResult<Bound<'py, PyDict>> {
    let n = forces.len();
    let d = PyDict::new(py);
    let shape3: Vec<usize> = if single { vec![3] } else { vec![n, 3] };
    let shape1: Vec<usize> = if single { vec![] } else { vec![n] };
    for (i, key) in KEYS.iter().enumerate() {
        let t = PyDict::new(py);
        let mut f = Vec::with_capacity(3 * n);
        let mut m = Vec::with_capacity(3 * n);
        let (mut cl, mut cd) = (Vec::with_capacity(n), Vec::with_capacity(n));
        for w in forces {
            let x = term_of(w, i);
            f.extend_from_slice(x.force_n.as_slice());
            m.extend_from_slice(x.moment_hinge_nm.as_slice());
            cl.push(x.c_l);
            cd.push(x.c_d);
        }
        if single {
            t.set_item("force_n", vec3(py, &term_of(&forces[0], i).force_n))?;
            t.set_item(
                "moment_hinge_nm",
                vec3(py, &term_of(&forces[0], i).moment_hinge_nm),
            )?;
            t.set_item("c_l", cl[0])?;
            t.set_item("c_d", cd[0])?;
        } else {
            t.set_item("force_n", shaped(py, f, &shape3)?)?;
            t.set_item("moment_hinge_nm", shaped(py, m, &shape3)?)?;
            t.set_item("c_l", shaped(py, cl, &shape1)?)?;
            t.set_item("c_d", shaped(py, cd, &shape1)?)?;
        }
        d.set_item(*key, t)?;
    }
    let angles = |get: fn(&WingForces) -> f64| -> PyResult<Bound<'py, PyAny>> {
        let v: Vec<f64> = forces.iter().map(get).collect();
        if single {
            Ok(v[0].into_pyobject(py)?.into_any())
        } else {
            shaped(py, v, &shape1)
        }
    };
    d.set_item("stroke_rad", angles(|w| w.angles.phi)?)?;
    d.set_item("pitch_rad", angles(|w| w.angles.theta)?)?;
    d.set_item("deviation_rad", angles(|w| w.angles.eta)?)?;
    d.set_item("t_star", angles(|w| w.phase.t_star)?)?;
    Ok(d)
}

#[pymethods]
impl Wing {
    /// Loads a wing: `model` is a wing model file or built-in name (`robofly`), or a vehicle
    /// model file or built-in name (`drosophila`, ...) with prescribed kinematics, whose `side`
    /// wing is taken on its hinge (forces in the body frame, moments about the hinge); an
    /// actuated vehicle's wing is refused (its motion is an output of its drive).
    #[new]
    #[pyo3(signature = (model = "robofly", side = "left"))]
    fn new(model: &str, side: &str) -> PyResult<Self> {
        let i = side_index(side)?;
        let mut builtins: Vec<(&str, &'static str)> = vec![("robofly", ROBOFLY_TOML)];
        builtins.extend(crate::vehicle::builtin_pairs());
        let (text, origin) = model_text(model, &builtins)?;
        let is_vehicle = text
            .parse::<toml::Table>()
            .map(|t| t.contains_key("body"))
            .unwrap_or(false);
        let wing = if is_vehicle {
            let v = flapsim::Vehicle::from_toml(&text, &origin).map_err(sim_err)?;
            if v.actuation.is_some() {
                // Its [kinematics] is only the nominal motion the first wingbeat starts from:
                // a Wing of it would evaluate a motion the vehicle never makes.
                return Err(PyValueError::new_err(format!(
                    "{origin}: `{}` has actuated wings, whose motion is an output of their drive and dynamics; a Wing evaluates prescribed kinematics. Its wing on the periodic motion its drive gives it: `flapwing forces --model {model}`, or Simulation(Vehicle({model:?}), mode=\"tethered\")",
                    v.name
                )));
            }
            v.wings[i].clone()
        } else {
            WingModelSpec::from_toml(&text, &origin)
                .and_then(|s| s.build(&origin))
                .map_err(wing_err)?
        };
        Ok(Self { wing, origin })
    }

    /// Where the model came from (a path or `<built-in NAME>`).
    #[getter]
    fn origin(&self) -> &str {
        &self.origin
    }
    /// The added-mass term's form: `"impulse"` (-dP/dt, MODEL.md 4.3), `"paper"` (eq 7-8)
    /// or `"off"`.
    #[getter]
    fn added_mass_form(&self) -> &'static str {
        self.wing.options().added_mass.name()
    }
    /// The paper's Reynolds number Re = V_ref c_bar / nu.
    #[getter]
    fn reynolds(&self) -> f64 {
        self.wing.reynolds()
    }
    /// V_ref, the peak stroke speed at the radius of gyration, m/s.
    #[getter]
    fn v_ref_m_s(&self) -> f64 {
        self.wing.v_ref_m_s()
    }
    /// 0.5 rho V_ref^2 S, the force scale of the coefficients, N.
    #[getter]
    fn reference_force_n(&self) -> f64 {
        self.wing.reference_force_n()
    }
    /// Wingbeat frequency, Hz.
    #[getter]
    fn freq_hz(&self) -> f64 {
        1.0 / self.wing.kinematics().period_s()
    }
    /// Wing area (one wing), m^2.
    #[getter]
    fn area_m2(&self) -> f64 {
        self.wing.geometry().area_m2
    }
    /// Span, m.
    #[getter]
    fn span_m(&self) -> f64 {
        self.wing.geometry().span_m
    }

    /// Forces at one wingbeat `phase` (cycles; 0 = start of the downstroke) with the body
    /// moving at `velocity_m_s` and `angular_velocity_rad_s` (body frame, relative to the
    /// air). Returns {term: {force_n, moment_hinge_nm, c_l, c_d}} for the four terms and
    /// `total`, and the angles.
    #[pyo3(signature = (phase, velocity_m_s = None, angular_velocity_rad_s = None))]
    fn evaluate<'py>(
        &self,
        py: Python<'py>,
        phase: &Bound<'py, PyAny>,
        velocity_m_s: Option<&Bound<'py, PyAny>>,
        angular_velocity_rad_s: Option<&Bound<'py, PyAny>>,
    ) -> PyResult<Bound<'py, PyDict>> {
        let phase = scalar("phase", phase)?;
        let m = motion(velocity_m_s, angular_velocity_rad_s)?;
        let f = self.wing.evaluate(phase, &m);
        if !all_finite(&f) {
            return Err(not_finite(phase, &m));
        }
        forces_dict(py, &[f], true)
    }

    /// Forces at every phase of `phases` (any 1-D array-like of finite reals) in one call
    /// (the GIL released meanwhile, Ctrl-C honoured), with the same body motion: the arrays
    /// of [`evaluate`] with a leading axis of len(phases). At most
    /// `MAX_OUTPUT_BYTES / 360` (2982616) phases per call.
    #[pyo3(signature = (phases, velocity_m_s = None, angular_velocity_rad_s = None))]
    fn evaluate_many<'py>(
        &self,
        py: Python<'py>,
        phases: &Bound<'py, PyAny>,
        velocity_m_s: Option<&Bound<'py, PyAny>>,
        angular_velocity_rad_s: Option<&Bound<'py, PyAny>>,
    ) -> PyResult<Bound<'py, PyDict>> {
        let a = real_array("phases", phases)?;
        if a.ndim() != 1 {
            return Err(PyValueError::new_err(format!(
                "`phases` must be 1-D (shape (n,)), got shape {}",
                shape_str(a.shape())
            )));
        }
        output_cap(
            "len(phases)",
            a.len() as u64,
            BYTES_PER_PHASE,
            ": evaluate in chunks",
        )?;
        let a = contiguous(&a)?;
        let ro = a.readonly();
        let p = ro.as_slice()?;
        finite("phases", p)?;
        let m = motion(velocity_m_s, angular_velocity_rad_s)?;
        let forces = evaluate_all(py, &self.wing, p, &m, "phases")?;
        forces_dict(py, &forces, false)
    }

    /// One whole wingbeat sampled at `samples` equally spaced phases (0, 1/n, ...): the
    /// `phase` array and the arrays of [`evaluate_many`]. `samples` is from 1 to 2982616
    /// (the 1 GiB output cap).
    #[pyo3(signature = (samples = None, velocity_m_s = None, angular_velocity_rad_s = None))]
    fn evaluate_cycle<'py>(
        &self,
        py: Python<'py>,
        samples: Option<&Bound<'py, PyAny>>,
        velocity_m_s: Option<&Bound<'py, PyAny>>,
        angular_velocity_rad_s: Option<&Bound<'py, PyAny>>,
    ) -> PyResult<Bound<'py, PyDict>> {
        let samples = match samples {
            None => 1000,
            Some(s) => arg_int(
                "samples",
                s,
                1,
                Some(crate::convert::MAX_OUTPUT_BYTES / BYTES_PER_PHASE),
            )?,
        } as usize;
        let m = motion(velocity_m_s, angular_velocity_rad_s)?;
        let mut p = try_vec::<f64>("samples", samples)?;
        p.extend((0..samples).map(|k| k as f64 / samples as f64));
        let forces = evaluate_all(py, &self.wing, &p, &m, "samples")?;
        let d = forces_dict(py, &forces, false)?;
        d.set_item("phase", PyArray1::from_vec(py, p))?;
        Ok(d)
    }

    fn __repr__(&self) -> String {
        format!(
            "Wing(origin={:?}, reynolds={:.1}, freq_hz={:.3})",
            self.origin,
            self.wing.reynolds(),
            1.0 / self.wing.kinematics().period_s()
        )
    }
}
