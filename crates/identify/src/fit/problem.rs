//! The solver's view of the fit: scaled parameters, residuals and the central-difference Jacobian for `levenberg-marquardt`.

use std::cell::{Cell, RefCell};

use levenberg_marquardt::LeastSquaresProblem;
use nalgebra::DMatrix;
use nalgebra_lm::{Dyn, Owned};
use rayon::prelude::*;

use super::segments::{STATE_UNKNOWNS, Setup, WingStart};
use super::types::Progress;

pub(super) type LmVector = nalgebra_lm::DVector<f64>;
pub(super) type LmMatrix = nalgebra_lm::DMatrix<f64>;

/// The solver's view of the fit.
pub(super) struct Problem<'s, 'a, 'o> {
    pub(super) setup: &'s Setup<'a>,
    /// All parameters, scaled (those not free stay at their start).
    pub(super) x: Vec<f64>,
    /// The parameters the solver varies (indices into `x`).
    pub(super) free: Vec<usize>,
    pub(super) r: RefCell<Option<Vec<f64>>>,
    pub(super) h: f64,
    pub(super) simulations: Cell<u64>,
    pub(super) iterations: Cell<u64>,
    pub(super) max_simulations: u64,
    pub(super) observer: RefCell<&'o mut dyn FnMut(&Progress) -> bool>,
    pub(super) stopped: Cell<bool>,
}

impl Problem<'_, '_, '_> {
    pub(super) fn tell(&self, n: u64, cost: Option<f64>) {
        self.simulations.set(self.simulations.get() + n);
        let p = Progress {
            simulations: self.simulations.get(),
            max_simulations: self.max_simulations,
            cost,
        };
        if !(self.observer.borrow_mut())(&p) {
            self.stopped.set(true);
        }
    }

    /// The Jacobian of the residuals in the unknowns `which` at `x` (indices into `x`:
    /// parameters first, then the start-state corrections).
    pub(super) fn jacobian_at(&self, x: &[f64], which: &[usize]) -> DMatrix<f64> {
        let m = self.setup.m;
        let n_params = self.setup.params.len();
        let (setup, h) = (self.setup, self.h);
        let (r0, _, wings) = setup.residuals_and_wings(x);
        let (params, states): (Vec<(usize, usize)>, Vec<(usize, usize)>) = which
            .iter()
            .copied()
            .enumerate()
            .partition(|&(_, i)| i < n_params);
        // Central differences; one-sided where a side makes the model invalid (a parameter
        // at a bound of the model's validation, e.g. an inertia at the triangle inequality).
        let cols: Vec<(usize, Vec<f64>)> = params
            .into_par_iter()
            .map(|(c, i)| {
                let mut xp = x.to_vec();
                let mut xm = x.to_vec();
                xp[i] += h;
                xm[i] -= h;
                let (rp, dp) = setup.residuals(&xp);
                let (rm, dm) = setup.residuals(&xm);
                let (a, b, d) = match (dp == usize::MAX, dm == usize::MAX) {
                    (false, false) => (&rp, &rm, 2.0 * h),
                    (true, false) => (&r0, &rm, h),
                    (false, true) => (&rp, &r0, h),
                    (true, true) => (&r0, &r0, h),
                };
                (c, a.iter().zip(b).map(|(a, b)| (a - b) / d).collect())
            })
            .collect();
        let mut j = DMatrix::zeros(m, which.len());
        for (c, col) in &cols {
            for (k, v) in col.iter().enumerate() {
                j[(k, *c)] = *v;
            }
        }
        // A start-state correction moves only its own segment's residuals: central
        // differences of that segment alone, on the model at `x` (built once).
        if !states.is_empty()
            && let Some(trial) = setup.trial(x)
        {
            let state_cols: Vec<(usize, usize, Vec<f64>)> = states
                .into_par_iter()
                .map(|(c, i)| {
                    let k = (i - n_params) / STATE_UNKNOWNS;
                    let mut xp = x.to_vec();
                    let mut xm = x.to_vec();
                    xp[i] += h;
                    xm[i] -= h;
                    // An actuated vehicle's wings start as they did at `x` (a start-state
                    // correction's effect on the next segment's wings is left out).
                    let w = wings.get(k).unwrap_or(&WingStart::Own);
                    let (rp, _) = setup.segment_residuals(&trial, k, &setup.start_state(k, &xp), w);
                    let (rm, _) = setup.segment_residuals(&trial, k, &setup.start_state(k, &xm), w);
                    let col = rp
                        .iter()
                        .zip(&rm)
                        .map(|(a, b)| (a - b) / (2.0 * h))
                        .collect();
                    (c, k, col)
                })
                .collect();
            for (c, k, col) in &state_cols {
                for (row, v) in setup.rows[*k].clone().zip(col) {
                    j[(row, *c)] = *v;
                }
            }
        }
        self.iterations.set(self.iterations.get() + 1);
        self.tell(self.jacobian_cost(which.len()), None);
        j
    }

    /// A Jacobian in `n` unknowns in full simulations of the flight (a start-state column
    /// flies one segment twice).
    pub(super) fn jacobian_cost(&self, n: usize) -> u64 {
        let n_params = n.min(self.setup.params.len()) as u64;
        let n_states = (n - n_params as usize) as u64;
        let segments = self.setup.segments.len().max(1) as u64;
        2 * n_params + 1 + (2 * n_states).div_ceil(segments)
    }
}

impl LeastSquaresProblem<f64, Dyn, Dyn> for Problem<'_, '_, '_> {
    type ResidualStorage = Owned<f64, Dyn>;
    type JacobianStorage = Owned<f64, Dyn, Dyn>;
    type ParameterStorage = Owned<f64, Dyn>;

    fn set_params(&mut self, x: &LmVector) {
        for (&i, v) in self.free.iter().zip(x.iter()) {
            self.x[i] = *v;
        }
        *self.r.borrow_mut() = None;
    }

    fn params(&self) -> LmVector {
        let v: Vec<f64> = self.free.iter().map(|&i| self.x[i]).collect();
        LmVector::from_column_slice(&v)
    }

    fn residuals(&self) -> Option<LmVector> {
        if self.stopped.get() {
            return None;
        }
        if self.r.borrow().is_none() {
            let (r, _) = self.setup.residuals(&self.x);
            let cost: f64 = r.iter().map(|v| v * v).sum();
            *self.r.borrow_mut() = Some(r);
            self.tell(1, Some(cost));
        }
        let r = self.r.borrow();
        r.as_ref().map(|r| LmVector::from_column_slice(r))
    }

    fn jacobian(&self) -> Option<LmMatrix> {
        if self.stopped.get() {
            return None;
        }
        let j = self.jacobian_at(&self.x, &self.free);
        Some(LmMatrix::from_column_slice(
            j.nrows(),
            j.ncols(),
            j.as_slice(),
        ))
    }
}
