//! The rates of eq. (33)'s problem along a parameter of a design case
//! ([`DesignCase::parameter_tangent`]): which of the problem's numbers the case's validation moves
//! when the field changes, and how fast. Every parameter of eq. (33) enters the problem affinely
//! (a load, a span, a mass, gravity, a bound, `δ_d`, `C_K`, the load factor), so these rates are
//! exact at every value; tests check them against problems rebuilt through
//! [`DesignCase::with_parameter`] and validation.

use crate::design_case::DesignCase;
use crate::error::CaseError;
use crate::parameter::{split, LOAD_SCALE};
use crate::per_item::PerItem;
use spine_design::{DesignProblem, ProblemTangent};

impl DesignCase {
    /// The rates of `problem`'s numbers (this case's problem, or the problem at another value of
    /// the same parameter) per unit of the parameter `name`, as this case's validation maps the
    /// field to the problem.
    pub fn parameter_tangent(&self, name: &str, problem: &DesignProblem) -> Result<ProblemTangent, CaseError> {
        self.parameter_value(name)?;
        let (field, index) = split(name)?;
        let mut tangent = ProblemTangent::zero(problem);
        let n = self.chain.links;
        let rates = tangent.rates_mut();
        let unit = |v: &mut Vec<f64>, index: Option<usize>| match index {
            Some(i) => v[i] = 1.0,
            None => v.iter_mut().for_each(|x| *x = 1.0),
        };
        // The default upper height bound is a quarter of L_x = Σ a_i.
        let height_max_rate = if self.bounds.height_max.is_none() { 0.25 } else { 0.0 };
        let s = &mut rates.structure;
        match field {
            "delta_d" => rates.delta_d = 1.0,
            "stiffness_scale" => rates.stiffness_scale = 1.0,
            LOAD_SCALE => s.passive.p_y.clone_from(&self.loads.p_y.expand(LOAD_SCALE, n + 1, "one per node")?),
            "loads.p_y" => unit(&mut s.passive.p_y, index),
            // One number is the end node's axial force; a list gives one per node.
            "loads.p_x" => match (&self.loads.p_x, index) {
                (PerItem::Uniform(_), None) => s.actuation.p_x[n] = 1.0,
                (_, i) => unit(&mut s.actuation.p_x, i),
            },
            "chain.length_x" => {
                s.chain.spans.iter_mut().for_each(|a| *a = 1.0 / n as f64);
                rates.bounds.height_max = height_max_rate;
            }
            "chain.spans" => {
                unit(&mut s.chain.spans, index);
                let moved: f64 = s.chain.spans.iter().sum();
                rates.bounds.height_max = height_max_rate * moved;
            }
            "chain.masses" => unit(&mut s.chain.masses, index),
            // Without self-weight the case's gravity does not reach the problem.
            "chain.gravity" => s.chain.gravity = if self.loads.self_weight { 1.0 } else { 0.0 },
            "bounds.theta0_max" => rates.bounds.theta0_max = 1.0,
            "bounds.relative_angle_max" => rates.bounds.relative_angle_max = 1.0,
            "bounds.stiffness_min" => unit(&mut rates.bounds.stiffness_min, index),
            "bounds.stiffness_max" => unit(&mut rates.bounds.stiffness_max, index),
            "bounds.height_min" => rates.bounds.height_min = 1.0,
            "bounds.height_max" => rates.bounds.height_max = 1.0,
            "bounds.height_ramp" => rates.bounds.height_ramp = 1.0,
            other => {
                return Err(CaseError::invalid("--param", format!("`{other}` has no rates in eq. (33)'s problem")))
            }
        }
        if !tangent.fits(problem) {
            return Err(CaseError::invalid("--param", format!("`{name}`: the problem is not this case's shape")));
        }
        Ok(tangent)
    }
}

#[cfg(test)]
mod tests {
    use crate::Case;
    use spine_design::ProblemTangent;

    fn case(text: &str) -> crate::DesignCase {
        let Case::Design(c) = Case::from_json(text).unwrap() else { panic!("a design case") };
        c
    }

    /// The tangent equals the secant of the problems the case's own validation builds at `p` and
    /// `p + h` (exact for the affine maps of every parameter; `p − h` may leave the case's
    /// range), for every kind of parameter (uniform and per-item fields, defaults that follow
    /// `L_x`, self-weight on and off), on cases given by `L_x` and by spans.
    #[test]
    fn tangents_match_the_rebuilt_problems() {
        let design5 = case(include_str!("../../../paper-cases/design5.json"));
        let mut by_spans = design5.clone();
        by_spans.chain.length_x = None;
        by_spans.chain.spans = Some(vec![0.09, 0.1, 0.11, 0.1, 0.1]);
        by_spans.chain.masses = crate::per_item::PerItem::Each(vec![0.1, 0.2, 0.3, 0.2, 0.1]);
        by_spans.loads.p_x = crate::per_item::PerItem::Each(vec![0.0, 0.0, -50.0, 0.0, -350.0, 0.0]);
        let mut weightless = design5.clone();
        weightless.loads.self_weight = false;
        weightless.chain.masses = crate::per_item::PerItem::Uniform(0.3);
        let names = [
            "delta_d",
            "stiffness_scale",
            "loads.scale",
            "loads.p_y[2]",
            "loads.p_x",
            "loads.p_x[4]",
            "chain.length_x",
            "chain.spans[1]",
            "chain.masses",
            "chain.masses[3]",
            "chain.gravity",
            "bounds.theta0_max",
            "bounds.relative_angle_max",
            "bounds.stiffness_min",
            "bounds.stiffness_max[2]",
            "bounds.height_min",
            "bounds.height_ramp",
        ];
        let mut checked = 0;
        for c in [&design5, &by_spans, &weightless] {
            let problem = c.validate().unwrap().problem;
            for name in names {
                let Ok(value) = c.parameter_value(name) else { continue };
                let tangent = c.parameter_tangent(name, &problem).unwrap();
                let h = 1e-3 * value.abs().max(1.0);
                let at =
                    |v: f64| ProblemTangent::flatten(&c.with_parameter(name, v).unwrap().validate().unwrap().problem);
                let (hi, lo) = (at(value + h), at(value));
                for (k, (&t, (a, b))) in
                    ProblemTangent::flatten(tangent.rates()).iter().zip(hi.iter().zip(&lo)).enumerate()
                {
                    let secant = (a - b) / h;
                    assert!((t - secant).abs() <= 1e-9 * (1.0 + secant.abs()), "{name}, number {k}: {t} vs {secant}");
                }
                checked += 1;
            }
        }
        assert!(checked >= 40, "only {checked} parameters checked");
    }
}
