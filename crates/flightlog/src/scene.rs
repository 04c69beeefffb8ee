//! The `foxglove.SceneUpdate` messages for Foxglove's 3D panel: the wing planforms
//! (`/scene/wings`, once) and each wing's aerodynamic force as an arrow (`/scene/forces`, every
//! sample).

use foxglove::messages::{ArrowPrimitive, Color, Pose, Quaternion, SceneEntity, SceneUpdate};
use nalgebra::Vector3;

use crate::proto;
use crate::sample::{Sample, timestamp};
use crate::schema::{FRAME_BODY, WingLayout};

/// An arrow's head, as a fraction of its whole length (the rest is the shaft).
pub const ARROW_HEAD_FRACTION: f64 = 0.2;
/// Shaft and head diameters of the force arrows, in body lengths.
pub const ARROW_SHAFT_DIAMETER_BODY: f64 = 0.02;
/// See [`ARROW_SHAFT_DIAMETER_BODY`].
pub const ARROW_HEAD_DIAMETER_BODY: f64 = 0.05;
/// Arrow colours, left wings and right wings (r, g, b, a).
const ARROW_COLOURS: [[f64; 4]; 2] = [[1.0, 0.45, 0.1, 0.9], [0.1, 0.6, 1.0, 0.9]];

/// Builds the `/scene/forces` message of a sample: per wing one entity `force_{label}` (the
/// wing's label of [`WingLayout`]: `force_left`, `force_right`, ...) in `base_link` (the
/// body frame the forces are in), `frame_locked`, holding one arrow from the hinge along the
/// wing's total aerodynamic force. Length = |F| / weight * body length (an arrow as long as
/// the body is a force equal to the weight, the scale of the Rerun recording's arrows).
#[derive(Debug, Clone)]
pub(crate) struct ForceArrows {
    hinge_m: Vec<Vector3<f64>>,
    /// Each wing's entity id.
    ids: Vec<String>,
    /// Arrow length per newton, m/N.
    m_per_n: f64,
    shaft_diameter_m: f64,
    head_diameter_m: f64,
}

impl ForceArrows {
    pub fn of(vehicle: &flapsim::Vehicle) -> Self {
        let length_m = vehicle.length_m;
        Self {
            hinge_m: vehicle
                .wings
                .iter()
                .map(|w| w.mount().hinge_in_body_m)
                .collect(),
            ids: WingLayout::new(vehicle.wings.len())
                .labels()
                .iter()
                .map(|l| format!("force_{l}"))
                .collect(),
            m_per_n: length_m / vehicle.weight_n(),
            shaft_diameter_m: ARROW_SHAFT_DIAMETER_BODY * length_m,
            head_diameter_m: ARROW_HEAD_DIAMETER_BODY * length_m,
        }
    }

    /// The arrows of sample `s`, written over `msg` (which keeps its allocations).
    pub fn build(&self, s: &Sample, msg: &mut SceneUpdate) {
        msg.deletions.clear();
        msg.entities
            .resize_with(self.ids.len(), SceneEntity::default);
        for (i, e) in msg.entities.iter_mut().enumerate() {
            let f = s.forces[i]
                .total
                .and_then(|t| t.force_n)
                .unwrap_or_default();
            e.timestamp = Some(timestamp(s.t_ns));
            set(&mut e.frame_id, FRAME_BODY);
            set(&mut e.id, &self.ids[i]);
            e.frame_locked = true;
            e.arrows.resize_with(1, ArrowPrimitive::default);
            let a = &mut e.arrows[0];
            let (orientation, length_m) = arrow_along(&f, self.m_per_n);
            let h = &self.hinge_m[i];
            a.pose = Some(Pose {
                position: Some(foxglove::messages::Vector3 {
                    x: h.x,
                    y: h.y,
                    z: h.z,
                }),
                orientation: Some(orientation),
            });
            a.shaft_length = (1.0 - ARROW_HEAD_FRACTION) * length_m;
            a.head_length = ARROW_HEAD_FRACTION * length_m;
            a.shaft_diameter = self.shaft_diameter_m;
            a.head_diameter = self.head_diameter_m;
            let [r, g, b, alpha] = ARROW_COLOURS[i % 2];
            a.color = Some(Color { r, g, b, a: alpha });
        }
    }
}

/// The orientation that turns an arrow's +x axis along `f`, and the arrow's length
/// (`|f| * m_per_n`). A zero or non-finite force gives a zero-length arrow.
fn arrow_along(f: &proto::Vector3, m_per_n: f64) -> (Quaternion, f64) {
    let identity = Quaternion {
        x: 0.0,
        y: 0.0,
        z: 0.0,
        w: 1.0,
    };
    let norm = (f.x * f.x + f.y * f.y + f.z * f.z).sqrt();
    if !(norm.is_finite() && norm > 0.0) {
        return (identity, 0.0);
    }
    let d = [f.x / norm, f.y / norm, f.z / norm];
    // The shortest rotation from x to d: axis x cross d = (0, -d_z, d_y), angle acos(d_x).
    let w = 1.0 + d[0];
    let q = if w < 1e-12 {
        // d = -x: half a turn about z.
        Quaternion {
            x: 0.0,
            y: 0.0,
            z: 1.0,
            w: 0.0,
        }
    } else {
        let n = (2.0 * w).sqrt();
        Quaternion {
            x: 0.0,
            y: -d[2] / n,
            z: d[1] / n,
            w: w / n,
        }
    };
    (q, norm * m_per_n)
}

fn set(s: &mut String, v: &str) {
    if s != v {
        s.clear();
        s.push_str(v);
    }
}

/// Vertices and triangles of a wing planform in its wing frame (x chordwise towards the
/// leading edge, y spanwise from the hinge).
pub(crate) fn planform_mesh(g: &wingforce::Geometry) -> (Vec<[f32; 3]>, Vec<[u32; 3]>) {
    let n = g.strips.len().max(1);
    let dr = g.span_m / n as f64;
    let mut rows: Vec<(f64, f64, f64)> = Vec::with_capacity(n + 2); // (r, le, te)
    for s in &g.strips {
        let c = if dr > 0.0 { s.area_m2 / dr } else { 0.0 };
        let le = s.x_cp_m + 0.25 * c;
        rows.push((s.r_m, le, le - c));
    }
    if let (Some(&first), Some(&last)) = (rows.first(), rows.last()) {
        rows.insert(0, (g.r_root_m, first.1, first.2));
        rows.push((g.r_tip_m, last.1, last.2));
    }
    let mut verts = Vec::with_capacity(2 * rows.len());
    for (r, le, te) in &rows {
        verts.push([*le as f32, *r as f32, 0.0]);
        verts.push([*te as f32, *r as f32, 0.0]);
    }
    let mut tris = Vec::new();
    for i in 0..rows.len().saturating_sub(1) as u32 {
        let (a, b, c, d) = (2 * i, 2 * i + 1, 2 * i + 2, 2 * i + 3);
        tris.push([a, b, c]);
        tris.push([b, d, c]);
    }
    (verts, tris)
}

/// The wing planforms as a `foxglove.SceneUpdate` (the `/scene/wings` channel, logged with
/// the first sample): one entity per wing in its wing frame, locked to the frame so the
/// planform flaps with `/tf/wing_*`, drawn as a triangle list.
pub(crate) fn wing_scene(vehicle: &flapsim::Vehicle, t_ns: u64) -> foxglove::messages::SceneUpdate {
    use foxglove::messages::{Point3, TriangleListPrimitive};
    let layout = WingLayout::new(vehicle.wings.len());
    let entities = vehicle
        .wings
        .iter()
        .enumerate()
        .map(|(i, wing)| {
            let frame = layout.frame(i);
            let (verts, tris) = planform_mesh(wing.geometry());
            let points = tris
                .iter()
                .flatten()
                .map(|&k| {
                    let v = verts[k as usize];
                    Point3 {
                        x: f64::from(v[0]),
                        y: f64::from(v[1]),
                        z: f64::from(v[2]),
                    }
                })
                .collect();
            SceneEntity {
                timestamp: Some(timestamp(t_ns)),
                frame_id: frame.clone(),
                id: format!("planform_{frame}"),
                frame_locked: true,
                triangles: vec![TriangleListPrimitive {
                    pose: Some(foxglove::messages::Pose {
                        position: Some(foxglove::messages::Vector3::default()),
                        orientation: Some(foxglove::messages::Quaternion {
                            w: 1.0,
                            ..Default::default()
                        }),
                    }),
                    points,
                    color: Some(Color {
                        r: 0.55,
                        g: 0.75,
                        b: 0.95,
                        a: 0.7,
                    }),
                    ..Default::default()
                }],
                ..Default::default()
            }
        })
        .collect();
    SceneUpdate {
        deletions: Vec::new(),
        entities,
    }
}
