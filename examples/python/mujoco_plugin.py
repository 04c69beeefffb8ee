"""flapwing in MuJoCo: the fruit fly of examples/mujoco/fly.xml, a MuJoCo free body whose
wings are flapwing's native engine plugin `flapwing.wings` (crates/mujoco), flies 0.1 s open
loop next to flapwing's own rapier simulation of the same model.

Run: ``python examples/python/mujoco_plugin.py`` (needs ``pip install ./crates/python mujoco``;
builds the plugin with crates/mujoco/build.sh, which needs cargo and gcc).

The native plugin takes its controls from the MJCF (config attributes) once, at load. To change
the controls while flying (a manoeuvre), the Python callback of ``fly_with_callback`` is kept as
a fallback: it steps a flapwing.Simulation for its wing loads and writes them into MuJoCo's
``xfrc_applied`` every step (a Python round trip per step).
"""

from __future__ import annotations

import pathlib
import subprocess
import sys

import numpy as np

import flapwing

try:
    import mujoco
except ImportError as e:  # pragma: no cover - the example needs MuJoCo
    raise SystemExit("this example needs MuJoCo: pip install mujoco") from e

ROOT = pathlib.Path(__file__).resolve().parents[2]
FLY_XML = ROOT / "examples" / "mujoco" / "fly.xml"


def build_plugin(python: str = sys.executable) -> pathlib.Path:
    """Builds the plugin (crates/mujoco/build.sh) against this Python's mujoco package and
    loads it into MuJoCo; returns its path."""
    out = subprocess.run([str(ROOT / "crates" / "mujoco" / "build.sh"), python],
                         capture_output=True, text=True)
    if out.returncode != 0:
        raise RuntimeError(f"crates/mujoco/build.sh failed ({out.returncode}): {out.stderr}")
    path = pathlib.Path(out.stdout.strip().splitlines()[-1])
    mujoco.mj_loadPluginLibrary(str(path))
    return path


def fly_xml(integrator: str = "Euler", model: str = "drosophila", **config: str) -> str:
    """fly.xml with another integrator, model (a built-in name or a model file) and extra
    plugin config attributes (strings)."""
    xml = FLY_XML.read_text()
    xml = xml.replace('integrator="Euler"', f'integrator="{integrator}"')
    extra = "".join(f'<config key="{k}" value="{v}"/>' for k, v in config.items())
    return xml.replace('<config key="model" value="drosophila"/>',
                       f'<config key="model" value="{model}"/>' + extra)


def fly_native(steps: int, integrator: str = "Euler", model: str = "drosophila",
               **config: str) -> dict:
    """Flies fly.xml (the plugin must be loaded) `steps` steps; returns per step the state
    after it (position_m, world_from_body_wxyz, velocity_m_s, angular_velocity_body_rad_s) and
    the wrench the plugin applied during it (force_n, moment_nm: body frame)."""
    m = mujoco.MjModel.from_xml_string(fly_xml(integrator, model, **config))
    d = mujoco.MjData(m)
    adr = m.plugin_stateadr[0]
    out = {k: np.empty((steps, n)) for k, n in (
        ("position_m", 3), ("world_from_body_wxyz", 4), ("velocity_m_s", 3),
        ("angular_velocity_body_rad_s", 3), ("force_n", 3), ("moment_nm", 3))}
    for k in range(steps):
        mujoco.mj_step(m, d)
        out["position_m"][k] = d.qpos[:3]
        out["world_from_body_wxyz"][k] = d.qpos[3:7]  # MuJoCo's quaternion is (w, x, y, z) too
        out["velocity_m_s"][k] = d.qvel[:3]  # free joint: world linear velocity ...
        out["angular_velocity_body_rad_s"][k] = d.qvel[3:6]  # ... and body-frame angular
        out["force_n"][k] = d.plugin_state[adr:adr + 3]
        out["moment_nm"][k] = d.plugin_state[adr + 3:adr + 6]
    out["dt_s"] = m.opt.timestep
    return out


def fly_flapwing(steps: int, model: str = "drosophila", **controls: float) -> dict:
    """flapwing's own rapier run of the same model and controls: the states after each step
    (like fly_native's) and the loads applied during it."""
    sim = flapwing.Simulation(flapwing.Vehicle(model), "free")
    if controls:
        sim.set_controls(**controls)  # before the first step: in force from step 0
    r = sim.run(steps + 1)  # records the state at the start of each step
    out = {k: r[k][1:] for k in ("position_m", "world_from_body_wxyz", "velocity_m_s",
                                  "angular_velocity_body_rad_s")}
    out["force_n"], out["moment_nm"] = r["force_n"][:-1], r["moment_nm"][:-1]
    out["dt_s"] = sim.dt_s
    return out


def mujoco_model(vehicle: flapwing.Vehicle, dt_s: float) -> "mujoco.MjModel":
    """(The callback fallback's body, no plugin.) A free body with the vehicle's mass and (diagonal) inertia, no contacts, MuJoCo's
    semi-implicit Euler integrator at flapwing's step."""
    ixx, iyy, izz = (float(x) for x in np.diag(vehicle.inertia_kg_m2))
    xml = f"""<mujoco model="flapwing">
  <option timestep="{float(dt_s)!r}" gravity="0 0 {-vehicle.gravity_m_s2!r}" integrator="Euler">
    <flag contact="disable"/>
  </option>
  <worldbody>
    <body name="fly">
      <freejoint/>
      <inertial pos="0 0 0" mass="{vehicle.mass_kg!r}" diaginertia="{ixx!r} {iyy!r} {izz!r}"/>
    </body>
  </worldbody>
</mujoco>"""
    return mujoco.MjModel.from_xml_string(xml)


def manoeuvre(k: int, n: int, amp0: float) -> dict | None:
    """Control changes of the open-loop manoeuvre at step k (n steps per wingbeat)."""
    if k == 2 * n:
        return {"amplitude_rad": amp0 + 0.05}
    if k == 4 * n:
        return {"diff_amplitude_rad": 0.05}
    return None


def fly_with_callback(model: str = "drosophila", wingbeats: int = 10) -> dict:
    """The fallback for control changes in flight: flies the manoeuvre in flapwing (rapier)
    and in MuJoCo fed by flapwing through ``xfrc_applied`` from Python; returns per step both
    states, the reference's total force magnitude and the body constants."""
    v = flapwing.Vehicle(model).trimmed()
    ref = flapwing.Simulation(v, "free")  # flapwing's own rigid body (rapier3d-f64)
    drv = flapwing.Simulation(v, "free")  # only its wing forces are used (the plugin)
    n = ref.steps_per_wingbeat
    m = mujoco_model(v, ref.dt_s)
    d = mujoco.MjData(m)
    s0 = ref.state
    d.qpos[:3] = s0["position_m"]
    d.qpos[3:7] = s0["world_from_body_wxyz"]  # MuJoCo's quaternion is (w, x, y, z) too
    d.qvel[:3] = s0["velocity_m_s"]  # free joint: world linear velocity ...
    d.qvel[3:6] = s0["angular_velocity_body_rad_s"]  # ... and body-frame angular velocity
    body = m.body("fly").id
    amp0 = ref.controls["amplitude_rad"]
    rot = np.zeros(9)
    out = {k: [] for k in ("p_ref", "p_mj", "w_ref", "w_mj", "force_n")}
    for k in range(wingbeats * n):
        change = manoeuvre(k, n, amp0)
        if change:
            ref.set_controls(**change)
            drv.set_controls(**change)
        # flapwing's loads at MuJoCo's state and flapwing's phase, body frame about the CoM.
        drv.set_state(position_m=d.qpos[:3].copy(), world_from_body_wxyz=d.qpos[3:7].copy(),
                      velocity_m_s=d.qvel[:3].copy(),
                      angular_velocity_body_rad_s=d.qvel[3:6].copy())
        loads = drv.step()["total"]
        mujoco.mju_quat2Mat(rot, d.qpos[3:7])
        r = rot.reshape(3, 3)
        d.xfrc_applied[body, :3] = r @ loads["force_n"]  # world frame, at the CoM
        d.xfrc_applied[body, 3:] = r @ loads["moment_nm"]
        mujoco.mj_step(m, d)
        f = ref.step()["total"]["force_n"]
        s = ref.state
        out["p_ref"].append(s["position_m"])
        out["p_mj"].append(d.qpos[:3].copy())
        out["w_ref"].append(s["angular_velocity_body_rad_s"])
        out["w_mj"].append(d.qvel[3:6].copy())
        out["force_n"].append(np.linalg.norm(f))
    res = {k: np.array(x) for k, x in out.items()}
    res.update(dt_s=ref.dt_s, mass_kg=v.mass_kg, inertia_diag=np.diag(v.inertia_kg_m2),
               length_m=v.length_m)
    return res


def integrator_bound(r: dict, roundoff: float = 1e-6) -> tuple[np.ndarray, np.ndarray]:
    """Bounds on |omega_ref - omega_mj| and |p_ref - p_mj| per step (see tests/python/
    test_mujoco.py for the derivation): the gyroscopic term's per-step effect summed, then
    integrated into attitude, velocity (the force turned by the attitude difference) and
    position; plus a round-off floor `roundoff` x the largest value so far."""
    dt, i = r["dt_s"], r["inertia_diag"]
    w = r["w_ref"]
    gyro = np.linalg.norm(np.cross(w, w * i) / i, axis=1)
    b_w = np.cumsum(dt * gyro)
    b_th = np.cumsum(dt * b_w)
    b_v = np.cumsum(dt * r["force_n"] / r["mass_kg"] * b_th)
    b_p = np.cumsum(dt * b_v)
    w_floor = roundoff * np.maximum.accumulate(np.linalg.norm(w, axis=1))
    p_floor = roundoff * np.maximum.accumulate(np.linalg.norm(r["p_ref"], axis=1))
    return b_w + w_floor, b_p + p_floor


if __name__ == "__main__":
    print(f"plugin: {build_plugin()}")
    steps = 2180  # 0.1 s at flapwing's step, 1 / (218 Hz x 100)
    mj, fw = fly_native(steps), fly_flapwing(steps)
    dp = np.linalg.norm(mj["position_m"] - fw["position_m"], axis=1)
    scale = np.linalg.norm(fw["position_m"], axis=1).max()
    print(f"native plugin, 0.1 s open loop: largest excursion {scale:.3e} m, "
          f"MuJoCo vs rapier position {dp.max():.3e} m ({dp.max() / scale:.1e} of it)")
    r = fly_with_callback()
    dp = np.linalg.norm(r["p_ref"] - r["p_mj"], axis=1)
    _, bp = integrator_bound(r)
    print(f"callback fallback, climb-and-roll manoeuvre: MuJoCo vs rapier position "
          f"{dp.max():.3e} m (bound {bp[-1]:.3e})")
