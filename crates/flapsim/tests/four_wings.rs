//! Four-winged vehicles (`[[pairs]]`) and the built-in dragonfly.
//!
//! Physics. flapwing's wings are quasi-steady and independent: each wing's force at an instant
//! depends on its own kinematics and the air's velocity relative to it, never on another wing's
//! wake. A further pair therefore adds its loads to the first pair's, evaluated at its own phase
//! (`phase + phase_offset`, carried by the pair's `wingforce::Kinematics`). Two consequences are
//! tested here exactly: a hind pair placed on the fore pair with the same kinematics and no
//! phase offset carries what the fore pair carries (so a two-winged vehicle with wings of twice
//! the area carries the same, in the terms that are linear in area), and a phase offset moves
//! the hind pair's loads in time without changing their cycle mean.
//!
//! The second consequence is also the model's limit. Real tandem wings interact: the forewing's
//! wake changes the hindwing's inflow, and the CFD of the same group that built the model
//! dragonfly of Wang & Sun 2005 (J Exp Biol 208:3785) measured it: in hover, with the hindwing
//! leading by 180 deg, the interaction lowers the fore- and hindwing's vertical forces by 14%
//! and 16% of what each wing makes alone (Sun & Lan 2004, J Exp Biol 207:1887, abstract).
//! In still air (the dragonfly's file) flapwing leaves this out, so its cycle-mean forces
//! do not depend on the fore/hind phase at all; the tests assert that flatness and state the
//! size of what is missing. Under the dynamic wake each pair also meets the share of the
//! other's induced flow that crosses its disc (`wingforce::inflow::interference`), whose
//! coaxial limit (two pairs on one disc) is tested against momentum theory at the end.
//!
//! The dragonfly itself (models/dragonfly.toml: Azuma & Watanabe 1988, J Exp Biol 137:221,
//! experiment 2, steady flight at 1.5 m/s) is checked against the only force its steady flight
//! publishes: the mean vertical force must carry its weight and the mean horizontal force must
//! balance its small body drag. The gap is measured and asserted as measured (nothing in the
//! model was tuned to it); docs/models.md reports it.

use flapsim::averaged::{FrozenState, mean_loads};
use flapsim::{FromVehicle, Vehicle, WingSet};
use nalgebra::{UnitQuaternion, Vector3};
use wingforce::{BodyMotion, Term};

fn vehicle(text: &str) -> Vehicle {
    Vehicle::from_toml(text, "test.toml").unwrap()
}

fn err(text: &str) -> String {
    Vehicle::from_toml(text, "bad.toml")
        .unwrap_err()
        .to_string()
}

fn hover(v: &Vehicle) -> FrozenState {
    FrozenState {
        world_from_body: v.initial_attitude,
        velocity_body_m_s: Vector3::zeros(),
        angular_velocity_body_rad_s: Vector3::zeros(),
    }
}

/// The fruit fly without the hover downwash (a many-wing model refuses it), at a fixed Re
/// (the fluid's viscosity then follows each wing's chord, so Re is the same at any area) and
/// without Lee et al.'s aspect-ratio and Rossby corrections (AR and Ro change with the chord).
fn fly_at_fixed_re(area: &str) -> String {
    let t = flapsim::DROSOPHILA_TOML
        .replacen(
            "inflow = \"frozen\"",
            "inflow = \"off\"\nar_ro_corrections = false",
            1,
        )
        .replacen("kinematic_viscosity_m2_s = 1.516e-5", "reynolds = 120.0", 1)
        .replacen("area_m2 = 2.0e-6", &format!("area_m2 = {area}"), 1);
    assert!(t.contains("reynolds = 120.0") && t.contains(area));
    t
}

/// A hind pair on the fore pair's hinges with the fore pair's planform and kinematics and no
/// phase offset.
const COINCIDENT_PAIR: &str = "
[[pairs]]
phase_offset_deg = 0.0
[pairs.hinge]
left_in_body_m = [0.28e-3, 0.45e-3, 0.28e-3]
stroke_plane_tilt_deg = 45.0
";

/// Limit: four wings, two on each hinge, against two wings of twice the area.
///
/// At a fixed span, twice the area is twice the chord everywhere. What scales with the chord
/// exactly (MODEL.md section 4), at a fixed Re and without f_AR f_Ro:
/// - translational: per strip 0.5 rho |u|^2 C(alpha, Re) c dr with u the pitch axis's velocity,
///   which does not depend on the chord: linear;
/// - wake capture: C(Re, dtau) 0.5 rho V_ref^2 S on the reference scale: linear;
/// - rotational: sqrt(S_xx S_yy) grows as c^2 and S_x|x| as c^3: not linear (and its cycle
///   mean on the fly's symmetric trapezoidal flip is zero to rounding, so it is only printed);
/// - added mass: (pi/4) rho c^2 per strip: quadratic, and its cycle mean is zero anyway (the
///   impulse form), so there is nothing to compare.
///
/// Forces only: the translational term's centre of pressure sits a fraction of the chord
/// behind the leading edge, so its moment is not linear in the chord. Without the fixed Re
/// and the corrections off, the translational term differs by what Re^-0.429, f_AR and f_Ro
/// change with the chord (printed below for the record, not asserted).
#[test]
fn a_hind_pair_on_the_fore_hinges_carries_what_twice_the_area_carries_in_the_linear_terms() {
    // Wings at one place are a valid model (the wing set refuses them; cycle means do not).
    let four = vehicle(&(fly_at_fixed_re("2.0e-6") + COINCIDENT_PAIR));
    assert_eq!(four.wings.len(), 4);
    assert_eq!(four.pair_phase_offsets(), vec![0.0, 0.0]);
    let two = vehicle(&fly_at_fixed_re("4.0e-6"));
    let (a, b) = (
        mean_loads(&four, &hover(&four), 400).unwrap(),
        mean_loads(&two, &hover(&two), 400).unwrap(),
    );
    let weight = four.weight_n();
    for term in [Term::Translational, Term::WakeCapture] {
        let (f4, f2) = (
            a.terms[term as usize].force_n,
            b.terms[term as usize].force_n,
        );
        // Tolerance: 1e-9 of the weight (rounding of sums over 400 phases and 20 strips).
        assert!(
            (f4 - f2).norm() <= 1e-9 * weight,
            "{term:?}: four wings {f4:?} N, two of twice the area {f2:?} N"
        );
        assert!(f4.z.abs() > 1e-3 * weight, "{term:?} carries something");
    }
    // Rotational: not linear in the chord; its mean is zero to rounding on this fly.
    let (r4, r2) = (
        a.terms[Term::Rotational as usize].force_n.z,
        b.terms[Term::Rotational as usize].force_n.z,
    );
    eprintln!(
        "rotational mean vertical force: four wings {r4:.4e} N, two of twice the area {r2:.4e} N"
    );
    // Added mass: zero mean in both (the impulse form), to 1e-9 of the weight.
    for m in [&a, &b] {
        assert!(m.terms[Term::AddedMass as usize].force_n.norm() <= 1e-9 * weight);
    }
    // The wing set, unlike the cycle mean, refuses two wings at one place, with an error.
    let e = WingSet::from_vehicle_sized(&four).unwrap_err().to_string();
    assert!(e.contains("same place"), "{e}");
    // For the record: the real fly (corrections on, its own viscosity) is not linear in area.
    let real = |area: &str| {
        flapsim::DROSOPHILA_TOML
            .replacen("inflow = \"frozen\"", "inflow = \"off\"", 1)
            .replacen("area_m2 = 2.0e-6", &format!("area_m2 = {area}"), 1)
    };
    let (f4, f2) = (
        vehicle(&(real("2.0e-6") + COINCIDENT_PAIR)),
        vehicle(&real("4.0e-6")),
    );
    let t4 = mean_loads(&f4, &hover(&f4), 400).unwrap().terms[0]
        .force_n
        .z;
    let t2 = mean_loads(&f2, &hover(&f2), 400).unwrap().terms[0]
        .force_n
        .z;
    eprintln!(
        "real fly, translational mean vertical force: four wings {t4:.4e} N, two of twice the area {t2:.4e} N ({:+.2}%)",
        100.0 * (t2 / t4 - 1.0)
    );
}

fn dragonfly_with_offset(deg: f64) -> Vehicle {
    let text = flapsim::DRAGONFLY_TOML.replacen(
        "phase_offset_deg = 61.0",
        &format!("phase_offset_deg = {deg:.1}"),
        1,
    );
    assert!(text.contains(&format!("phase_offset_deg = {deg:.1}")));
    // 100 steps a wingbeat, so that half a wingbeat is a whole number of steps.
    let mut v = vehicle(&text);
    v.sim.steps_per_wingbeat = 100;
    v
}

/// Azuma & Watanabe 1988, experiment 2: 1.5 m/s, 1.1 deg below the horizontal, body level.
fn forward_flight() -> FrozenState {
    let (s, c) = (-1.1f64).to_radians().sin_cos();
    FrozenState {
        world_from_body: UnitQuaternion::identity(),
        velocity_body_m_s: Vector3::new(1.5 * c, 0.0, 1.5 * s),
        angular_velocity_body_rad_s: Vector3::zeros(),
    }
}

/// A phase offset of half a wingbeat is the hind pair's loads half a wingbeat later: in the
/// wing's own evaluation (bit for bit) and in the wing set's stepping.
#[test]
fn a_phase_offset_of_half_a_wingbeat_shifts_the_hind_pair_by_half_a_wingbeat() {
    let (zero, half) = (dragonfly_with_offset(0.0), dragonfly_with_offset(180.0));
    assert_eq!(half.pair_phase_offsets(), vec![0.0, 0.5]);
    let body = BodyMotion {
        velocity_m_s: forward_flight().velocity_body_m_s,
        angular_velocity_rad_s: Vector3::zeros(),
    };
    for k in 0..200 {
        let p = k as f64 / 200.0;
        for i in 0..4 {
            let shifted = if i >= 2 { p + 0.5 } else { p };
            let (a, b) = (
                half.wings[i].evaluate(p, &body),
                zero.wings[i].evaluate(shifted, &body),
            );
            assert_eq!(a.total.force_n, b.total.force_n, "wing {i} at phase {p}");
        }
    }
    // The wing set: the hind wings of the offset set at step k are those of the unshifted
    // set at step k + N/2 (N = 100 steps a wingbeat), the fore wings are those at step k.
    let (mut a, mut b) = (
        WingSet::from_vehicle_sized(&half).unwrap(),
        WingSet::from_vehicle_sized(&zero).unwrap(),
    );
    let still = flapsim::State::at_rest();
    let (fa, fb): (Vec<_>, Vec<_>) = (0..200)
        .map(|_| {
            (
                a.step(&still).unwrap().wings.clone(),
                b.step(&still).unwrap().wings.clone(),
            )
        })
        .unzip();
    for k in 0..100 {
        for i in 0..4 {
            let j = if i >= 2 { k + 50 } else { k };
            let (x, y) = (fa[k][i].total.force_n, fb[j][i].total.force_n);
            // Tolerance: 1e-9 of the force (the two phases differ by rounding: k/N + 1/2
            // against (k + N/2)/N).
            assert!(
                (x - y).norm() <= 1e-9 * y.norm().max(1e-12),
                "wing {i}, step {k}: {x:?} against {y:?}"
            );
        }
    }
}

/// The wing set's steps and the cycle mean evaluate the same wings at the same phases, the
/// hind pair's offset included: over one wingbeat of 100 steps, the body still and level, the
/// set's mean load is `mean_loads`' at 100 phases (to 1e-12 of the weight: the sums' order).
#[test]
fn the_wing_set_and_the_cycle_mean_agree_on_four_wings() {
    let mut v = vehicle(flapsim::DRAGONFLY_TOML);
    // `mean_loads` samples the N phases of the step starts.
    v.sim.load_sampling = Some(flapsim::LoadSampling::StepStart);
    v.sim.steps_per_wingbeat = 100;
    let mut set = WingSet::from_vehicle_sized(&v).unwrap();
    assert_eq!(set.len(), 4);
    let still = flapsim::State::at_rest();
    let mut f = Vector3::zeros();
    let mut m = Vector3::zeros();
    for _ in 0..100 {
        let out = set.step(&still).unwrap();
        f += out.total.force_n / 100.0;
        m += out.total.moment_nm / 100.0;
    }
    let frozen = FrozenState {
        world_from_body: UnitQuaternion::identity(),
        velocity_body_m_s: Vector3::zeros(),
        angular_velocity_body_rad_s: Vector3::zeros(),
    };
    let mean = mean_loads(&v, &frozen, 100).unwrap();
    let w = v.weight_n();
    assert!(
        (f - mean.total.force_n).norm() <= 1e-12 * w,
        "{f:?} against {:?}",
        mean.total.force_n
    );
    assert!(
        (m - mean.total.moment_nm).norm() <= 1e-12 * w * v.length_m,
        "{m:?} against {:?}",
        mean.total.moment_nm
    );
}

/// The dragonfly at its published forward flight (Azuma & Watanabe 1988, experiment 2):
/// steady flight, so the wings' mean vertical force carries the weight (790 mg: 7.75 mN) and
/// their mean horizontal force balances the body's drag, a small fraction of the weight
/// (estimate: 0.5 rho U^2 C_D A with A the 6 mm body's frontal area, 2.8e-5 m^2, and C_D
/// about 1 gives 0.04 mN, 0.5% of the weight), so zero within 1% of the weight is published.
#[test]
fn the_dragonfly_in_forward_flight_against_its_weight() {
    let v = vehicle(flapsim::DRAGONFLY_TOML);
    assert_eq!(v.wings.len(), 4);
    assert!((v.pair_phase_offsets()[1] - 61.0 / 360.0).abs() < 1e-15);
    let m = mean_loads(&v, &forward_flight(), 400).unwrap();
    let w = v.weight_n();
    let (fx, fz) = (m.total.force_n.x, m.total.force_n.z);
    eprintln!(
        "dragonfly, A&W 1988 exp. 2: mean vertical {:.3} mN ({:.3} of the weight {:.3} mN), horizontal {:.3} mN ({:+.3} of the weight)",
        1e3 * fz,
        fz / w,
        1e3 * w,
        1e3 * fx,
        fx / w
    );
    for term in Term::ALL {
        let f = m.terms[term as usize].force_n;
        eprintln!("  {term:?}: x {:.3} mN, z {:.3} mN", 1e3 * f.x, 1e3 * f.z);
    }
    // Measured (docs/models.md): 6.756 mN up, 0.872 of the weight, and 1.070 mN of net drag,
    // 0.138 of the weight, where steady flight says 1 and 0 (within the body drag's 0.005).
    // The quasi-steady wings, twisted as Table 3 measured, carry 87% of the weight at the
    // published kinematics (rigid wings feathering as at 0.75R carried 0.769 and 0.081 of
    // drag, before 2026-12-06): the gap is the model's (no forewing-hindwing interaction in
    // still air, no unsteady lift beyond its four terms, the twist in the translational term
    // only), not tuned away. Pinned to 0.01 of the weight so that a change in the model
    // shows here.
    assert!(
        (fz / w - 0.872).abs() <= 0.01,
        "vertical {fz} N against the weight {w} N"
    );
    assert!((fx / w + 0.138).abs() <= 0.01, "horizontal {fx} N");
    // Published: steady flight, vertical = weight; the gap asserted, not hidden.
    assert!((fz / w - 1.0).abs() > 0.1 && (fz / w - 1.0).abs() < 0.15);
    for (i, pair) in [(0, "fore"), (2, "hind")] {
        let mut z = 0.0;
        let mut x = 0.0;
        let body = BodyMotion {
            velocity_m_s: forward_flight().velocity_body_m_s,
            angular_velocity_rad_s: Vector3::zeros(),
        };
        for k in 0..400 {
            for wing in &v.wings[i..i + 2] {
                let f = wing.evaluate(k as f64 / 400.0, &body).total.force_n;
                z += f.z / 400.0;
                x += f.x / 400.0;
            }
        }
        eprintln!("  {pair} pair: x {:.3} mN, z {:.3} mN", 1e3 * x, 1e3 * z);
    }
}

/// The fore/hind phase offset over a wingbeat against the published trend.
#[test]
fn the_mean_force_does_not_depend_on_the_fore_hind_phase() {
    let offsets = [0.0, 90.0, 180.0, 270.0];
    let (mut means, mut swings) = (Vec::new(), Vec::new());
    for deg in offsets {
        let v = dragonfly_with_offset(deg);
        let m = mean_loads(&v, &forward_flight(), 400).unwrap();
        // The time course of the vertical force over one wingbeat.
        let body = BodyMotion {
            velocity_m_s: forward_flight().velocity_body_m_s,
            angular_velocity_rad_s: Vector3::zeros(),
        };
        let fz: Vec<f64> = (0..400)
            .map(|k| {
                v.wings
                    .iter()
                    .map(|w| w.evaluate(k as f64 / 400.0, &body).total.force_n.z)
                    .sum()
            })
            .collect();
        let (lo, hi) = fz
            .iter()
            .fold((f64::MAX, f64::MIN), |(l, h), &x| (l.min(x), h.max(x)));
        eprintln!(
            "offset {deg:>5.1} deg: mean vertical {:.4} mN, peak-to-peak over the wingbeat {:.3} mN",
            1e3 * m.total.force_n.z,
            1e3 * (hi - lo)
        );
        means.push(m.total.force_n.z);
        swings.push(hi - lo);
    }
    // The published trend in time: Rüppell 1989 (J Exp Biol 144:13, abstract) filmed
    // dragonflies' flight as uniform when fore and hind wings counterstroke (antiphase) and
    // irregular when they stroke phase-shifted and, most of all, in parallel; Wang & Sun
    // 2005 (abstract) likewise find two vertical-force peaks a cycle at 180 deg that merge
    // into one at 90, 60 and 0 deg. Here: the vertical force swings least at 180 deg (15.5 mN
    // peak to peak), most in phase (29.6 mN), 20.3 and 25.6 mN at 90 and 270 deg (the rigid
    // wings before 2026-12-06: 14.2, 27.0, 18.9 and 23.6 mN).
    assert!(swings[2] < swings[1] && swings[2] < swings[3], "{swings:?}");
    assert!(swings[0] > swings[1] && swings[0] > swings[3], "{swings:?}");
    // The mean, though, is flat: each wing's cycle mean is a mean over its whole period,
    // wherever it starts. The published CFD is not: in hover with the hindwing 180 deg ahead
    // the interaction takes 14% and 16% off the fore- and hindwing's vertical force (Sun & Lan
    // 2004, abstract), an effect of that order (about 15% of the weight, over 1 mN here) that
    // flapwing leaves out and whose change with the phase it cannot show.
    // Tolerance: 1e-9 of the weight (the phases sampled differ by rounding only, 400 samples).
    let w = dragonfly_with_offset(0.0).weight_n();
    for m in &means {
        assert!((m - means[0]).abs() <= 1e-9 * w, "{means:?}");
    }
}

/// Bad `[[pairs]]`: errors naming the file, the field, the value and what is allowed.
#[test]
fn bad_pairs_name_file_field_value_and_range() {
    let good = flapsim::DRAGONFLY_TOML;
    for (to, value) in [
        ("", "missing"),
        ("phase_offset_deg = nan", "NaN"),
        ("phase_offset_deg = inf", "inf"),
        ("phase_offset_deg = 400.0", "400"),
    ] {
        let e = err(&good.replacen("phase_offset_deg = 61.0", to, 1));
        assert!(
            e.starts_with("bad.toml")
                && e.contains("pairs[0].phase_offset_deg")
                && e.contains(value)
                && e.contains("[-360, 360]")
                && e.contains("required"),
            "{to}: {e}"
        );
    }
    // A pair at another frequency.
    let fast = good.replacen(
        "[pairs.kinematics]",
        "[pairs.kinematics]\n# overridden below\n",
        1,
    );
    let at = fast.rfind("t_s = [").unwrap();
    let mut other = fast.clone();
    other.replace_range(at..at + "t_s = [".len(), "t_s = [");
    let hind_times_end = other[at..].find(']').unwrap() + at;
    let times: Vec<f64> = other[at + 7..hind_times_end]
        .split(',')
        .filter_map(|x| x.trim().parse().ok())
        .collect();
    let doubled = times
        .iter()
        .map(|t| format!("{:.9}", 2.0 * t))
        .collect::<Vec<_>>()
        .join(", ");
    other.replace_range(at + 7..hind_times_end, &doubled);
    let e = err(&other);
    assert!(
        e.starts_with("bad.toml")
            && e.contains("pairs[0].kinematics")
            && e.contains("one frequency"),
        "{e}"
    );
    // The frozen hover downwash is one pair's (the dynamic wake models tandem pairs).
    for line in ["induced_inflow = true", "inflow = \"frozen\""] {
        let e = err(&format!("{good}\n[aero]\n{line}\n"));
        assert!(
            e.starts_with("bad.toml")
                && e.contains("aero.inflow")
                && e.contains("[[pairs]]")
                && e.contains("\"dynamic\""),
            "{line}: {e}"
        );
    }
    // Unknown fields in a pair are errors too.
    let e = err(&good.replacen(
        "phase_offset_deg = 61.0",
        "phase_offset_deg = 61.0\nphase = 0.2",
        1,
    ));
    assert!(e.contains("bad.toml") && e.contains("phase"), "{e}");
    // A component of one pair refuses four wings with an error naming the model.
    let v = vehicle(good);
    let e = v
        .require_one_pair("flight logging")
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("dragonfly") && e.contains("4 wings") && e.contains("one left/right pair"),
        "{e}"
    );
}

/// The first pair of a two-winged model is untouched: the wings and their kinematics are
/// those a model without `[[pairs]]` always built (no phase offset).
#[test]
fn a_two_winged_model_has_one_pair_without_offset() {
    let v = vehicle(flapsim::DROSOPHILA_TOML);
    assert_eq!(v.wings.len(), 2);
    assert_eq!(v.pair_phase_offsets(), vec![0.0]);
    assert!(v.require_one_pair("x").is_ok());
}

/// Trim takes every pair: a fly given a second, identical pair 0.6 mm behind the first (its
/// own hinges, a quarter wingbeat ahead) trims at a smaller stroke than the fly alone, and at
/// the same one whatever the second pair's phase (the cycle means do not depend on it).
#[test]
fn a_four_winged_fly_trims_on_all_its_wings() {
    let fly = flapsim::DROSOPHILA_TOML.replacen("inflow = \"frozen\"", "inflow = \"off\"", 1);
    let with_pair = |deg: f64| {
        format!(
            "{fly}\n[[pairs]]\nphase_offset_deg = {deg:.1}\n[pairs.hinge]\nleft_in_body_m = [-0.32e-3, 0.45e-3, 0.28e-3]\nstroke_plane_tilt_deg = 45.0\n"
        )
    };
    let two = vehicle(&fly);
    let t2 = flapsim::trim::trim(&two).unwrap();
    let (a, b) = (vehicle(&with_pair(90.0)), vehicle(&with_pair(0.0)));
    let (ta, tb) = (
        flapsim::trim::trim(&a).unwrap(),
        flapsim::trim::trim(&b).unwrap(),
    );
    let amp = |v: &Vehicle, t: &flapsim::trim::Trim| {
        (v.base_kinematics[0].amplitude_rad + t.controls.amplitude_rad).to_degrees()
    };
    eprintln!(
        "trimmed stroke: two wings {:.2} deg, four {:.2} deg (offset 90), {:.2} deg (offset 0)",
        amp(&two, &t2),
        amp(&a, &ta),
        amp(&b, &tb)
    );
    // Converged (the trim's own residuals), and the second pair carries a share of the weight.
    assert!(ta.max_residual() < 1e-6 && tb.max_residual() < 1e-6);
    assert!(amp(&a, &ta) < amp(&two, &t2) - 10.0);
    // The same trim at either phase (tolerance: 1e-6 deg, the Newton iteration's residual).
    assert!((amp(&a, &ta) - amp(&b, &tb)).abs() < 1e-6);
    assert!((ta.pitch_rad - tb.pitch_rad).abs() < 1e-8);
}

/// The dynamic wake of tandem pairs (`wingforce::inflow::interference`) in its coaxial limit:
/// two pairs on one disc (the hind pair 1 um behind the fore pair, same planform and
/// kinematics) each meet the other's downwash in their momentum balance, so together they
/// induce what one disc carrying both thrusts does, sqrt(T / (2 rho A)) over the disc's area
/// A (the simple momentum theory of a coaxial rotor, Leishman & Ananthan 2006, AHS 62nd
/// Forum; Rankine-Froude for the disc): the sum of the pairs' mean inflow over the wingbeat
/// within 2% of it, with T the four wings' mean thrust along the stroke-plane normal (the
/// states follow a thrust pulsing twice a wingbeat, so their mean is not exactly the balance
/// of the mean thrust). Apart by more than the discs' diameters, each pair meets only its
/// own wake.
#[test]
fn tandem_pairs_on_one_disc_induce_what_one_disc_carrying_both_does() {
    let fly = flapsim::DROSOPHILA_TOML.replacen("inflow = \"frozen\"", "inflow = \"dynamic\"", 1);
    let with_pair_at = |x_m: f64| {
        vehicle(&format!(
            "{fly}\n[[pairs]]\nphase_offset_deg = 0.0\n[pairs.hinge]\nleft_in_body_m = [{x_m:e}, 0.45e-3, 0.28e-3]\nstroke_plane_tilt_deg = 45.0\n"
        ))
    };
    let v = with_pair_at(0.28e-3 - 1e-6);
    let motion = BodyMotion::default();
    let p = flapsim::averaged::periodic_inflow(&v, &motion, 200)
        .unwrap()
        .expect("the wake answers");
    let normal_body = v.wings[0].body_from_stroke() * Vector3::z();
    let thrust_n = p.mean.total.force_n.dot(&normal_body);
    let disc = p_disc(&v);
    let expected = disc.hover_m_s(thrust_n);
    let total: f64 = p.state_means.iter().map(|s| s.mean_m_s).sum();
    eprintln!(
        "coincident pairs: inflow {:.4} + {:.4} = {total:.4} m/s, sqrt(T / (2 rho A)) {expected:.4} m/s (T {thrust_n:.4e} N)",
        p.state_means[0].mean_m_s, p.state_means[1].mean_m_s
    );
    assert!(
        (total / expected - 1.0).abs() < 0.02,
        "{total} against {expected}"
    );
    // Apart: each pair alone, as the fly's own pair (the same thrust, the same disc; the
    // fly at half the mass, so that its wings start from the same share of the weight, on
    // which the added-mass term's inflow rests: wingforce::Wing::set_inflow_field).
    let apart = with_pair_at(0.28e-3 - 0.02);
    let q = flapsim::averaged::periodic_inflow(&apart, &motion, 200)
        .unwrap()
        .unwrap();
    let alone = vehicle(&fly.replacen("mass_kg = 1.0e-6", "mass_kg = 0.5e-6", 1));
    let r = flapsim::averaged::periodic_inflow(&alone, &motion, 200)
        .unwrap()
        .unwrap();
    for s in &q.state_means {
        assert!(
            (s.mean_m_s / r.state_means[0].mean_m_s - 1.0).abs() < 1e-12,
            "{s:?} against {:?}",
            r.state_means[0]
        );
    }
}

/// The disc of the fly's first pair: its stroke amplitude and tip radius.
fn p_disc(v: &Vehicle) -> wingforce::inflow::InflowDisc {
    let w = &v.wings[0];
    wingforce::inflow::InflowDisc::swept(
        w.fluid().density_kg_m3,
        w.kinematics().amplitude_rad,
        w.geometry().r_tip_m,
        2,
    )
}
