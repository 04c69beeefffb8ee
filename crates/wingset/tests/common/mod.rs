//! Helpers shared by the wing set's integration tests.

use wingforce::{Mount, Side, Wing, WingModelSpec};

/// A robofly wing (models/robofly.toml) fixed on `side`.
pub fn wing(side: Side) -> Wing {
    let text = include_str!("../../../../models/robofly.toml");
    let w = WingModelSpec::from_toml(text, "robofly.toml")
        .unwrap()
        .build("robofly.toml")
        .unwrap();
    Wing::builder(w.geometry().clone(), w.kinematics().clone())
        .mount(Mount::fixed(side))
        .fluid(*w.fluid())
        .options(w.options().clone())
        .build()
}
