"""Type stubs of flapwing's native module (crates/python/src). SI units, radians; body
frame x forward, y left, z up, origin at the centre of mass; world z up; quaternions as
(w, x, y, z).

Arguments: arrays are any array-like of real numbers (lists, tuples, numpy arrays of any
float or integer dtype); complex, boolean, text or object values raise TypeError, a wrong
shape or a NaN/infinity ValueError. Integers accept anything with __index__ (numpy
integers too); a non-integer raises TypeError, an integer out of range ValueError. Every
message names the argument, the value and what is allowed; nothing is reshaped.

Limits: one call builds at most 1 GiB of output arrays (MAX_OUTPUT_BYTES: `run(record=True)`
2982616 steps, `evaluate_many`/`evaluate_cycle` 2982616 phases); a VecHoverTask holds at
most 4096 tasks; an action lasts at most 1000000 wingbeats. Long calls release the GIL and
raise KeyboardInterrupt on Ctrl-C (within about 50 ms)."""

from typing import Any, Optional, Sequence

import numpy as np
import numpy.typing as npt

FloatArray = npt.NDArray[np.float64]
Vec3 = npt.ArrayLike

class DivergedError(RuntimeError):
    """A simulation left the physically meaningful region (flapsim's Error::Diverged)."""

class AnalysisError(RuntimeError):
    """Trim, a stability analysis or a task could not do what it was asked."""

__version__: str
"""The package version (the Rust crates' version, CARGO_PKG_VERSION)."""

def builtin_models() -> list[str]:
    """Names of the built-in vehicles (what `Vehicle` and `Simulation` take; `HoverTask` and
    the Gymnasium environments take those that hover and have a `[sensors]` table: all but
    the `robobee`, whose published drive lifts less than its weight, and the four-winged
    forward-flight `dragonfly`)."""

def builtin_wings() -> list[str]:
    """Names of the built-in wing-only models (`robofly`); `Wing` takes these and every
    vehicle of `builtin_models()`."""

def envelope(vehicle: "Vehicle", speeds_m_s: Sequence[float],
             climbs_m_s: Optional[Sequence[float]] = None) -> list[dict[str, Any]]:
    """Trim, power, limit margin and modes at every forward speed with every climb rate
    (default [0.0]), in parallel: one dict per condition (climb rates outermost) with
    `condition`, `point` (None when it does not trim) and `no_trim_reason`. ValueError for
    an empty or non-finite grid, TypeError for values that are not real numbers (booleans
    included); Ctrl-C raises KeyboardInterrupt within a second."""

def log_topics(path: str) -> list[str]:
    """The topics of a flapwing MCAP log or a ROS 2 bag, in file order."""

def log_damage(path: str) -> str | None:
    """None for a complete log; else where it is truncated or damaged and what was recovered."""

def read_channel(path: str, topic: str) -> dict[str, Any]:
    """One channel as {column: array}: `log_time_ns` (int64), numeric fields as float64
    arrays (NaN where missing), others as lists of str. Of a ROS 2 bag: one topic with the
    columns of `flapwing replay BAG --csv TOPIC`; a topic that cannot be decoded raises
    ValueError."""

class Wing:
    """One wing with its kinematics, fluid and aerodynamic options."""

    def __init__(self, model: str = "robofly", side: str = "left") -> None:
        """A wing model (file or `robofly`) or the `side` wing of a vehicle model (one with
        prescribed kinematics: an actuated vehicle's wing moves as its drive makes it, and
        is refused with a ValueError naming where that motion is evaluated)."""
    @property
    def origin(self) -> str: ...
    @property
    def added_mass_form(self) -> str:
        """The added-mass term's form: "impulse" (-dP/dt), "paper" (eq 7-8) or "off"."""
    @property
    def reynolds(self) -> float:
        """Re = V_ref c_bar / nu (the seed paper's)."""
    @property
    def v_ref_m_s(self) -> float: ...
    @property
    def reference_force_n(self) -> float:
        """0.5 rho V_ref^2 S, the scale of c_l and c_d."""
    @property
    def freq_hz(self) -> float: ...
    @property
    def area_m2(self) -> float: ...
    @property
    def span_m(self) -> float: ...
    def evaluate(self, phase: float, velocity_m_s: Optional[Vec3] = None,
                 angular_velocity_rad_s: Optional[Vec3] = None) -> dict[str, Any]:
        """{term: {force_n (3,), moment_hinge_nm (3,), c_l, c_d}} for `translational`,
        `rotational`, `added_mass`, `wake_capture` and `total`; and stroke_rad, pitch_rad,
        deviation_rad, t_star. Body motion relative to the air, body frame. ValueError when
        the motion is so large that the forces overflow (not finite)."""
    def evaluate_many(self, phases: npt.ArrayLike, velocity_m_s: Optional[Vec3] = None,
                      angular_velocity_rad_s: Optional[Vec3] = None) -> dict[str, Any]:
        """`evaluate` at every phase in one call: arrays with a leading axis len(phases)
        (1-D, finite, at most 2982616 phases: 1 GiB of output)."""
    def evaluate_cycle(self, samples: Optional[int] = 1000, velocity_m_s: Optional[Vec3] = None,
                       angular_velocity_rad_s: Optional[Vec3] = None) -> dict[str, Any]:
        """One wingbeat at `samples` (1 to 2982616; None: 1000) equally spaced phases; adds
        the `phase` array."""

class Vehicle:
    """A vehicle model (built-in name or file)."""

    def __init__(self, model: str = "drosophila") -> None: ...
    @property
    def name(self) -> str: ...
    @property
    def origin(self) -> str: ...
    @property
    def model_toml(self) -> str: ...
    @property
    def added_mass_form(self) -> str:
        """The added-mass term's form: "impulse" (-dP/dt), "paper" (eq 7-8) or "off"."""
    @property
    def inflow_model(self) -> str:
        """`[aero] inflow`: "off", "frozen" or "dynamic"."""
    @property
    def mass_kg(self) -> float: ...
    @property
    def inertia_kg_m2(self) -> FloatArray:
        """3x3 about the centre of mass, body frame."""
    @property
    def length_m(self) -> float: ...
    @property
    def weight_n(self) -> float: ...
    @property
    def gravity_m_s2(self) -> float: ...
    @property
    def freq_hz(self) -> float: ...
    @property
    def steps_per_wingbeat(self) -> int: ...
    @property
    def load_sampling(self) -> str:
        """`[sim] load_sampling`: "step_start" (first order) or "midpoint" (second order)."""
    @property
    def accurate_steps_per_wingbeat(self) -> int | None:
        """`[sim] accurate_steps_per_wingbeat`: the fewest steps per wingbeat holding the
        model file's stated accuracy (from the error-cost frontier), or None."""
    @property
    def coarse_step_warning(self) -> str | None:
        """A warning when the vehicle is stepped more coarsely than that bound, else None."""
    @property
    def actuated(self) -> bool: ...
    @property
    def control_channels(self) -> list[str]:
        """The four channels of trim, the LQR and the tasks."""
    @property
    def controls(self) -> dict[str, float]: ...
    def with_controls(self, **controls: float) -> "Vehicle": ...
    def with_initial_state(self, state: dict[str, Any]) -> "Vehicle": ...
    def with_inflow(self, model: str) -> "Vehicle":
        """A copy whose wings meet another induced flow: "off", "frozen" or "dynamic"
        (`[aero] inflow`); ValueError for another name or a flow the vehicle cannot take."""
    @property
    def trim_lift(self) -> str:
        """What its trims vary to carry the weight: "amplitude", "angle_of_attack" or
        "frequency" (`[trim] lift_variable`)."""
    def with_trim_lift(self, variable: str) -> "Vehicle":
        """A copy whose trims (trim, trimmed, stability, envelope) carry the weight on
        `variable`; "angle_of_attack" holds the stroke amplitude and frequency. ValueError
        for another name, or anything but "amplitude" on an actuated vehicle."""
    def trim(self, speed_m_s: float = 0.0, climb_m_s: float = 0.0) -> dict[str, Any]:
        """Trim in hover or at a flight condition (forward speed, climb rate, m/s):
        condition, controls, pitch_rad, residuals, iterations, lift_variable."""
    def trimmed(self, speed_m_s: float = 0.0, climb_m_s: float = 0.0) -> "Vehicle":
        """The vehicle at its trim (controls applied, attitude at the trim pitch; at a
        flight condition its velocity, and the induced inflow frozen there)."""
    def stability(self, floquet: bool = True, speed_m_s: float = 0.0,
                  climb_m_s: float = 0.0) -> dict[str, Any]:
        """a_longitudinal, a_lateral (arrays) with their state names, eigenvalues_* (complex
        arrays), *_modes (eigenvalue, eigenvector, description), derivatives, and with
        `floquet` the Floquet analysis of the longitudinal motion: floquet_monodromy (the
        monodromy matrix Phi over one wingbeat, rows and columns floquet_states),
        floquet_multipliers (its eigenvalues mu, complex), floquet_exponents (ln(mu) / T,
        so mu = exp(exponent * T) with T = floquet_period_s), floquet_eigenvectors (complex,
        column k the eigenvector of multiplier k: Phi v = mu v, unit norm, largest entry
        real and positive) and floquet_longitudinal (the same per mode, as dicts)."""
    def lqr(self, delay_wingbeats: int = 0, **weights: float) -> "HoverController":
        """The per-wingbeat hover LQR at the trim (weights: flapsim's LqrWeights fields,
        Bryson's-rule maxima, each finite and > 0; delay_wingbeats >= 0)."""

class HoverController:
    """Per-wingbeat hover LQR with position integral."""

    @property
    def gain(self) -> FloatArray:
        """K (4 x 15); u = -K [error state, position integral]."""
    @property
    def trim(self) -> dict[str, Any]: ...
    @property
    def weights(self) -> dict[str, float]: ...
    @property
    def trim_channels(self) -> FloatArray: ...
    def error_state(self, state: dict[str, Any]) -> FloatArray:
        """The 12 error states of a state dict (keys it leaves out are at the hover
        reference; an empty dict is a ValueError)."""
    def update(self, state: dict[str, Any]) -> dict[str, float]:
        """Controls for the next wingbeat (pass to Simulation.set_controls(**c)); the state
        dict as for error_state."""

class Simulation:
    """One vehicle on rapier3d-f64."""

    def __init__(self, vehicle: "Vehicle | str | None" = None, mode: str = "free",
                 mcap: Optional[str] = None, log_rate_hz: Optional[float] = 2000.0, *,
                 force: bool = False) -> None:
        """mode: "free", "tethered" or "longitudinal"; `mcap` logs every step there at
        `log_rate_hz` (> 0; None: every step). An existing `mcap` file raises
        FileExistsError unless `force=True` (the CLI's --force)."""
    @property
    def vehicle(self) -> Vehicle: ...
    @property
    def mode(self) -> str: ...
    @property
    def dt_s(self) -> float: ...
    @property
    def steps(self) -> int: ...
    @property
    def time_s(self) -> float: ...
    @property
    def phase(self) -> float: ...
    @property
    def steps_per_wingbeat(self) -> int: ...
    @property
    def state(self) -> dict[str, FloatArray]:
        """position_m, world_from_body_wxyz, velocity_m_s (world),
        angular_velocity_body_rad_s, euler_rad."""
    def set_state(self, **state: Vec3) -> None: ...
    @property
    def controls(self) -> dict[str, float]: ...
    def set_controls(self, **controls: float) -> None:
        """From the start of the next wingbeat."""
    def set_control_channels(self, values: npt.ArrayLike) -> None: ...
    def set_wind(self, wind_world_m_s: Vec3) -> None: ...
    def set_wind_model(self, wind: Optional[dict[str, Any]]) -> None:
        """A wind field in the form of a model's `[wind]` table (steady_world_m_s,
        turbulence, gusts, ...), evaluated at each wing's hinge every step, on top of
        `set_wind`; None removes it. A model with a `[wind]` table starts in it."""
    @property
    def wing_winds_m_s(self) -> FloatArray:
        """Each wing's wind at its hinge at the last step, world, m/s: (n_wings, 3)
        (0 rows before the first step or without a wind field)."""
    def loads(self) -> dict[str, Any]: ...
    def step(self) -> dict[str, Any]:
        """step, t_s, phase, state (at the step's start), terms, wing_inertia, total
        ({force_n, moment_nm}, body frame about the CoM), controls."""
    def run(self, steps: int, record: bool = True) -> Optional[dict[str, FloatArray]]:
        """`steps` (>= 0) steps in one call, without the GIL; per-step arrays when `record`
        (360 bytes a step, at most 2982616 steps: 1 GiB; else ValueError: run in chunks or
        with record=False). Ctrl-C raises KeyboardInterrupt, keeping the steps taken."""
    def run_wingbeats(self, wingbeats: int, record: bool = True
                      ) -> Optional[dict[str, FloatArray]]:
        """`wingbeats` x steps_per_wingbeat steps (checked: no overflow); see `run`."""
    def summary(self) -> dict[str, Any]:
        """Cycle-mean loads per term over complete wingbeats, mean_lift_over_weight, final
        pose, drift; for an actuated vehicle also wing_motion: {wings: [left, right] with
        stroke/pitch amplitude (half peak-to-peak, deg), pitch_phase_deg (+ advanced, -
        delayed), mid_stroke_aoa_deg, drive_amplitude_v, drive_bias_v, freq_hz, ...},
        amplitude_change_deg} over the last complete drive period."""
    def close_log(self) -> Optional[dict[str, int]]: ...

class WingSet:
    """The wings of a vehicle model as a force element for a Python host (PyBullet, Isaac,
    your own integrator): step it with the body's state, apply the wrench it returns."""

    def __init__(self, vehicle: "Vehicle | str | None" = None,
                 dt_s: Optional[float] = None) -> None:
        """dt_s: the host's step (None: the model's own, 1 / (f steps_per_wingbeat))."""
    @property
    def dt_s(self) -> float: ...
    @property
    def time_s(self) -> float: ...
    @property
    def phase(self) -> float: ...
    @property
    def steps(self) -> int: ...
    def __len__(self) -> int: ...
    @property
    def load_sampling(self) -> str:
        """The model's `[sim] load_sampling` ("midpoint": the body's midpoint state is
        predicted from the last two states `step` was given)."""
    def restart_motion(self) -> None:
        """Forget earlier states: call after moving the body by hand."""
    def __copy__(self) -> "WingSet":
        """A copy in the state this set is in now; it steps as this one would, bit for bit."""
    def __deepcopy__(self, memo: object) -> "WingSet": ...
    def save_state(self, saved: "WingSet") -> None:
        """Copy this set's state into `saved`, a copy of it (copy.copy, made once), for
        restore_state; ValueError if `saved` is not a copy of this set."""
    def restore_state(self, saved: "WingSet") -> None:
        """Put back the state saved in `saved`: the steps that follow repeat those that
        followed the save, bit for bit; ValueError if `saved` is not a copy of this set."""
    def gyroscopic_correction_nm(self, inertia_body_kg_m2: npt.ArrayLike) -> list[float]:
        """After a step: the body-frame moment to add when your integrator takes w x I w at
        the step's start (makes its rates' update the midpoint rule); zeros for step_start."""
    @property
    def inflow_states(self) -> list[tuple[float, float, float]]:
        """Each pair's dynamic inflow (w0, w_x, w_y), m/s; empty unless the wake answers."""
    def set_inflow_states(self, states: list[tuple[float, float, float]]) -> None:
        """Replace each pair's dynamic inflow states; ValueError if the wake does not answer."""
    @property
    def controls(self) -> dict[str, float]: ...
    def set_controls(self, **controls: float) -> None:
        """From the start of the next wingbeat."""
    def set_wind(self, wind_world_m_s: Vec3) -> None: ...
    def step(self, position_m: Vec3, world_from_body_wxyz: npt.ArrayLike,
             velocity_m_s: Vec3, angular_velocity_body_rad_s: Vec3) -> dict[str, Any]:
        """The loads over [t_k, t_k + dt_s] from the body's state at t_k: force_body_n,
        moment_body_nm (about the CoM, body frame; the wings' loads plus the body's air
        drag from the model's drag area, also on its own as body_drag), terms,
        wing_inertia, wing_forces_body_n (n_wings x 3), t_s, phase. A body state or wind
        whose loads overflow raises ValueError."""
    def step_wrench(self, state: FloatArray, out: FloatArray) -> None:
        """The lean step: `state` a float64 array of 13 (position_m, world_from_body_wxyz,
        velocity_m_s, angular_velocity_body_rad_s), the wrench written into `out`, a float64
        array of 6 (force_body_n then moment_body_nm, the total `step` returns)."""


class HoverTask:
    """flapsim's hover or recovery task (see flapwing.envs)."""

    def __init__(self, model: str = "drosophila", task: str = "hover",
                 randomize: Optional[str] = None, **spec: float | str) -> None:
        """spec: TaskSpec fields; action_wingbeats is an integer from 1 to 1000000;
        observe is "sensors" (default) or "estimate"."""
    @property
    def spec(self) -> dict[str, Any]: ...
    @property
    def action_limit(self) -> FloatArray: ...
    @property
    def observation_len(self) -> int: ...
    @property
    def control_channels(self) -> list[str]: ...
    @property
    def steps_per_action(self) -> int: ...
    @property
    def time_s(self) -> float: ...
    @property
    def state(self) -> dict[str, FloatArray]: ...
    @property
    def trim(self) -> dict[str, Any]: ...
    @property
    def draws(self) -> dict[str, float]: ...
    def reset(self, seed: int) -> FloatArray:
        """seed: 0 to 2**64 - 1."""
    def step(self, action: npt.ArrayLike
             ) -> tuple[FloatArray, float, bool, bool, Optional[str]]:
        """action: shape (4,), finite, within +-action_limit. Ctrl-C raises
        KeyboardInterrupt and ends the episode."""

class VecHoverTask:
    """Many tasks stepped in parallel Rust threads."""

    def __init__(self, num: int, model: str = "drosophila", task: str = "hover",
                 randomize: Optional[str] = None, **spec: float) -> None:
        """num: 1 to 4096 tasks, built in parallel without the GIL."""
    def __len__(self) -> int: ...
    @property
    def observation_len(self) -> int: ...
    @property
    def action_limit(self) -> FloatArray: ...
    def reset(self, seeds: Sequence[int]) -> FloatArray: ...
    def step(self, actions: npt.ArrayLike, reset_seeds: Optional[Sequence[Optional[int]]] = None
             ) -> tuple[FloatArray, FloatArray, npt.NDArray[np.bool_], npt.NDArray[np.bool_]]:
        """actions: shape exactly (num, 4) (never reshaped), finite, within +-action_limit."""
    def reset_one(self, i: int, seed: int) -> FloatArray: ...
    def draws(self, i: int) -> dict[str, float]: ...
