//! The added-mass term (MODEL.md 4.3): the force of the fluid that a flat wing accelerates,
//! in one of two forms, and the choice between them.
//!
//! Both forms sum strips of a thin flat plate in 2-D ideal flow, whose fluid carries the
//! impulse P = m' v_n n per strip, m' = (pi/4) rho c^2 dr, n the wing normal and v_n the
//! normal velocity of the strip's mid-chord point p = r e_span + x e_le relative to the air
//! (x: the mid-chord's offset from the pitch axis, towards the leading edge).
//!
//! * [`AddedMassForm::Impulse`] (MODEL.md's revised default): dF = -dP/dt in an inertial
//!   frame, dF = -m' (dv_n/dt) n - m' v_n (omega x n). With the air's velocity relative to
//!   the stroke frame u constant, v_n = n . (u + omega x p) and
//!   dv_n/dt = (omega x n) . u + n . (alpha x p): the two centripetal parts,
//!   (omega x n) . (omega x p) and n . (omega x (omega x p)), cancel identically. So
//!   v_n = a0 + a1 r + a2 x and dv_n/dt = b0 + b1 r + b2 x, and the span integrals of
//!   c^2 {1, r, x, r^2, r x, x^2} give the whole wing. Over any periodic motion P repeats, so
//!   the cycle mean of the force is zero in every direction: added mass moves fluid back and
//!   forth and carries no weight. The moment about the hinge is that of each strip's force
//!   at its mid-chord point, plus the strip's rotational added inertia about the span axis,
//!   -(pi/128) rho c^4 dr (alpha . e_span), the moment of a flat plate pitching about its
//!   mid-chord in ideal flow.
//! * [`AddedMassForm::Paper`] (the seed paper's eq 7-8, Sane and Dickinson's form): the
//!   normal component of the mid-chord point's acceleration along the turning normal,
//!   dF = -m' (n . a) n. Its cycle mean is not zero; kept so that the paper's own
//!   blade-element comparisons can be reproduced.
//!
//! Which is the default: the impulse form, as MODEL.md 4.3 makes it. A model chooses with
//! `[aero] added_mass`, and every report names the form it used; `models/robofly.toml`
//! chooses the paper's form, because it reproduces the paper's own blade-element numbers.
//!
//! The impulse form here takes the air as moving steadily relative to the stroke frame (the
//! induced inflow): the body's own velocity and acceleration do not enter it. Prescribed
//! kinematics on a tethered body, or a hovering body whose motion is slow beside the wing's,
//! are what it is exact for; the body's coupling comes with the wing force element that a
//! host steps with the body's acceleration.

use nalgebra::Vector3;
use serde::{Deserialize, Serialize};

use crate::frame::WingFrame;
use crate::planform::AddedMassIntegrals;

/// Which added-mass force a wing computes (`[aero] added_mass` in a model file).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum AddedMassForm {
    /// -dP/dt of the strips' fluid impulse (MODEL.md 4.3, revised): no cycle-mean force.
    /// The default.
    #[default]
    Impulse,
    /// The seed paper's eq 7-8 (a cycle-mean force that ideal flow does not allow), kept to
    /// reproduce the paper's own blade-element comparisons.
    Paper,
    /// No added-mass term.
    Off,
}

impl AddedMassForm {
    /// Every form, in the order of its name in model files.
    pub const ALL: [AddedMassForm; 3] = [Self::Impulse, Self::Paper, Self::Off];

    /// The name in model files, logs and reports.
    pub fn name(self) -> &'static str {
        match self {
            Self::Impulse => "impulse",
            Self::Paper => "paper",
            Self::Off => "off",
        }
    }

    /// What a report says of an added-mass figure made by this form.
    pub fn describe(self) -> &'static str {
        match self {
            Self::Impulse => "impulse form, -dP/dt (MODEL.md 4.3)",
            Self::Paper => "paper form, eq 7-8",
            Self::Off => "off",
        }
    }

    /// The form named `name`.
    pub fn from_name(name: &str) -> Option<Self> {
        Self::ALL.into_iter().find(|f| f.name() == name)
    }

    /// True unless the term is off.
    pub fn is_on(self) -> bool {
        self != Self::Off
    }
}

impl<'de> Deserialize<'de> for AddedMassForm {
    /// A form's name; also `true` (the paper's form, what the switch meant before the
    /// forms existed) and `false` (off).
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        #[derive(Deserialize)]
        #[serde(untagged)]
        enum Written {
            Switch(bool),
            Name(String),
        }
        match Written::deserialize(d)? {
            Written::Switch(true) => Ok(Self::Paper),
            Written::Switch(false) => Ok(Self::Off),
            Written::Name(n) => Self::from_name(&n).ok_or_else(|| {
                serde::de::Error::custom(format!(
                    "unknown added-mass form `{n}`: allowed \"impulse\", \"paper\", \"off\" (or true for \"paper\", false for \"off\")"
                ))
            }),
        }
    }
}

/// A term's force and moment about the hinge, stroke frame.
pub(crate) struct ForceMoment {
    pub force_n: Vector3<f64>,
    pub moment_nm: Vector3<f64>,
}

/// Eq 7-8: `k` is -(pi/4) rho.
#[inline(always)]
pub(crate) fn paper(frame: &WingFrame, am: &AddedMassIntegrals, k: f64) -> ForceMoment {
    let acc = |p: &Vector3<f64>| frame.alpha.cross(p) + frame.omega.cross(&frame.omega.cross(p));
    let k1 = frame.n.dot(&acc(&frame.e_span));
    let k2 = frame.n.dot(&acc(&frame.e_le));
    let f_mag = k * (k1 * am.c2_r + k2 * am.c2_x);
    let rf = k * (k1 * am.c2_r2 + k2 * am.c2_rx);
    let xf = k * (k1 * am.c2_rx + k2 * am.c2_x2);
    ForceMoment {
        force_n: f_mag * frame.n,
        moment_nm: frame.e_span.cross(&(rf * frame.n)) + frame.e_le.cross(&(xf * frame.n)),
    }
}

/// The strips' fluid impulse P = sum m' v_n n, stroke frame, N s (`k` and `u_s` as in
/// [`impulse`], whose force is -dP/dt of it).
#[inline]
pub(crate) fn fluid_impulse(
    frame: &WingFrame,
    am: &AddedMassIntegrals,
    k: f64,
    u_s: &Vector3<f64>,
) -> Vector3<f64> {
    let n = &frame.n;
    let a0 = n.dot(u_s);
    let a1 = n.dot(&frame.omega.cross(&frame.e_span));
    let a2 = n.dot(&frame.omega.cross(&frame.e_le));
    // k = -(pi/4) rho: P = -k int c^2 v_n dr n.
    -k * (a0 * am.c2 + a1 * am.c2_r + a2 * am.c2_x) * n
}

/// The impulse form's moment about the hinge split as M = dW/dt + R: the potential W (the
/// strips' -p x P plus their rotational added inertia's angular impulse
/// (k c^4 / 32) (omega . e_span) e_span) and the remainder R, which holds rates and no
/// accelerations ((omega x e_span) x and (omega x e_le) x the strips' impulse moments, and
/// the spin's -(k c^4 / 32)(omega . e_span)(omega x e_span)). Stroke frame. A step's mean
/// moment is then (W_end - W_start)/dt plus R's mean, exact for the part that jumps with the
/// accelerations (`Wing::kinematic_loads_over_step`).
pub(crate) fn impulse_moment_parts(
    frame: &WingFrame,
    am: &AddedMassIntegrals,
    k: f64,
    u_s: &Vector3<f64>,
) -> (Vector3<f64>, Vector3<f64>) {
    let n = &frame.n;
    let a0 = n.dot(u_s);
    let a1 = n.dot(&frame.omega.cross(&frame.e_span));
    let a2 = n.dot(&frame.omega.cross(&frame.e_le));
    let rv = k * (a0 * am.c2_r + a1 * am.c2_r2 + a2 * am.c2_rx);
    let xv = k * (a0 * am.c2_x + a1 * am.c2_rx + a2 * am.c2_x2);
    let ds = frame.omega.cross(&frame.e_span);
    let dl = frame.omega.cross(&frame.e_le);
    let spin_k = k / 32.0 * am.c4 * frame.omega.dot(&frame.e_span);
    let potential =
        frame.e_span.cross(&(rv * n)) + frame.e_le.cross(&(xv * n)) + spin_k * frame.e_span;
    let remainder = -(ds.cross(&(rv * n)) + dl.cross(&(xv * n))) - spin_k * ds;
    (potential, remainder)
}

/// -dP/dt: `k` is -(pi/4) rho, `u_s` the wing's velocity relative to the air from the air's
/// own (steady) motion, stroke frame.
#[inline(always)]
pub(crate) fn impulse(
    frame: &WingFrame,
    am: &AddedMassIntegrals,
    k: f64,
    u_s: &Vector3<f64>,
) -> ForceMoment {
    let n = &frame.n;
    let dn = frame.omega.cross(n);
    // v_n = a0 + a1 r + a2 x; dv_n/dt = b0 + b1 r + b2 x.
    let a0 = n.dot(u_s);
    let a1 = n.dot(&frame.omega.cross(&frame.e_span));
    let a2 = n.dot(&frame.omega.cross(&frame.e_le));
    let b0 = dn.dot(u_s);
    let b1 = n.dot(&frame.alpha.cross(&frame.e_span));
    let b2 = n.dot(&frame.alpha.cross(&frame.e_le));
    // Span integrals of m' v_n and m' dv_n/dt, and their first moments in r and x.
    let lin = |c0: f64, c1: f64, c2: f64| {
        [
            k * (c0 * am.c2 + c1 * am.c2_r + c2 * am.c2_x),
            k * (c0 * am.c2_r + c1 * am.c2_r2 + c2 * am.c2_rx),
            k * (c0 * am.c2_x + c1 * am.c2_rx + c2 * am.c2_x2),
        ]
    };
    let [fv, rv, xv] = lin(a0, a1, a2);
    let [fa, ra, xa] = lin(b0, b1, b2);
    let force_n = fa * n + fv * dn;
    let strips = frame.e_span.cross(&(ra * n + rv * dn)) + frame.e_le.cross(&(xa * n + xv * dn));
    // The strips' rotational added inertia about the span axis: k c^4 / 32 = -(pi/128) rho c^4.
    let spin = k / 32.0 * am.c4 * frame.alpha.dot(&frame.e_span) * frame.e_span;
    ForceMoment {
        force_n,
        moment_nm: strips + spin,
    }
}
