#!/usr/bin/env python3
"""What a reset of the flapwing.wings plugin costs against building (and trimming) its wings.

    python crates/mujoco/bench_reset.py [ROUNDS]

For each built-in model with the `trim` attribute ("0 0", hover) on examples/mujoco/fly.xml's
body (gravity off, so no model falls apart whatever its mass): the time of a new mjData, whose
`init` builds and trims the wings, against the time of mj_resetData after two steps, which
since the plugin keeps a copy of the wings it built clones that copy (before, a reset built and
trimmed them again: the new mjData's cost). Rounds interleave the two; medians are printed.
"""

import importlib.util
import pathlib
import sys
import time

import mujoco
import numpy as np

ROOT = pathlib.Path(__file__).resolve().parents[2]
spec = importlib.util.spec_from_file_location(
    "mujoco_plugin", ROOT / "examples" / "python" / "mujoco_plugin.py")
plugin = importlib.util.module_from_spec(spec)
spec.loader.exec_module(plugin)


def main(rounds: int) -> None:
    plugin.build_plugin()
    for name in ["drosophila", "bumblebee", "robobee_kinematic", "dragonfly", "hummingbird"]:
        m = mujoco.MjModel.from_xml_string(plugin.fly_xml(model=name, trim="0 0"))
        m.opt.gravity[:] = 0
        builds, resets = [], []
        for _ in range(rounds):
            t = time.perf_counter()
            d = mujoco.MjData(m)
            builds.append(time.perf_counter() - t)
            mujoco.mj_step(m, d)
            mujoco.mj_step(m, d)
            t = time.perf_counter()
            mujoco.mj_resetData(m, d)
            resets.append(time.perf_counter() - t)
            del d
        b, r = np.median(builds), np.median(resets)
        print(f"{name:18s} build and trim {b * 1e3:10.3f} ms   reset {r * 1e3:8.4f} ms   "
              f"{b / r:9.0f}x", flush=True)


if __name__ == "__main__":
    main(int(sys.argv[1]) if len(sys.argv) > 1 else 5)
