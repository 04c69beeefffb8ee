"""Wingbeats per wall-second: the fruit fly of examples/mujoco/fly.xml (one free body, wings =
the flapwing.wings plugin, 100 steps per wingbeat) against the flybody fly (TuragaLab/flybody
fruitfly.xml: 60+ bodies, wings as jointed bodies under MuJoCo's fluid model with
fluidshape="ellipsoid" on the wing-fluid geoms, its own 1e-4 s step), its wings driven by
sinusoidal position controls at 218 Hz. Interleaved A/B rounds; prints the ratio (not a test).

Usage: python crates/mujoco/bench_flybody.py FLYBODY_ASSETS_DIR [ROUNDS]
(FLYBODY_ASSETS_DIR: flybody/fruitfly/assets of github.com/TuragaLab/flybody.)
"""
import pathlib
import sys
import time

import numpy as np
import mujoco

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parents[2] / "examples" / "python"))
import mujoco_plugin  # noqa: E402

F_HZ = 218.0


def flybody_model(assets: pathlib.Path) -> mujoco.MjModel:
    xml = (assets / "fruitfly.xml").read_text()
    # Meshes absent from the assets (the stored snapshot lacks six head/thorax meshes) are
    # replaced by another of the fly's meshes: same cost class, other looks and mass.
    for line in xml.splitlines():
        if "<mesh name=" in line and 'file="' in line:
            f = line.split('file="')[1].split('"')[0]
            if not (assets / f).exists() or (assets / f).stat().st_size == 0:
                xml = xml.replace(f'file="{f}"', 'file="abdomen_1_body.obj"')
    xml = xml.replace('<geom type="ellipsoid" group="3" mass="0"/>',
                      '<geom type="ellipsoid" group="3" mass="0" fluidshape="ellipsoid"/>')
    spec = mujoco.MjSpec.from_string(xml)
    spec.meshdir = str(assets)
    return spec.compile()


def rate_flybody(m, d, wingbeats):
    wing = [m.actuator(n).id for n in ("wing_yaw_left", "wing_roll_left", "wing_pitch_left",
                                       "wing_yaw_right", "wing_roll_right", "wing_pitch_right")]
    steps = int(round(wingbeats / (F_HZ * m.opt.timestep)))
    t0 = time.perf_counter()
    for _ in range(steps):
        s = np.sin(2 * np.pi * F_HZ * d.time)
        d.ctrl[wing] = [s, 0.3 * s, 0.5 * s, s, 0.3 * s, 0.5 * s]
        mujoco.mj_step(m, d)
    return steps * m.opt.timestep * F_HZ / (time.perf_counter() - t0)


def rate_plugin(m, d, wingbeats):
    steps = int(round(wingbeats / (F_HZ * m.opt.timestep)))
    t0 = time.perf_counter()
    for _ in range(steps):
        mujoco.mj_step(m, d)
    return steps * m.opt.timestep * F_HZ / (time.perf_counter() - t0)


def main():
    assets = pathlib.Path(sys.argv[1])
    rounds = int(sys.argv[2]) if len(sys.argv) > 2 else 5
    mujoco_plugin.build_plugin()
    ma = mujoco.MjModel.from_xml_path(str(mujoco_plugin.FLY_XML))
    mb = flybody_model(assets)
    a, b = [], []
    for _ in range(rounds):
        da, db = mujoco.MjData(ma), mujoco.MjData(mb)  # fresh flights, interleaved
        a.append(rate_plugin(ma, da, 20))
        b.append(rate_flybody(mb, db, 20))
    a, b = np.median(a), np.median(b)
    print(f"flapwing plugin fly: {a:.0f} wingbeats/s; flybody fly: {b:.0f} wingbeats/s; "
          f"ratio {a / b:.1f} (median of {rounds} interleaved rounds of 20 wingbeats; "
          f"steps per wingbeat {1 / (F_HZ * ma.opt.timestep):.0f} vs "
          f"{1 / (F_HZ * mb.opt.timestep):.1f}; nbody {ma.nbody} vs {mb.nbody})")


if __name__ == "__main__":
    main()
