//! The three dynamic kinds (`simulate`, `damping`, `periodic`): one case format
//! ([`DynamicsCase`]), a case type per kind that knows its task.

use crate::dynamics_case::{DynamicKind, DynamicsCase, ValidDynamics};
use crate::error::CaseError;
use serde::{Deserialize, Serialize};

/// The case types of the three dynamic kinds: a [`DynamicsCase`] that knows its kind, so that a
/// case is checked for its task by its type (`SimulateCase::validate`), never by a kind string.
macro_rules! dynamic_kinds {
    ($( $(#[$doc:meta])* $name:ident => $kind:ident, )+) => {$(
        $(#[$doc])*
        #[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
        #[serde(transparent)]
        pub struct $name(pub DynamicsCase);

        /// The schema of a [`DynamicsCase`], inlined: a case file's alternative for this kind
        /// adds `"kind"` to its properties, which a reference would refuse.
        impl schemars::JsonSchema for $name {
            fn schema_name() -> std::borrow::Cow<'static, str> {
                stringify!($name).into()
            }

            fn inline_schema() -> bool {
                true
            }

            fn json_schema(generator: &mut schemars::SchemaGenerator) -> schemars::Schema {
                DynamicsCase::json_schema(generator)
            }
        }

        impl $name {
            /// The kind this case type is.
            pub const KIND: DynamicKind = DynamicKind::$kind;

            /// Checks every value for this kind's task; errors name the field.
            pub fn validate(&self) -> Result<ValidDynamics, CaseError> {
                self.0.validate_for(Self::KIND)
            }
        }

        impl std::ops::Deref for $name {
            type Target = DynamicsCase;
            fn deref(&self) -> &DynamicsCase {
                &self.0
            }
        }
    )+};
}

dynamic_kinds! {
    /// `"kind": "simulate"`: a step or periodic response of a given or eq. (33) design.
    SimulateCase => Simulate,
    /// `"kind": "damping"`: the damping design of eq. (35).
    DampingCase => Damping,
    /// `"kind": "periodic"`: the periodic-load design of eq. (37).
    PeriodicCase => Periodic,
}
