//! Matrix helpers the averaged model's modes and the Floquet analysis share: a matrix's rows,
//! an eigenvalue's complex eigenvector and its normalised form.

use nalgebra::{Complex, DMatrix, DVector};

pub(super) fn rows(a: &DMatrix<f64>) -> Vec<Vec<f64>> {
    (0..a.nrows())
        .map(|i| a.row(i).iter().copied().collect())
        .collect()
}

/// Complex eigenvector of `a` for eigenvalue `l`: the null vector of a - l I by SVD (the
/// right singular vector of the smallest singular value), unit 2-norm.
pub(super) fn complex_eigenvector(a: &DMatrix<f64>, l: Complex<f64>) -> DVector<Complex<f64>> {
    let n = a.nrows();
    let m = DMatrix::from_fn(n, n, |i, j| {
        Complex::new(a[(i, j)], 0.0) - if i == j { l } else { Complex::new(0.0, 0.0) }
    });
    let svd = m.svd(false, true);
    let Some(vt) = svd.v_t else {
        return DVector::zeros(n);
    };
    let k = svd
        .singular_values
        .iter()
        .enumerate()
        .fold(0, |best, (i, s)| {
            if *s < svd.singular_values[best] {
                i
            } else {
                best
            }
        });
    // The rows of V^H are the conjugated right singular vectors.
    DVector::from_iterator(n, vt.row(k).iter().map(|c| c.conj()))
}

/// `v` scaled to unit 2-norm with its largest entry real and positive, as (re, im) pairs.
pub(super) fn normalized(v: &DVector<Complex<f64>>) -> Vec<(f64, f64)> {
    let k = v.iter().enumerate().fold(
        0,
        |best, (i, c)| if c.norm() > v[best].norm() { i } else { best },
    );
    let (norm, big) = (v.norm(), v[k]);
    let phase = if big.norm() > 0.0 && norm > 0.0 {
        big.conj() / (big.norm() * norm)
    } else {
        Complex::new(1.0, 0.0)
    };
    v.iter()
        .enumerate()
        .map(|(i, c)| {
            let z = c * phase;
            // The largest entry exactly real (its rotation leaves round-off in Im).
            if i == k {
                (z.norm(), 0.0)
            } else {
                (z.re, z.im)
            }
        })
        .collect()
}
