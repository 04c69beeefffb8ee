//! Cost of one wing evaluation: 20 strips, all four terms, with body motion.
use criterion::{Criterion, criterion_group, criterion_main};
use nalgebra::Vector3;
use std::hint::black_box;
use wingforce::{BodyMotion, WingModelSpec};

fn bench(c: &mut Criterion) {
    let text = include_str!("../../../models/robofly.toml");
    let wing = WingModelSpec::from_toml(text, "robofly.toml")
        .and_then(|s| s.build("robofly.toml"))
        .expect("built-in model");
    let body = BodyMotion {
        velocity_m_s: Vector3::new(0.01, 0.002, -0.003),
        angular_velocity_rad_s: Vector3::new(0.1, -0.2, 0.05),
    };
    let mut phase = 0.0;
    c.bench_function("wing_evaluate_20_strips_all_terms", |b| {
        b.iter(|| {
            phase += 0.0137;
            black_box(wing.evaluate(black_box(phase), black_box(&body)))
        })
    });
    let mut t = 0.0;
    c.bench_function("kinematics_angles_trapezoidal", |b| {
        b.iter(|| {
            t += 0.0137;
            black_box(wing.kinematics().angles(black_box(t)))
        })
    });
}

criterion_group!(benches, bench);
criterion_main!(benches);
