"""flapwing as a MuJoCo plugin: a MuJoCo free body with the vehicle's mass and inertia,
stepped at flapwing's step, fed flapwing's wing forces and moments every step through
``xfrc_applied``; it flies the same open-loop manoeuvre as flapwing's own rapier simulation.

Run: ``python examples/python/mujoco_plugin.py`` (needs ``pip install ./crates/python mujoco``).
The manoeuvre from the hover trim: 2 wingbeats at trim, then +0.05 rad of stroke amplitude
(climb), then from wingbeat 4 also 0.05 rad of left-minus-right amplitude (roll), to
wingbeat 10.
"""

from __future__ import annotations

import numpy as np

import flapwing

try:
    import mujoco
except ImportError as e:  # pragma: no cover - the example needs MuJoCo
    raise SystemExit("this example needs MuJoCo: pip install mujoco") from e


def mujoco_model(vehicle: flapwing.Vehicle, dt_s: float) -> "mujoco.MjModel":
    """A free body with the vehicle's mass and (diagonal) inertia, no contacts, MuJoCo's
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


def fly_both(model: str = "drosophila", wingbeats: int = 10) -> dict:
    """Flies the manoeuvre in flapwing (rapier) and in MuJoCo fed by flapwing; returns per
    step both states, the reference's total force magnitude and the body constants."""
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
    r = fly_both()
    dw = np.linalg.norm(r["w_ref"] - r["w_mj"], axis=1)
    dp = np.linalg.norm(r["p_ref"] - r["p_mj"], axis=1)
    bw, bp = integrator_bound(r)
    print(f"largest excursion (rapier): {np.linalg.norm(r['p_ref'], axis=1).max():.3e} m, "
          f"largest body rate {np.linalg.norm(r['w_ref'], axis=1).max():.2f} rad/s")
    print(f"MuJoCo vs rapier: position {dp.max():.3e} m (bound {bp[-1]:.3e}), "
          f"body rate {dw.max():.3e} rad/s (bound {bw[-1]:.3e})")
