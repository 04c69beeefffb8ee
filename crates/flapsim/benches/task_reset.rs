//! A Gym task's reset for the actuated vehicles (`flapsim::task::Task::reset`), against the
//! settling of their wings on the periodic motion at the trim, which every reset did before
//! the task kept the settled wings (they depend on the vehicle and its trim only): a reset
//! then cost the two together. 15 interleaved rounds of 10 resets and 10 settlings (this
//! VM's speed changes by up to 2x from minute to minute); prints the medians.
use std::hint::black_box;
use std::time::Instant;

use criterion::{Criterion, criterion_group, criterion_main};
use flapsim::actuated::periodic::settle_at_rest;
use flapsim::task::{Task, TaskSpec};
use flapsim::trim::{trim, trimmed_vehicle};
use flapsim::{Vehicle, builtin_model};

fn rounds(name: &str) {
    let text = builtin_model(name).expect("a built-in model");
    let mut task = Task::new(text, name, TaskSpec::recover(), None).expect("a task");
    let v = Vehicle::from_toml(text, name).expect("its model");
    let trimmed = trimmed_vehicle(&v, &trim(&v).expect("a hover trim")).expect("trimmed");
    let (mut reset, mut settle) = (Vec::new(), Vec::new());
    for round in 0..15u64 {
        let t0 = Instant::now();
        for k in 0..10 {
            black_box(task.reset(100 * round + k).expect("a reset"));
        }
        reset.push(t0.elapsed().as_secs_f64() / 10.0);
        let t0 = Instant::now();
        for _ in 0..10 {
            black_box(settle_at_rest(&trimmed).expect("settled wings"));
        }
        settle.push(t0.elapsed().as_secs_f64() / 10.0);
    }
    let median = |v: &mut Vec<f64>| {
        v.sort_by(f64::total_cmp);
        v[v.len() / 2]
    };
    let (r, s) = (median(&mut reset), median(&mut settle));
    println!(
        "{name}: a reset {:.3} ms; the settling it no longer repeats {:.3} ms; a reset before {:.3} ms ({:.1}x now), 15 interleaved rounds of 10",
        1e3 * r,
        1e3 * s,
        1e3 * (r + s),
        (r + s) / r
    );
}

fn bench(_c: &mut Criterion) {
    // The only actuated vehicle that hovers (the RoboBee has no hover trim: no task).
    rounds("hummingbird");
}

criterion_group!(benches, bench);
criterion_main!(benches);
