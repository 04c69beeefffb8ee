//! The published dragonfly flights against flapwing's quasi-steady wings: Azuma et al. 1985
//! (J Exp Biol 116:79, a *Sympetrum frequens* climbing at 0.54 m/s, 50 deg above the
//! horizontal) and the four experiments of Azuma & Watanabe 1988 (J Exp Biol 137:221, *Anax
//! parthenope julius* at 0.7, 1.5, 2.3 and 3.2 m/s), built as the model files
//! `models/dragonfly_azuma1985.toml` and `models/dragonfly_azuma1988_exp{1,2,3,4}.toml`.
//!
//! Sources. The 1988 numbers are the paper's Table 2 (speed, flight-path angle, body attitude,
//! frequency, stroke planes from the horizontal and from the body axis, flapping amplitudes,
//! the hindwing's lead, and the paper's own "calculated load factor" n) and Table 3 (the
//! feathering Fourier series at 0.75R), read from the scans of those tables in the public
//! repository github.com/jpecquet/dragonfly-flight-control (commit b7816df) and cross-checked
//! against its digitised case data (commit cf19b0a). The 1985 numbers are that repository's
//! digitised reading of the paper (commits fe767a9 and cf19b0a), checked against the paper
//! itself (its PDF in the same repository's history), which also gives the body attitude
//! (10 deg head-up), the stroke planes' reference (Fig. 4: 37 and 40 deg from the horizontal,
//! 47 and 50 from the body axis) and the flight's direction ("nearly normal to the stroke
//! plane": 50 deg; the repository's 60 deg has no source). Each file says which numbers are
//! estimates (hinges, inertia, r1, and for 1985 the coning angles, which that paper does not
//! give).
//!
//! Physics. Each flight was steady (Azuma & Watanabe: "steady trimmed flight"; Azuma et al.
//! 1985: "steady climbing flight"), so the wings' cycle-mean aerodynamic force balances the
//! weight and the body's drag: mean vertical force = weight and mean horizontal force = the
//! body drag's small share (estimate: 0.5 rho V^2 C_D A with the 6 mm body's frontal area
//! 2.8e-5 m^2 and C_D about 1 gives 0.5% of the weight at 1.5 m/s, 2.2% at 3.2 m/s), i.e.
//! about 0. flapwing evaluates the wings at the published kinematics with the body at its
//! published attitude moving at the published velocity (a frozen state: `mean_loads` over
//! 400 phases), and reports both forces in the world frame over the weight. The model files
//! fly in still air; each case is also evaluated under the dynamic wake (`[aero] inflow =
//! "dynamic"`: each pair's induced flow, and the share of the other pair's that crosses its
//! disc, `wingforce::inflow::interference`; Azuma's local circulation method, which gives
//! the paper's n, has a non-uniform unsteady version of both). The 1988 files' wings twist
//! as Table 3 measured (its 0.75R column their pitch, 0.25R and 0.5R their
//! `[kinematics.twist]`: each blade element of the translational term at its own feathering,
//! linear between the stations and extended beyond them, an estimate); the rigid variants
//! (`DragonflyFlight::at_rigid_stations`) show what the twist does.
//!
//! Results (measured here, asserted as measured: nothing in the model files was tuned):
//!
//! | case | V, m/s | vertical / weight | horizontal / weight | dynamic wake: vertical (horizontal) | rigid as at 0.75R: vertical | published | |
//! |---|---|---|---|---|---|---|---|
//! | 1985 climb | 0.54 at 50 deg | 1.467 | +0.932 | 1.018 (+0.643) | (no stations) | 1 and 0 (the paper's own forces: 1.002 and 0.065) | **miss**; dynamic: vertical within 15%, thrust still large (on the upstrokes) |
//! | 1988 exp. 1 | 0.7 | 0.836 | -0.260 | 0.810 | 0.853 | 1 and 0 (A&W's n = 1.1) | **miss**, 16% short (dynamic 19%) |
//! | 1988 exp. 2 | 1.5 | 0.872 | -0.138 | 0.834 | 0.769 | 1 and 0 (n = 0.97) | within 15% (dynamic 17% short) |
//! | 1988 exp. 3 | 2.3 | 1.027 | -0.259 | 0.991 | 0.882 | 1 and 0 (n = 1.25) | within 3% (dynamic 1%) |
//! | 1988 exp. 4 | 3.2 | 0.535 | +0.116 | 0.485 | 0.498 | 1 and 0 (n = 1.05) | **miss**, 47% short |
//!
//! The horizontal force misses in every case (more than the body drag's 2.2% of the weight).
//! Trimmed at each case's speed and climb rate (`trim_at`, which adds one stroke-amplitude
//! offset to all four wings and sets the mean stroke angle and the body pitch), every case
//! trims; the forewing's stroke at trim over the published stroke (twice Table 2's flapping
//! amplitude) is 0.724 (1985), 1.129, 1.201, 1.225 and 1.003 (1988 exp. 1-4).

use flapsim::Vehicle;
use flapsim::averaged::{FrozenState, mean_loads};
use flapsim::flight::FlightCondition;
use flapsim::trim::{trim_at, trimmed_vehicle};
use flapsim::vehicle_validation::dragonfly::{DRAGONFLY_FLIGHTS, DragonflyFlight};
use nalgebra::{UnitQuaternion, Vector3};

/// One published flight (`flapsim::vehicle_validation::dragonfly::DRAGONFLY_FLIGHTS`) and
/// what flapwing measured there.
struct Case {
    flight: &'static DragonflyFlight,
    /// Measured here: mean vertical and horizontal force over the weight in still air (the
    /// files' own wake) and under the dynamic wake, and the trimmed forewing stroke (deg) and
    /// body pitch (deg) in still air.
    vertical: f64,
    horizontal: f64,
    dynamic: [f64; 2],
    trimmed_stroke_deg: f64,
    trimmed_pitch_deg: f64,
}

const AZUMA_1985: Case = Case {
    flight: &DRAGONFLY_FLIGHTS[0],
    vertical: 1.467,
    horizontal: 0.932,
    dynamic: [1.0177, 0.643],
    trimmed_stroke_deg: 62.29,
    trimmed_pitch_deg: 36.36,
};

const EXPERIMENTS_1988: [Case; 4] = [
    Case {
        flight: &DRAGONFLY_FLIGHTS[1],
        vertical: 0.836,
        horizontal: -0.260,
        dynamic: [0.8096, f64::NAN],
        trimmed_stroke_deg: 81.30,
        trimmed_pitch_deg: 7.25,
    },
    Case {
        flight: &DRAGONFLY_FLIGHTS[2],
        vertical: 0.872,
        horizontal: -0.138,
        dynamic: [0.8342, f64::NAN],
        trimmed_stroke_deg: 60.07,
        trimmed_pitch_deg: 10.47,
    },
    Case {
        flight: &DRAGONFLY_FLIGHTS[3],
        vertical: 1.027,
        horizontal: -0.259,
        dynamic: [0.9912, f64::NAN],
        trimmed_stroke_deg: 61.27,
        trimmed_pitch_deg: 0.16,
    },
    Case {
        flight: &DRAGONFLY_FLIGHTS[4],
        vertical: 0.535,
        horizontal: 0.116,
        dynamic: [0.4852, f64::NAN],
        trimmed_stroke_deg: 76.25,
        trimmed_pitch_deg: 8.94,
    },
];

impl Case {
    fn vehicle(&self) -> Vehicle {
        self.flight.vehicle().unwrap()
    }

    /// The flight velocity, world frame (x forward, z up).
    fn velocity_world_m_s(&self) -> Vector3<f64> {
        self.flight.velocity_world_m_s()
    }

    /// Cycle-mean world force over the weight, [horizontal, vertical], at the published
    /// flight, and the fore pair's share of the vertical force (still air: the wings'
    /// forces add).
    fn mean_force_over_weight(&self) -> ([f64; 2], f64) {
        let v = self.vehicle();
        let f = self.flight.forces(&v).unwrap();
        let [fore, _] = self.flight.vertical_alone(&v).unwrap();
        ([f.horizontal, f.vertical], fore / f.vertical)
    }

    /// Checks the file's flight against the case, the forces against the measured values,
    /// and trims at the case's speed and climb rate; returns the vertical force over weight.
    fn check(&self) -> f64 {
        let v = self.vehicle();
        assert_eq!(v.wings.len(), 4, "{}", self.flight.name);
        // The file's flight is the case's.
        let (_, pitch, _) = v.initial_attitude.euler_angles();
        assert!((-pitch.to_degrees() - self.flight.attitude_deg).abs() < 1e-9);
        assert!((v.initial_velocity_m_s - self.velocity_world_m_s()).norm() < 1e-4);
        for (i, stroke) in [
            (0, self.flight.stroke_deg[0]),
            (2, self.flight.stroke_deg[1]),
        ] {
            let amp = v.base_kinematics[i].amplitude_rad.to_degrees();
            assert!(
                (amp - stroke).abs() < 1e-6,
                "{}: wing {i} {amp}",
                self.flight.name
            );
        }
        let ([fx, fz], fore_share) = self.mean_force_over_weight();
        eprintln!(
            "{} ({} m/s at {} deg, body {} deg): mean vertical {:.4} of the weight (fore pair {:.0}%), horizontal {:+.4}; published 1 and 0 (the paper's own model: {})",
            self.flight.name,
            self.flight.speed_m_s,
            self.flight.path_deg,
            self.flight.attitude_deg,
            fz,
            100.0 * fore_share,
            fx,
            self.flight.paper_load_factor
        );
        // Tolerance: 0.005 of the weight around the measured value (printed to 3 decimals),
        // so that a change in the model shows here.
        assert!(
            (fz - self.vertical).abs() <= 0.005,
            "{}: vertical {fz}",
            self.flight.name
        );
        assert!(
            (fx - self.horizontal).abs() <= 0.005,
            "{}: horizontal {fx}",
            self.flight.name
        );
        // Steady flight publishes about 0 in the horizontal: each case misses it by more
        // than the body drag's 2.2% of the weight.
        assert!(fx.abs() > 0.05, "{}", self.flight.name);

        // Under the dynamic wake (each pair's induced flow and the other pair's share of it,
        // wingforce::inflow::interference): measured values, 0.005 of the weight around them.
        let dynamic = v
            .with_inflow_model(wingforce::InflowModel::Dynamic)
            .unwrap();
        let d = self.flight.forces(&dynamic).unwrap();
        eprintln!(
            "  under the dynamic wake: vertical {:.4}, horizontal {:+.4} of the weight",
            d.vertical, d.horizontal
        );
        assert!(
            (d.vertical - self.dynamic[0]).abs() <= 0.005,
            "{}: dynamic vertical {}",
            self.flight.name,
            d.vertical
        );
        if self.dynamic[1].is_finite() {
            assert!(
                (d.horizontal - self.dynamic[1]).abs() <= 0.005,
                "{}: dynamic horizontal {}",
                self.flight.name,
                d.horizontal
            );
        }

        // Trim at the case's speed and climb rate.
        let u = self.velocity_world_m_s();
        let condition = FlightCondition::new(u.x, u.z).unwrap();
        let t = trim_at(&v, v.trim_lift, &condition).unwrap();
        assert!(t.max_residual() < 1e-7, "{}: {t:?}", self.flight.name);
        let tv = trimmed_vehicle(&v, &t).unwrap();
        let fore = tv.wings[0].kinematics().amplitude_rad.to_degrees();
        let hind = tv.wings[2].kinematics().amplitude_rad.to_degrees();
        eprintln!(
            "  trimmed at {}: fore stroke {fore:.2} deg ({:.3} of the published {}), hind {hind:.2} deg ({:.3} of {}), mean stroke {:+.2} deg, body pitch {:.2} deg (the file's body attitude {})",
            condition.describe(),
            fore / self.flight.stroke_deg[0],
            self.flight.stroke_deg[0],
            hind / self.flight.stroke_deg[1],
            self.flight.stroke_deg[1],
            t.controls.mean_stroke_rad.to_degrees(),
            t.pitch_rad.to_degrees(),
            self.flight.attitude_deg,
        );
        // Tolerance: 0.05 deg around the measured trim (Newton converged to 1e-7 of the
        // weight; the values are printed to 2 decimals).
        assert!(
            (fore - self.trimmed_stroke_deg).abs() < 0.05,
            "{}: {fore}",
            self.flight.name
        );
        assert!(
            (t.pitch_rad.to_degrees() - self.trimmed_pitch_deg).abs() < 0.05,
            "{}: pitch {}",
            self.flight.name,
            t.pitch_rad.to_degrees()
        );
        // One amplitude offset for all four wings.
        assert!(
            (hind - fore - (self.flight.stroke_deg[1] - self.flight.stroke_deg[0])).abs() < 1e-9
        );
        fz
    }
}

/// Azuma et al. 1985: steady climb at 0.54 m/s, 50 deg above the horizontal ("nearly normal
/// to the stroke plane", p. 87), the body 10 deg head-up (p. 84) and the stroke planes 37 and
/// 40 deg from the horizontal (Fig. 4). The paper's own forces (local circulation method)
/// average 1.002 of the weight. flapwing: 1.467 up and 0.932 of the weight forward, a
/// **miss** in both; trimmed, the forewing's stroke is 62.3 deg (0.724 of the published 86)
/// with the body pitched 36.4 deg nose up, which turns the stroke planes to 11-14 deg from the
/// horizontal. Per half stroke the forward excess is on the upstrokes (the last test).
#[test]
fn azuma_1985_climb_against_its_weight() {
    AZUMA_1985.check();
}

/// Azuma & Watanabe 1988, experiment 1 (0.7 m/s descending at 12 deg, body at 20 deg):
/// 0.836 of the weight, **miss** (16% short; the paper's own model: n = 1.1; rigid wings
/// feathering as at 0.75R: 0.853). Trimmed: the forewing's stroke 81.3 deg, 1.129 of the
/// published 72.
#[test]
fn azuma_watanabe_1988_experiment_1_against_its_weight() {
    EXPERIMENTS_1988[0].check();
}

/// Experiment 2 (1.5 m/s, body at 12 deg; models/dragonfly.toml's flight): 0.872 of the
/// weight, within 15% (13% short; n = 0.97; rigid wings as at 0.75R: 0.769, 23% short).
/// Trimmed: 60.1 deg, 1.201 of the published 50. models/dragonfly.toml, which holds the body
/// level with the stroke planes at their angles to the horizontal and the same twisted wings,
/// has the same world forces (to 1e-9 of the weight: only the frames differ).
#[test]
fn azuma_watanabe_1988_experiment_2_against_its_weight() {
    EXPERIMENTS_1988[1].check();
    let level = Vehicle::from_toml(flapsim::DRAGONFLY_TOML, "dragonfly").unwrap();
    let velocity = EXPERIMENTS_1988[1].velocity_world_m_s();
    let m = mean_loads(
        &level,
        &FrozenState {
            world_from_body: UnitQuaternion::identity(),
            velocity_body_m_s: velocity,
            angular_velocity_body_rad_s: Vector3::zeros(),
        },
        400,
    )
    .unwrap();
    let w = level.weight_n();
    let flight = EXPERIMENTS_1988[1].flight;
    let f = flight.forces(&flight.vehicle().unwrap()).unwrap();
    assert!((m.total.force_n.z / w - f.vertical).abs() < 1e-9);
    assert!((m.total.force_n.x / w - f.horizontal).abs() < 1e-9);
}

/// Experiment 3 (2.3 m/s climbing at 4.8 deg, body at 4 deg): 1.027 of the weight, within
/// 3% (n = 1.25; rigid wings as at 0.75R: 0.882). Trimmed: 61.3 deg, 1.225 of the published 50.
#[test]
fn azuma_watanabe_1988_experiment_3_against_its_weight() {
    EXPERIMENTS_1988[2].check();
}

/// Experiment 4 (dragonfly B, with dragonfly A's morphology as an estimate; 3.2 m/s level,
/// body at 2 deg): 0.535 of the weight, **miss** (47% short; n = 1.05; rigid wings as at
/// 0.75R: 0.498), the hindwings on their steep (68 deg) stroke plane carrying only 20% of it.
/// Trimmed: 76.3 deg, 1.003 of the published 76, with the mean stroke moved 16 deg back.
#[test]
fn azuma_watanabe_1988_experiment_4_against_its_weight() {
    EXPERIMENTS_1988[3].check();
}

/// The trend over Azuma & Watanabe's speeds. Published: every flight was steady, so the mean
/// vertical force is the weight at 0.7, 1.5, 2.3 and 3.2 m/s, flat; the paper's own model
/// (Table 2's n) gives 1.1, 0.97, 1.25, 1.05. flapwing, with the wings' measured twist:
/// 0.836, 0.872, 1.027, 0.535, spread over 0.49 of the weight (**miss**): experiments 1-3
/// (dragonfly A) within 17% of the weight and highest at 2.3 m/s as in the paper's model,
/// 0.76-0.90 of its n; experiment 4 (dragonfly B, at the highest speed) at 0.51 of it.
/// (Rigid wings feathering as at 0.75R gave 0.853, 0.769, 0.882, 0.498.)
#[test]
fn vertical_force_over_the_1988_speeds_against_the_published_trend() {
    let fz: Vec<f64> = EXPERIMENTS_1988
        .iter()
        .map(|c| c.mean_force_over_weight().0[1])
        .collect();
    for (c, f) in EXPERIMENTS_1988.iter().zip(&fz) {
        eprintln!(
            "{} m/s: flapwing {f:.3} of the weight, published 1 (the paper's n {}: flapwing/n {:.3})",
            c.flight.speed_m_s,
            c.flight.paper_load_factor,
            f / c.flight.paper_load_factor
        );
    }
    // Published flat at 1: experiments 1-3 within 17% of it, and they spread (measured 0.492,
    // to 0.01).
    assert!(fz[..3].iter().all(|f| (f - 1.0).abs() < 0.17), "{fz:?}");
    let (lo, hi) = fz
        .iter()
        .fold((f64::MAX, f64::MIN), |(l, h), &f| (l.min(f), h.max(f)));
    assert!((hi - lo - 0.492).abs() < 0.01, "{fz:?}");
    // The paper's model and flapwing both put experiment 3 highest of 1-3.
    assert!(fz[2] > fz[0] && fz[2] > fz[1], "{fz:?}");
    let n: Vec<f64> = EXPERIMENTS_1988
        .iter()
        .map(|c| c.flight.paper_load_factor)
        .collect();
    assert!(n[2] > n[0] && n[2] > n[1]);
    // Experiment 4 departs from both: the lowest here, above 1 in the paper's model.
    assert!(fz.iter().all(|f| *f >= fz[3]) && n[3] > 1.0);
}

/// Where the 1985 climb's forward force comes from: each pair's force per half stroke, beside
/// the paper's own calculation (its Fig. 16 as digitised,
/// `flapsim::vehicle_validation::dragonfly::AZUMA_1985_FIG16_MN`). The split is of the cycle
/// mean, so the half strokes of both pairs sum to the mean force (still air: the wings' forces
/// add), and the paper's to its digitised means, 1.002 of the weight up and 0.065 forward.
/// Measured (still air): the model's upstrokes give 1.537 of the weight forward where the
/// paper's give 0.300, its downstrokes -0.605 where the paper's give -0.235: the excess is on
/// the upstrokes, which in the paper carry almost nothing up ("The vertical force is mostly
/// generated in the downstroke of the respective wings", p. 106).
#[test]
fn azuma_1985_forward_force_by_half_stroke() {
    let flight = AZUMA_1985.flight;
    let v = AZUMA_1985.vehicle();
    let [fore, hind] = flight.half_strokes(&v).unwrap();
    let f = flight.forces(&v).unwrap();
    let sum = |k: usize| fore[k] + fore[k + 2] + hind[k] + hind[k + 2];
    assert!(
        (sum(0) - f.horizontal).abs() < 1e-3,
        "{} {}",
        sum(0),
        f.horizontal
    );
    assert!(
        (sum(1) - f.vertical).abs() < 1e-3,
        "{} {}",
        sum(1),
        f.vertical
    );
    let [pf, ph] = flight.paper_half_strokes.unwrap();
    let paper = |k: usize| pf[k] + pf[k + 2] + ph[k] + ph[k + 2];
    assert!((paper(0) - 0.065).abs() < 1e-3 && (paper(1) - 1.002).abs() < 1e-3);
    // Each pair's upstrokes, measured: the hind pair's push the most.
    assert!((fore[2] - 0.569).abs() < 0.005, "{fore:?}");
    assert!((hind[2] - 0.967).abs() < 0.005, "{hind:?}");
    let up = fore[2] + hind[2];
    let down = fore[0] + hind[0];
    eprintln!(
        "forward: upstrokes {up:+.3}, downstrokes {down:+.3}; the paper's {:+.3} and {:+.3}",
        pf[2] + ph[2],
        pf[0] + ph[0]
    );
    // Measured values, 0.005 of the weight around them.
    assert!((up - 1.537).abs() < 0.005, "{up}");
    assert!((down + 0.605).abs() < 0.005, "{down}");
}

/// The 1985 file holds the body 10 deg head-up with the stroke planes 47 and 50 deg from the
/// body axis (Fig. 4): the same stroke planes in the world as a level body with 37 and 40 deg,
/// so the same wing forces (at a frozen state the wings move with the body's velocity alone,
/// wherever the hinges sit); only the moments differ.
#[test]
fn azuma_1985_body_attitude_keeps_the_stroke_planes_in_the_world() {
    let flight = AZUMA_1985.flight;
    let text = flight
        .toml
        .replace(
            "stroke_plane_tilt_deg = 47.0",
            "stroke_plane_tilt_deg = 37.0",
        )
        .replace(
            "stroke_plane_tilt_deg = 50.0",
            "stroke_plane_tilt_deg = 40.0",
        )
        .replace(
            "attitude_deg = [0.0, 10.0, 0.0]",
            "attitude_deg = [0.0, 0.0, 0.0]",
        );
    assert_ne!(text, flight.toml);
    let level = Vehicle::from_toml(&text, "level").unwrap();
    let (a, b) = (
        flight.forces(&AZUMA_1985.vehicle()).unwrap(),
        flight.forces(&level).unwrap(),
    );
    assert!((a.vertical - b.vertical).abs() < 1e-9, "{a:?} {b:?}");
    assert!((a.horizontal - b.horizontal).abs() < 1e-9, "{a:?} {b:?}");
}
