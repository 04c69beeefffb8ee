//! The wing set on its own, without flapsim: a pair of robofly wings built one by one, and
//! controls mapped onto them by a control map of the test's own.

mod common;

use nalgebra::Vector3;
use wingforce::{Side, Wing};
use wingset::{ControlMap, Controls, Error, State, WingSet};

use common::wing;

/// Maps `amplitude_rad` onto both wings' amplitude; refuses a frequency offset.
#[derive(Debug, Clone)]
struct Amplitude {
    base: Vec<Wing>,
    wings: Vec<Wing>,
}

impl ControlMap for Amplitude {
    fn apply(&mut self, c: &Controls) -> wingset::Result<()> {
        if c.freq_hz != 0.0 {
            return Err(Error::Analysis("no frequency control here".into()));
        }
        for (w, b) in self.wings.iter_mut().zip(&self.base) {
            let mut k = b.kinematics().clone();
            k.amplitude_rad += c.amplitude_rad;
            w.set_kinematics(k);
        }
        Ok(())
    }
    fn wings(&self) -> &[Wing] {
        &self.wings
    }
    fn drives(&self) -> Option<&[wingset::actuated::Drive]> {
        None
    }
    fn clone_box(&self) -> Box<dyn ControlMap> {
        Box::new(self.clone())
    }
}

fn steps_per_wingbeat(set: &WingSet) -> usize {
    (1.0 / (set.freq_hz() * set.dt_s())).round() as usize
}

#[test]
fn a_mirrored_pair_lifts_without_rolling() {
    let f = wing(Side::Left).kinematics().freq_hz;
    let mut set = WingSet::builder(1.0 / (f * 100.0))
        .wing(wing(Side::Left))
        .wing(wing(Side::Right))
        .build()
        .unwrap();
    assert_eq!(set.len(), 2);
    let mut mean = Vector3::zeros();
    let mut roll = 0.0_f64;
    for _ in 0..steps_per_wingbeat(&set) {
        let out = set.step(&State::at_rest()).unwrap();
        assert!(out.total.is_finite());
        mean += out.total.force_n / 100.0;
        roll = roll.max(out.total.moment_nm.x.abs());
    }
    assert!(mean.z.abs() > 0.0, "{mean:?}");
    assert!(mean.y.abs() <= 1e-12 * mean.z.abs(), "{mean:?}");
    assert!(roll <= 1e-12 * mean.z.abs(), "{roll}");
    assert!((set.phase() - 1.0).abs() < 1e-12, "{}", set.phase());
}

#[test]
fn controls_reach_the_wings_through_the_map_at_the_next_wingbeat() {
    let wings = vec![wing(Side::Left), wing(Side::Right)];
    let a0 = wings[0].kinematics().amplitude_rad;
    let f = wings[0].kinematics().freq_hz;
    let map = Amplitude {
        base: wings.clone(),
        wings,
    };
    let mut set = WingSet::with_control_map(
        Box::new(map),
        None,
        0.0,
        1.0 / (f * 50.0),
        Controls::default(),
    )
    .unwrap();
    set.step(&State::at_rest()).unwrap();
    let c = Controls {
        amplitude_rad: 0.1,
        ..Controls::default()
    };
    set.set_controls(c).unwrap();
    assert_eq!(set.requested_controls(), c);
    assert_eq!(set.wings()[0].kinematics().amplitude_rad, a0);
    for _ in 0..50 {
        set.step(&State::at_rest()).unwrap();
    }
    assert_eq!(set.controls(), c);
    assert_eq!(set.output().controls, c);
    assert_eq!(set.wings()[1].kinematics().amplitude_rad, a0 + 0.1);
    let map = set.control_map().unwrap() as &dyn std::any::Any;
    assert!(map.downcast_ref::<Amplitude>().is_some());

    // What the map refuses comes back unchanged from the step that applies it.
    set.set_controls(Controls {
        freq_hz: 1.0,
        ..Controls::default()
    })
    .unwrap();
    let e = (0..50)
        .find_map(|_| set.step(&State::at_rest()).err())
        .unwrap();
    assert_eq!(e, Error::Analysis("no frequency control here".into()));
}

#[test]
fn a_set_without_a_map_refuses_controls() {
    let mut set = WingSet::builder(1e-4)
        .wing(wing(Side::Left))
        .build()
        .unwrap();
    let e = set.set_controls(Controls::default()).unwrap_err();
    assert!(
        matches!(e, Error::Input(ref m) if m.contains("need a vehicle model")),
        "{e}"
    );
}
