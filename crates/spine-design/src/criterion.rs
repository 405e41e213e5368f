//! The objective's elements in the full space, one group per criterion ([`crate::Objective`]):
//! the paper's strain energies of the `N + 1` springs at `θ1`, the springs' stiffnesses, the
//! powers of the joint moments at `θ1` and `θ2`, or the compliance load's work on each link at
//! `θ3`. Each is a sum of local elements, so its gradient and Hessian are exact and assembled
//! like the constraints'.

use crate::assembly::{group, AnyGroup, Placed, Row};
use crate::layout::{Layout, LoadState, StateForm};
use crate::numbers::{Criterion, Numbers};
use spine_model::chain::spring_links;
use spine_model::local::{DeflectionSpringEnergy, LinkWork, MomentPower, SpringEnergy, SpringStiffness};

/// The objective's group for `numbers.criterion`.
pub(crate) fn objective(layout: &Layout, numbers: &Numbers<f64>) -> Box<dyn AnyGroup + Send + Sync> {
    let stiffness_scale = numbers.stiffness_scale;
    match &numbers.criterion {
        Criterion::StrainEnergy => springs(layout, stiffness_scale, Row::Objective),
        Criterion::TotalStiffness => group((0..=layout.n).map(|j| Placed {
            element: SpringStiffness { stiffness_scale },
            vars: [Some(layout.stiffness(j))],
            row: Row::Objective,
        })),
        Criterion::PeakMoment { exponent, reference } => {
            let element = MomentPower { stiffness_scale, reference: *reference, exponent: *exponent };
            let states = [LoadState::Passive, LoadState::Loaded];
            group(
                states.into_iter().flat_map(|s| {
                    spring_slots(layout, s).map(move |vars| Placed { element, vars, row: Row::Objective })
                }),
            )
        }
        Criterion::Compliance { probe } => {
            let deflection = layout.states == StateForm::Deflection;
            group((0..layout.n).map(|i| Placed {
                element: LinkWork {
                    span: numbers.spans[i],
                    vertical: probe.vertical[i],
                    axial: probe.axial[i],
                    deflection,
                },
                vars: [Some(layout.state_angle(LoadState::Probe, i)), Some(layout.theta0(i))],
                row: Row::Objective,
            }))
        }
    }
}

/// Spring `j`'s five slots `[θ_{j−1}, θ0_{j−1}, θ_j, θ0_j, k_j]` in state `s`, `j = 0..=N` (a
/// missing neighbour has none); on deflections the `θ0` slots are empty, so that the
/// [`SpringEnergy`]-shaped elements see `[u_{j−1}, 0, u_j, 0, k_j]`.
fn spring_slots(layout: &Layout, s: LoadState) -> impl Iterator<Item = [Option<usize>; 5]> + '_ {
    let n = layout.n;
    let angle = move |i: usize| layout.state_angle(s, i);
    let theta0 = move |i: usize| (layout.states == StateForm::Absolute).then(|| layout.theta0(i));
    (0..=n).map(move |j| {
        let (prev, this) = spring_links(n, j);
        [prev.map(angle), prev.and_then(theta0), this.map(angle), this.and_then(theta0), Some(layout.stiffness(j))]
    })
}

/// The paper's objective `U(θ1)`: the `N + 1` springs' strain energies in the passive state, on
/// `row` (the objective, or the strain-energy budget's row).
pub(crate) fn springs(layout: &Layout, stiffness_scale: f64, row: Row) -> Box<dyn AnyGroup + Send + Sync> {
    let slots = spring_slots(layout, LoadState::Passive);
    match layout.states {
        StateForm::Absolute => group(slots.map(|vars| Placed { element: SpringEnergy { stiffness_scale }, vars, row })),
        // The deflections' own element, three slots (fewer Hessian pairs than five with two empty).
        StateForm::Deflection => group(slots.map(|[prev, _, this, _, k]| Placed {
            element: DeflectionSpringEnergy { stiffness_scale },
            vars: [prev, this, k],
            row,
        })),
    }
}
