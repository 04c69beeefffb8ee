//! Cost of one wing evaluation: 20 strips, all four terms, with body motion; the added-mass
//! term in its two forms (MODEL.md 4.3: the impulse form, -dP/dt, and the paper's eq 7-8).
//!
//! Besides the criterion groups, `form_ratio_rounds` interleaves the two forms (this VM's
//! speed changes by up to 2x from minute to minute, so only ratios measured side by side mean
//! anything) and prints the median cost ratio impulse / paper.
use criterion::{Criterion, criterion_group, criterion_main};
use nalgebra::Vector3;
use std::hint::black_box;
use std::time::Instant;
use wingforce::{AddedMassForm, BodyMotion, Wing, WingModelSpec};

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
    let mut ratios = Vec::new();
    for round in 0..21 {
        // Alternate which form goes first.
        let (ti, tp) = if round % 2 == 0 {
            let ti = time(&impulse);
            (ti, time(&paper))
        } else {
            let tp = time(&paper);
            (time(&impulse), tp)
        };
        ratios.push(ti / tp);
    }
    ratios.sort_by(f64::total_cmp);
    let q = |f: f64| ratios[((ratios.len() - 1) as f64 * f).round() as usize];
    println!(
        "added-mass forms, impulse / paper cost of a whole wing evaluation (robofly, 20 strips, interleaved, 21 rounds of {n}): median {:.3}x [quartiles {:.3} {:.3}]",
        q(0.5),
        q(0.25),
        q(0.75)
    );
}

criterion_group!(benches, bench);
criterion_main!(benches);
