#!/usr/bin/env python3
"""The RoboBee wing motion in the Harvard Microrobotics Lab's high-speed video, as `flapwing
validate` compares it (crates/flapsim/src/vehicle_validation/data.rs, ROBOBEE_VIDEO_165HZ).

Usage: scripts/research/robobee3d_video.py ROBOBEE3D_CHECKOUT
(git clone https://github.com/avikde/robobee3d; the numbers in data.rs are from commit
93e135471e37e8793a24375f4cf5be5bab396a4b.)

Data: flapopt/data/Bee1_Static_165Hz_180V_7500sf.csv (left wing) and ..._r.csv (right wing):
four tracked points per frame over one wingbeat of a clamped bee at 165 Hz and 180 V, filmed
from above the stroke plane at 7500 frames/s (the tracker's clock runs at 30 frames/s, so
t_ms = 1000 t / 250). Points A and B lie on the leading-edge spar, C and D on the membrane,
5.345 and 4.047 mm from the spar. Method: the lab's own reconstruction (loadVideoData in
flapopt/w2d_loaddata.jl), written again here: the stroke pivot is the least-squares point
on every frame's spar line; the stroke angle is the spar's direction about it; seen from
above, a membrane point's offset from the spar line is its distance times the sine of the
pitch from vertical, so sin(pitch) is the least-squares fit of the two offsets.

Printed per wing: the stroke's peak-to-peak angle, the pitch's half peak-to-peak, and the
pitch-stroke phase in flapwing's convention (0 symmetric rotation: the wing passes vertical
at stroke reversal; + advanced: before it), from first-harmonic fits at 165 Hz. Neither
mirror of the image changes the phase: flipping the pitch's or the stroke's sign moves
the fitted phase by 180 deg, which leaves the zero crossings where they were.
"""

import csv
import math
import sys

FREQ_HZ = 165.0
FRAMES_PER_S_OVER_TRACKER = 250.0
SPAR_TO_C_MM = 5.345
SPAR_TO_D_MM = 4.047


def load(path):
    with open(path, encoding="utf-8-sig") as f:
        rows = [r for r in csv.reader(f)][2:]
    rows = [[float(x) for x in r if x != ""] for r in rows if any(r)]
    t_ms = [1000.0 * r[0] / FRAMES_PER_S_OVER_TRACKER for r in rows]
    points = [[(r[3 * i + 1], r[3 * i + 2]) for r in rows] for i in range(4)]
    return t_ms, points


def pivot(a_pts, b_pts):
    """Least-squares point on every frame's spar line A-B."""
    s11 = s12 = s22 = r1 = r2 = 0.0
    for a, b in zip(a_pts, b_pts):
        n = (-(b[1] - a[1]), b[0] - a[0])
        rhs = n[0] * a[0] + n[1] * a[1]
        s11 += n[0] * n[0]
        s12 += n[0] * n[1]
        s22 += n[1] * n[1]
        r1 += n[0] * rhs
        r2 += n[1] * rhs
    det = s11 * s22 - s12 * s12
    return ((s22 * r1 - s12 * r2) / det, (s11 * r2 - s12 * r1) / det)


def angles(points):
    a_pts, b_pts, c_pts, d_pts = points
    p0 = pivot(a_pts, b_pts)
    stroke, pitch = [], []
    for b, c, d in zip(b_pts, c_pts, d_pts):
        phi = math.atan2(b[1] - p0[1], b[0] - p0[0])
        u = (math.cos(phi), math.sin(phi))

        def offset(q):
            return -u[1] * (q[0] - p0[0]) + u[0] * (q[1] - p0[1])

        s = (SPAR_TO_C_MM * offset(c) + SPAR_TO_D_MM * offset(d)) / (
            SPAR_TO_C_MM**2 + SPAR_TO_D_MM**2
        )
        stroke.append(phi)
        pitch.append(math.asin(max(-1.0, min(1.0, s))))
    for i in range(1, len(stroke)):
        while stroke[i] - stroke[i - 1] > math.pi:
            stroke[i] -= 2.0 * math.pi
        while stroke[i] - stroke[i - 1] < -math.pi:
            stroke[i] += 2.0 * math.pi
    return stroke, pitch


def first_harmonic(t_ms, y):
    """y ~ c0 + amp cos(w t + phase): least squares over the samples."""
    w = 2.0 * math.pi * FREQ_HZ / 1000.0
    x = [(1.0, math.cos(w * t), math.sin(w * t)) for t in t_ms]
    a = [[sum(r[i] * r[j] for r in x) for j in range(3)] for i in range(3)]
    rhs = [sum(r[i] * v for r, v in zip(x, y)) for i in range(3)]
    m = [a[i] + [rhs[i]] for i in range(3)]
    for i in range(3):
        p = max(range(i, 3), key=lambda k: abs(m[k][i]))
        m[i], m[p] = m[p], m[i]
        for k in range(3):
            if k != i:
                f = m[k][i] / m[i][i]
                m[k] = [m[k][j] - f * m[i][j] for j in range(4)]
    c = [m[i][3] / m[i][i] for i in range(3)]
    return math.hypot(c[1], c[2]), math.atan2(-c[2], c[1])


def wing(path):
    t_ms, points = load(path)
    stroke, pitch = angles(points)
    _, stroke_phase = first_harmonic(t_ms, stroke)
    _, pitch_phase = first_harmonic(t_ms, pitch)
    # With stroke ~ cos(w t) the pitch crosses zero (the wing vertical) at w t = 90 deg -
    # delta (mod 180), delta the pitch's lead over the stroke: after the stroke's extreme
    # by that much, so flapwing's phase (+ advanced) is its negative, wrapped to (-90, 90].
    delta = math.degrees(pitch_phase - stroke_phase)
    after = (90.0 - delta) % 180.0
    if after > 90.0:
        after -= 180.0
    return {
        "stroke_peak_to_peak_deg": math.degrees(max(stroke) - min(stroke)),
        "pitch_half_peak_to_peak_deg": 0.5 * math.degrees(max(pitch) - min(pitch)),
        "pitch_stroke_phase_deg": -after,
        "frames": len(t_ms),
        "span_ms": t_ms[-1] - t_ms[0],
    }


def main():
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    base = sys.argv[1].rstrip("/") + "/flapopt/data/Bee1_Static_165Hz_180V_7500sf"
    for side, path in (("left", base + ".csv"), ("right", base + "_r.csv")):
        w = wing(path)
        print(
            f"{side:5} {w['frames']} frames over {w['span_ms']:.3f} ms: stroke "
            f"{w['stroke_peak_to_peak_deg']:.1f} deg peak-to-peak, pitch "
            f"+-{w['pitch_half_peak_to_peak_deg']:.1f} deg, phase "
            f"{w['pitch_stroke_phase_deg']:+.1f} deg (+ advanced)"
        )


if __name__ == "__main__":
    main()
