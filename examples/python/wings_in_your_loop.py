"""The wings in your own simulator's loop (what a PyBullet or Isaac user writes).

flapwing's `WingSet` is the force element: each step, give it the body's state and apply the
wrench it returns. Here the "simulator" is a few lines of numpy: a rigid body integrated by
semi-implicit Euler (velocity first, then position and attitude), the scheme rapier uses, so
the fly below follows flapwing's own `Simulation` closely. In PyBullet the loop body becomes
`p.applyExternalForce(..., p.LINK_FRAME)`, `p.applyExternalTorque(...)`, `p.stepSimulation()`
with `p.setTimeStep(wings.dt_s)`.

Run: python examples/python/wings_in_your_loop.py
"""

import numpy as np

import flapwing


def quat_mul(a, b):
    w1, x1, y1, z1 = a
    w2, x2, y2, z2 = b
    return np.array([
        w1 * w2 - x1 * x2 - y1 * y2 - z1 * z2,
        w1 * x2 + x1 * w2 + y1 * z2 - z1 * y2,
        w1 * y2 - x1 * z2 + y1 * w2 + z1 * x2,
        w1 * z2 + x1 * y2 - y1 * x2 + z1 * w2,
    ])


def rotate(q, v):
    """world_from_body (w, x, y, z) applied to a body-frame vector."""
    w, x, y, z = q
    r = np.array([
        [1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
        [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
        [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)],
    ])
    return r @ v


def fly(wingbeats=20, model="drosophila", gyroscopic_correction=True, **controls):
    """Open-loop flight from the model's initial state (with control offsets `controls`, e.g.
    diff_amplitude_rad); returns the final state. `gyroscopic_correction=False` leaves the
    loop's rates first order in a flight that turns about more than one axis."""
    vehicle = flapwing.Vehicle(model)
    wings = flapwing.WingSet(vehicle)
    if controls:
        wings.set_controls(**controls)
    sim = flapwing.Simulation(vehicle)  # for the body's mass, inertia and initial state
    mass_kg = vehicle.mass_kg
    inertia = np.asarray(vehicle.inertia_kg_m2)
    g = np.array([0.0, 0.0, -vehicle.gravity_m_s2])
    s = sim.state
    p, q = np.array(s["position_m"]), np.array(s["world_from_body_wxyz"])
    v, w = np.array(s["velocity_m_s"]), np.array(s["angular_velocity_body_rad_s"])
    dt = wings.dt_s
    for _ in range(wingbeats * sim.steps_per_wingbeat):
        out = wings.step(p, q, v, w)
        f_world = rotate(q, out["force_body_n"])
        # This loop takes the gyroscopic term w x I w at the step's start: the wings' correction
        # makes its update of w the midpoint rule, second order as the loads are.
        m_body = out["moment_body_nm"]
        if gyroscopic_correction:
            m_body = m_body + wings.gyroscopic_correction_nm(inertia)
        # Your simulator's step: Newton and Euler, semi-implicit.
        v = v + dt * (f_world / mass_kg + g)
        w = w + dt * np.linalg.solve(inertia, m_body - np.cross(w, inertia @ w))
        p = p + dt * v
        angle = np.linalg.norm(w) * dt
        if angle > 0:
            axis = w / np.linalg.norm(w)
            dq = np.concatenate([[np.cos(angle / 2)], np.sin(angle / 2) * axis])
            q = quat_mul(q, dq)
            q = q / np.linalg.norm(q)
    return p, q, v, w


if __name__ == "__main__":
    p, q, v, w = fly()
    print(f"after 20 wingbeats: position {1e3 * p} mm, velocity {1e3 * v} mm/s")
