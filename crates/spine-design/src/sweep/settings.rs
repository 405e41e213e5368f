//! What a sweep covers and how it steps ([`SweepSettings`]): the parameter's range, the points
//! reported, the branch tolerance and the halvings of a step.

use serde::Serialize;
use spine_check::{require, FieldError};

/// What a sweep covers and how it steps.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct SweepSettings {
    /// The parameter's first and last value (either order).
    pub from: f64,
    pub to: f64,
    /// Reported points, equally spaced from `from` to `to` (both included).
    pub points: usize,
    /// How many times a step may be halved before a jump is declared.
    pub halvings: usize,
    /// Bisection steps locating each event.
    pub bisections: usize,
    /// Largest accepted move of the corrector from the prediction, as a fraction of the design box.
    pub branch_tolerance: f64,
    /// Ipopt's `mu_init` of the corrector.
    pub mu_init: f64,
}

impl SweepSettings {
    /// `points` from `from` to `to`, with the default stepping controls.
    pub fn new(from: f64, to: f64, points: usize) -> Self {
        SweepSettings { from, to, points, halvings: 8, bisections: 10, branch_tolerance: 0.05, mu_init: 1e-9 }
    }

    /// Why these settings are not usable, naming the field (`from`, `to`, `points`, …).
    pub fn validate(&self) -> Result<(), FieldError> {
        require(self.from.is_finite(), "from", || format!("must be a finite number, got {}", self.from))?;
        require(self.to.is_finite(), "to", || format!("must be a finite number, got {}", self.to))?;
        let span = self.to != self.from && (self.to - self.from).is_finite();
        require(span, "to", || format!("must differ from `from` ({}) by a finite span", self.from))?;
        require((2..=100_000).contains(&self.points), "points", || {
            format!("must be 2 to 100000, got {}", self.points)
        })?;
        require(self.halvings <= 30, "halvings", || format!("must be at most 30, got {}", self.halvings))?;
        require(self.bisections <= 50, "bisections", || format!("must be at most 50, got {}", self.bisections))?;
        require(self.branch_tolerance > 0.0 && self.branch_tolerance <= 1.0, "branch_tolerance", || {
            format!("must be in (0, 1], got {}", self.branch_tolerance)
        })?;
        require(self.mu_init > 0.0 && self.mu_init <= 0.1, "mu_init", || {
            format!("must be in (0, 0.1], got {}", self.mu_init)
        })
    }

    /// The `k`-th reported parameter value.
    pub fn value(&self, k: usize) -> f64 {
        if k + 1 == self.points {
            return self.to;
        }
        self.from + (self.to - self.from) * k as f64 / (self.points - 1) as f64
    }
}
