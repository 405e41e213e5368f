//! One sensitivity step, shared by the calling thread and one helper ([`super::shared`]).
//!
//! The work, in the order the caller takes it:
//! 1. the optimum evaluated and its active set identified ([`Stage`]);
//! 2. the reduced KKT matrix factorised ([`ActiveSystem`]);
//! 3. each parameter's rates ([`rates`]) and LICQ's measure, which the helper starts on at once;
//! 4. each parameter's derivative (one solve each).
//!
//! The helper takes the rates from the first, then LICQ's measure once the active set is known,
//! then waits (yielding) for the factorised system and takes derivatives. Every task is claimed
//! by whichever thread asks first, and each result has its slot, so the report is the same
//! whichever thread computed what. A thread that waits for a result the other thread claimed
//! stops waiting when that thread has ended (a panic then reaches the caller through the scope).

use super::derivative::{derivative, one_sided, weak_candidates, WeakCandidates};
use super::rates::{rates, Rates};
use super::shared::{self, Claims, Flag};
use super::SensitivityReport;
use super::{active_labels, conditions, Optimum, Parameter, ParameterSensitivity, SensitivityError};
use crate::assembly::AnyGroup;
use crate::layout::Layout;
use crate::optimality::active_set::{ActiveSet, MAX_WEAK};
use crate::optimality::system::{self, ActiveSystem, Matrices};
use std::sync::OnceLock;

/// The optimum evaluated: its evaluation, matrices and active set.
struct Stage {
    at: crate::optimality::point::Evaluation,
    matrices: Matrices,
    set: ActiveSet,
}

impl Stage {
    fn of(optimum: &Optimum<'_>) -> Self {
        let (layout, x) = (optimum.layout, optimum.x);
        let assembled = crate::full_space::assemble(optimum.problem, layout.states);
        let (at, matrices) = Matrices::of(&assembled, optimum.problem, layout, x, &optimum.multipliers.constraints);
        let set = ActiveSet::identify(x, &at, &matrices.jacobian_pattern, optimum.multipliers);
        Stage { at, matrices, set }
    }

    /// LICQ's measure: the smallest singular value of the active rows' Jacobian on the free
    /// variables. (Rows that depend on others are left out of the system, their multipliers not
    /// being unique; each derivative is then checked against them.)
    fn licq(&self, layout: Layout) -> Option<f64> {
        let jacobian = (&self.matrices.jacobian_pattern[..], &self.matrices.jacobian[..]);
        system::smallest_singular_value(layout.num_variables(), &self.set.variables, &self.set.rows, jacobian)
    }
}

/// What the derivatives need beyond the stage: the factorised system, whether the derivatives
/// are two-sided, and the weak bounds' candidate systems.
struct Ready {
    system: ActiveSystem,
    two_sided: bool,
    candidates: Option<WeakCandidates>,
}

/// The step's tasks and their results.
pub(super) struct Work<'s, 'a> {
    optimum: &'s Optimum<'a>,
    parameters: &'s [Parameter],
    stage: OnceLock<Stage>,
    ready: OnceLock<Ready>,
    rate_claims: Claims,
    rates: Vec<OnceLock<Result<Rates, SensitivityError>>>,
    licq: shared::Once<Option<f64>>,
    derivative_claims: Claims,
    derivatives: Vec<OnceLock<ParameterSensitivity>>,
    /// The active bounds by name: the last task, for whichever thread is free first.
    labels: shared::Once<Vec<String>>,
    caller: Flag,
    helper_started: Flag,
    helper: Flag,
}

impl<'s, 'a> Work<'s, 'a> {
    pub fn new(optimum: &'s Optimum<'a>, parameters: &'s [Parameter]) -> Self {
        Work {
            optimum,
            parameters,
            stage: OnceLock::new(),
            ready: OnceLock::new(),
            rate_claims: Claims::new(parameters.len()),
            rates: parameters.iter().map(|_| OnceLock::new()).collect(),
            licq: shared::Once::new(),
            derivative_claims: Claims::new(parameters.len()),
            derivatives: parameters.iter().map(|_| OnceLock::new()).collect(),
            labels: shared::Once::new(),
            caller: Flag::default(),
            helper_started: Flag::default(),
            helper: Flag::default(),
        }
    }

    /// Runs the step on this thread and one helper, and assembles the report.
    pub fn run(self) -> Result<SensitivityReport, SensitivityError> {
        shared::with_helper(|| self.help(), || self.lead());
        // Invariant: `with_helper` returns once `lead` has returned, and `lead` takes every piece
        // of work the helper has not claimed (`shared`), so every slot below is filled.
        let layout = self.optimum.layout;
        let Stage { set, .. } = self.stage.into_inner().expect("the caller evaluated the optimum");
        let Ready { system, .. } = self.ready.into_inner().expect("the caller factorised the system");
        let rates =
            self.rates.into_iter().map(|slot| slot.into_inner().expect("every parameter's rates were computed"));
        // The first parameter whose rates failed, in order.
        for rate in rates {
            rate?;
        }
        let conditions = conditions(&set, &system, layout, self.licq.into_inner().expect("the caller measured LICQ"));
        let parameters =
            self.derivatives.into_iter().map(|slot| slot.into_inner().expect("every derivative was computed"));
        let active = self.labels.into_inner().expect("a thread named the active bounds");
        Ok(SensitivityReport { conditions, active, parameters: parameters.collect() })
    }

    /// The caller's part: everything, in order, that the helper has not claimed.
    fn lead(&self) {
        let _ended = self.caller.raise_on_drop();
        let (optimum, layout) = (self.optimum, self.optimum.layout);
        let stage = self.stage.get_or_init(|| Stage::of(optimum));
        let set = &stage.set;
        let system = ActiveSystem::new(&stage.matrices, layout, set.variables.clone(), set.rows.clone());
        self.rates_and_licq();
        let weak = set.weak_variables.len() + set.weak_rows.len();
        let candidates = (weak > 0 && weak <= MAX_WEAK).then(|| weak_candidates(optimum, &stage.matrices, set));
        let two_sided = weak == 0 && system.certified().is_some();
        let ready = self.ready.get_or_init(|| Ready { system, two_sided, candidates });
        self.derivatives(stage, ready, &self.helper);
        // A helper that has started ends within its last task: waiting for it here, awake,
        // spares the end of the scope a sleep and a wake-up (15 µs here, a tenth of the step).
        if self.helper_started.raised() {
            shared::wait(&self.helper, || None::<()>);
        }
    }

    /// The helper's part: rates from the first, LICQ's measure, then derivatives once the
    /// system is factorised.
    fn help(&self) {
        let _ended = self.helper.raise_on_drop();
        self.helper_started.raise();
        self.rates_and_licq();
        let ready = shared::wait(&self.caller, || {
            // LICQ's measure may become possible while waiting.
            self.licq_if_known();
            self.ready.get()
        });
        if let (Some(ready), Some(stage)) = (ready, self.stage.get()) {
            self.derivatives(stage, ready, &self.caller);
        }
    }

    /// The rates still unclaimed (on elements of this thread's own), then LICQ's measure if the
    /// active set is known.
    fn rates_and_licq(&self) {
        let (optimum, layout) = (self.optimum, self.optimum.layout);
        let mut elements: Option<Vec<Box<dyn AnyGroup + Send + Sync>>> = None;
        while let Some(i) = self.rate_claims.claim() {
            let elements = elements.get_or_insert_with(|| {
                crate::full_space::groups(&crate::numbers::Numbers::of(optimum.problem), layout.states)
            });
            let p = &self.parameters[i];
            let _ = self.rates[i].set(rates(optimum, elements, &p.name, &p.tangent));
        }
        self.licq_if_known();
    }

    /// LICQ's measure, if no thread has claimed it and the active set is known.
    fn licq_if_known(&self) {
        if let Some(stage) = self.stage.get() {
            self.licq.run(|| stage.licq(self.optimum.layout));
        }
    }

    /// The derivatives still unclaimed; a parameter's rates that `other` claimed are waited for
    /// while `other` runs.
    fn derivatives(&self, stage: &Stage, ready: &Ready, other: &Flag) {
        let step = Step { optimum: self.optimum, at: &stage.at, matrices: &stage.matrices, system: &ready.system };
        while let Some(i) = self.derivative_claims.claim() {
            let Some(rates) = shared::wait(other, || self.rates[i].get()) else { return };
            // A parameter whose rates failed gets no derivative: the step reports the error.
            let Ok(rates) = rates else { continue };
            let p = &self.parameters[i];
            let _ = self.derivatives[i].set(step.differentiate(p, rates, ready.two_sided, ready.candidates.as_ref()));
        }
        self.labels.run(|| active_labels(&stage.set, self.optimum.layout));
    }
}

/// What every parameter's derivative is formed from: the optimum, its evaluation, matrices and
/// factorised system.
struct Step<'s, 'a> {
    optimum: &'s Optimum<'a>,
    at: &'s crate::optimality::point::Evaluation,
    matrices: &'s Matrices,
    system: &'s ActiveSystem,
}

impl Step<'_, '_> {
    /// The sensitivity to one parameter whose NLP data moves at `rates`: two-sided where
    /// `two_sided` (the conditions hold but for dependent rows, which it is checked against),
    /// one-sided over the weak `candidates`.
    fn differentiate(
        &self,
        parameter: &Parameter,
        rates: &Rates,
        two_sided: bool,
        candidates: Option<&WeakCandidates>,
    ) -> ParameterSensitivity {
        let (optimum, matrices, at) = (self.optimum, self.matrices, self.at);
        let mut note = None;
        let solution = two_sided.then(|| derivative(optimum, matrices, self.system, rates, at, false)).flatten();
        let derivative = solution.and_then(|s| match s.broken_row {
            Some(row) => {
                note = Some(format!(
                    "the active rows are dependent (LICQ fails) and constraint row {row} cannot follow the parameter: no two-sided derivative"
                ));
                None
            }
            None => Some(s.derivative),
        });
        let (increase, decrease) = match candidates {
            Some(c) => {
                (one_sided(optimum, matrices, c, rates, at, 1.0), one_sided(optimum, matrices, c, rates, at, -1.0))
            }
            None => (None, None),
        };
        ParameterSensitivity {
            name: parameter.name.clone(),
            value: parameter.value,
            derivative,
            increase,
            decrease,
            note,
        }
    }
}
