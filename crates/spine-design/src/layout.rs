//! Where each quantity of eq. (33) sits in the full-space variable and constraint vectors (the
//! table of [`crate::full_space`]).

use spine_model::{Design, State};

/// Index map of the full-space variables and constraints.
#[derive(Clone, Copy, Debug)]
pub struct Layout {
    pub n: usize,
    /// How the two states are Ipopt's variables.
    pub states: StateForm,
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

/// The two load states.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum LoadState {
    Passive,
    Loaded,
}

impl Layout {
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
        }
    }
    pub fn lambda(&self, s: LoadState) -> usize {
        self.state_angle(s, self.n)
    }
    /// Interior node `j = 1..N−1` (0-based node index; node 0 is the base, node N the end).
    pub fn height(&self, j: usize) -> Option<usize> {
        (j >= 1 && j < self.n).then(|| 4 * self.n + 2 + j)
    }
    pub fn num_variables(&self) -> usize {
        5 * self.n + 2
    }

    pub fn equilibrium_row(&self, s: LoadState, i: usize) -> usize {
        match s {
            LoadState::Passive => i,
            LoadState::Loaded => self.n + 1 + i,
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
    pub fn num_constraints(&self) -> usize {
        4 * self.n + 2
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

    /// What a state variable is measured from: `θ0_i` for deflections, 0 for absolute angles.
    fn offset(&self, theta0: f64) -> f64 {
        match self.states {
            StateForm::Absolute => 0.0,
            StateForm::Deflection => theta0,
        }
    }
}
