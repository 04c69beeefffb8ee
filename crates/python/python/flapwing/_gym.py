"""Registration of flapwing's Gymnasium environments, without importing the environments.

`flapwing/__init__.py` calls `register()` when Gymnasium is installed, so that
`import flapwing; gymnasium.make("flapwing/Hover-v0")` works; `flapwing.envs` calls it too.
The entry points are strings: Gymnasium imports `flapwing.envs` only at `make`.
"""

from __future__ import annotations

#: (Gymnasium id, flapsim task kind) of every environment flapwing registers.
ENV_IDS = (("flapwing/Hover-v0", "hover"), ("flapwing/Recover-v0", "recover"))


def register() -> None:
    """Registers the environments with Gymnasium (imports it; a no-op for ids it has)."""
    import gymnasium as gym

    for env_id, task in ENV_IDS:
        if env_id not in gym.registry:
            gym.register(id=env_id, entry_point="flapwing.envs:FlapwingEnv",
                         kwargs={"task": task})
