//! The solver's view of the fit: scaled parameters, residuals and the central-difference Jacobian for `levenberg-marquardt`.

use std::cell::{Cell, RefCell};

use levenberg_marquardt::LeastSquaresProblem;
use nalgebra::DMatrix;
use nalgebra_lm::{Dyn, Owned};
use rayon::prelude::*;

use super::segments::Setup;
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

    /// The Jacobian of the residuals in the parameters `cols` at `x`.
    pub(super) fn jacobian_at(&self, x: &[f64], which: &[usize]) -> DMatrix<f64> {
        let n = which.len();
        let m = self.setup.m;
        let (setup, h) = (self.setup, self.h);
        let (r0, _) = setup.residuals(x);
        // Central differences; one-sided where a side makes the model invalid (a parameter
        // at a bound of the model's validation, e.g. an inertia at the triangle inequality).
        let cols: Vec<Vec<f64>> = (0..n)
            .into_par_iter()
            .map(|c| {
                let i = which[c];
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
                a.iter().zip(b).map(|(a, b)| (a - b) / d).collect()
            })
            .collect();
        let mut j = DMatrix::zeros(m, n);
        for (i, c) in cols.iter().enumerate() {
            for (k, v) in c.iter().enumerate() {
                j[(k, i)] = *v;
            }
        }
        self.iterations.set(self.iterations.get() + 1);
        self.tell(2 * n as u64 + 1, None);
        j
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
