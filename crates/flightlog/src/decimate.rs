//! Which steps a log keeps ([`Decimator`]): the sample grid of a log rate.

/// Picks the steps to log: with a rate `r`, step k (time t_k) is logged when
/// `floor(t_k r)` differs from that of the last logged step (the first step is always
/// logged), so samples are at most one step late on a grid of 1/r seconds. With no rate,
/// every step is logged. `flapwing replay --check` uses the same rule.
#[derive(Debug, Clone, PartialEq)]
pub struct Decimator {
    rate_hz: Option<f64>,
    last_bucket: Option<i64>,
}

impl Decimator {
    /// A decimator for `rate_hz` (`None`: every step).
    pub fn new(rate_hz: Option<f64>) -> Self {
        Self {
            rate_hz,
            last_bucket: None,
        }
    }

    /// True when the step at `t_s` is to be logged (call once per step, in order).
    pub fn take(&mut self, t_s: f64) -> bool {
        let Some(rate) = self.rate_hz else {
            return true;
        };
        let b = (t_s * rate).floor();
        let bucket = if b.is_finite() { b as i64 } else { i64::MIN };
        if self.last_bucket == Some(bucket) {
            false
        } else {
            self.last_bucket = Some(bucket);
            true
        }
    }
}
