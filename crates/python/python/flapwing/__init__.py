"""flapwing: insect-scale flapping-wing aerodynamics and flight simulation.

The classes are the Rust crates' own (wingforce, flapsim, flightlog) through a native
module; every array is numpy, SI units, radians, frames as in the Rust crates (world z up;
body x forward, y left, z up, origin at the centre of mass).

- `Wing`: one wing's four force terms (translational, rotational, added mass, wake capture)
  and their total at a phase, or over many phases in one call.
- `Vehicle`: a vehicle model (built-in name or file): trim and stability in hover or at a
  flight condition (`speed_m_s`, `climb_m_s`), LQR design.
- `envelope(vehicle, speeds_m_s, climbs_m_s)`: trim, power, limit margin and modes over a
  grid of flight conditions, in parallel.
- `Simulation`: the vehicle on rapier3d-f64, stepped one step or many per call.
- `WingSet`: the wings alone as a force element for your own simulator (PyBullet, Isaac, a
  numpy integrator): give it the body's state each step, apply the wrench it returns.
- `HoverTask`, `VecHoverTask`: flapsim's control tasks (sensors, reward, termination).
- `read_log`, `read_channel`: a flapwing MCAP log, each channel as a dict of numpy arrays
  (or a pandas DataFrame when pandas is installed); `Simulation(..., mcap=PATH)` writes one.
- `flapwing.envs`: Gymnasium environments (`flapwing/Hover-v0`, `flapwing/Recover-v0`),
  registered by `import flapwing` itself (lazily: right after Gymnasium is imported, with
  `pip install 'flapwing[gym]'`), so `gymnasium.make("flapwing/Hover-v0")` works after
  `import flapwing, gymnasium` in either order.
- `builtin_models()`: the built-in vehicles (what `Vehicle`, `Simulation`, `HoverTask` and
  the environments take); `builtin_wings()`: the built-in wing-only models, which `Wing`
  takes besides every vehicle.
- `__version__`: the package version (the Rust crates' version).

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
    WingSet,
    builtin_models,
    envelope,
    log_damage,
    log_topics,
    read_channel,
)
from ._flapwing import __version__, builtin_wings
from .logs import TruncatedLogWarning, read_log

from ._gym import register_when_imported as _register_when_imported

# Gymnasium environments: registered right after Gymnasium is imported (at once if it
# already is); `import flapwing` itself imports neither Gymnasium nor numpy.
_register_when_imported()

__all__ = [
    "__version__",
    "AnalysisError",
    "DivergedError",
    "HoverController",
    "HoverTask",
    "Simulation",
    "VecHoverTask",
    "Vehicle",
    "Wing",
    "WingSet",
    "builtin_models",
    "builtin_wings",
    "envelope",
    "log_damage",
    "log_topics",
    "read_channel",
    "read_log",
    "TruncatedLogWarning",
]
