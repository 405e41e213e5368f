//! MUMPS 5.5 as Debian ships it (the sequential `libdmumps_seq` that Debian's Ipopt 3.11.9
//! factorises with) as a reference for spine-kkt: the same matrices factorised by both, for the
//! inertia tests and the factorisation benchmark (`benchmarks/benches/kkt.rs`).
//!
//! [`Mumps`] analyses a symmetric matrix given by one triangle, factorises its values as often as
//! asked (`JOB = 2`, with the controls Ipopt sets by default: ICNTL(6) = 7, ICNTL(7) = 7,
//! ICNTL(8) = 77, ICNTL(13) = 1, ICNTL(14) = 1000, pivot tolerance 1e-6) and reports the number of
//! negative pivots (`INFOG(12)`), which with ICNTL(13) = 1 is the number of negative eigenvalues.
//! All `unsafe` code is in the `ffi` module.
//!
//! ```
//! use spine_mumps::Mumps;
//!
//! // [[2, 1], [1, 0]] by its upper triangle in 0-based coordinates: one negative eigenvalue.
//! let mut mumps = Mumps::analyse(2, &[(0, 0), (0, 1)], &[2.0, 1.0]).unwrap();
//! assert_eq!(mumps.factorize(&[2.0, 1.0]).unwrap(), 1);
//! let mut b = vec![3.0, 1.0];
//! mumps.solve(&mut b).unwrap();
//! assert!((b[0] - 1.0).abs() < 1e-14 && (b[1] - 1.0).abs() < 1e-14);
//! ```
#![deny(unsafe_code)]

#[allow(unsafe_code)]
mod ffi;

use std::ptr::NonNull;

/// What MUMPS reported, or why it was not called.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum MumpsError {
    /// The arrays handed in do not describe a matrix.
    #[error("invalid input: {0}")]
    Input(String),
    /// MUMPS returned a negative `INFOG(1)` in this phase.
    #[error("MUMPS failed in the {phase} with INFOG(1) = {info}")]
    Failed { phase: &'static str, info: i32 },
}

/// An analysed matrix and its latest factorisation. The coordinate and value arrays MUMPS points
/// to are owned here.
pub struct Mumps {
    handle: NonNull<ffi::Handle>,
    n: usize,
    _irn: Vec<i32>,
    _jcn: Vec<i32>,
    values: Vec<f64>,
}

impl Mumps {
    /// Analyses the symmetric matrix of order `n` with these entries of one triangle (0-based
    /// `(row, column)`) and values.
    pub fn analyse(n: usize, entries: &[(usize, usize)], values: &[f64]) -> Result<Self, MumpsError> {
        if entries.len() != values.len() {
            return Err(MumpsError::Input(format!("{} entries but {} values", entries.len(), values.len())));
        }
        let order = i32::try_from(n).map_err(|_| MumpsError::Input(format!("order {n} too large")))?;
        let one_based = |i: usize| -> Result<i32, MumpsError> {
            if i < n {
                Ok(i as i32 + 1)
            } else {
                Err(MumpsError::Input(format!("index {i} outside the order {n}")))
            }
        };
        let mut irn = entries.iter().map(|&(r, _)| one_based(r)).collect::<Result<Vec<_>, _>>()?;
        let mut jcn = entries.iter().map(|&(_, c)| one_based(c)).collect::<Result<Vec<_>, _>>()?;
        let mut values = values.to_vec();
        let handle = ffi::analyse(order, &mut irn, &mut jcn, &mut values)
            .map_err(|info| MumpsError::Failed { phase: "analysis", info })?;
        Ok(Self { handle, n, _irn: irn, _jcn: jcn, values })
    }

    /// Factorises the matrix with these values (in the order of the entries given to
    /// [`Mumps::analyse`]); returns the number of negative eigenvalues.
    pub fn factorize(&mut self, values: &[f64]) -> Result<usize, MumpsError> {
        if values.len() != self.values.len() {
            return Err(MumpsError::Input(format!("{} values for {} entries", values.len(), self.values.len())));
        }
        self.values.copy_from_slice(values);
        let info = ffi::factor(self.handle);
        if info < 0 {
            return Err(MumpsError::Failed { phase: "factorisation", info });
        }
        Ok(ffi::negative(self.handle).max(0) as usize)
    }

    /// Overwrites `b` with the solution of the last factorised system.
    pub fn solve(&mut self, b: &mut [f64]) -> Result<(), MumpsError> {
        if b.len() != self.n {
            return Err(MumpsError::Input(format!("right-hand side of length {} for order {}", b.len(), self.n)));
        }
        match ffi::solve(self.handle, b) {
            info if info < 0 => Err(MumpsError::Failed { phase: "solve", info }),
            _ => Ok(()),
        }
    }
}

impl Drop for Mumps {
    fn drop(&mut self) {
        ffi::free(self.handle);
    }
}
