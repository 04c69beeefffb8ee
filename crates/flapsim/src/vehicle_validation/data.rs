//! The measured values the rows compare with, each with its source, and the model's
//! estimates and the values not found (listed by `flapwing validate`).

use super::rows::Estimate;

/// RoboBee bench data: robobee3d flapopt/data/normstroke/"Param opt manuf 2 - sdab1.csv"
/// (notes 1c ii): single-actuator SDAB bee, 54.4 mm^2 wing, 180 V; (frequency Hz, stroke
/// peak-to-peak deg).
pub const ROBOBEE_STROKE_180V: [(f64, f64); 7] = [
    (100.0, 56.3),
    (120.0, 56.83),
    (140.0, 56.93),
    (155.0, 59.49),
    (160.0, 64.76),
    (165.0, 82.89),
    (170.0, 85.81),
];

pub(super) const ROBOBEE_STROKE_SOURCE: &str = "robobee3d bench CSV sdab1 (Harvard MRL lab data, notes 1c ii: single-actuator bee, 54.4 mm^2 wing), its 180 V read as peak-to-peak";

/// The bench files' voltages read as peak-to-peak: the lab's note "75mN unidirectional at
/// 200Vpp" (robobee3d, the source of the model's force per volt) puts the actuator's rated
/// force at 200 V peak-to-peak, and the bench runs go up to 200 V. The model's drive
/// amplitude is half of it.
pub const BENCH_VOLTS_TO_AMPLITUDE: f64 = 0.5;

/// RoboBee bench pitch (notes 1c iii: robobee3d template/data "bee2 static numkin data", top
/// wing pair at 170 Hz): (volts, mean of the two wings' pitch, deg).
pub const ROBOBEE_PITCH_170HZ: [(f64, f64); 2] = [(160.0, 39.5), (200.0, 40.75)];

/// RoboBee wing motion in the lab's high-speed video (robobee3d flapopt/data/
/// Bee1_Static_165Hz_180V_7500sf.csv and ..._r.csv, commit 93e1354: one wingbeat per wing of
/// a clamped bee at 165 Hz and 180 V, 7500 frames/s), reconstructed by the lab's own method
/// (flapopt/w2d_loaddata.jl loadVideoData) in `scripts/research/robobee3d_video.py`, which
/// prints these numbers: (stroke peak-to-peak, pitch half peak-to-peak, pitch-stroke phase
/// with + advanced), deg, left and right wing.
pub const ROBOBEE_VIDEO_165HZ_180V: [(f64, f64, f64); 2] =
    [(56.0, 46.2, -2.5), (68.0, 51.4, -18.1)];

pub(super) const ROBOBEE_VIDEO_SOURCE: &str = "robobee3d high-speed video Bee1 static 165 Hz 180 V (Harvard MRL lab data, one wingbeat per wing; scripts/research/robobee3d_video.py: left, right wing)";

/// Jafferis, Graule & Wood 2016 (ICRA, abstract): the dual-actuator RoboBee's mean lift before
/// their hinge and transmission redesign, 140 mg-f, N.
pub const ROBOBEE_MEAN_LIFT_N: f64 = 140.0e-6 * 9.80665;

/// flappy's hover drive amplitude (pid_controller.py `hover_voltage_`, notes 2c), V.
pub const HUMMINGBIRD_HOVER_V: f64 = 9.3;

/// flappy's wing-rotation stops (`left_rotate_lower/upper` = +-0.785 rad, notes 2b), deg.
pub const HUMMINGBIRD_STOP_DEG: f64 = 45.0;

/// The built-in vehicles' parameters that are estimates (their model files say so too; a
/// test checks every key named here appears in its file).
pub const ESTIMATES: [Estimate; 12] = [
    Estimate {
        vehicle: "dragonfly",
        parameter: "hinge.left_in_body_m",
        why: "wing bases 3 mm above the centre of mass, 2.5 mm to each side, forewings 3.5 mm ahead of it and hindwings 3.5 mm behind: Azuma & Watanabe 1988 give no hinge positions (they move the moments, not the forces)",
    },
    Estimate {
        vehicle: "dragonfly",
        parameter: "body.inertia_diag_kg_m2",
        why: "a solid ellipsoid 75 mm long (A&W 1988) and 6 mm thick (an aeshnid's abdomen, not from the paper)",
    },
    Estimate {
        vehicle: "dragonfly",
        parameter: "wing.planform.r1_hat",
        why: "Anax's own r1 not found: Aeshna cyanea's (Wakeling 1997, forewing 0.505-0.517, hindwing 0.460-0.466)",
    },
    Estimate {
        vehicle: "robobee",
        parameter: "actuation.piezo.force_per_volt_n_v",
        why: "the lab's note '75mN unidirectional at 200Vpp' (0.75 mN/V of amplitude); no blocked-force table read; robobee3d's other values 0.28-0.47 mN/V",
    },
    Estimate {
        vehicle: "robobee",
        parameter: "actuation.piezo.voltage_limit_v",
        why: "100 V amplitude = the same note's 200 Vpp; no published drive range of Ma et al. 2013 read",
    },
    Estimate {
        vehicle: "robobee",
        parameter: "actuation.wing_inertia.mass_kg",
        why: "no weighed wing mass; robobee3d's 0.55 mg is fitted to the stroke inertia",
    },
    Estimate {
        vehicle: "robobee",
        parameter: "actuation.wing_inertia.com_chord_m",
        why: "half a mean chord behind the spar: robobee3d's modelling assumption",
    },
    Estimate {
        vehicle: "robobee",
        parameter: "actuation.wing_inertia.com_span_m",
        why: "robobee3d's lumped position ycp = 8.5 mm, a modelling value",
    },
    Estimate {
        vehicle: "robobee",
        parameter: "actuation.hinge.stiffness_nm_rad",
        why: "the lab's hinge model at w = 2.5 mm (7.5e-6); its other values and a system ID span 2.4e-6 to 7.5e-6 N m/rad; no published table",
    },
    Estimate {
        vehicle: "robobee",
        parameter: "actuation.hinge.damping_nm_s_rad",
        why: "the lab's hinge model at w = 2.5 mm (4.5e-9); its other values 2e-9 to 3e-9 N m s/rad",
    },
    Estimate {
        vehicle: "robobee",
        parameter: "actuation.drive.amplitude_v",
        why: "a starting point (the bench's 180 Vpp): no flight drive voltage read; trim finds the hover value",
    },
    Estimate {
        vehicle: "hummingbird",
        parameter: "actuation.hinge.stop.restitution",
        why: "0, the inelastic joint limit of flappy's simulator (DART); no measured restitution of the robot's stops",
    },
];

/// What no source gave, per vehicle (printed as NOT FOUND).
pub const NOT_FOUND: [(&str, &str); 6] = [
    (
        "dragonfly",
        "Azuma & Watanabe 1988's specimen data (Table 1, dragonflies A and B) read directly: the model's morphology is the public digitised case data of jpecquet/dragonfly-flight-control; its kinematics are cross-checked against the scans of the paper's Tables 2 and 3 in the same repository (commit b7816df)",
    ),
    (
        "dragonfly",
        "Wang & Sun 2005's tables (trimmed angles of attack, force coefficients, fore/hind interaction in forward flight): only the abstract was readable, so none of its numbers is compared",
    ),
    (
        "robobee",
        "published pitch-stroke phase (Whitney & Wood 2010 and Ma et al. 2013 not readable): the phase row compares with the lab's own high-speed video (robobee3d, one wingbeat per wing, unpublished)",
    ),
    (
        "robobee",
        "hover trim voltage of the real vehicle: the trim row checks only that it lies inside the actuator's range",
    ),
    (
        "hummingbird",
        "pitch amplitude and hover drive measured on the robot (Tu et al. 2020 not readable): the rows compare with the flappy simulator's stops and hover voltage",
    ),
    (
        "bumblebee",
        "Sun & Xiong 2005's trimmed angles of attack, their I_y and their non-dimensional mass and inertia: only the abstract and the derivative table were readable, so the model keeps its estimated 40 deg angle of attack and ellipsoid I_y (with the table's derivatives that I_y gives the abstract's modes within 9%)",
    ),
];
