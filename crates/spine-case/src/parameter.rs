//! Numeric fields of a design case as parameters of eq. (33), named by their field path:
//! `delta_d`, `loads.p_x`, `loads.p_y`, `loads.p_y[3]` (node 3; a single number in the file is
//! expanded to one per node), `stiffness_scale`, `chain.length_x`, `chain.masses`,
//! `bounds.stiffness_max[2]`, …, and `loads.scale`, a factor on the transverse load vector
//! (value 1). [`DesignCase::with_parameter`] returns the case with one of them changed, so that the
//! problem at another value is built by the same validation as the case itself.

use crate::design_case::DesignCase;
use crate::error::CaseError;
use serde_json::Value;

/// The factor on the whole transverse load vector `loads.p_y`.
pub const LOAD_SCALE: &str = "loads.scale";

/// Fields with one entry per node (`N + 1`) or per link (`N`) when given as a list.
fn entries(field: &str, links: usize) -> Option<usize> {
    match field {
        "loads.p_y" | "loads.p_x" | "bounds.stiffness_min" | "bounds.stiffness_max" => Some(links + 1),
        "chain.masses" | "chain.spans" => Some(links),
        _ => None,
    }
}

/// `field[index]` split into the field and the index.
pub(crate) fn split(name: &str) -> Result<(&str, Option<usize>), CaseError> {
    match name.split_once('[') {
        None => Ok((name, None)),
        Some((field, rest)) => {
            let index = rest
                .strip_suffix(']')
                .and_then(|i| i.parse().ok())
                .ok_or_else(|| CaseError::invalid("--param", format!("`{name}`: an index is written `field[i]`")))?;
            Ok((field, Some(index)))
        }
    }
}

/// A parameter's name with its index written plainly (`loads.p_y[02]` is `loads.p_y[2]`); a name
/// that is not `field[i]` is returned as it is.
///
/// ```
/// assert_eq!(spine_case::canonical_parameter("loads.p_y[02]"), "loads.p_y[2]");
/// assert_eq!(spine_case::canonical_parameter("delta_d"), "delta_d");
/// ```
pub fn canonical_parameter(name: &str) -> String {
    match split(name) {
        Ok((field, Some(i))) => format!("{field}[{i}]"),
        _ => name.to_string(),
    }
}

/// The fields that are numbers of the physics (loads, geometry, masses, gravity, bounds, δ_d,
/// C_K): what a sensitivity or a sweep may change. Counts (`chain.links`), the start, the
/// multi-start's seed and the solver's settings are not parameters of eq. (33).
pub const PHYSICS: [&str; 16] = [
    "delta_d",
    "stiffness_scale",
    "loads.p_y",
    "loads.p_x",
    "chain.length_x",
    "chain.spans",
    "chain.masses",
    "chain.gravity",
    "bounds.theta0_max",
    "bounds.relative_angle_max",
    "bounds.stiffness_min",
    "bounds.stiffness_max",
    "bounds.height_min",
    "bounds.height_max",
    "bounds.height_ramp",
    LOAD_SCALE,
];

/// The number at the field path `name` of the case's JSON (`links`: the case's `N`, for the length
/// of a per-item field given as one number).
fn number(json: &Value, name: &str, links: usize) -> Result<f64, CaseError> {
    let (field, index) = split(name)?;
    if !PHYSICS.contains(&field) {
        return Err(CaseError::invalid(
            "--param",
            format!(
                "`{}` is not a parameter of eq. (33); allowed: {} (a list field with an index, e.g. loads.p_y[2])",
                spine_check::shown(name),
                PHYSICS.join(", ")
            ),
        ));
    }
    let value = field.split('.').try_fold(json, |v, key| v.get(key)).filter(|v| !v.is_null());
    // The ramp is left out of the case's JSON at its default, the paper's bound.
    let ramp = Value::from(0.0);
    let value = value.or((field == "bounds.height_ramp").then_some(&ramp));
    let number = match (value, index) {
        (Some(Value::Number(x)), None) => x.as_f64(),
        (Some(Value::Number(x)), Some(i)) if entries(field, links).is_some_and(|len| i < len) => x.as_f64(),
        (Some(Value::Array(items)), Some(i)) => items.get(i).and_then(Value::as_f64),
        _ => None,
    };
    number.ok_or_else(|| {
        CaseError::invalid(
            "--param",
            format!("`{name}` is not a number of this case (a field path such as delta_d, loads.p_y[2], chain.length_x, or {LOAD_SCALE})"),
        )
    })
}

impl DesignCase {
    /// The parameters a sensitivity reports by default: `δ_d`, the loads (`loads.scale`, each
    /// node's `loads.p_y[i]` and `loads.p_x`), `C_K`, `L_x`, the masses where the chain has any,
    /// and the scalar bounds.
    pub fn default_parameters(&self) -> Vec<String> {
        let n = self.chain.links;
        let mut out = vec!["delta_d".to_string(), LOAD_SCALE.to_string()];
        out.extend((1..=n).map(|i| format!("loads.p_y[{i}]")));
        out.push("loads.p_x".into());
        out.push("stiffness_scale".into());
        if self.chain.length_x.is_some() {
            out.push("chain.length_x".into());
        }
        if self.parameter_value("chain.masses").is_ok_and(|m| m != 0.0) {
            out.push("chain.masses".into());
        }
        out.extend(
            ["bounds.stiffness_min", "bounds.stiffness_max", "bounds.theta0_max", "bounds.relative_angle_max"]
                .into_iter()
                .filter(|f| self.parameter_value(f).is_ok())
                .map(String::from),
        );
        out
    }

    /// The value of a parameter in this case.
    pub fn parameter_value(&self, name: &str) -> Result<f64, CaseError> {
        if name == LOAD_SCALE {
            return Ok(1.0);
        }
        number(&self.to_json()?, name, self.chain.links)
    }

    /// The case as JSON, the form its parameters are read and changed in.
    fn to_json(&self) -> Result<Value, CaseError> {
        serde_json::to_value(self).map_err(|e| CaseError::invalid("--param", e.to_string()))
    }

    /// This case with the parameter set to `value` (a per-item field given as one number is
    /// expanded to one per item first when one entry changes).
    pub fn with_parameter(&self, name: &str, value: f64) -> Result<DesignCase, CaseError> {
        let mut json = self.to_json()?;
        if name == LOAD_SCALE {
            let p_y = &mut json["loads"]["p_y"];
            *p_y = match p_y.take() {
                Value::Array(items) => items.iter().map(|v| v.as_f64().unwrap_or(0.0) * value).collect(),
                other => Value::from(other.as_f64().unwrap_or(0.0) * value),
            };
        } else {
            number(&json, name, self.chain.links)?;
            let (field, index) = split(name)?;
            let mut slot = &mut json;
            for key in field.split('.') {
                slot = &mut slot[key];
            }
            match index {
                None => *slot = Value::from(value),
                Some(i) => {
                    if let Some(x) = slot.as_f64() {
                        let len = entries(field, self.chain.links).unwrap_or(i + 1);
                        *slot = Value::Array(vec![Value::from(x); len]);
                    }
                    slot[i] = Value::from(value);
                }
            }
        }
        serde_json::from_value(json).map_err(|e| CaseError::invalid(name, e.to_string()))
    }
}

#[cfg(test)]
mod tests {
    use crate::Case;

    fn design5() -> crate::DesignCase {
        let text = include_str!("../../../paper-cases/design5.json");
        let Case::Design(c) = Case::from_json(text).unwrap() else { panic!("design5 is a design case") };
        c
    }

    #[test]
    fn the_documented_parameters_are_the_parsers() {
        let doc = include_str!("../../../docs/sensitivity.md");
        let (_, rest) = doc.split_once("<!-- parameters: begin -->").expect("docs/sensitivity.md has the list");
        let (list, _) = rest.split_once("<!-- parameters: end -->").expect("the list ends");
        let documented: Vec<&str> = list.split('`').skip(1).step_by(2).collect();
        assert_eq!(documented, super::PHYSICS, "docs/sensitivity.md's parameter list is not spine_case's PHYSICS");
        assert_eq!(design5().parameter_value("bounds.height_ramp").unwrap(), 0.0, "the ramp is a parameter");
    }

    #[test]
    fn parameters_are_read_and_changed_by_field_path() {
        let case = design5();
        assert_eq!(case.parameter_value("delta_d").unwrap(), -0.02);
        assert_eq!(case.parameter_value("loads.p_y[2]").unwrap(), -10.0);
        assert_eq!(case.parameter_value("loads.scale").unwrap(), 1.0);
        let changed = case.with_parameter("loads.p_y[2]", -12.0).unwrap();
        let problem = changed.validate().unwrap().problem;
        let original = case.validate().unwrap().problem;
        assert_eq!(problem.structure.passive.p_y[2], -12.0);
        assert_eq!(problem.structure.passive.p_y[3], original.structure.passive.p_y[3]);
        let scaled = case.with_parameter("loads.scale", 2.0).unwrap().validate().unwrap().problem;
        assert_eq!(scaled.structure.passive.p_y[4], 2.0 * original.structure.passive.p_y[4]);
        assert_eq!(case.with_parameter("delta_d", -0.03).unwrap().validate().unwrap().problem.delta_d, -0.03);
        assert!(case.default_parameters().contains(&"chain.length_x".to_string()));
        for bad in
            ["nothing", "loads.p_y[9]", "loads.p_y[x]", "title", "start.theta0[0]", "chain.links", "multistart.seed"]
        {
            let err = case.parameter_value(bad).unwrap_err().to_string();
            assert!(err.contains("--param"), "{bad}: {err}");
        }
    }
}
