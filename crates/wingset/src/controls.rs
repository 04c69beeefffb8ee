//! Control inputs: offsets on a vehicle's base kinematics (angles, frequency) or, for an
//! actuated vehicle, on its drive (volts), and the four channels of each kind that trim, the
//! averaged model and the hover LQR work on.

use serde::{Deserialize, Serialize};

/// Control inputs in SI units (radians, hertz); a [`crate::ControlMap`] maps them onto the
/// wings (flapsim's `ControlSpec` reads them from a model file).
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize, Deserialize)]
pub struct Controls {
    /// Mean stroke angle offset, rad.
    pub mean_stroke_rad: f64,
    /// Amplitude offset, rad.
    pub amplitude_rad: f64,
    /// Pitch bias offset, rad.
    pub pitch_bias_rad: f64,
    /// Mid-stroke angle-of-attack offset, both half strokes alike, rad (Sun & Xiong 2005's
    /// weight-support variable; measured tables have no mid-stroke angle to move).
    #[serde(default)]
    pub aoa_rad: f64,
    /// Frequency offset, Hz.
    pub freq_hz: f64,
    /// Left-minus-right amplitude, rad.
    pub diff_amplitude_rad: f64,
    /// Left-minus-right pitch bias, rad.
    pub diff_pitch_bias_rad: f64,
    /// Left-minus-right mean stroke angle, rad.
    pub diff_mean_stroke_rad: f64,
    /// Drive bias offset, V (actuated vehicles).
    #[serde(default)]
    pub bias_v: f64,
    /// Drive amplitude offset, V (actuated vehicles).
    #[serde(default)]
    pub amplitude_v: f64,
    /// Left-minus-right drive amplitude, V (actuated vehicles).
    #[serde(default)]
    pub diff_amplitude_v: f64,
    /// Left-minus-right drive bias, V (actuated vehicles).
    #[serde(default)]
    pub diff_bias_v: f64,
    /// Left-minus-right second-harmonic fraction (actuated vehicles).
    #[serde(default)]
    pub diff_second_harmonic: f64,
}

/// The four control channels of the averaged model, trim and the hover LQR, for a vehicle
/// with prescribed kinematics (angles) or an actuated one (drive voltages).
pub const KINEMATIC_CHANNELS: [&str; 4] = [
    "mean_stroke_rad",
    "amplitude_rad",
    "diff_amplitude_rad",
    "diff_pitch_bias_rad",
];
/// See [`KINEMATIC_CHANNELS`]: bias (pitch), amplitude (height), left-minus-right amplitude
/// (roll) and left-minus-right second harmonic (yaw), the RoboBee's control scheme (Ma et
/// al. 2013 steer pitch by the drive's bias, roll by the amplitude difference and yaw by
/// split-cycle asymmetry).
pub const DRIVE_CHANNELS: [&str; 4] = [
    "bias_v",
    "amplitude_v",
    "diff_amplitude_v",
    "diff_second_harmonic",
];

impl Controls {
    /// Adds offsets `u` on the four control channels of `channels` (see
    /// [`KINEMATIC_CHANNELS`] and [`DRIVE_CHANNELS`]) to these controls.
    pub fn with_channels(&self, drive: bool, u: &[f64]) -> Controls {
        let mut c = *self;
        if drive {
            c.bias_v += u[0];
            c.amplitude_v += u[1];
            c.diff_amplitude_v += u[2];
            c.diff_second_harmonic += u[3];
        } else {
            c.mean_stroke_rad += u[0];
            c.amplitude_rad += u[1];
            c.diff_amplitude_rad += u[2];
            c.diff_pitch_bias_rad += u[3];
        }
        c
    }

    /// The values of the four channels (inverse of [`Controls::with_channels`] on zero).
    pub fn channels(&self, drive: bool) -> [f64; 4] {
        if drive {
            [
                self.bias_v,
                self.amplitude_v,
                self.diff_amplitude_v,
                self.diff_second_harmonic,
            ]
        } else {
            [
                self.mean_stroke_rad,
                self.amplitude_rad,
                self.diff_amplitude_rad,
                self.diff_pitch_bias_rad,
            ]
        }
    }

    /// The kinematic angle offsets are all zero (the frequency offset applies to both kinds;
    /// a control mapping of actuated wings refuses the others).
    pub fn kinematic_is_zero(&self) -> bool {
        [
            self.mean_stroke_rad,
            self.amplitude_rad,
            self.pitch_bias_rad,
            self.aoa_rad,
            self.diff_amplitude_rad,
            self.diff_pitch_bias_rad,
            self.diff_mean_stroke_rad,
        ]
        .iter()
        .all(|x| *x == 0.0)
    }

    /// The drive offsets are all zero (a control mapping of prescribed kinematics refuses
    /// the others).
    pub fn drive_is_zero(&self) -> bool {
        self.channels(true) == [0.0; 4] && self.diff_bias_v == 0.0
    }
}
