//! A sparse symmetric indefinite `LDLᵀ` factorisation with exact inertia, built for the KKT
//! matrices Ipopt factorises at every iteration of eq. (33), and served to Ipopt through Pardiso's
//! interface.
//!
//! * [`Structure`]: a symmetric matrix by one triangle in compressed rows.
//! * [`SymmetricSolver`]: the analysis (dense rows first, then reverse Cuthill–McKee, which finds
//!   the band of a chain), the factorisation (a frontal sweep with Bunch–Kaufman pivoting among
//!   the fully summed variables, delayed pivots, Ruiz scaling, no pivot perturbation, so the
//!   inertia is exact; from the second factorisation on, the pivots of the one before are replayed,
//!   each tested again) and solves with iterative refinement to round-off. From [`SPLIT_FROM`]
//!   variables on, the chain is cut in two halves swept at once on two threads toward a root front
//!   where they meet ([`SweepOptions`]; the factor is the same to the bit on one thread).
//! * [`install`]: makes this solver the `libpardiso.so` of the process, so that Debian's Ipopt
//!   3.11 (or a 3.14) uses it with `linear_solver pardiso`; `spine-ipopt` does this for its
//!   default linear solver `"spine"`.
//!
//! All `unsafe` code of the crate is in the `abi` module (the C entry points and the loading of the
//! shim); everything else is safe Rust.
//!
//! Further modules:
//!
//! * [`dump`]: The text form of a recorded KKT system (`SPINE_KKT_DUMP`, `SPINE_KKT_DUMP_BAD`): the
//!   order, then Pardiso's 1-based CSR arrays `ia`, `ja`, `a` of the upper triangle, then
//!   optionally a right-hand side, one bracketed list per line.
//! * [`ordering`]: The elimination order of the frontal factorisation: the few dense rows first
//!   (they stay in the front from start to end), then the rest by reverse Cuthill–McKee, which
//!   finds the band of a chain-like graph so that the front stays as narrow as the band.
//! * `analysis`: The symbolic phase: the elimination order and, for each step of the frontal sweep,
//!   which entries enter the front and which variables become fully summed (free to be pivots).
//! * `factor`: The numerical factorisation `P S A S Pᵀ = L D Lᵀ` (Pardiso's phase 22), and solves
//!   with it.
//! * `front`: The front of the sweep: a small dense symmetric matrix over the variables that have
//!   entered and are not yet eliminated, stored by its lower triangle (slot `i` keeps `a_ij` for `j
//!   ≤ i`) with a row stride that grows on demand.
//! * `pardiso`: Pardiso's calling convention (the interface Ipopt's `linear_solver pardiso` calls)
//!   over `SymmetricSolver`, in safe Rust: the C entry points of `crate::abi` turn their pointers
//!   into these slices and call `init` and `State::call`.
//! * `pivot`: The pivot test of the frontal sweep (`crate::factor`): Bunch–Kaufman among the fully
//!   summed variables, threshold and Duff–Reid tests where the partner is not summed yet, a test
//!   against the dense rows, and the thresholds that relax while a variable waits.
//! * `solver`: A factorised symmetric system with iterative refinement: what Ipopt's linear solver
//!   has to do.
//! * `sweep`: One frontal sweep (a stage of the analysis, or the root of a split) and the
//!   triangular solves with its pivots.
//! * `symmetric`: A symmetric sparse matrix stored by one triangle in compressed rows: the form in
//!   which Ipopt hands its KKT matrix to Pardiso (the upper triangle, 1-based; here 0-based).
//!
//! ```
//! use spine_kkt::{Structure, SymmetricSolver};
//!
//! // The saddle-point matrix [[2, 1], [1, 0]] (upper triangle by rows): one positive and one
//! // negative eigenvalue.
//! let structure = Structure::new(2, vec![0, 2, 2], vec![0, 1]).unwrap();
//! let mut solver = SymmetricSolver::new(structure);
//! let inertia = solver.factorize(&[2.0, 1.0]).unwrap();
//! assert_eq!((inertia.positive, inertia.negative), (1, 1));
//! let mut b = vec![3.0, 1.0]; // A [1, 1] = [3, 1]
//! solver.solve(&mut b).unwrap();
//! assert!((b[0] - 1.0).abs() < 1e-15 && (b[1] - 1.0).abs() < 1e-15);
//! ```
#![deny(unsafe_code)]

#[allow(unsafe_code)]
mod abi;
mod analysis;
pub mod dump;
mod factor;
mod front;
mod install;
pub mod ordering;
pub mod pardiso;
mod pivot;
mod solver;
mod sweep;
mod symmetric;

pub use analysis::{Analysis, ROOT_LIMIT, SPLIT_FROM};
pub use dump::Dump;
pub use factor::{
    Factor, FactorStats, Inertia, BORDER_THRESHOLD, LAST_RESORT_THRESHOLD, PATIENCE, RELAXED_THRESHOLD, SINGULAR,
    THRESHOLD,
};
pub use install::install;
pub use solver::{
    SolveReport, SweepOptions, SymmetricSolver, BACKWARD_ERROR, COMPONENTWISE_ERROR, GMRES_ITERATIONS, KRYLOV_AFTER,
    MAX_REFINEMENT,
};
pub use symmetric::Structure;

/// Why the shim library could not be written to a folder or loaded from it (`install`).
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum LoadError {
    /// The file could not be created or written (the system's message).
    #[error("{path}: {message}")]
    Write { path: String, message: String },
    /// Eight names in the folder were taken.
    #[error("{dir}: no free file name for the shim")]
    NoFreeName { dir: String },
    /// The path holds a NUL byte, which `dlopen` cannot take.
    #[error("{path}: NUL in path")]
    NulInPath { path: String },
    /// `dlopen` refused the file (its `dlerror`).
    #[error("dlopen {path}: {message}")]
    Open { path: String, message: String },
    /// The file loaded but has no `spine_kkt_register` (its `dlerror`).
    #[error("{path}: no spine_kkt_register: {message}")]
    NoRegister { path: String, message: String },
}

/// Why a factorisation or solve could not be done.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum KktError {
    /// The arrays handed in do not describe a matrix (lengths, indices, non-finite values).
    #[error("invalid input: {0}")]
    Input(String),
    /// A fully summed column vanished: the matrix is singular to working precision.
    #[error("the matrix is singular (zero pivot at variable {pivot} of the elimination order)")]
    Singular { pivot: usize },
    /// A solve before any successful factorisation.
    #[error("solve without a factorisation")]
    NotFactorized,
    /// The shim library could not be written or loaded: why, in each folder tried.
    #[error("cannot load the Pardiso shim: {}", .0.iter().map(|e| e.to_string()).collect::<Vec<_>>().join("; "))]
    Load(Vec<LoadError>),
    /// A step of the factorisation did not happen (a broken invariant: a bug of this crate).
    #[error("internal error: {0}")]
    Internal(String),
}
