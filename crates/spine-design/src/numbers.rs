//! The numbers of eq. (33)'s NLP that come from the problem rather than from its variables: the
//! spans, the load resultants of both load states, `C_K`, the end target `L_x + δ_d` and the
//! bounds, in any number type. With duals carrying a [`ProblemTangent`]'s rates they give the
//! exact rates of the elements' constants and of the bounds along a parameter of the problem (the
//! scaled stiffness bounds `K/C_K` included), which the optimum's sensitivities need.

use crate::objective::Objective;
use crate::problem::DesignProblem;
use num_dual::Dual64;
use spine_model::Scalar;

/// The rates of a [`DesignProblem`]'s numbers along one parameter, per unit of the parameter, held
/// in a problem's own shape: the spans (m), masses (kg), gravity (m/s²), the nodal forces of the
/// passive load and the actuation (N), `δ_d` (m), `C_K` and the bounds, each zero where it does not
/// move. A case builds it for each of its parameters (`spine_case`'s `parameter_tangent`).
#[derive(Clone, Debug)]
pub struct ProblemTangent(DesignProblem);

impl ProblemTangent {
    /// The tangent in which nothing moves, shaped as `problem`.
    pub fn zero(problem: &DesignProblem) -> Self {
        let mut rates = problem.clone();
        numbers_mut(&mut rates).into_iter().for_each(|v| v.fill(0.0));
        Self(rates)
    }

    /// `problem + t · rates`, every number moved along the tangent.
    pub fn moved(&self, problem: &DesignProblem, t: f64) -> DesignProblem {
        let (mut moved, mut rates) = (problem.clone(), self.0.clone());
        for (v, r) in numbers_mut(&mut moved).into_iter().zip(numbers_mut(&mut rates)) {
            v.iter_mut().zip(r.iter()).for_each(|(v, r)| *v += t * r);
        }
        moved
    }

    /// Every number of a problem in one fixed order (the order [`ProblemTangent::moved`] goes
    /// over): to compare problems number by number.
    pub fn flatten(problem: &DesignProblem) -> Vec<f64> {
        numbers_mut(&mut problem.clone()).concat()
    }

    /// Whether the tangent has `problem`'s shape (as many spans, masses, loads and bounds; the
    /// other numbers of `numbers_mut` are scalars).
    pub fn fits(&self, problem: &DesignProblem) -> bool {
        let lengths = |d: &DesignProblem| {
            let (s, b) = (&d.structure, &d.bounds);
            [&s.chain.spans, &s.chain.masses, &s.passive.p_x, &s.passive.p_y, &s.actuation.p_x, &s.actuation.p_y]
                .map(|v| v.len())
                .into_iter()
                .chain([b.stiffness_min.len(), b.stiffness_max.len()])
                .collect::<Vec<_>>()
        };
        let criterion = |d: &DesignProblem| match &d.objective {
            Objective::Compliance { load } => (d.objective.name(), load.p_x.len() + load.p_y.len()),
            other => (other.name(), 0),
        };
        lengths(&self.0) == lengths(problem)
            && criterion(&self.0) == criterion(problem)
            && self.0.strain_energy_max.is_some() == problem.strain_energy_max.is_some()
    }

    /// The rates, in the problem's shape.
    pub fn rates(&self) -> &DesignProblem {
        &self.0
    }

    /// The rates, to set the numbers that move.
    pub fn rates_mut(&mut self) -> &mut DesignProblem {
        &mut self.0
    }
}

/// Every number of a problem as a slice (a scalar as a slice of one), in one fixed order: the one
/// list [`ProblemTangent::zero`], [`ProblemTangent::moved`] and [`ProblemTangent::flatten`] go
/// over, so that a number added to the problem is added here once.
fn numbers_mut(p: &mut DesignProblem) -> Vec<&mut [f64]> {
    use std::slice::from_mut;
    let (s, b) = (&mut p.structure, &mut p.bounds);
    let mut numbers: Vec<&mut [f64]> = vec![
        &mut s.chain.spans,
        &mut s.chain.masses,
        from_mut(&mut s.chain.gravity),
        &mut s.passive.p_x,
        &mut s.passive.p_y,
        &mut s.actuation.p_x,
        &mut s.actuation.p_y,
        from_mut(&mut p.delta_d),
        from_mut(&mut p.stiffness_scale),
        from_mut(&mut b.theta0_max),
        from_mut(&mut b.relative_angle_max),
        &mut b.stiffness_min,
        &mut b.stiffness_max,
        from_mut(&mut b.height_min),
        from_mut(&mut b.height_max),
        from_mut(&mut b.height_ramp),
    ];
    if let Some(budget) = &mut p.strain_energy_max {
        numbers.push(from_mut(budget));
    }
    match &mut p.objective {
        Objective::StrainEnergy | Objective::TotalStiffness => {}
        Objective::PeakMoment { reference, .. } => numbers.push(from_mut(reference)),
        Objective::Compliance { load } => numbers.extend([&mut load.p_x[..], &mut load.p_y[..]]),
    }
    numbers
}

/// The load resultants of one load state (eq. (48)), N.
#[derive(Clone, Debug)]
pub(crate) struct Resultants<T> {
    pub vertical: Vec<T>,
    pub axial: Vec<T>,
}

/// The criterion's own numbers ([`Objective`]) in `T`.
#[derive(Clone, Debug)]
pub(crate) enum Criterion<T> {
    StrainEnergy,
    TotalStiffness,
    /// `p` and `M_ref` (N·m).
    PeakMoment {
        exponent: u32,
        reference: T,
    },
    /// The resultants of the second load case alone (no self-weight), N.
    Compliance {
        probe: Resultants<T>,
    },
}

/// The bounds of the full space's variables and rows.
pub(crate) struct FullSpaceBounds<T> {
    pub lower: Vec<T>,
    pub upper: Vec<T>,
    pub row_lower: Vec<T>,
    pub row_upper: Vec<T>,
}

/// The problem's numbers in the NLP, in `T`.
#[derive(Clone, Debug)]
pub(crate) struct Numbers<T> {
    /// `a_i`, m.
    pub spans: Vec<T>,
    /// The resultants of the passive load and of the passive load plus the actuation.
    pub passive: Resultants<T>,
    pub loaded: Resultants<T>,
    /// `C_K` of eq. (34).
    pub stiffness_scale: T,
    /// `L_x + δ_d`, m: the end row's value.
    pub end_target: T,
    pub theta0_max: T,
    pub relative_angle_max: T,
    /// `K` bounds, N·m/rad (`N + 1` each).
    pub stiffness_min: Vec<T>,
    pub stiffness_max: Vec<T>,
    pub height_min: T,
    pub height_max: T,
    /// [`crate::DesignBounds::height_ramp`], m.
    pub height_ramp: T,
    /// What the objective measures.
    pub criterion: Criterion<T>,
    /// `U_max` of the strain-energy budget row, J.
    pub strain_energy_max: Option<T>,
}

impl Numbers<f64> {
    /// The problem's numbers.
    pub fn of(problem: &DesignProblem) -> Self {
        Self::lifted(problem, problem, |value, _| value)
    }

    /// Whether any number the elements take as a constant (span, resultant, `C_K`) is nonzero:
    /// for rates, whether any element's constants move.
    pub fn moves_elements(&self) -> bool {
        let any = |v: &[f64]| v.iter().any(|&x| x != 0.0);
        let loads = |r: &Resultants<f64>| any(&r.vertical) || any(&r.axial);
        let criterion = match &self.criterion {
            Criterion::StrainEnergy | Criterion::TotalStiffness => false,
            Criterion::PeakMoment { reference, .. } => *reference != 0.0,
            Criterion::Compliance { probe } => loads(probe),
        };
        any(&self.spans) || loads(&self.passive) || loads(&self.loaded) || self.stiffness_scale != 0.0 || criterion
    }
}

impl Numbers<Dual64> {
    /// The problem's numbers with their rates along `tangent`.
    pub fn along(problem: &DesignProblem, tangent: &ProblemTangent) -> Self {
        Self::lifted(problem, tangent.rates(), Dual64::new)
    }

    /// The rates alone.
    pub fn rates(&self) -> Numbers<f64> {
        self.map(|d| d.eps)
    }
}

impl<T: Scalar> Numbers<T> {
    /// Every number `v` of `problem` as `lift(v, its rate in rates)`.
    fn lifted(problem: &DesignProblem, rates: &DesignProblem, lift: impl Fn(f64, f64) -> T) -> Self {
        let each = |v: &[f64], r: &[f64]| -> Vec<T> { v.iter().zip(r).map(|(&v, &r)| lift(v, r)).collect() };
        let (s, r) = (&problem.structure, &rates.structure);
        let masses = each(&s.chain.masses, &r.chain.masses);
        let gravity = lift(s.chain.gravity, r.chain.gravity);
        let resultants = |p_y: &[T], p_x: &[T]| {
            let (vertical, axial) = spine_model::loads::resultants(p_y, p_x, &masses, gravity);
            Resultants { vertical, axial }
        };
        let (p_y, p_x) = (each(&s.passive.p_y, &r.passive.p_y), each(&s.passive.p_x, &r.passive.p_x));
        let plus = |a: &[T], b: &[T]| -> Vec<T> { a.iter().zip(b).map(|(&a, &b)| a + b).collect() };
        let total_y = plus(&p_y, &each(&s.actuation.p_y, &r.actuation.p_y));
        let total_x = plus(&p_x, &each(&s.actuation.p_x, &r.actuation.p_x));
        let spans = each(&s.chain.spans, &r.chain.spans);
        let length_x = spans.iter().fold(T::zero(), |sum, &a| sum + a);
        let (b, rb) = (&problem.bounds, &rates.bounds);
        let criterion = match (&problem.objective, &rates.objective) {
            (Objective::PeakMoment { exponent, reference }, Objective::PeakMoment { reference: rate, .. }) => {
                Criterion::PeakMoment { exponent: *exponent, reference: lift(*reference, *rate) }
            }
            (Objective::Compliance { load }, Objective::Compliance { load: rate }) => {
                let (p_y, p_x) = (each(&load.p_y, &rate.p_y), each(&load.p_x, &rate.p_x));
                let (vertical, axial) = spine_model::loads::resultants(&p_y, &p_x, &masses, T::zero());
                Criterion::Compliance { probe: Resultants { vertical, axial } }
            }
            (Objective::TotalStiffness, Objective::TotalStiffness) => Criterion::TotalStiffness,
            (Objective::StrainEnergy, Objective::StrainEnergy) => Criterion::StrainEnergy,
            (objective, rate) => panic!("rates of {} for objective {}", rate.name(), objective.name()),
        };
        let strain_energy_max = match (problem.strain_energy_max, rates.strain_energy_max) {
            (Some(v), r) => Some(lift(v, r.unwrap_or(0.0))),
            (None, _) => None,
        };
        Numbers {
            criterion,
            strain_energy_max,
            passive: resultants(&p_y, &p_x),
            loaded: resultants(&total_y, &total_x),
            spans,
            stiffness_scale: lift(problem.stiffness_scale, rates.stiffness_scale),
            end_target: length_x + lift(problem.delta_d, rates.delta_d),
            theta0_max: lift(b.theta0_max, rb.theta0_max),
            relative_angle_max: lift(b.relative_angle_max, rb.relative_angle_max),
            stiffness_min: each(&b.stiffness_min, &rb.stiffness_min),
            stiffness_max: each(&b.stiffness_max, &rb.stiffness_max),
            height_min: lift(b.height_min, rb.height_min),
            height_max: lift(b.height_max, rb.height_max),
            height_ramp: lift(b.height_ramp, rb.height_ramp),
        }
    }

    /// Every number mapped by `f`.
    pub fn map<U>(&self, f: impl Fn(T) -> U) -> Numbers<U> {
        let each = |v: &[T]| v.iter().map(|&x| f(x)).collect::<Vec<U>>();
        let resultants = |r: &Resultants<T>| Resultants { vertical: each(&r.vertical), axial: each(&r.axial) };
        Numbers {
            spans: each(&self.spans),
            passive: resultants(&self.passive),
            loaded: resultants(&self.loaded),
            stiffness_scale: f(self.stiffness_scale),
            end_target: f(self.end_target),
            theta0_max: f(self.theta0_max),
            relative_angle_max: f(self.relative_angle_max),
            stiffness_min: each(&self.stiffness_min),
            stiffness_max: each(&self.stiffness_max),
            height_min: f(self.height_min),
            height_max: f(self.height_max),
            height_ramp: f(self.height_ramp),
            strain_energy_max: self.strain_energy_max.map(&f),
            criterion: match &self.criterion {
                Criterion::StrainEnergy => Criterion::StrainEnergy,
                Criterion::TotalStiffness => Criterion::TotalStiffness,
                Criterion::PeakMoment { exponent, reference } => {
                    Criterion::PeakMoment { exponent: *exponent, reference: f(*reference) }
                }
                Criterion::Compliance { probe } => Criterion::Compliance { probe: resultants(probe) },
            },
        }
    }

    /// Bounds shared by both formulations: `θ0` (indices `0..N`), `k = K / C_K` (indices
    /// `N..2N+1`) and the lifted node heights at `height(j)`; every other entry is left as it is.
    pub fn variable_bounds(&self, lower: &mut [T], upper: &mut [T], height: impl Fn(usize) -> Option<usize>) {
        let n = self.spans.len();
        for i in 0..n {
            lower[i] = -self.theta0_max;
            upper[i] = self.theta0_max;
        }
        for j in 0..=n {
            lower[n + j] = self.stiffness_min[j] / self.stiffness_scale;
            upper[n + j] = self.stiffness_max[j] / self.stiffness_scale;
        }
        let floors = crate::problem::height_floors(self.height_min, self.height_ramp, &self.spans);
        for (j, floor) in (1..n).zip(floors) {
            // Invariant: the layout has a height variable for every interior node `1..n`.
            let v = height(j).expect("interior node has a height variable");
            lower[v] = floor;
            upper[v] = self.height_max;
        }
    }

    /// Every bound of the full space in `layout`: `(lower, upper)` of the variables (the states
    /// free) and of the rows ([`Numbers::variable_bounds`], [`Numbers::constraint_bounds`]).
    pub fn full_space_bounds(&self, layout: &crate::layout::Layout) -> FullSpaceBounds<T> {
        let (n, m) = (layout.num_variables(), layout.num_constraints());
        let (mut lower, mut upper) = (vec![T::from(f64::NEG_INFINITY); n], vec![T::from(f64::INFINITY); n]);
        self.variable_bounds(&mut lower, &mut upper, |j| layout.height(j));
        let (mut row_lower, mut row_upper) = (vec![T::zero(); m], vec![T::zero(); m]);
        let (end, budget) = (layout.end_row(), layout.budget_row_if_any());
        self.constraint_bounds(&mut row_lower, &mut row_upper, end, |i| layout.relative_row(i), budget);
        FullSpaceBounds { lower, upper, row_lower, row_upper }
    }

    /// Constraint bounds shared by both formulations: every row is an equality `= 0` except the
    /// end displacement row (`X_{N+1}(θ2) = L_x + δ_d`), the relative-angle rows (`±π/6` by
    /// default) and the strain-energy budget's row (`−∞ < U(θ1) ≤ U_max`, when the problem has
    /// a budget and the formulation the row).
    pub fn constraint_bounds(
        &self,
        lower: &mut [T],
        upper: &mut [T],
        end_row: usize,
        relative_row: impl Fn(usize) -> usize,
        budget_row: Option<usize>,
    ) {
        lower.fill(T::zero());
        upper.fill(T::zero());
        lower[end_row] = self.end_target;
        upper[end_row] = self.end_target;
        for i in 0..self.spans.len().saturating_sub(1) {
            lower[relative_row(i)] = -self.relative_angle_max;
            upper[relative_row(i)] = self.relative_angle_max;
        }
        if let (Some(r), Some(budget)) = (budget_row, self.strain_energy_max) {
            lower[r] = T::from(f64::NEG_INFINITY);
            upper[r] = budget;
        }
    }
}
