//! Where each quantity of eq. (33) sits in the full-space variable and constraint vectors (the
//! table of [`crate::full_space`]).

use spine_model::{Design, State};

/// Index map of the full-space variables and constraints.
#[derive(Clone, Copy, Debug)]
pub struct Layout {
    pub n: usize,
    /// How the states are Ipopt's variables.
    pub states: StateForm,
    /// Whether the NLP has the third state `θ3`, the equilibrium under the compliance's load case
    /// ([`crate::objective::Objective::Compliance`]): `N + 1` variables after the node heights and `N + 1`
    /// equilibrium rows after the relative angles.
    pub probe: bool,
    /// Whether the NLP has the strain-energy budget row `U(θ1) ≤ U_max`
    /// ([`crate::problem::DesignProblem::strain_energy_max`]), the last row.
    pub budget: bool,
}

/// How the states `θ1`, `θ2` are variables of the full space (case field
/// `solver.state_variables`, resolved by [`crate::settings::StateVariables::resolve`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum StateForm {
    /// The absolute link angles `θ` (rad), as the paper writes eq. (33).
    Absolute,
    /// The deflections `u = θ − θ0` from the unloaded shape (rad): the springs' moments
    /// `K (u_i − u_{i−1})` are then computed to round-off of themselves, not of `K θ`.
    Deflection,
}

/// The load states: `θ1` (passive), `θ2` (passive + actuation), and `θ3` (the compliance's load
/// case alone, [`Layout::probe`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum LoadState {
    Passive,
    Loaded,
    Probe,
}

impl Layout {
    /// The layout of `problem`'s NLP with its states in `states`.
    pub fn of(problem: &crate::problem::DesignProblem, states: StateForm) -> Self {
        Layout {
            n: problem.n_links(),
            states,
            probe: problem.objective.has_probe(),
            budget: problem.strain_energy_max.is_some(),
        }
    }

    /// The load states the NLP holds, in the layout's order.
    pub fn load_states(&self) -> &'static [LoadState] {
        if self.probe {
            &[LoadState::Passive, LoadState::Loaded, LoadState::Probe]
        } else {
            &[LoadState::Passive, LoadState::Loaded]
        }
    }

    pub fn theta0(&self, i: usize) -> usize {
        i
    }
    pub fn stiffness(&self, j: usize) -> usize {
        self.n + j
    }
    /// Link `i`'s state variable in state `s`: `θ_i`, or its deflection `u_i = θ_i − θ0_i` (rad)
    /// ([`StateForm`]).
    pub fn state_angle(&self, s: LoadState, i: usize) -> usize {
        match s {
            LoadState::Passive => 2 * self.n + 1 + i,
            LoadState::Loaded => 3 * self.n + 2 + i,
            LoadState::Probe => self.probe_variables() + i,
        }
    }
    pub fn lambda(&self, s: LoadState) -> usize {
        self.state_angle(s, self.n)
    }
    /// Interior node `j = 1..N−1` (0-based node index; node 0 is the base, node N the end).
    pub fn height(&self, j: usize) -> Option<usize> {
        (j >= 1 && j < self.n).then(|| 4 * self.n + 2 + j)
    }
    /// The first variable of `θ3` (or where it would be).
    fn probe_variables(&self) -> usize {
        5 * self.n + 2
    }
    pub fn num_variables(&self) -> usize {
        self.probe_variables() + if self.probe { self.n + 1 } else { 0 }
    }

    pub fn equilibrium_row(&self, s: LoadState, i: usize) -> usize {
        match s {
            LoadState::Passive => i,
            LoadState::Loaded => self.n + 1 + i,
            LoadState::Probe => self.probe_rows() + i,
        }
    }
    pub fn constraint_row(&self, s: LoadState) -> usize {
        self.equilibrium_row(s, self.n)
    }
    pub fn height_row(&self, j: usize) -> usize {
        2 * self.n + 2 + j
    }
    pub fn end_row(&self) -> usize {
        3 * self.n + 2
    }
    pub fn relative_row(&self, i: usize) -> usize {
        3 * self.n + 3 + i
    }
    /// The first row of `θ3`'s equilibrium (or where it would be).
    fn probe_rows(&self) -> usize {
        4 * self.n + 2
    }
    /// The strain-energy budget's row (the last, when [`Layout::budget`]).
    pub fn budget_row(&self) -> usize {
        self.probe_rows() + if self.probe { self.n + 1 } else { 0 }
    }
    pub fn num_constraints(&self) -> usize {
        self.budget_row() + usize::from(self.budget)
    }
    /// [`Layout::budget_row`] when the layout has the row.
    pub fn budget_row_if_any(&self) -> Option<usize> {
        self.budget.then(|| self.budget_row())
    }

    /// Packs a design, both states (in [`StateForm`]) and the node heights into a variable vector.
    pub fn pack(
        &self,
        design: &Design,
        stiffness_scale: f64,
        passive: &State,
        loaded: &State,
        heights: &[f64],
    ) -> Vec<f64> {
        let mut x = vec![0.0; self.num_variables()];
        for i in 0..self.n {
            x[self.theta0(i)] = design.theta0[i];
            let offset = self.offset(design.theta0[i]);
            x[self.state_angle(LoadState::Passive, i)] = passive.theta[i] - offset;
            x[self.state_angle(LoadState::Loaded, i)] = loaded.theta[i] - offset;
        }
        for j in 0..=self.n {
            x[self.stiffness(j)] = design.stiffness[j] / stiffness_scale;
        }
        x[self.lambda(LoadState::Passive)] = passive.lambda;
        x[self.lambda(LoadState::Loaded)] = loaded.lambda;
        for j in 1..self.n {
            x[self.height(j).unwrap()] = heights[j];
        }
        x
    }

    /// Writes `θ3` (absolute angles) into a packed `x` ([`Layout::pack`]) of a layout with the
    /// probe state.
    pub fn pack_probe(&self, x: &mut [f64], probe: &State) {
        assert!(self.probe, "the layout has no probe state");
        for i in 0..self.n {
            x[self.state_angle(LoadState::Probe, i)] = probe.theta[i] - self.offset(x[self.theta0(i)]);
        }
        x[self.lambda(LoadState::Probe)] = probe.lambda;
    }

    /// The design in physical units (`K = C_K k`).
    pub fn design(&self, x: &[f64], stiffness_scale: f64) -> Design {
        Design {
            theta0: x[..self.n].to_vec(),
            stiffness: (0..=self.n).map(|j| x[self.stiffness(j)] * stiffness_scale).collect(),
        }
    }

    /// State `s` in absolute angles (`θ_i = θ0_i + u_i` for deflections).
    pub fn state(&self, x: &[f64], s: LoadState) -> State {
        let theta = (0..self.n).map(|i| self.offset(x[self.theta0(i)]) + x[self.state_angle(s, i)]).collect();
        State { theta, lambda: x[self.lambda(s)] }
    }

    /// A bounded variable's name in the paper's 1-based numbering: `theta0[i]` (link `i`),
    /// `K[j]` (spring `j`), `Y0[j]` (node `j`'s unloaded height); the states, which have no
    /// bounds, as `theta1[i]`, `theta2[i]`, `theta3[i]`, `lambda1`, `lambda2`, `lambda3`.
    pub fn variable_label(&self, v: usize) -> String {
        let n = self.n;
        match v {
            v if v < n => format!("theta0[{}]", v + 1),
            v if v <= 2 * n => format!("K[{}]", v - n + 1),
            v if v < 3 * n + 1 => format!("theta1[{}]", v - 2 * n),
            v if v == 3 * n + 1 => "lambda1".into(),
            v if v < 4 * n + 2 => format!("theta2[{}]", v - 3 * n - 1),
            v if v == 4 * n + 2 => "lambda2".into(),
            v if v < self.probe_variables() => format!("Y0[{}]", v - 4 * n - 2 + 1),
            v if v < self.probe_variables() + n => format!("theta3[{}]", v - self.probe_variables() + 1),
            _ => "lambda3".into(),
        }
    }

    /// A constraint row's name: the equilibrium rows, `Y0 step[j]`, `end displacement`, and the
    /// relative angles `theta0[i]-theta0[i+1]` (1-based).
    pub fn row_label(&self, r: usize) -> String {
        let n = self.n;
        match r {
            r if r <= n => format!("passive equilibrium[{}]", r + 1),
            r if r <= 2 * n + 1 => format!("loaded equilibrium[{}]", r - n),
            r if r < 3 * n + 2 => format!("Y0 step[{}]", r - 2 * n - 1),
            r if r == 3 * n + 2 => "end displacement".into(),
            r if r < self.probe_rows() => format!("theta0[{}]-theta0[{}]", r - 3 * n - 2, r - 3 * n - 1),
            r if r < self.budget_row() => format!("probe equilibrium[{}]", r - self.probe_rows() + 1),
            _ => "strain energy budget".into(),
        }
    }

    /// What a state variable is measured from: `θ0_i` for deflections, 0 for absolute angles.
    fn offset(&self, theta0: f64) -> f64 {
        match self.states {
            StateForm::Absolute => 0.0,
            StateForm::Deflection => theta0,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn labels_follow_the_index_map() {
        let l = Layout { n: 4, states: StateForm::Absolute, probe: false, budget: false };
        assert_eq!(l.variable_label(l.theta0(0)), "theta0[1]");
        assert_eq!(l.variable_label(l.stiffness(4)), "K[5]");
        assert_eq!(l.variable_label(l.state_angle(LoadState::Passive, 3)), "theta1[4]");
        assert_eq!(l.variable_label(l.lambda(LoadState::Passive)), "lambda1");
        assert_eq!(l.variable_label(l.state_angle(LoadState::Loaded, 0)), "theta2[1]");
        assert_eq!(l.variable_label(l.lambda(LoadState::Loaded)), "lambda2");
        assert_eq!(l.variable_label(l.height(1).unwrap()), "Y0[2]");
        assert_eq!(l.variable_label(l.height(3).unwrap()), "Y0[4]");
        assert_eq!(l.row_label(l.equilibrium_row(LoadState::Passive, 0)), "passive equilibrium[1]");
        assert_eq!(l.row_label(l.constraint_row(LoadState::Loaded)), "loaded equilibrium[5]");
        assert_eq!(l.row_label(l.height_row(0)), "Y0 step[1]");
        assert_eq!(l.row_label(l.height_row(3)), "Y0 step[4]");
        assert_eq!(l.row_label(l.end_row()), "end displacement");
        assert_eq!(l.row_label(l.relative_row(0)), "theta0[1]-theta0[2]");
        assert_eq!(l.row_label(l.relative_row(2)), "theta0[3]-theta0[4]");
        assert_eq!(l.num_constraints(), l.relative_row(2) + 1);
        assert_eq!(l.num_variables(), l.height(3).unwrap() + 1);
        let p = Layout { probe: true, ..l };
        assert_eq!(p.variable_label(p.state_angle(LoadState::Probe, 0)), "theta3[1]");
        assert_eq!(p.variable_label(p.state_angle(LoadState::Probe, 3)), "theta3[4]");
        assert_eq!(p.variable_label(p.lambda(LoadState::Probe)), "lambda3");
        assert_eq!(p.num_variables(), p.lambda(LoadState::Probe) + 1);
        assert_eq!(p.row_label(p.relative_row(2)), "theta0[3]-theta0[4]");
        assert_eq!(p.row_label(p.equilibrium_row(LoadState::Probe, 0)), "probe equilibrium[1]");
        assert_eq!(p.row_label(p.constraint_row(LoadState::Probe)), "probe equilibrium[5]");
        assert_eq!(p.num_constraints(), p.constraint_row(LoadState::Probe) + 1);
        let b = Layout { budget: true, ..p };
        assert_eq!(b.row_label(b.budget_row()), "strain energy budget");
        assert_eq!(b.row_label(b.constraint_row(LoadState::Probe)), "probe equilibrium[5]");
        assert_eq!(b.num_constraints(), b.budget_row() + 1);
    }
}
