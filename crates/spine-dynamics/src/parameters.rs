//! Which parameters a simulation differentiates with respect to (its sensitivities, its
//! adjoint's products).

/// The parameters `p` whose sensitivities `∂y/∂p` a [`crate::SpineOde`] propagates (and whose
/// products [`crate::vjp`] gives).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Parameters {
    /// None: a plain simulation.
    #[default]
    None,
    /// The dampers `C_1..C_{N+1}`, N·m·s/rad (eq. (35)).
    Dampers,
    /// The springs `K_1..K_{N+1}`, N·m/rad (eq. (37)).
    Springs,
}
