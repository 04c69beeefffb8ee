//! The body's parasite drag, for hosts that hand the set's whole wrench to their engine.
//!
//! A vehicle's body feels drag 0.5 rho |V| V C_D S against its velocity V through the air, at
//! its centre of mass (flapsim's `[body] drag_area_m2`, `flapsim::flight`). The trims of a
//! forward flight balance it: the wings' cycle-mean force carries the weight and pushes the
//! body against its drag. flapsim's own hosts apply the drag themselves; a host that applies
//! only what the set returns (the C ABI, and on it the MuJoCo plugin and the FMU, Python's
//! `WingSet`) turns it on with [`WingSet::set_body_drag_area_m2`], and the set reports it as
//! its own load ([`WingSetOutput::body_drag`](super::WingSetOutput::body_drag)), included
//! in the total.

use nalgebra::Vector3;

use super::WingSet;
use super::body::{BodyLoad, State};
use crate::error::{Error, Result};

impl WingSet {
    /// The body's parasite drag area C_D S, m^2, applied with every step from then on (0, the
    /// default, leaves body drag to the host). The air's density is the first wing's fluid's.
    /// A negative or non-finite area is an error that changes nothing.
    pub fn set_body_drag_area_m2(&mut self, area_m2: f64) -> Result<()> {
        if !(area_m2 >= 0.0 && area_m2.is_finite()) {
            return Err(Error::Input(format!(
                "wing set: body drag area = {area_m2} m^2; allowed: a finite C_D S >= 0 m^2"
            )));
        }
        self.body_drag_area_m2 = area_m2;
        Ok(())
    }

    /// The body's parasite drag area C_D S the set applies, m^2 (0: none).
    pub fn body_drag_area_m2(&self) -> f64 {
        self.body_drag_area_m2
    }

    /// The air's velocity at the body's centre of mass, world frame, m/s: the uniform wind,
    /// or the wings' own winds averaged (as flapsim's `Simulation` takes it).
    pub(super) fn body_air_m_s(&self) -> Vector3<f64> {
        match &self.wing_winds_world_m_s {
            Some(w) => w.iter().sum::<Vector3<f64>>() / w.len() as f64,
            None => self.wind_world_m_s,
        }
    }

    /// The body's drag at `body`, body frame, about the centre of mass (no moment): zero
    /// without a drag area.
    pub(super) fn body_drag(&self, body: &State) -> BodyLoad {
        if self.body_drag_area_m2 == 0.0 {
            return BodyLoad::default();
        }
        let rho = self.wings[0].fluid().density_kg_m3;
        let v = body.velocity_m_s - self.body_air_m_s();
        let drag_world = -0.5 * rho * self.body_drag_area_m2 * v.norm() * v;
        BodyLoad {
            force_n: body.world_from_body.inverse() * drag_world,
            moment_nm: Vector3::zeros(),
        }
    }
}
