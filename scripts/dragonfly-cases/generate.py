#!/usr/bin/env python3
"""Writes models/dragonfly_azuma*.toml from the published Fourier series (see each case below).

The sampling and sign conventions are those of models/dragonfly.toml (Azuma & Watanabe 1988,
experiment 2), which this script reproduces exactly as a check (`--check`):
  flapwing stroke  = -(psi0 + psi1 cos(w t + delta))     (A&W's flapping angle, positive up)
  flapwing pitch   = theta0 + sum_n theta_n cos(n w t + delta_n)   (A&W's feathering angle)
  the hindwing written in its own wingbeat (t' = t + delta_h / w, `phase_offset_deg = delta_h`),
  each pitch harmonic n moved by -n delta_h; coning as a constant deviation.
48 samples a wingbeat plus the closing one.
"""
import math
import sys

N = 48


def series(mean, terms, t, w):
    return mean + sum(a * math.cos(n * w * t + math.radians(p)) for n, (a, p) in enumerate(terms, 1))


def table(name, values, fmt, per_line=10):
    lines = [f"{name} = ["]
    for i in range(0, len(values), per_line):
        lines.append("    " + ", ".join(fmt % v for v in values[i:i + per_line]) + ",")
    lines.append("]")
    return "\n".join(lines)


def wing_tables(f, flap_mean, flap_amp, pitch_mean, pitch_terms, cone, lead_deg, twist=None):
    """Tables in the wing's own wingbeat (its flapping's top at t = 0). `twist`: the
    feathering series at further stations, [(r_frac, mean, terms)], written as the table's
    `[...kinematics.twist]` (`twist_block`) with the pitch at 0.75R its reference."""
    w = 2 * math.pi * f
    ts = [k / (N * f) for k in range(N + 1)]

    def pitch_of(mean, terms):
        shifted = [(a, p - n * lead_deg) for n, (a, p) in enumerate(terms, 1)]
        return [series(mean, [(a, ((p + 180) % 360) - 180) for a, p in shifted], t, w) for t in ts], shifted

    stroke = [-flap_mean - flap_amp * math.cos(w * t) for t in ts]
    pitch, shifted = pitch_of(pitch_mean, pitch_terms)
    text = "\n".join([
        'family = "tabulated"',
        table("t_s", ts, "%.9f"),
        table("stroke_deg", stroke, "%.4f"),
        table("pitch_deg", pitch, "%.4f"),
        table("deviation_deg", [cone] * (N + 1), "%.1f"),
    ])
    if twist:
        rows = [pitch_of(mean, terms)[0] for _, mean, terms in twist]
        text += "\n" + twist_block([r for r, _, _ in twist], rows)
    return text, shifted


def twist_block(stations, rows):
    """The `twist` keys of a table (its section header is the caller's)."""
    lines = ["TWIST_HEADER", "reference_r_frac = 0.75",
             "stations_r_frac = [" + ", ".join(f"{r:g}" for r in stations) + "]", "pitch_deg = ["]
    for row in rows:
        lines.append("    [")
        for i in range(0, len(row), 10):
            lines.append("        " + ", ".join("%.4f" % v for v in row[i:i + 10]) + ",")
        lines.append("    ],")
    lines.append("]")
    return "\n".join(lines)


if __name__ == "__main__" and "--check" in sys.argv:
    # Azuma & Watanabe 1988, experiment 2: must reproduce models/dragonfly.toml's tables.
    text = open("models/dragonfly.toml").read()
    fore, _ = wing_tables(28.1, 0.0, 25.0, 88.0, [(54, 93), (4, 135), (4, -68), (5, 113)], 8.0, 0.0)
    hind, _ = wing_tables(28.1, 0.0, 26.0, 81.0, [(30, 154), (6, -69), (2, -52), (2, 83)], -2.0, 61.0)
    for t in (fore, hind):
        for block in t.split("\n]\n"):
            body = block.split("[\n", 1)[-1]
            assert body in text, block[:200]
    print("models/dragonfly.toml reproduced")


A88 = """Azuma & Watanabe 1988 (J Exp Biol 137:221), Table 2 (flight) and Table 3
# (feathering: 0.75R the pitch, 0.25R and 0.5R the twist), read from the scans of the two tables in the public repository
# github.com/jpecquet/dragonfly-flight-control (data/case_studies/azuma1988/table2.png and
# table3.png, commit b7816df) and cross-checked against its digitised case data
# (data/case_studies/azuma1988/case.json, cases/azuma1988_exp*/case.yaml, commit cf19b0a)"""

# Azuma & Watanabe 1988, Table 2 (flight) and Table 3 (feathering at 0.75R).
# Where Table 2's flapping-to-feathering phase difference disagrees with Table 3's 0.75R phase
# (the files use Table 3; docs/models.md gives the forces with Table 2's values).
TABLE_NOTES = {
    1: ("hind", "Table 2 gives the hindwing's flapping-to-feathering phase difference as 102 deg,\n"
                "#     i.e. a first-harmonic phase of 51 + 102 = 153 deg, 29 deg from Table 3's -178 (used here)"),
    3: ("hind", "Table 2 gives the hindwing's flapping-to-feathering phase difference as 95 deg,\n"
                "#     i.e. a first-harmonic phase of 61 + 95 = 156 deg, 40 deg from Table 3's -164 (used here)"),
    4: ("fore", "Table 2 gives the forewing's flapping-to-feathering phase difference as 89 deg,\n"
                "#     10 deg from Table 3's 99 (used here)"),
}

EXPERIMENTS = {
    1: dict(fly="A", V=0.7, Gamma=-12.0, Theta=20.0, f=26.5, gf=40, gh=38, gfb=60, ghb=58, pf=36, ph=26, dh=51, n=1.1,
            tf=(100, [(54, 89), (2, -88), (7, 52), (1, -7)]), th=(107, [(38, -178), (6, -112), (2, -37), (1, -216)])),
    2: dict(fly="A", V=1.5, Gamma=-1.1, Theta=12.0, f=28.1, gf=55, gh=48, gfb=67, ghb=60, pf=25, ph=26, dh=61, n=0.97,
            tf=(88, [(54, 93), (4, 135), (4, -68), (5, 113)]), th=(81, [(30, 154), (6, -69), (2, -52), (2, 83)])),
    3: dict(fly="A", V=2.3, Gamma=4.8, Theta=4.0, f=29.0, gf=58, gh=52, gfb=62, ghb=56, pf=25, ph=26, dh=61, n=1.25,
            tf=(81, [(46, 91), (6, 154), (3, 45), (4, 106)]), th=(79, [(24, -164), (11, -81), (2, -66), (2, 169)])),
    4: dict(fly="B", V=3.2, Gamma=0.0, Theta=2.0, f=27.0, gf=63, gh=68, gfb=65, ghb=70, pf=38, ph=34, dh=93, n=1.05,
            tf=(83, [(48, 99), (6, 98), (4, 142), (4, -117)]), th=(76, [(41, 174), (3, -88), (3, -10), (3, 53)])),
}


# Azuma & Watanabe 1988, Table 3, all three stations (0.25R, 0.5R, 0.75R): theta_0..theta_4 then
# phi_1..phi_4, deg, read from the same scan (table3.png, commit b7816df). The files use the
# 0.75R column as the pitch (EXPERIMENTS, checked equal below) and the other columns as the
# wing's spanwise twist (`[kinematics.twist]`). `--stations DIR` writes each experiment as a
# rigid wing feathering as at each station, to measure what the twist does (docs/models.md,
# "The published dragonfly flights").
STATIONS = (0.25, 0.5, 0.75)
TABLE3 = {
    "fore": {
        1: ([91, 95, 100], [24, 36, 54], [5, 5, 2], [3, 7, 7], [2, 4, 1],
            [95, 87, 89], [-124, -86, -88], [-33, 12, 52], [77, 27, -7]),
        2: ([86, 90, 88], [25, 36, 54], [4, 4, 4], [4, 4, 4], [1, 0, 5],
            [77, 89, 93], [144, 137, 135], [-77, -65, -68], [17, -165, 113]),
        3: ([77, 82, 81], [14, 29, 46], [3, 1, 6], [1, 3, 3], [3, 1, 4],
            [104, 88, 91], [-92, 160, 154], [148, 65, 45], [-68, -3, 106]),
        4: ([72, 79, 83], [17, 30, 48], [3, 5, 6], [3, 4, 4], [2, 3, 4],
            [94, 99, 99], [-90, 82, 98], [6, 112, 142], [62, -101, -117]),
    },
    "hind": {
        1: ([103, 105, 107], [19, 27, 38], [5, 9, 6], [2, 1, 2], [2, 1, 1],
            [-163, -169, -178], [-144, -131, -112], [-107, 148, -37], [-15, -104, -216]),
        2: ([85, 84, 81], [9, 23, 30], [3, 4, 6], [0, 2, 2], [0, 2, 2],
            [146, 154, 154], [-140, -100, -69], [10, -98, -52], [-96, 197, 83]),
        3: ([83, 82, 79], [10, 22, 24], [3, 9, 11], [0, 4, 2], [4, 2, 2],
            [147, 163, -164], [-67, -71, -81], [-106, -86, -66], [-154, -159, 169]),
        4: ([73, 74, 76], [23, 30, 41], [4, 3, 3], [3, 2, 3], [1, 3, 3],
            [164, 167, 174], [-158, -91, -88], [109, -25, -10], [58, 50, 53]),
    },
}


def station_series(wing, k, station):
    """Table 3's feathering series of `wing` in experiment `k` at `station` (a fraction of R)."""
    c = TABLE3[wing][k]
    i = STATIONS.index(station)
    return (c[0][i], [(c[1 + n][i], c[5 + n][i]) for n in range(4)])


for _k, _e in EXPERIMENTS.items():
    assert station_series("fore", _k, 0.75) == _e["tf"] and station_series("hind", _k, 0.75) == _e["th"]


def fmt_series(mean, terms, var="w t"):
    s = f"{mean:g}"
    for n, (a, p) in enumerate(terms, 1):
        arg = var if n == 1 else f"{n} {var}"
        sign = "+" if a >= 0 else "-"
        ps = f" + {p:g}" if p >= 0 else f" - {-p:g}"
        s += f" {sign} {abs(a):g} cos({arg}{ps})"
    return s


def write_1988(k, station=0.75, path=None, rigid=False):
    """Experiment `k`'s model file at `path` (its models/ file by default): the pitch
    Table 3's column at `station` (the files': 0.75R), with the twist of the other stations
    unless `rigid` (a variant: the whole wing feathering as at `station`)."""
    e = dict(EXPERIMENTS[k], tf=station_series("fore", k, station), th=station_series("hind", k, station))
    # The model (0.75R) carries the twist: Table 3's inner stations; a station variant is a
    # rigid wing feathering as at its station.
    inner = [s for s in STATIONS if s != 0.75]
    twist = (lambda wing: None) if rigid else (lambda wing: [(s, *station_series(wing, k, s)) for s in inner])
    header = ("# Table 3's feathering at 0.25R and 0.5R (the pitch above is 0.75R's): the wing's spanwise\n"
              "# twist, sampled as the pitch ({} time).\n[{}kinematics.twist]")
    fore, _ = wing_tables(e["f"], 0.0, e["pf"], *e["tf"], 8.0, 0.0, twist("fore"))
    fore = fore.replace("TWIST_HEADER", header.format("the forewing's", ""))
    hind, shifted = wing_tables(e["f"], 0.0, e["ph"], *e["th"], -2.0, float(e["dh"]), twist("hind"))
    hind = hind.replace("TWIST_HEADER", header.format("the hindwing's own", "pairs."))
    shifted = [(a, ((p + 180) % 360) - 180) for a, p in shifted]
    g, s = math.radians(e["Gamma"]), e["V"]
    note = TABLE_NOTES.get(k)
    fnote = f"\n#   note: {note[1]};" if note and note[0] == "fore" else ""
    hnote = f"\n#   note: {note[1]};" if note and note[0] == "hind" else ""
    b_note = ("" if e["fly"] == "A" else
              "\n# Dragonfly B: its own morphology (the paper's Table 1) was not read in this session; the\n"
              "# repository's case data reuse dragonfly A's numbers for B, and so does this file (estimate).")
    text = f'''# Azuma & Watanabe 1988 ("Flight performance of a dragonfly", J Exp Biol 137:221-252), experiment
# {k}: dragonfly {e["fly"]} (Anax parthenope julius) at {e["V"]} m/s, flight path {e["Gamma"]:g} deg from the horizontal, body
# attitude {e["Theta"]:g} deg (nose up), {e["f"]} Hz. Azuma & Watanabe's own calculation gives a load factor
# n = {e["n"]} for this flight (Table 2, "calculated load factor").
#
# Source of the numbers: {A88}.
# Written by scripts/dragonfly-cases/generate.py in the sign conventions and sampling of
# models/dragonfly.toml (experiment 2), which the script reproduces (`--check`).
# "estimate:" marks numbers not found in any source; the morphology, fluid, inertia and hinge
# estimates are models/dragonfly.toml's (the same specimen, dragonfly A).{b_note}
# Nothing here was tuned to meet a check (crates/flapsim/tests/dragonfly_cases.rs compares
# the forces with the weight).
name = "dragonfly_azuma1988_exp{k}"

[fluid]
density_kg_m3 = 1.204               # dry air, 20 C (standard tables), as models/dragonfly.toml
kinematic_viscosity_m2_s = 1.516e-5 # dry air, 20 C (standard tables)

[body]
mass_kg = 790.0e-6                  # 790 mg (A&W 1988, specimen data, as models/dragonfly.toml)
# estimate: models/dragonfly.toml's solid ellipsoid (75 mm long, 6 mm thick).
inertia_diag_kg_m2 = [2.84e-9, 2.236e-7, 2.236e-7]
length_m = 75.0e-3                  # body length 75 mm (A&W 1988, specimen data)

[wing.planform]
shape = "ellington_beta"
span_m = 50.0e-3                    # forewing length 50 mm (A&W 1988, specimen data)
area_m2 = 5.0e-4                    # forewing area 5.0 cm^2 (A&W 1988, specimen data)
r1_hat = 0.51                       # estimate: Aeshna cyanea's forewing (Wakeling 1997), as models/dragonfly.toml
root_offset_m = 0.0                 # estimate: as models/dragonfly.toml
pitch_axis_from_le_frac = 0.25      # estimate: as models/dragonfly.toml

[hinge]
left_in_body_m = [3.5e-3, 2.5e-3, 3.0e-3]  # estimate: as models/dragonfly.toml
# Forewing stroke plane {e["gfb"]} deg from the body axis (Table 2: gamma_f + Theta = {e["gf"]} + {e["Theta"]:g}; {e["gf"]} deg
# from the horizontal), the body at its published attitude (see [initial]).
stroke_plane_tilt_deg = {float(e["gfb"]):.1f}

[kinematics]
# Table 2 and 3, sampled 48 times a wingbeat at f = {e["f"]} Hz:
#   stroke: phi = -{e["pf"]} cos(w t) deg (flapping amplitude psi_f = {e["pf"]} deg, a {2 * e["pf"]} deg stroke; t = 0 the top);
#   pitch (feathering at 0.75R): theta = {fmt_series(*e["tf"])} deg;{fnote}
#   deviation: the forewing's coning angle, +8 deg (A&W 1988, as models/dragonfly.toml).
{fore}

# The hindwings.
[[pairs]]
# Table 2: the hindwing's flapping leads the forewing's by delta_h = {e["dh"]} deg.
phase_offset_deg = {float(e["dh"]):.1f}

[pairs.hinge]
left_in_body_m = [-3.5e-3, 2.5e-3, 3.0e-3]  # estimate: as models/dragonfly.toml
# Hindwing stroke plane {e["ghb"]} deg from the body axis (Table 2: {e["gh"]} + {e["Theta"]:g}; {e["gh"]} deg from the horizontal).
stroke_plane_tilt_deg = {float(e["ghb"]):.1f}

[pairs.wing.planform]
shape = "ellington_beta"
span_m = 48.5e-3                    # hindwing length 48.5 mm (A&W 1988, specimen data)
area_m2 = 6.0e-4                    # hindwing area 6.0 cm^2 (A&W 1988, specimen data)
r1_hat = 0.46                       # estimate: Aeshna cyanea's hindwing (Wakeling 1997), as models/dragonfly.toml
root_offset_m = 0.0                 # estimate: as the forewing
pitch_axis_from_le_frac = 0.25      # estimate: as the forewing

[pairs.kinematics]
# Table 2 and 3, in the hindwing's own wingbeat (each pitch harmonic n moved by -{e["dh"]} n deg):
#   stroke: phi = -{e["ph"]} cos(w t') deg (psi_h = {e["ph"]} deg);
#   pitch, published: theta = {fmt_series(*e["th"])} deg,
#     in the hindwing's time: theta = {fmt_series(e["th"][0], shifted, "w t'")} deg;{hnote}
#   deviation: coning -2 deg (A&W 1988, as models/dragonfly.toml).
{hind}

[sim]
steps_per_wingbeat = 100

[initial]
# Table 2: {e["V"]} m/s at {e["Gamma"]:g} deg from the horizontal, body attitude {e["Theta"]:g} deg nose up.
attitude_deg = [0.0, {e["Theta"]:.1f}, 0.0]
velocity_m_s = [{s * math.cos(g):.4f}, 0.0, {s * math.sin(g):.4f}]
'''
    if rigid:
        text = text.replace("(feathering at 0.75R)",
                            f"(feathering at {station}R over the whole span: a rigid variant, not the model)")
        text = text.replace(f'name = "dragonfly_azuma1988_exp{k}"',
                            f'name = "dragonfly_azuma1988_exp{k}_rigid_{station}R"')
    open(path or f"models/dragonfly_azuma1988_exp{k}.toml", "w").write(text)


A85 = """Azuma et al. 1985 ("Flight mechanics of a dragonfly", J Exp Biol
# 116:79-107): the specimen, flight and Fourier series as digitised in the public repository
# github.com/jpecquet/dragonfly-flight-control (cases/azuma1985/case.yaml, commit fe767a9, and
# its page docs/validation/azuma1985.md, whose Tables 1-4 tabulate the paper's Table 1, Eqs 1-2
# and Fig. 4, commit cf19b0a), checked against the paper itself (the PDF in that repository's
# history, azuma1985.pdf, added in fe767a9 and removed in 6b22936). That repository writes
# the series in its simulator's convention (flapping phi = -paper, pitch psi = paper theta - 90
# deg), the same convention as its Azuma & Watanabe 1988 cases, whose experiment 2 is
# models/dragonfly.toml: flapwing's stroke is -phi and its pitch psi + 90 deg in both"""


def write_1985():
    f = 41.5
    fore_pitch = (98.0, [(-77, -49), (-3, 67), (-8, 29)])
    hind_pitch = (93.0, [(-65, 18), (8, 74), (8, 28)])
    fore, _ = wing_tables(f, 3.0, 43.0, *fore_pitch, 8.0, 0.0)
    hind, shifted = wing_tables(f, -2.0, 47.0, *hind_pitch, -2.0, 77.0)
    shifted = [(a, ((p + 180) % 360) - 180) for a, p in shifted]
    g, s = math.radians(50.0), 0.54
    text = f'''# Azuma et al. 1985 ("Flight mechanics of a dragonfly", J Exp Biol 116:79-107): a dragonfly
# (Sympetrum frequens, as Azuma & Watanabe 1988's introduction names it: "can make steady
# climbing flight", journals.biologists.com/jeb/article/137/1/221) in "almost steady flight
# ... in very slow climbing flight" (p. 84) at 0.54 m/s "in a direction nearly normal to the
# stroke plane" (p. 87, (v)): 50 deg above the horizontal, normal to the stroke planes at
# gamma = 40 deg (p. 84, (ii); the arrow of Fig. 4 reads about 50 deg too), 41.5 Hz, the body
# "tipped about 10 deg head-up with respect to the horizontal" (p. 84, (i)). The paper's own
# calculation of the forces (local circulation method, Fig. 16; its fore- and hindwing force
# curves as digitised in the repository's cases/azuma1985/paper_data.csv, commit 6b22936)
# averages 2.557 up over the wingbeat, read as mN: the weight (260 mg, 2.551 mN), 1.002 of it;
# and in the horizontal fore -0.156, hind +0.323, together +0.167 (Fig. 16A, captioned
# "Thrust": forward read as positive; the text, p. 104: "The mean horizontal force is a very
# small positive value because the dragonfly is climbing only slowly").
#
# Source of the numbers: {A85}.
# Written by scripts/dragonfly-cases/generate.py with models/dragonfly.toml's sampling.
# "estimate:" marks numbers not found in any source. Nothing here was tuned to meet a check
# (crates/flapsim/tests/dragonfly_cases.rs compares the forces with the weight).
name = "dragonfly_azuma1985"

[fluid]
density_kg_m3 = 1.204               # dry air, 20 C (standard tables), as models/dragonfly.toml
kinematic_viscosity_m2_s = 1.516e-5 # dry air, 20 C (standard tables)

[body]
mass_kg = 260.0e-6                  # 260 mg (Azuma et al. 1985, Table 1, digitised)
# estimate: solid ellipsoid of the body's mass, 40 mm long (Table 1) and 4 mm thick (not from the
# paper): Ixx = m 2 b^2 / 5, Iyy = Izz = m (a^2 + b^2) / 5, a = 20 mm, b = 2 mm.
inertia_diag_kg_m2 = [4.16e-10, 4.2016e-8, 4.2016e-8]
length_m = 40.0e-3                  # body length 40 mm (Table 1)

[wing.planform]
shape = "ellington_beta"
span_m = 33.5e-3                    # forewing length 33.5 mm (Table 1)
area_m2 = 2.21e-4                   # forewing area 221 mm^2 (Table 1)
r1_hat = 0.51                       # estimate: models/dragonfly.toml's aeshnid forewing (Wakeling 1997's Aeshna cyanea)
root_offset_m = 0.0                 # estimate: as models/dragonfly.toml
pitch_axis_from_le_frac = 0.25      # estimate: as models/dragonfly.toml

[hinge]
# estimate: models/dragonfly.toml's hinges scaled by the body length (40/75).
left_in_body_m = [1.9e-3, 1.3e-3, 1.6e-3]
# Forewing stroke plane 47 deg from the body axis: 37 deg from the horizontal with the body
# 10 deg head-up (Fig. 4 gives both; p. 84, (ii): "about 50 deg with respect to the body axis,
# or gamma = 40 deg with respect to the horizontal").
stroke_plane_tilt_deg = 47.0

[kinematics]
# Eqs 1-2 (p. 87; the repository's Tables 2-3, in its convention phi, psi), sampled 48 times a
# wingbeat at f = 41.5 Hz (the pitch theta "with respect to the stroke plane", p. 87, (vi),
# observed at the painted wing tips and taken along the whole span, as the paper's simple
# analysis takes it: assumption (ii), p. 89; no spanwise twist was measured):
#   flapping phi = 3 + 43 cos(w t) deg: flapwing's stroke -3 - 43 cos(w t) (an 86 deg stroke; t = 0 the top);
#   pitch psi = 8 - 77 cos(w t - 49) - 3 cos(2 w t + 67) - 8 cos(3 w t + 29) deg:
#     flapwing's theta = psi + 90 = {fmt_series(*fore_pitch)} deg
#     (37 deg at mid-downstroke, 180 - 161 = 19 deg at mid-upstroke);
#   deviation: estimate: +8 deg, Azuma & Watanabe 1988's forewing coning angle (the 1985 paper
#   gives none; the repository's case takes 1988's), as models/dragonfly.toml reads it.
{fore}

# The hindwings.
[[pairs]]
# The hindwing leads by 77 deg (p. 104: "the phase lead of the hindwing ... = 77 deg").
phase_offset_deg = 77.0

[pairs.hinge]
left_in_body_m = [-1.9e-3, 1.3e-3, 1.6e-3]  # estimate: see [hinge]
stroke_plane_tilt_deg = 50.0                 # hindwing stroke plane 50 deg from the body axis, 40 deg from the horizontal (Fig. 4; see [hinge])

[pairs.wing.planform]
shape = "ellington_beta"
span_m = 32.5e-3                    # hindwing length 32.5 mm (Table 1)
area_m2 = 2.72e-4                   # hindwing area 272 mm^2 (Table 1)
r1_hat = 0.46                       # estimate: models/dragonfly.toml's aeshnid hindwing
root_offset_m = 0.0                 # estimate: as the forewing
pitch_axis_from_le_frac = 0.25      # estimate: as the forewing

[pairs.kinematics]
# Eqs 1-2 in the hindwing's own wingbeat (each pitch harmonic n moved by -77 n deg):
#   flapping phi = -2 + 47 cos(w t + 77) deg: flapwing's stroke 2 - 47 cos(w t') (a 94 deg stroke);
#   pitch psi = 3 - 65 cos(w t + 18) + 8 cos(2 w t + 74) + 8 cos(3 w t + 28) deg:
#     theta = psi + 90 = {fmt_series(hind_pitch[0], shifted, "w t'")} deg;
#   deviation: estimate: -2 deg, Azuma & Watanabe 1988's hindwing coning angle (none in 1985).
{hind}

[sim]
steps_per_wingbeat = 100

[initial]
# 0.54 m/s at 50 deg above the horizontal, the body 10 deg head-up (p. 84, (i); p. 87, (v);
# Fig. 4). (The repository's case reads 60 deg, with no source given for it.)
attitude_deg = [0.0, 10.0, 0.0]
velocity_m_s = [{s * math.cos(g):.4f}, 0.0, {s * math.sin(g):.4f}]
'''
    open("models/dragonfly_azuma1985.toml", "w").write(text)


if __name__ == "__main__" and "--check" in sys.argv:
    # models/dragonfly.toml's wings twist as experiment 2's file's: Table 3's inner stations.
    text = open("models/dragonfly.toml").read()
    for wing, lead in (("fore", 0.0), ("hind", 61.0)):
        e = EXPERIMENTS[2]
        twist = [(s, *station_series(wing, 2, s)) for s in STATIONS if s != 0.75]
        terms = e["tf"] if wing == "fore" else e["th"]
        amp, cone = (e["pf"], 8.0) if wing == "fore" else (e["ph"], -2.0)
        tables, _ = wing_tables(e["f"], 0.0, amp, *terms, cone, lead, twist)
        body = tables.split("TWIST_HEADER\n", 1)[1]
        assert body in text, (wing, body[:200])
    print("models/dragonfly.toml's twist reproduced")


if __name__ == "__main__" and "--stations" in sys.argv:
    # Rigid-wing variants, the whole wing feathering as at each station (the model files carry
    # the twist), read by `flapwing validate` and `cargo run --example dragonfly_stations`:
    # regenerate with
    #   python3 scripts/dragonfly-cases/generate.py --stations crates/flapsim/src/vehicle_validation/dragonfly_stations
    out = sys.argv[sys.argv.index("--stations") + 1]
    for k in EXPERIMENTS:
        for station in STATIONS:
            write_1988(k, station, f"{out}/exp{k}_{round(station * 100)}R.toml", rigid=True)
    print(f"wrote {len(EXPERIMENTS) * len(STATIONS)} station variants to {out}")

if __name__ == "__main__" and "--write" in sys.argv:
    write_1985()
    for k in EXPERIMENTS:
        write_1988(k)
