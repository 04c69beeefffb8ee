//! Cost of one wing evaluation: 20 strips, all four terms, with body motion; the added-mass
//! term in its two forms (MODEL.md 4.3: the impulse form, -dP/dt, and the paper's eq 7-8).
//!
//! Besides the criterion groups, `form_ratio_rounds` interleaves the two forms (this VM's
//! speed changes by up to 2x from minute to minute, so only ratios measured side by side mean
//! anything) and prints the median cost ratio impulse / paper; `twist_pair_ratio_rounds`
//! likewise times a mirrored pair of twisted wings evaluated side by side
//! (`Wing::evaluate_pair_with`, SIMD lanes, one sine and cosine per strip) against each wing
//! alone (the path twisted pairs took before 2026-12-06).
use criterion::{Criterion, criterion_group, criterion_main};
use nalgebra::Vector3;
use std::hint::black_box;
use std::time::Instant;
use wingforce::{
    AddedMassForm, BodyMotion, KinematicsSpec, Side, TwistSpec, Validator, Wing, WingModelSpec,
};

fn robofly(form: AddedMassForm) -> Wing {
    let text = include_str!("../../../models/robofly.toml");
    let mut wing = WingModelSpec::from_toml(text, "robofly.toml")
        .and_then(|s| s.build("robofly.toml"))
        .expect("built-in model");
    let mut options = wing.options().clone();
    options.added_mass = form;
    wing.set_options(options);
    wing
}

fn body() -> BodyMotion {
    BodyMotion {
        velocity_m_s: Vector3::new(0.01, 0.002, -0.003),
        angular_velocity_rad_s: Vector3::new(0.1, -0.2, 0.05),
    }
}

fn bench(c: &mut Criterion) {
    let body = body();
    for form in [AddedMassForm::Impulse, AddedMassForm::Paper] {
        let wing = robofly(form);
        let mut phase = 0.0;
        c.bench_function(
            &format!("wing_evaluate_20_strips_all_terms_{}", form.name()),
            |b| {
                b.iter(|| {
                    phase += 0.0137;
                    black_box(wing.evaluate(black_box(phase), black_box(&body)))
                })
            },
        );
    }
    let wing = robofly(AddedMassForm::Impulse);
    let mut t = 0.0;
    c.bench_function("kinematics_angles_trapezoidal", |b| {
        b.iter(|| {
            t += 0.0137;
            black_box(wing.kinematics().angles(black_box(t)))
        })
    });
    form_ratio_rounds();
    let [left, right] = twisted_pair();
    let mut phase = 0.0;
    c.bench_function("twisted_mirrored_pair_side_by_side", |b| {
        b.iter(|| {
            phase += 0.0137;
            black_box(Wing::evaluate_mirrored_pair(
                &left,
                &right,
                black_box(phase),
                black_box(&body),
            ))
        })
    });
    twist_pair_ratio_rounds();
}

/// The robofly's planform on a tabulated harmonic wingbeat (stroke -60 cos, pitch 90 - 45 sin,
/// deg) twisted at 0.25R by a wave of 5 +- 20 deg (its table's pitch at 0.75R), as a mirrored
/// pair (left, right).
fn twisted_pair() -> [Wing; 2] {
    let robofly = robofly(AddedMassForm::Impulse);
    let n = 64;
    let w = |i: usize| 2.0 * std::f64::consts::PI * i as f64 / n as f64;
    let pitch = |extra: f64| -> Vec<f64> {
        (0..=n)
            .map(|i| 90.0 - 45.0 * w(i).sin() + extra * (w(i) + 0.3).sin())
            .collect()
    };
    let kinematics = KinematicsSpec::Tabulated {
        t_s: (0..=n).map(|i| 0.2 * i as f64 / n as f64).collect(),
        stroke_deg: (0..=n).map(|i| -60.0 * w(i).cos()).collect(),
        pitch_deg: pitch(0.0),
        deviation_deg: None,
        twist: Some(TwistSpec {
            reference_r_frac: 0.75,
            stations_r_frac: vec![0.25],
            pitch_deg: vec![pitch(20.0).iter().map(|p| p + 5.0).collect()],
        }),
    }
    .build(&Validator::new("aero_kernel bench"), "kinematics", 0.2)
    .expect("a valid twisted table");
    let wing = |side: Side| {
        let mut mount = *robofly.mount();
        mount.side = side;
        Wing::builder(robofly.geometry().clone(), kinematics.clone())
            .fluid(*robofly.fluid())
            .options(robofly.options().clone())
            .mount(mount)
            .build()
    };
    [wing(Side::Left), wing(Side::Right)]
}

/// Interleaved rounds of 100,000 phases: the twisted pair side by side against each wing
/// alone (the same loads, bit for bit); prints the median cost ratio.
fn twist_pair_ratio_rounds() {
    let [left, right] = twisted_pair();
    let body = body();
    let n = 100_000;
    let time = |paired: bool| {
        let t0 = Instant::now();
        for i in 0..n {
            let phase = i as f64 * 0.0137;
            if paired {
                black_box(Wing::evaluate_mirrored_pair(
                    &left,
                    &right,
                    black_box(phase),
                    black_box(&body),
                ));
            } else {
                let k = Wing::mirrored_kinematic_loads(&left, &right, black_box(phase));
                black_box(left.evaluate_with(&k[0], black_box(&body)));
                black_box(right.evaluate_with(&k[1], black_box(&body)));
            }
        }
        t0.elapsed().as_secs_f64()
    };
    print_ratio(
        &format!(
            "twisted mirrored pair, side by side / each wing alone (robofly planform, 20 strips, all four terms, interleaved, 21 rounds of {n})"
        ),
        interleaved_ratios(|| time(true), || time(false)),
    );
}

/// Interleaved rounds of 200,000 evaluations per form; prints the median cost ratio.
fn form_ratio_rounds() {
    let (impulse, paper) = (
        robofly(AddedMassForm::Impulse),
        robofly(AddedMassForm::Paper),
    );
    let body = body();
    let n = 200_000;
    let time = |wing: &Wing| {
        let t0 = Instant::now();
        for i in 0..n {
            let phase = i as f64 * 0.0137;
            black_box(wing.evaluate(black_box(phase), black_box(&body)));
        }
        t0.elapsed().as_secs_f64()
    };
    print_ratio(
        &format!(
            "added-mass forms, impulse / paper cost of a whole wing evaluation (robofly, 20 strips, interleaved, 21 rounds of {n})"
        ),
        interleaved_ratios(|| time(&impulse), || time(&paper)),
    );
}

/// The ratios a / b of 21 interleaved rounds of two timed runs (which goes first alternates).
fn interleaved_ratios(mut a: impl FnMut() -> f64, mut b: impl FnMut() -> f64) -> Vec<f64> {
    (0..21)
        .map(|round| {
            let (ta, tb) = if round % 2 == 0 {
                let ta = a();
                (ta, b())
            } else {
                let tb = b();
                (a(), tb)
            };
            ta / tb
        })
        .collect()
}

/// Prints the median of `ratios` with its quartiles.
fn print_ratio(label: &str, mut ratios: Vec<f64>) {
    ratios.sort_by(f64::total_cmp);
    let q = |f: f64| ratios[((ratios.len() - 1) as f64 * f).round() as usize];
    println!(
        "{label}: median {:.3}x [quartiles {:.3} {:.3}]",
        q(0.5),
        q(0.25),
        q(0.75)
    );
}

criterion_group!(benches, bench);
criterion_main!(benches);
