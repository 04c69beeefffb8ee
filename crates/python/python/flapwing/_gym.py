"""Registration of flapwing's Gymnasium environments, without importing Gymnasium early.

`import flapwing` calls `register_when_imported()`: if Gymnasium is already imported the
environments are registered at once, otherwise a finder on `sys.meta_path` waits for the
first `import gymnasium` and registers them right after Gymnasium's own module has run.
Either way `import flapwing, gymnasium; gymnasium.make("flapwing/Hover-v0")` works, in
either import order, and `import flapwing` alone imports neither Gymnasium nor numpy (a
few ms, against about 0.2 s for numpy and Gymnasium, measured on the development VM). The
entry points are strings: Gymnasium imports `flapwing.envs` only at `make`.
"""

from __future__ import annotations

import importlib.abc
import importlib.util
import sys

#: (Gymnasium id, flapsim task kind) of every environment flapwing registers.
ENV_IDS = (("flapwing/Hover-v0", "hover"), ("flapwing/Recover-v0", "recover"))


def register() -> None:
    """Registers the environments with Gymnasium (imports it; a no-op for ids it has)."""
    import gymnasium as gym

    for env_id, task in ENV_IDS:
        if env_id not in gym.registry:
            gym.register(id=env_id, entry_point="flapwing.envs:FlapwingEnv",
                         kwargs={"task": task})


class _RegisterAfterGymnasium(importlib.abc.MetaPathFinder):
    """Finds `gymnasium` through the other finders and wraps its loader so that the
    environments are registered once the module has executed; then steps aside."""

    def find_spec(self, fullname, path=None, target=None):
        if fullname != "gymnasium":
            return None
        _remove_finder()
        spec = importlib.util.find_spec(fullname)
        if spec is None or spec.loader is None or not hasattr(spec.loader, "exec_module"):
            return spec
        exec_module = spec.loader.exec_module

        def exec_and_register(module):
            exec_module(module)
            register()

        spec.loader.exec_module = exec_and_register
        return spec


def _remove_finder() -> None:
    sys.meta_path[:] = [f for f in sys.meta_path if not isinstance(f, _RegisterAfterGymnasium)]


def register_when_imported() -> None:
    """Registers now if Gymnasium is imported, else right after it is (if ever)."""
    if sys.modules.get("gymnasium") is not None:
        register()
    elif not any(isinstance(f, _RegisterAfterGymnasium) for f in sys.meta_path):
        sys.meta_path.insert(0, _RegisterAfterGymnasium())
