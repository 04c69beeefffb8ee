"""flapwing: insect-scale flapping-wing aerodynamics and flight simulation.

The classes are the Rust crates' own (wingforce, flapsim, flightlog) through a native
module; every array is numpy, SI units, radians, frames as in the Rust crates (world z up;
body x forward, y left, z up, origin at the centre of mass).

- `Wing`: one wing's four force terms (translational, rotational, added mass, wake capture)
  and their total at a phase, or over many phases in one call.
- `Vehicle`: a vehicle model (built-in name or file): trim, stability, LQR design.
- `Simulation`: the vehicle on rapier3d-f64, stepped one step or many per call.
- `HoverTask`, `VecHoverTask`: flapsim's control tasks (sensors, reward, termination).
- `read_log`, `read_channel`: a flapwing MCAP log, each channel as a dict of numpy arrays
  (or a pandas DataFrame when pandas is installed); `Simulation(..., mcap=PATH)` writes one.
- `flapwing.envs`: Gymnasium environments (`flapwing/Hover-v0`, `flapwing/Recover-v0`).

Errors: a bad model or argument raises `ValueError` with flapwing's message (file, field,
value, what is allowed); a run that diverges raises `DivergedError`; a failed trim or
analysis raises `AnalysisError`; unreadable files raise `OSError`.
"""

from ._flapwing import (
    AnalysisError,
    DivergedError,
    HoverController,
    HoverTask,
    Simulation,
    VecHoverTask,
    Vehicle,
    Wing,
    builtin_models,
    log_topics,
    read_channel,
)
from .logs import read_log

__all__ = [
    "AnalysisError",
    "DivergedError",
    "HoverController",
    "HoverTask",
    "Simulation",
    "VecHoverTask",
    "Vehicle",
    "Wing",
    "builtin_models",
    "log_topics",
    "read_channel",
    "read_log",
]
