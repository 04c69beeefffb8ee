//! The motion-capture CSV (format in the crate's README.md): a header line naming the
//! columns, then one row per motion-capture frame. Lines starting with `#` and blank lines
//! are skipped. Required: `t_s,x_m,y_m,z_m,qw,qx,qy,qz` and the vehicle's four control
//! channels (`mean_stroke_rad,amplitude_rad,diff_amplitude_rad,diff_pitch_bias_rad`);
//! optional: `gyro_x_rad_s,gyro_y_rad_s,gyro_z_rad_s` and `accel_x_m_s2,accel_y_m_s2,
//! accel_z_m_s2` (all three of a group, IMU samples taken at the row's time) and the other
//! kinematic controls `pitch_bias_rad,aoa_rad,diff_mean_stroke_rad` (0 when absent).
//! Times strictly increasing.

use std::path::Path;

use flapsim::{Controls, Vehicle};
use nalgebra::{Quaternion, UnitQuaternion, Vector3};

use crate::error::{Error, Result};
use crate::frames::{ImuFrame, MocapFrame};

/// The pose columns, in their order of meaning.
pub const POSE_COLUMNS: [&str; 8] = ["t_s", "x_m", "y_m", "z_m", "qw", "qx", "qy", "qz"];
/// Optional gyroscope columns.
pub const GYRO_COLUMNS: [&str; 3] = ["gyro_x_rad_s", "gyro_y_rad_s", "gyro_z_rad_s"];
/// Optional accelerometer columns.
pub const ACCEL_COLUMNS: [&str; 3] = ["accel_x_m_s2", "accel_y_m_s2", "accel_z_m_s2"];
/// Optional control columns besides the vehicle's four channels.
pub const EXTRA_CONTROL_COLUMNS: [&str; 3] = ["pitch_bias_rad", "aoa_rad", "diff_mean_stroke_rad"];

/// A parsed CSV.
#[derive(Debug, Clone)]
pub(crate) struct Csv {
    pub mocap: Vec<MocapFrame>,
    pub imu: Vec<ImuFrame>,
    /// (time, controls in force) of every row.
    pub controls: Vec<(f64, Controls)>,
}

fn allowed_columns(vehicle: &Vehicle) -> Vec<&'static str> {
    let mut v: Vec<&str> = POSE_COLUMNS.to_vec();
    v.extend(vehicle.control_channels());
    v.extend(EXTRA_CONTROL_COLUMNS);
    v.extend(GYRO_COLUMNS);
    v.extend(ACCEL_COLUMNS);
    v
}

/// Parses the text of `path`.
pub(crate) fn parse(path: &Path, text: &str, vehicle: &Vehicle) -> Result<Csv> {
    let err = |line: usize, detail: String| Error::Csv {
        path: path.to_owned(),
        line,
        detail,
    };
    let mut lines = text
        .lines()
        .enumerate()
        .map(|(i, l)| (i + 1, l.trim()))
        .filter(|(_, l)| !l.is_empty() && !l.starts_with('#'));
    let Some((header_line, header)) = lines.next() else {
        return Err(err(
            1,
            format!(
                "the file has no header line; allowed columns: {}",
                allowed_columns(vehicle).join(",")
            ),
        ));
    };
    let names: Vec<&str> = header.split(',').map(str::trim).collect();
    let allowed = allowed_columns(vehicle);
    for (i, n) in names.iter().enumerate() {
        if !allowed.contains(n) {
            return Err(err(
                header_line,
                format!(
                    "column {} `{n}` is not a known column; allowed: {}",
                    i + 1,
                    allowed.join(",")
                ),
            ));
        }
        if names[..i].contains(n) {
            return Err(err(header_line, format!("column `{n}` appears twice")));
        }
    }
    let find = |n: &str| names.iter().position(|x| *x == n);
    let mut required: Vec<&str> = POSE_COLUMNS.to_vec();
    required.extend(vehicle.control_channels());
    let missing: Vec<&str> = required
        .iter()
        .copied()
        .filter(|n| find(n).is_none())
        .collect();
    if !missing.is_empty() {
        return Err(err(
            header_line,
            format!(
                "missing column(s) {}; required: {} (the last four are the control channels of `{}`)",
                missing.join(","),
                required.join(","),
                vehicle.name
            ),
        ));
    }
    let group = |cols: &[&'static str]| -> Result<Option<[usize; 3]>> {
        let found: Vec<Option<usize>> = cols.iter().map(|c| find(c)).collect();
        match found.iter().filter(|f| f.is_some()).count() {
            0 => Ok(None),
            3 => Ok(Some([
                found[0].unwrap_or(0),
                found[1].unwrap_or(0),
                found[2].unwrap_or(0),
            ])),
            _ => Err(err(
                header_line,
                format!(
                    "the IMU columns come in threes: {} (all or none)",
                    cols.join(",")
                ),
            )),
        }
    };
    let gyro = group(&GYRO_COLUMNS)?;
    let accel = group(&ACCEL_COLUMNS)?;
    if gyro.is_some() != accel.is_some() {
        return Err(err(
            header_line,
            format!(
                "an IMU needs both the gyroscope and the accelerometer columns: {},{}",
                GYRO_COLUMNS.join(","),
                ACCEL_COLUMNS.join(",")
            ),
        ));
    }
    let pose: Vec<usize> = POSE_COLUMNS.iter().filter_map(|n| find(n)).collect();
    let channels: Vec<usize> = vehicle
        .control_channels()
        .iter()
        .filter_map(|n| find(n))
        .collect();
    let extra: Vec<Option<usize>> = EXTRA_CONTROL_COLUMNS.iter().map(|n| find(n)).collect();

    let mut out = Csv {
        mocap: Vec::new(),
        imu: Vec::new(),
        controls: Vec::new(),
    };
    let mut last_t: Option<(usize, f64)> = None;
    for (line, l) in lines {
        let cells: Vec<&str> = l.split(',').map(str::trim).collect();
        if cells.len() != names.len() {
            return Err(err(
                line,
                format!(
                    "{} fields where the header has {} columns",
                    cells.len(),
                    names.len()
                ),
            ));
        }
        let get = |i: usize| -> Result<f64> {
            cells[i]
                .parse::<f64>()
                .ok()
                .filter(|x| x.is_finite())
                .ok_or_else(|| {
                    err(
                        line,
                        format!(
                            "column `{}` = `{}` is not a finite number",
                            names[i], cells[i]
                        ),
                    )
                })
        };
        let t = get(pose[0])?;
        if t < 0.0 {
            return Err(err(
                line,
                format!("column `t_s` = {t}: allowed times >= 0 (t = 0 is a wingbeat start)"),
            ));
        }
        if let Some((prev_line, prev)) = last_t
            && t <= prev
        {
            return Err(err(
                line,
                format!(
                    "column `t_s` = {t} is not after {prev} on line {prev_line}: times must be strictly increasing (sort the rows by time)"
                ),
            ));
        }
        last_t = Some((line, t));
        let position_m = Vector3::new(get(pose[1])?, get(pose[2])?, get(pose[3])?);
        let q = Quaternion::new(get(pose[4])?, get(pose[5])?, get(pose[6])?, get(pose[7])?);
        if (q.norm() - 1.0).abs() > 1e-3 {
            return Err(err(
                line,
                format!(
                    "the quaternion qw,qx,qy,qz = {},{},{},{} has norm {}; allowed: a unit quaternion (norm 1 +- 1e-3), world_from_body, scalar first",
                    q.w,
                    q.i,
                    q.j,
                    q.k,
                    q.norm()
                ),
            ));
        }
        out.mocap.push(MocapFrame {
            t_s: t,
            position_m,
            attitude: UnitQuaternion::from_quaternion(q),
        });
        if let (Some(g), Some(a)) = (gyro, accel) {
            out.imu.push(ImuFrame {
                t_s: t,
                gyro_rad_s: Vector3::new(get(g[0])?, get(g[1])?, get(g[2])?),
                accel_m_s2: Vector3::new(get(a[0])?, get(a[1])?, get(a[2])?),
            });
        }
        let mut u = [0.0; 4];
        for (o, &i) in u.iter_mut().zip(&channels) {
            *o = get(i)?;
        }
        let mut c = vehicle.controls_with(&Controls::default(), &u);
        let ex = |k: usize| -> Result<f64> { extra[k].map_or(Ok(0.0), get) };
        c.pitch_bias_rad += ex(0)?;
        c.aoa_rad += ex(1)?;
        c.diff_mean_stroke_rad += ex(2)?;
        out.controls.push((t, c));
    }
    if out.mocap.is_empty() {
        return Err(err(
            header_line,
            "the file has a header but no data rows".into(),
        ));
    }
    Ok(out)
}

/// Writes flight data as the CSV [`parse`] reads (for tests and for exporting a synthetic
/// flight): one row per motion-capture frame, with the IMU sample nearest in time when
/// there is one and the controls in force at the frame's time.
pub fn write(
    frames: &[MocapFrame],
    imu: &[ImuFrame],
    controls_at: impl Fn(f64) -> Controls,
    vehicle: &Vehicle,
) -> String {
    use std::fmt::Write;
    let mut s = String::new();
    let ch = vehicle.control_channels();
    let with_imu = !imu.is_empty();
    let mut header: Vec<&str> = POSE_COLUMNS.to_vec();
    if with_imu {
        header.extend(GYRO_COLUMNS);
        header.extend(ACCEL_COLUMNS);
    }
    header.extend(ch);
    let _ = writeln!(s, "{}", header.join(","));
    for f in frames {
        let q = f.attitude.quaternion();
        let _ = write!(
            s,
            "{:e},{:e},{:e},{:e},{:e},{:e},{:e},{:e}",
            f.t_s, f.position_m.x, f.position_m.y, f.position_m.z, q.w, q.i, q.j, q.k
        );
        if with_imu {
            let i = imu.partition_point(|x| x.t_s < f.t_s).min(imu.len() - 1);
            let m = &imu[i];
            for v in [m.gyro_rad_s, m.accel_m_s2] {
                let _ = write!(s, ",{:e},{:e},{:e}", v.x, v.y, v.z);
            }
        }
        let c = controls_at(f.t_s);
        let u = if vehicle.drive_controlled() {
            [
                c.bias_v,
                c.amplitude_v,
                c.diff_amplitude_v,
                c.diff_second_harmonic,
            ]
        } else {
            [
                c.mean_stroke_rad,
                c.amplitude_rad,
                c.diff_amplitude_rad,
                c.diff_pitch_bias_rad,
            ]
        };
        let _ = writeln!(s, ",{:e},{:e},{:e},{:e}", u[0], u[1], u[2], u[3]);
    }
    s
}
