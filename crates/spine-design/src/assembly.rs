//! Sparse assembly of an NLP from local elements ([`spine_model::local`]).
//!
//! Each [`Placed`] element adds its value to one row (the objective or a constraint) and maps its
//! `M` local slots to global variables (`None` for a slot that holds a constant zero, such as the
//! missing neighbour of the first link). A [`Group`] of elements of one kind computes, in one pass
//! over its elements with fixed-size duals:
//!
//! * values: `f` and `g`;
//! * first derivatives: `∇f` and the Jacobian values at the positions of the sparsity pattern;
//! * second derivatives: the weighted local Hessians scattered into the lower triangle of the
//!   Hessian of the Lagrangian, only at the pairs each element declares
//!   ([`Element::HESSIAN_PAIRS`]).
//!
//! The patterns are built once by [`Patterns`]; cost per evaluation is linear in the number of
//! elements.
//!
//! The rates of the values and first derivatives along a parameter of the problem
//! ([`rates`]) come from the same groups built from the problem's rates: element by
//! element, one pass of a tangent jet ([`local::rates`]) where the element's constants move.

use spine_model::local::{self, Element};
// The patterns are keyed by `(row, column)` pairs of small integers: Fx hashing, not SipHash
// (no untrusted keys; assembly was a third of a sensitivity's cost with SipHash).
use rustc_hash::FxHashMap as HashMap;

/// Which function an element adds to.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Row {
    Objective,
    Constraint(usize),
}

/// An element with its global variables and its row.
#[derive(Clone, Debug)]
pub struct Placed<E, const M: usize> {
    pub element: E,
    pub vars: [Option<usize>; M],
    pub row: Row,
}

/// Sparsity patterns under construction: Jacobian `(row, column)` and Hessian lower-triangle
/// `(row, column)` entries, each with its position in the value arrays.
#[derive(Default, Debug)]
pub struct Patterns {
    pub jacobian: Vec<(usize, usize)>,
    pub hessian: Vec<(usize, usize)>,
    jacobian_index: HashMap<(usize, usize), usize>,
    hessian_index: HashMap<(usize, usize), usize>,
}

/// Marks a slot without a global variable or a position.
pub const NONE: usize = usize::MAX;

impl Patterns {
    fn jacobian_position(&mut self, row: usize, col: usize) -> usize {
        *self.jacobian_index.entry((row, col)).or_insert_with(|| {
            self.jacobian.push((row, col));
            self.jacobian.len() - 1
        })
    }

    fn hessian_position(&mut self, a: usize, b: usize) -> usize {
        let key = (a.max(b), a.min(b));
        *self.hessian_index.entry(key).or_insert_with(|| {
            self.hessian.push(key);
            self.hessian.len() - 1
        })
    }
}

/// Elements of one kind, with their positions in the sparsity patterns.
pub struct Group<E, const M: usize> {
    items: Vec<Placed<E, M>>,
    jacobian_positions: Vec<[usize; M]>,
    hessian_positions: Vec<usize>,
    /// Per pair of `E::HESSIAN_PAIRS`, its index in `E::CONSTANT_PAIRS`, if it is constant.
    constant_index: Vec<Option<usize>>,
    /// Per element, the values of its `E::CONSTANT_PAIRS`, taken once at registration.
    constant_values: Vec<f64>,
}

impl<E: Element<M>, const M: usize> Group<E, M> {
    pub fn new(items: Vec<Placed<E, M>>) -> Self {
        let constant_index = E::HESSIAN_PAIRS.iter().map(|p| E::CONSTANT_PAIRS.iter().position(|c| c == p)).collect();
        Group {
            items,
            jacobian_positions: Vec::new(),
            hessian_positions: Vec::new(),
            constant_index,
            constant_values: Vec::new(),
        }
    }

    fn local(&self, item: &Placed<E, M>, x: &[f64]) -> [f64; M] {
        std::array::from_fn(|k| item.vars[k].map_or(0.0, |v| x[v]))
    }
}

/// The operations every group offers, independent of its element kind and size.
pub trait AnyGroup {
    /// Registers the group's Jacobian and Hessian entries; called once, before any evaluation.
    fn register(&mut self, patterns: &mut Patterns);
    /// At most how many Jacobian and Hessian entries the group registers (to size the patterns).
    fn most_entries(&self) -> (usize, usize);
    /// Adds the values to the objective and the constraints.
    fn add_values(&self, x: &[f64], objective: &mut f64, g: &mut [f64]);
    /// Adds first derivatives to `∇f` and to the Jacobian values.
    fn add_first_derivatives(&self, x: &[f64], gradient: &mut [f64], jacobian: &mut [f64]);
    /// Adds `σ ∇²f + Σ λ_r ∇²g_r` of the group's elements to the Hessian values.
    fn add_hessian(&self, x: &[f64], sigma: f64, lambda: &[f64], hessian: &mut [f64]);
    /// The group as [`std::any::Any`], so that [`AnyGroup::add_rates`] can take its direction.
    fn as_any(&self) -> &dyn std::any::Any;
    /// Adds the exact rates along a parameter: `direction` is this group built from the problem's
    /// rates (the same elements in the same order, each holding its constants' rates). Adds each
    /// element's value rate to its row's and `w ∂∇e/∂p` to `rates.lagrangian_gradient`, with `w` 1
    /// for the objective and `λ_r` for row `r`. Elements whose constants do not move are skipped.
    ///
    /// # Panics
    /// If `direction` is a group of another kind or size (a programming error).
    fn add_rates(&self, direction: &dyn AnyGroup, x: &[f64], lambda: &[f64], rates: &mut NlpRates);
}

/// The rates along a parameter of the NLP's objective, constraints and Lagrangian gradient
/// `∇f + Σ λ_r ∇g_r` (without the bound multipliers) at a point.
#[derive(Clone, Debug, PartialEq)]
pub struct NlpRates {
    pub objective: f64,
    pub constraints: Vec<f64>,
    pub lagrangian_gradient: Vec<f64>,
}

/// Whether any of `element`'s constants moves at `rates`: the element evaluated in [`Nothing`], so
/// that each constant passes through the lift once and nothing else is computed.
fn moves<E: Element<M>, const M: usize>(element: &E, rates: &E) -> bool {
    let moving = std::cell::Cell::new(false);
    let lift = |_: f64, r: f64| {
        if r != 0.0 {
            moving.set(true);
        }
        Nothing
    };
    element.eval_moving(rates, lift, &[Nothing; M]);
    moving.get()
}

/// A number type whose every operation computes nothing: an element evaluated in it only runs
/// through its structure (see [`moves`]).
#[derive(Clone, Copy, Debug)]
struct Nothing;

impl std::ops::Add for Nothing {
    type Output = Self;
    fn add(self, _: Self) -> Self {
        Nothing
    }
}
impl std::ops::Sub for Nothing {
    type Output = Self;
    fn sub(self, _: Self) -> Self {
        Nothing
    }
}
impl std::ops::Mul for Nothing {
    type Output = Self;
    fn mul(self, _: Self) -> Self {
        Nothing
    }
}
impl std::ops::Mul<f64> for Nothing {
    type Output = Self;
    fn mul(self, _: f64) -> Self {
        Nothing
    }
}
impl std::ops::Neg for Nothing {
    type Output = Self;
    fn neg(self) -> Self {
        Nothing
    }
}
impl spine_model::jet::Elementary for Nothing {
    fn sin_cos(self) -> (Self, Self) {
        (Nothing, Nothing)
    }
    fn sin(self) -> Self {
        Nothing
    }
    fn cos(self) -> Self {
        Nothing
    }
    fn tan(self) -> Self {
        Nothing
    }
    fn recip(self) -> Self {
        Nothing
    }
}

impl<E: Element<M> + 'static, const M: usize> AnyGroup for Group<E, M> {
    fn most_entries(&self) -> (usize, usize) {
        (self.items.len() * M, self.items.len() * E::HESSIAN_PAIRS.len())
    }

    fn register(&mut self, patterns: &mut Patterns) {
        self.jacobian_positions.clear();
        self.hessian_positions.clear();
        self.constant_values.clear();
        self.jacobian_positions.reserve(self.items.len());
        self.hessian_positions.reserve(self.items.len() * E::HESSIAN_PAIRS.len());
        self.constant_values.reserve(self.items.len() * E::CONSTANT_PAIRS.len());
        for item in &self.items {
            // The constant second derivatives, the same at every point (tested per element).
            if !E::CONSTANT_PAIRS.is_empty() {
                let h = local::hessian(&item.element, &[0.0; M]);
                self.constant_values.extend(E::CONSTANT_PAIRS.iter().map(|&(a, b)| h[a][b]));
            }
            self.jacobian_positions.push(std::array::from_fn(|k| match (item.row, item.vars[k]) {
                (Row::Constraint(r), Some(v)) => patterns.jacobian_position(r, v),
                _ => NONE,
            }));
            for &(a, b) in E::HESSIAN_PAIRS {
                let position = match (item.vars[a], item.vars[b]) {
                    (Some(va), Some(vb)) => patterns.hessian_position(va, vb),
                    _ => NONE,
                };
                self.hessian_positions.push(position);
            }
        }
    }

    fn add_values(&self, x: &[f64], objective: &mut f64, g: &mut [f64]) {
        for item in &self.items {
            let v = local::value(&item.element, &self.local(item, x));
            match item.row {
                Row::Objective => *objective += v,
                Row::Constraint(r) => g[r] += v,
            }
        }
    }

    fn add_first_derivatives(&self, x: &[f64], gradient: &mut [f64], jacobian: &mut [f64]) {
        for (item, positions) in self.items.iter().zip(&self.jacobian_positions) {
            let (_, grad) = local::gradient(&item.element, &self.local(item, x));
            for k in 0..M {
                match item.row {
                    Row::Objective => {
                        if let Some(v) = item.vars[k] {
                            gradient[v] += grad[k];
                        }
                    }
                    Row::Constraint(_) => {
                        if positions[k] != NONE {
                            jacobian[positions[k]] += grad[k];
                        }
                    }
                }
            }
        }
    }

    fn add_hessian(&self, x: &[f64], sigma: f64, lambda: &[f64], hessian: &mut [f64]) {
        let pairs = E::HESSIAN_PAIRS;
        if pairs.is_empty() {
            return;
        }
        let constants = E::CONSTANT_PAIRS.len();
        for (e, (item, positions)) in
            self.items.iter().zip(self.hessian_positions.chunks_exact(pairs.len())).enumerate()
        {
            let weight = match item.row {
                Row::Objective => sigma,
                Row::Constraint(r) => lambda[r],
            };
            if weight == 0.0 {
                continue;
            }
            let h = item.element.varying_hessian(&self.local(item, x));
            for ((&(a, b), &position), constant) in pairs.iter().zip(positions).zip(&self.constant_index) {
                if position != NONE {
                    let value = constant.map_or(h[a][b], |c| self.constant_values[e * constants + c]);
                    hessian[position] += weight * value;
                }
            }
        }
    }

    fn as_any(&self) -> &dyn std::any::Any {
        self
    }

    fn add_rates(&self, direction: &dyn AnyGroup, x: &[f64], lambda: &[f64], rates: &mut NlpRates) {
        // Invariant: `NlpRates` pairs each group with the same group of the direction's
        // assembly, which `groups` builds in the same order for any number type.
        let direction = direction.as_any().downcast_ref::<Self>().expect("the direction is a group of the same kind");
        assert_eq!(direction.items.len(), self.items.len(), "the direction has the group's elements");
        for (item, moving) in self.items.iter().zip(&direction.items) {
            if !moves(&item.element, &moving.element) {
                continue;
            }
            let (value, gradient) = local::rates(&item.element, &moving.element, &self.local(item, x));
            let weight = match item.row {
                Row::Objective => {
                    rates.objective += value;
                    1.0
                }
                Row::Constraint(r) => {
                    rates.constraints[r] += value;
                    lambda[r]
                }
            };
            for (k, g) in gradient.iter().enumerate() {
                if let Some(v) = item.vars[k] {
                    rates.lagrangian_gradient[v] += weight * g;
                }
            }
        }
    }
}

/// A group of placed elements of one kind, boxed for [`Assembled::new`].
pub(crate) fn group<E, const M: usize>(items: impl Iterator<Item = Placed<E, M>>) -> Box<dyn AnyGroup + Send + Sync>
where
    E: Element<M> + Send + Sync + 'static,
{
    Box::new(Group::new(items.collect()))
}

/// An NLP assembled from groups of elements: the objective and constraints are sums of elements.
pub struct Assembled {
    pub groups: Vec<Box<dyn AnyGroup + Send + Sync>>,
    pub patterns: Patterns,
}

impl Assembled {
    /// Registers every group and fixes the sparsity patterns.
    pub fn new(mut groups: Vec<Box<dyn AnyGroup + Send + Sync>>) -> Self {
        let mut patterns = Patterns::default();
        // Sized once: growing the index maps entry by entry was a third of the registration.
        let (jacobian, hessian) = groups.iter().fold((0, 0), |(j, h), g| {
            let (gj, gh) = g.most_entries();
            (j + gj, h + gh)
        });
        patterns.jacobian_index.reserve(jacobian);
        patterns.hessian_index.reserve(hessian);
        patterns.jacobian.reserve(jacobian);
        patterns.hessian.reserve(hessian);
        for group in &mut groups {
            group.register(&mut patterns);
        }
        Assembled { groups, patterns }
    }

    /// Objective and constraint values (the constraint array is overwritten).
    pub fn values(&self, x: &[f64], g: &mut [f64]) -> f64 {
        g.fill(0.0);
        let mut objective = 0.0;
        for group in &self.groups {
            group.add_values(x, &mut objective, g);
        }
        objective
    }

    /// `∇f` and the Jacobian values (both overwritten).
    pub fn first_derivatives(&self, x: &[f64], gradient: &mut [f64], jacobian: &mut [f64]) {
        gradient.fill(0.0);
        jacobian.fill(0.0);
        for group in &self.groups {
            group.add_first_derivatives(x, gradient, jacobian);
        }
    }

    /// Hessian of the Lagrangian values (overwritten).
    pub fn hessian(&self, x: &[f64], sigma: f64, lambda: &[f64], hessian: &mut [f64]) {
        hessian.fill(0.0);
        for group in &self.groups {
            group.add_hessian(x, sigma, lambda, hessian);
        }
    }
}

/// The rates at `x` along a parameter whose direction is `direction`: `groups` (registered or
/// not: the rates need no sparsity pattern) built again from the problem's rates
/// (`crate::full_space::groups`); constraint multipliers `lambda`.
pub fn rates(
    groups: &[Box<dyn AnyGroup + Send + Sync>],
    direction: &[Box<dyn AnyGroup + Send + Sync>],
    x: &[f64],
    lambda: &[f64],
) -> NlpRates {
    let mut rates =
        NlpRates { objective: 0.0, constraints: vec![0.0; lambda.len()], lagrangian_gradient: vec![0.0; x.len()] };
    assert_eq!(direction.len(), groups.len(), "one direction per group");
    for (group, moving) in groups.iter().zip(direction) {
        group.add_rates(moving.as_ref(), x, lambda, &mut rates);
    }
    rates
}
