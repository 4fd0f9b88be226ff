//! A 6 x 6 elastic tensor in Voigt's notation: strains `(e_xx, e_yy, e_zz,
//! 2 e_yz, 2 e_xz, 2 e_xy)`, energy per volume `eps . C eps / 2`.

use faer::{Mat, Side};
use serde::{Deserialize, Serialize};

/// A symmetric 6 x 6 tensor, rows and columns in the order of
/// [`crate::truth::Strain::ALL`] (xx, yy, zz, yz, xz, xy).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Voigt(pub [[f64; 6]; 6]);

impl Voigt {
    pub const ZERO: Voigt = Voigt([[0.0; 6]; 6]);

    /// From a Gram matrix of truth's strain columns (a shear column there
    /// is `E_ij = E_ji = 1`, twice Voigt's unit shear) times `scale`.
    pub fn of_strain_columns(gram: &[[f64; 6]; 6], scale: f64) -> Voigt {
        let d = |i: usize| if i < 3 { 1.0 } else { 0.5 };
        let mut c = [[0.0; 6]; 6];
        for (i, row) in c.iter_mut().enumerate() {
            for (j, x) in row.iter_mut().enumerate() {
                *x = scale * d(i) * d(j) * 0.5 * (gram[i][j] + gram[j][i]);
            }
        }
        Voigt(c)
    }

    /// Voigt's average shear modulus:
    /// `(C11 + C22 + C33 - C12 - C13 - C23 + 3 (C44 + C55 + C66)) / 15`.
    pub fn shear(&self) -> f64 {
        let c = &self.0;
        let diag = c[0][0] + c[1][1] + c[2][2];
        let off = c[0][1] + c[0][2] + c[1][2];
        let shears = c[3][3] + c[4][4] + c[5][5];
        (diag - off + 3.0 * shears) / 15.0
    }

    /// Voigt's average bulk modulus: `(C11 + C22 + C33 + 2 (C12 + C13 + C23)) / 9`.
    pub fn bulk(&self) -> f64 {
        let c = &self.0;
        (c[0][0] + c[1][1] + c[2][2] + 2.0 * (c[0][1] + c[0][2] + c[1][2])) / 9.0
    }

    /// Eigenvalues, largest first, with their unit eigenvectors.
    pub fn spectrum(&self) -> Vec<(f64, [f64; 6])> {
        let m = Mat::from_fn(6, 6, |i, j| self.0[i][j]);
        let evd = m
            .self_adjoint_eigen(Side::Lower)
            .expect("a 6 x 6 symmetric eigenproblem converges");
        let (s, u) = (evd.S(), evd.U());
        let mut out: Vec<(f64, [f64; 6])> = (0..6)
            .map(|k| (s[k], std::array::from_fn(|i| u[(i, k)])))
            .collect();
        out.sort_by(|a, b| b.0.total_cmp(&a.0));
        out
    }

    /// The tensor kept on its `rank` largest eigenvalues.
    pub fn truncated(&self, rank: usize) -> Voigt {
        let mut c = [[0.0; 6]; 6];
        for (l, v) in self.spectrum().into_iter().take(rank) {
            for (i, row) in c.iter_mut().enumerate() {
                for (j, x) in row.iter_mut().enumerate() {
                    *x += l * v[i] * v[j];
                }
            }
        }
        // Symmetric to the last bit.
        Voigt(std::array::from_fn(|i| {
            std::array::from_fn(|j| 0.5 * (c[i][j] + c[j][i]))
        }))
    }

    /// The largest absolute entry.
    pub fn largest(&self) -> f64 {
        self.0.iter().flatten().fold(0.0, |m, x| m.max(x.abs()))
    }

    /// `self - other`.
    pub fn minus(&self, other: &Voigt) -> Voigt {
        Voigt(std::array::from_fn(|i| {
            std::array::from_fn(|j| self.0[i][j] - other.0[i][j])
        }))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_isotropic_tensor_averages_to_its_own_moduli() {
        // Lamé lambda = 2, mu = 3: C11 = lambda + 2 mu, C12 = lambda, C44 = mu.
        let (lambda, mu) = (2.0, 3.0);
        let v = Voigt(std::array::from_fn(|i| {
            std::array::from_fn(|j| match (i < 3, j < 3) {
                (true, true) => lambda + if i == j { 2.0 * mu } else { 0.0 },
                _ if i == j => mu,
                _ => 0.0,
            })
        }));
        assert!((v.shear() - mu).abs() < 1e-12);
        assert!((v.bulk() - (lambda + 2.0 * mu / 3.0)).abs() < 1e-12);
        // Eigenvalues 3 K (once), 2 mu (twice), mu (three times).
        let s: Vec<f64> = v.spectrum().iter().map(|e| e.0).collect();
        let want = [3.0 * (lambda + 2.0 * mu / 3.0), 6.0, 6.0, 3.0, 3.0, 3.0];
        assert!(
            s.iter().zip(want).all(|(a, b)| (a - b).abs() < 1e-12),
            "{s:?}"
        );
        assert!(v.truncated(6).minus(&v).largest() < 1e-12);
        assert_eq!(v.truncated(0), Voigt::ZERO);
    }
}
