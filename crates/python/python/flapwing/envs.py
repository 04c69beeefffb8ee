"""Gymnasium environments on flapsim's control tasks (flapsim::task).

`import flapwing` registers (when Gymnasium is installed; so does importing this module):

- ``flapwing/Hover-v0``: hold the hover point for 0.2 s from the trim (sensor noise only).
- ``flapwing/Recover-v0``: the same from a random roll and pitch error of up to 10 deg and a
  random velocity of up to 1 body length per second.

Both take keyword arguments: ``model`` (a built-in vehicle that hovers and has a
``[sensors]`` table: ``drosophila``, ``bumblebee``, ``robobee_kinematic``, ``hummingbird``;
or a model file with one; default ``drosophila``; the other built-in vehicles are refused
with the reason of `UNSUPPORTED`, the table "Gym tasks by vehicle" of docs/python.md), ``randomize`` (a domain-randomisation file, see
flapsim::randomize; the draws are in ``info["draws"]``) and any TaskSpec field:
``duration_s``, ``action_wingbeats`` (wingbeats per action, default 1), ``disturbance_deg``,
``disturbance_body_lengths_s``, ``max_position_body_lengths``, ``max_attitude_deg``, and
``observe`` (``"sensors"``, the default, or ``"estimate"``). A model with a ``[wind]`` table
flies every episode in that wind (turbulence seeded from the episode's seed; its numbers can
be randomised like any other field of the model).

Action: offsets from the hover trim on the vehicle's four control channels (radians, or
volts for actuated vehicles), each within +-``action_limit``: 3x the LQR design excursion,
cut to what the vehicle accepts about its trim (its actuators' voltage limit, a stroke
amplitude of at most 180 deg), so that every action of the box is controls it can fly.
``step`` before the first ``reset`` raises ``gymnasium.error.ResetNeeded``.
Observation: the IMU's newest delivered sample (gyro, rad/s; specific force minus the hover
value, m/s^2; body frame), then the motion-capture frame's position error (m) and attitude
error as a rotation vector (rad); every sensor with its noise, bias and latency. The sensors
run for their longest latency before the release, the body held at its initial state, so
the reset observation is already a delivered reading of that state (Recover-v0's tilt shows
in the specific force and the attitude error) rather than zeros. With
``observe="estimate"`` the observation is instead the state estimated from those readings by
flapsim's error-state Kalman filter (position error from the hover point, m; velocity, m/s,
world; attitude error from the trim as a rotation vector, rad; angular rate, rad/s, body) at
its newest IMU sample: 12 numbers, and the model needs motion capture.
Reward per action: 1 - (position error / body length)^2 - (attitude error / 10 deg)^2.
Terminated: position error beyond 2 body lengths, attitude error beyond 60 deg, or a
diverged simulation. Truncated: at ``duration_s``.

``VecHoverEnv`` is the vectorised form: ``num_envs`` tasks stepped in parallel Rust threads
in one call (a ``gymnasium.vector.VectorEnv`` with autoreset on the next step).
"""

from __future__ import annotations

from typing import Any

import numpy as np

import gymnasium as gym
from gymnasium import spaces

from . import _gym
from ._flapwing import HoverTask, VecHoverTask

__all__ = ["FlapwingEnv", "VecHoverEnv"]

_OBS_BOUND = 1e6  # observations are physical values; the box is only their dtype's range

#: The built-in vehicles (``flapwing.builtin_models()``) that the tasks cannot fly, and why
#: (the table "Gym tasks by vehicle" of docs/python.md and crates/python/README.md; the test
#: ``tests/python/test_envs.py`` checks that the tasks really fail on each of them and fly
#: every other built-in vehicle).
UNSUPPORTED = {
    "robobee": "it has no hover trim at its 120 Hz drive: the balance needs a drive peaking "
               "at 101.9 V and its piezo actuators allow 100 V",
}

_TABLE = "the table \"Gym tasks by vehicle\" in docs/python.md"


def _check_model(model: str) -> None:
    if isinstance(model, str) and model in UNSUPPORTED:
        raise ValueError(
            f"model={model!r}: the built-in {model} cannot fly flapwing's Gym tasks "
            f"(Hover-v0, Recover-v0): {UNSUPPORTED[model]}; see {_TABLE}")


class FlapwingEnv(gym.Env):
    """A flapsim task as a Gymnasium environment (see the module docstring)."""

    metadata = {"render_modes": []}

    def __init__(self, task: str = "hover", model: str = "drosophila",
                 randomize: str | None = None, **spec: Any) -> None:
        super().__init__()
        _check_model(model)
        self._task = HoverTask(model, task, randomize, **spec)
        lim = np.asarray(self._task.action_limit, dtype=np.float64)
        self.action_space = spaces.Box(-lim, lim, dtype=np.float64)
        n = self._task.observation_len
        self.observation_space = spaces.Box(-_OBS_BOUND, _OBS_BOUND, shape=(n,),
                                            dtype=np.float64)
        self.control_channels = list(self._task.control_channels)
        self._rng_seed = None
        self._was_reset = False

    def reset(self, *, seed: int | None = None, options: dict | None = None):
        super().reset(seed=seed)
        episode_seed = int(self.np_random.integers(0, 2**63 - 1))
        obs = self._task.reset(episode_seed)
        self._was_reset = True
        return obs, self._info()

    def step(self, action):
        if not self._was_reset:
            raise gym.error.ResetNeeded(
                "FlapwingEnv.step called before reset(): call env.reset() to start an episode")
        # The task checks the action (shape (4,), real, finite, in range): no reshaping here.
        obs, reward, terminated, truncated, reason = self._task.step(action)
        info = self._info()
        if reason is not None:
            info["reason"] = reason
        return obs, float(reward), bool(terminated), bool(truncated), info

    def _info(self) -> dict:
        return {"t_s": self._task.time_s, "draws": dict(self._task.draws)}

    @property
    def task(self) -> HoverTask:
        """The underlying flapwing.HoverTask (true state, trim, draws)."""
        return self._task


class VecHoverEnv(gym.vector.VectorEnv):
    """``num_envs`` flapsim tasks stepped in parallel Rust threads, one call per action.

    Autoreset: a sub-environment that ends is reset at the *next* step (Gymnasium's
    "next-step" mode): that step's observation is its new first observation, with reward 0
    and terminated = truncated = False.
    """

    metadata = {"autoreset_mode": gym.vector.AutoresetMode.NEXT_STEP}

    def __init__(self, num_envs: int, task: str = "hover", model: str = "drosophila",
                 randomize: str | None = None, **spec: Any) -> None:
        _check_model(model)
        self._vec = VecHoverTask(num_envs, model, task, randomize, **spec)
        self.num_envs = num_envs
        lim = np.asarray(self._vec.action_limit, dtype=np.float64)
        self.single_action_space = spaces.Box(-lim, lim, dtype=np.float64)
        n = self._vec.observation_len
        self.single_observation_space = spaces.Box(-_OBS_BOUND, _OBS_BOUND, shape=(n,),
                                                   dtype=np.float64)
        self.action_space = gym.vector.utils.batch_space(self.single_action_space, num_envs)
        self.observation_space = gym.vector.utils.batch_space(self.single_observation_space,
                                                              num_envs)
        self._done = np.zeros(num_envs, dtype=bool)
        self._np_random = None
        self._was_reset = False

    def _seeds(self, n: int) -> list[int]:
        return [int(s) for s in self.np_random.integers(0, 2**63 - 1, size=n)]

    def reset(self, *, seed: int | None = None, options: dict | None = None):
        if seed is not None:
            self._np_random, _ = gym.utils.seeding.np_random(seed)
        obs = self._vec.reset(self._seeds(self.num_envs))
        self._done[:] = False
        self._was_reset = True
        return obs, {}

    def step(self, actions):
        if not self._was_reset:
            raise gym.error.ResetNeeded(
                "VecHoverEnv.step called before reset(): call reset() to start the episodes")
        # Exactly (num_envs, 4), checked by the task: reshaping would mix envs' channels.
        a = actions
        resets = None
        if self._done.any():
            seeds = iter(self._seeds(int(self._done.sum())))
            resets = [next(seeds) if d else None for d in self._done]
        obs, rew, term, trunc = self._vec.step(a, resets)
        self._done = term | trunc
        return obs, rew, term, trunc, {}

    def draws(self, i: int) -> dict:
        """Sub-environment ``i``'s randomised parameters this episode."""
        return dict(self._vec.draws(i))


_gym.register()  # usually done already: `import flapwing` registers once Gymnasium is imported
