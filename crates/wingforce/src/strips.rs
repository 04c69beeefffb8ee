//! The translational term's strip sums: Lee et al. (2016) on one wing or on two side by side
//! in SIMD lanes (bit for bit the same), and Dickinson et al. (1999). Per strip, the relative
//! velocity of the pitch axis at radius r is linear in r (`StripVelocity`), and each strip's
//! lift and drag are summed with their first moments (`StripSums`); [`crate::wing::Wing`]
//! turns the sums into the term's force and moment.

use wide::f64x2;

use crate::cache::{Cache, StripK};
use crate::coefficients::{self, TranslationalModel};
use crate::kinematics::TwistAt;

/// Components of the pitch-axis velocity at radius r: u_le = a_le + r b_le, u_n = a_n + r b_n.
#[derive(Debug, Clone, Copy)]
pub(crate) struct StripVelocity {
    pub(crate) a_le: f64,
    pub(crate) b_le: f64,
    pub(crate) a_n: f64,
    pub(crate) b_n: f64,
}

/// Sums over the strips of the (e_le, n) force components and their first moments.
#[derive(Debug, Clone, Copy, Default)]
pub(crate) struct StripSums {
    pub(crate) f_le: f64,
    pub(crate) f_n: f64,
    pub(crate) rf_le: f64,
    pub(crate) rf_n: f64,
    pub(crate) xf_n: f64,
}

/// One strip's Lee et al. force in its chord's (e_le, n) components, from its velocity
/// components there.
#[inline(always)]
fn lee2016_strip(c: &Cache, u_le: f64, u_n: f64, half_rho_area: f64) -> (f64, f64) {
    let v2 = (u_le * u_le + u_n * u_n).max(f64::MIN_POSITIVE);
    let inv = 1.0 / v2.sqrt();
    let lift = c.kl2 * u_n * u_le * inv;
    let drag = (c.cd0 + c.kd2 * u_n * u_n * inv * inv) * (v2 * inv);
    (
        half_rho_area * (lift * u_n - drag * u_le),
        half_rho_area * (-(lift * u_le) - drag * u_n),
    )
}

/// Lee et al. translational strip sums of one wing: the arithmetic of [`lee2016_lanes`] on
/// plain numbers (the same operations in the same order, so the same bits), written out over
/// pairs of strips, which the compiler schedules better than the generic form.
#[inline(always)]
pub(crate) fn lee2016_sums(c: &Cache, u: &StripVelocity) -> StripSums {
    let strip = |s: &StripK| {
        let u_le = u.a_le + s.r_m * u.b_le;
        let u_n = u.a_n + s.r_m * u.b_n;
        lee2016_strip(c, u_le, u_n, s.half_rho_area)
    };
    let mut acc = [[0.0f64; 5]; 2];
    let mut add = |k: usize, s: &StripK| {
        let (fl, fn_) = strip(s);
        let a = &mut acc[k];
        a[0] += fl;
        a[1] += fn_;
        a[2] += s.r_m * fl;
        a[3] += s.r_m * fn_;
        a[4] += s.x_cp_m * fn_;
    };
    let pairs = c.strips.chunks_exact(2);
    let rest = pairs.remainder();
    for pair in pairs {
        add(0, &pair[0]);
        add(1, &pair[1]);
    }
    for s in rest {
        add(0, s);
    }
    StripSums {
        f_le: acc[0][0] + acc[1][0],
        f_n: acc[0][1] + acc[1][1],
        rf_le: acc[0][2] + acc[1][2],
        rf_n: acc[0][3] + acc[1][3],
        xf_n: acc[0][4] + acc[1][4],
    }
}

/// Lee et al. translational strip sums of two wings with the same number of strips, side by
/// side in the two lanes of a SIMD register (each lane's arithmetic is that of
/// [`lee2016_sums`], so the results are identical bit for bit).
pub(crate) fn lee2016_sums_pair(c: [&Cache; 2], u: [&StripVelocity; 2]) -> [StripSums; 2] {
    lee2016_lanes::<f64x2, 2>(c, u)
}

/// Arithmetic on one value or on two side by side.
trait Lanes:
    Copy
    + std::ops::Add<Output = Self>
    + std::ops::Sub<Output = Self>
    + std::ops::Mul<Output = Self>
    + std::ops::Div<Output = Self>
    + std::ops::Neg<Output = Self>
{
    /// The lanes from a function of the lane index.
    fn gather(f: impl Fn(usize) -> f64) -> Self;
    /// The same value in every lane.
    fn splat(x: f64) -> Self;
    /// Lane `l`.
    fn lane(self, l: usize) -> f64;
    /// Square root, lane by lane.
    fn sqrt(self) -> Self;
    /// The larger of the two, lane by lane (`other` where `self` is NaN).
    fn max(self, other: Self) -> Self;
}

impl Lanes for f64 {
    #[inline(always)]
    fn gather(f: impl Fn(usize) -> f64) -> Self {
        f(0)
    }
    #[inline(always)]
    fn splat(x: f64) -> Self {
        x
    }
    #[inline(always)]
    fn lane(self, _: usize) -> f64 {
        self
    }
    #[inline(always)]
    fn sqrt(self) -> Self {
        f64::sqrt(self)
    }
    #[inline(always)]
    fn max(self, other: Self) -> Self {
        f64::max(self, other)
    }
}

impl Lanes for f64x2 {
    #[inline(always)]
    fn gather(f: impl Fn(usize) -> f64) -> Self {
        f64x2::new([f(0), f(1)])
    }
    #[inline(always)]
    fn splat(x: f64) -> Self {
        f64x2::splat(x)
    }
    #[inline(always)]
    fn lane(self, l: usize) -> f64 {
        self.to_array()[l]
    }
    #[inline(always)]
    fn sqrt(self) -> Self {
        f64x2::sqrt(self)
    }
    #[inline(always)]
    fn max(self, other: Self) -> Self {
        f64x2::max(self, other)
    }
}

/// What every strip of the Lee et al. sums needs, wing `l` in lane `l` of `T`: the force
/// coefficients and the velocity's linear coefficients along the span.
struct LeeLanes<T> {
    kl2: T,
    cd0: T,
    kd2: T,
    a_le: T,
    b_le: T,
    a_n: T,
    b_n: T,
}

impl<T: Lanes> LeeLanes<T> {
    #[inline(always)]
    fn new<const L: usize>(c: [&Cache; L], u: [&StripVelocity; L]) -> Self {
        Self {
            kl2: T::gather(|l| c[l].kl2),
            cd0: T::gather(|l| c[l].cd0),
            kd2: T::gather(|l| c[l].kd2),
            a_le: T::gather(|l| u[l].a_le),
            b_le: T::gather(|l| u[l].b_le),
            a_n: T::gather(|l| u[l].a_n),
            b_n: T::gather(|l| u[l].b_n),
        }
    }

    /// The velocity components (u_le, u_n) at radius `r`.
    #[inline(always)]
    fn velocity(&self, r: T) -> (T, T) {
        (self.a_le + r * self.b_le, self.a_n + r * self.b_n)
    }

    /// A strip's force (f_le, f_n) from its velocity components in its chord's axes:
    /// [`lee2016_strip`]'s operations, lane by lane.
    #[inline(always)]
    fn force(&self, u_le: T, u_n: T, hra: T) -> (T, T) {
        let v2 = (u_le * u_le + u_n * u_n).max(T::splat(f64::MIN_POSITIVE));
        let inv = T::splat(1.0) / v2.sqrt();
        let lift = self.kl2 * u_n * u_le * inv;
        let drag = (self.cd0 + self.kd2 * u_n * u_n * inv * inv) * (v2 * inv);
        (
            hra * (lift * u_n - drag * u_le),
            hra * (-(lift * u_le) - drag * u_n),
        )
    }
}

/// The Lee et al. strip sums, wing `l` in lane `l` of `T` (which has `L` lanes; every wing
/// has the same number of strips). In the (e_le, n) plane with u = (u_le, u_n),
/// |V|^2 sin(2 alpha) along the lift direction is 2 u_le u_n (u_n, -u_le)/|V| and
/// sin^2(alpha) is u_n^2/|V|^2, so no trigonometry is needed per strip. Branch-free: a strip
/// at rest has u = 0 and gets zero force from the same expressions. Even and odd strips
/// accumulate separately (two independent chains keep the FP pipelines busy) and are added
/// at the end.
#[inline(always)]
fn lee2016_lanes<T: Lanes, const L: usize>(
    c: [&Cache; L],
    u: [&StripVelocity; L],
) -> [StripSums; L] {
    let n = c[0].strips.len();
    // Slices of one known length, so the indexing below needs no bounds checks.
    let strips: [&[StripK]; L] = std::array::from_fn(|l| &c[l].strips[..n]);
    let lee = LeeLanes::<T>::new(c, u);
    let strip = |i: usize| -> [T; 5] {
        let r = T::gather(|l| strips[l][i].r_m);
        let hra = T::gather(|l| strips[l][i].half_rho_area);
        let x_cp = T::gather(|l| strips[l][i].x_cp_m);
        let (u_le, u_n) = lee.velocity(r);
        let (fl, fn_) = lee.force(u_le, u_n, hra);
        [fl, fn_, r * fl, r * fn_, x_cp * fn_]
    };
    let zero = T::splat(0.0);
    let (mut even, mut odd) = ([zero; 5], [zero; 5]);
    let add = |acc: &mut [T; 5], d: [T; 5]| {
        for (a, d) in acc.iter_mut().zip(d) {
            *a = *a + d;
        }
    };
    let mut i = 0;
    while i + 1 < n {
        add(&mut even, strip(i));
        add(&mut odd, strip(i + 1));
        i += 2;
    }
    if i < n {
        add(&mut even, strip(i));
    }
    let s: [T; 5] = std::array::from_fn(|k| even[k] + odd[k]);
    std::array::from_fn(|l| StripSums {
        f_le: s[0].lane(l),
        f_n: s[1].lane(l),
        rf_le: s[2].lane(l),
        rf_n: s[3].lane(l),
        xf_n: s[4].lane(l),
    })
}

/// The translational strip sums of a twisted wing (`crate::kinematics` `twist`): each strip
/// at its own feathering offset d from the reference chord (r over `r_tip_m` into `twist`).
/// Its chord is the reference's turned by d about the span towards n (e_le' = cos d e_le +
/// sin d n, n' = -sin d e_le + cos d n), so its velocity components are turned into those
/// axes, its lift and drag computed there by `model`, and the force turned back. The normal
/// force's moment about the pitch axis keeps its form: e_le' x n' = e_le x n. The Lee et al.
/// model takes [`twisted_lanes`] on one lane (the pair's arithmetic, so a pair evaluates bit
/// for bit as each wing alone).
pub(crate) fn twisted_sums(
    c: &Cache,
    u: &StripVelocity,
    model: TranslationalModel,
    r_tip_m: f64,
    twist: &TwistAt,
) -> StripSums {
    if model == TranslationalModel::Lee2016 {
        let [s] = twisted_lanes::<f64, 1>([c], [u], [r_tip_m], [twist]);
        return s;
    }
    let mut s = StripSums::default();
    for k in &c.strips {
        let u_le = u.a_le + k.r_m * u.b_le;
        let u_n = u.a_n + k.r_m * u.b_n;
        let (sd, cd) = twist.offset_rad(k.r_m / r_tip_m).sin_cos();
        let (ul, un) = (cd * u_le + sd * u_n, -sd * u_le + cd * u_n);
        let v2 = ul * ul + un * un;
        if v2 <= 0.0 {
            continue;
        }
        let (fl, fn_) = strip_lift_drag_dickinson(ul, un, v2, k.half_rho_area);
        let (f_le, f_n) = (cd * fl - sd * fn_, sd * fl + cd * fn_);
        s.f_le += f_le;
        s.f_n += f_n;
        s.rf_le += k.r_m * f_le;
        s.rf_n += k.r_m * f_n;
        s.xf_n += k.x_cp_m * fn_;
    }
    s
}

/// Lee et al. translational strip sums of two twisted wings with the same number of strips,
/// side by side in the two lanes of a SIMD register; each lane's arithmetic is that of
/// [`twisted_sums`], so the results are identical bit for bit. A strip whose wings share its
/// feathering offset (a mirrored pair: the same twist at the same radius) takes its sine and
/// cosine once.
pub(crate) fn twisted_sums_pair(
    c: [&Cache; 2],
    u: [&StripVelocity; 2],
    r_tip_m: [f64; 2],
    twist: [&TwistAt; 2],
) -> [StripSums; 2] {
    twisted_lanes::<f64x2, 2>(c, u, r_tip_m, twist)
}

/// [`twisted_sums`]' Lee et al. strips, wing `l` in lane `l` of `T`: one accumulation chain
/// per sum, in strip order, the strip's force from [`lee2016_strip`]'s operations.
#[inline(always)]
fn twisted_lanes<T: Lanes, const L: usize>(
    c: [&Cache; L],
    u: [&StripVelocity; L],
    r_tip_m: [f64; L],
    twist: [&TwistAt; L],
) -> [StripSums; L] {
    let n = c[0].strips.len();
    let strips: [&[StripK]; L] = std::array::from_fn(|l| &c[l].strips[..n]);
    let lee = LeeLanes::<T>::new(c, u);
    let zero = T::splat(0.0);
    let mut acc = [zero; 5];
    for i in 0..n {
        // Each lane's (sin d, cos d), taken once where the lanes' offsets are the same.
        let mut sc = [(0.0, 0.0); L];
        for l in 0..L {
            let shared = (0..l).find(|&m| {
                twist[m] == twist[l]
                    && strips[m][i].r_m == strips[l][i].r_m
                    && r_tip_m[m] == r_tip_m[l]
            });
            sc[l] = match shared {
                Some(m) => sc[m],
                None => twist[l].offset_rad(strips[l][i].r_m / r_tip_m[l]).sin_cos(),
            };
        }
        let (sd, cd) = (T::gather(|l| sc[l].0), T::gather(|l| sc[l].1));
        let r = T::gather(|l| strips[l][i].r_m);
        let hra = T::gather(|l| strips[l][i].half_rho_area);
        let x_cp = T::gather(|l| strips[l][i].x_cp_m);
        let (u_le, u_n) = lee.velocity(r);
        let (ul, un) = (cd * u_le + sd * u_n, -sd * u_le + cd * u_n);
        let (fl, fn_) = lee.force(ul, un, hra);
        let (f_le, f_n) = (cd * fl - sd * fn_, sd * fl + cd * fn_);
        acc[0] = acc[0] + f_le;
        acc[1] = acc[1] + f_n;
        acc[2] = acc[2] + r * f_le;
        acc[3] = acc[3] + r * f_n;
        acc[4] = acc[4] + x_cp * fn_;
    }
    std::array::from_fn(|l| StripSums {
        f_le: acc[0].lane(l),
        f_n: acc[1].lane(l),
        rf_le: acc[2].lane(l),
        rf_n: acc[3].lane(l),
        xf_n: acc[4].lane(l),
    })
}

/// Dickinson et al. (1999) translational strip sums (angle of attack from the velocity).
pub(crate) fn dickinson1999_sums(strips: &[StripK], u: StripVelocity) -> StripSums {
    let mut s = StripSums::default();
    for k in strips {
        let u_le = u.a_le + k.r_m * u.b_le;
        let u_n = u.a_n + k.r_m * u.b_n;
        let v2 = u_le * u_le + u_n * u_n;
        if v2 <= 0.0 {
            continue;
        }
        let (fl, fn_) = strip_lift_drag_dickinson(u_le, u_n, v2, k.half_rho_area);
        s.f_le += fl;
        s.f_n += fn_;
        s.rf_le += k.r_m * fl;
        s.rf_n += k.r_m * fn_;
        s.xf_n += k.x_cp_m * fn_;
    }
    s
}

/// Dickinson et al. (1999) strip force in the (e_le, n) components, alpha from the velocity.
#[inline]
fn strip_lift_drag_dickinson(u_le: f64, u_n: f64, v2: f64, half_rho_area: f64) -> (f64, f64) {
    let vm = v2.sqrt();
    let alpha = u_n.abs().atan2(u_le); // 0..pi
    // Beyond 90 deg the flow meets the trailing edge first: the plate looks like one at
    // 180 - alpha with its lift reversed.
    let (cl, cd) = if alpha <= std::f64::consts::FRAC_PI_2 {
        coefficients::dickinson1999_deg(alpha.to_degrees())
    } else {
        let (cl, cd) = coefficients::dickinson1999_deg(180.0 - alpha.to_degrees());
        (-cl, cd)
    };
    let sgn = if u_n < 0.0 { -1.0 } else { 1.0 };
    // Lift direction sgn(u_n) (u_n e_le - u_le n)/|V|; drag along -(u_le e_le + u_n n)/|V|.
    let q = half_rho_area * v2;
    let fl = q * (cl * sgn * u_n - cd * u_le) / vm;
    let fn_ = q * (-cl * sgn * u_le - cd * u_n) / vm;
    (fl, fn_)
}

#[cfg(test)]
mod lanes_tests {
    use super::*;

    #[test]
    fn one_lane_generic_equals_the_written_out_loop() {
        // The generic lane code on plain numbers and the written-out single-wing loop must
        // agree bit for bit (the pair path relies on it), for odd and even strip counts.
        for n in [1usize, 2, 7, 20] {
            let wing = crate::model::WingModelSpec::from_toml(
                &include_str!("../../../models/robofly.toml")
                    .replace("strips = 20", &format!("strips = {n}")),
                "robofly",
            )
            .and_then(|s| s.build("robofly"))
            .expect("robofly model");
            let u = StripVelocity {
                a_le: 0.031,
                b_le: -0.7,
                a_n: 0.002,
                b_n: 0.35,
            };
            let a = lee2016_sums(&wing.cache, &u);
            let [b] = lee2016_lanes::<f64, 1>([&wing.cache], [&u]);
            assert_eq!(
                [a.f_le, a.f_n, a.rf_le, a.rf_n, a.xf_n],
                [b.f_le, b.f_n, b.rf_le, b.rf_n, b.xf_n],
                "{n} strips"
            );
        }
    }
}
