//! The parts of a case file that several kinds share (notes, chain, given design, loads, the
//! continuation options) and the validators of single values.

use crate::error::CaseError;
use crate::parse::INNER_PATH;
use crate::per_item::check_finite;
use crate::per_item::PerItem;
use serde::{Deserialize, Serialize};
use spine_model::kinematics::end_constraint;
use spine_model::{Chain, Design, LinkLoads, NodalLoads, State};
use spine_solve::ContinuationOptions;
use std::f64::consts::FRAC_PI_2;

/// Where the numbers come from: what the paper states, and every value it does not state with the
/// reason for the choice.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct Notes {
    /// Values and statements taken from the paper.
    #[serde(default)]
    pub paper: Vec<String>,
    /// Values the paper does not give, each with the reason for the choice.
    #[serde(default)]
    pub assumptions: Vec<Assumption>,
}

/// A value chosen where the paper is silent.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct Assumption {
    /// The field (e.g. `chain.length_x`).
    pub what: String,
    /// Why this value.
    pub reason: String,
}

/// The chain: number of links, spans, masses, gravity.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct ChainSpec {
    /// Number of links `N` (≥ 1).
    pub links: usize,
    /// Total horizontal length `L_x`, m, split into `N` equal spans. Give this or `spans`.
    #[serde(default)]
    pub length_x: Option<f64>,
    /// Horizontal span of each link, m (`N` entries, each > 0). Give this or `length_x`.
    #[serde(default)]
    pub spans: Option<Vec<f64>>,
    /// Link masses, kg: one number for all links or `N` numbers (default 0).
    #[serde(default)]
    pub masses: PerItem,
    /// Gravitational acceleration along −Y, m/s² (default 9.81).
    #[serde(default = "default_gravity")]
    pub gravity: f64,
}

fn default_gravity() -> f64 {
    spine_model::STANDARD_GRAVITY
}

/// A given design.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct GivenDesign {
    /// Unloaded link angles `θ0`, rad (`N` entries, `|θ0| < π/2`, `Σ a_i tan θ0_i = 0`).
    pub theta0: Vec<f64>,
    /// Spring stiffnesses `K`, N·m/rad: one number or `N + 1` numbers, each ≥ 0.
    pub stiffness: PerItem,
}

/// `"design": {"theta0": …, "stiffness": …}` or `"design": "optimise"` (found by the optimiser).
#[derive(Clone, Debug, PartialEq)]
pub enum DesignSpec {
    Given(GivenDesign),
    ToBeOptimised,
}

/// Written as it is read: the given design's object, or `"optimise"`.
impl Serialize for DesignSpec {
    fn serialize<S: serde::Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        match self {
            Self::Given(design) => design.serialize(serializer),
            Self::ToBeOptimised => serializer.serialize_str("optimise"),
        }
    }
}

impl<'de> Deserialize<'de> for DesignSpec {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        use serde::de::Error;
        let v = serde_json::Value::deserialize(d)?;
        match v {
            serde_json::Value::String(s) if s == "optimise" => Ok(Self::ToBeOptimised),
            serde_json::Value::String(s) => {
                Err(D::Error::custom(format!("unknown design keyword {s:?}; give \"optimise\" or an object")))
            }
            obj @ serde_json::Value::Object(_) => serde_path_to_error::deserialize::<_, GivenDesign>(obj)
                .map(Self::Given)
                // The inner path travels in the message between two markers; `parse` joins it on.
                .map_err(|e| {
                    let path = e.path().to_string();
                    D::Error::custom(format!("{INNER_PATH}{path}{INNER_PATH}{}", e.into_inner()))
                }),
            _ => Err(D::Error::custom("expected an object {\"theta0\": [...], \"stiffness\": ...} or \"optimise\"")),
        }
    }
}

/// `"optimise"` or a [`GivenDesign`], as [`DesignSpec`] reads them.
impl schemars::JsonSchema for DesignSpec {
    fn schema_name() -> std::borrow::Cow<'static, str> {
        "DesignSpec".into()
    }

    fn json_schema(generator: &mut schemars::SchemaGenerator) -> schemars::Schema {
        let given = generator.subschema_for::<GivenDesign>();
        schemars::json_schema!({
            "description": "The design: given as theta0 and stiffness, or \"optimise\" (found by eq. (33)).",
            "oneOf": [ { "const": "optimise" }, given ]
        })
    }
}

/// Loads: transverse forces (passive) and the axial forces (actuation).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct LoadSpec {
    /// Transverse force `P_Y` at each node, N, positive up: one number for every node or `N + 1`
    /// numbers (node 0 is the base, node `N` the slider).
    pub p_y: PerItem,
    /// Axial force `P_X`, N (negative pushes toward the base): one number, applied at the end node
    /// (the paper's actuation), or `N + 1` numbers, one per node (node 0, the base, carries its
    /// force into the support). Default 0.
    #[serde(default)]
    pub p_x: PerItem,
    /// Include the links' self-weight in the passive load (default true).
    #[serde(default = "yes")]
    pub self_weight: bool,
}

fn yes() -> bool {
    true
}

impl LoadSpec {
    /// The passive load (the transverse forces) and the actuation (the axial forces: one number
    /// at the end node, or one per node) on `chain`, checked; switches the chain's self-weight
    /// off when `self_weight` is false.
    pub fn resolve(&self, chain: &mut Chain) -> Result<(NodalLoads, NodalLoads), CaseError> {
        let n = chain.n_links();
        let p_y = self.p_y.expand("loads.p_y", n + 1, "one per node, N + 1")?;
        let p_x = axial_forces("loads.p_x", &self.p_x, n)?;
        if !self.self_weight {
            chain.gravity = 0.0;
        }
        Ok((NodalLoads { p_x: vec![0.0; n + 1], p_y }, NodalLoads { p_x, p_y: vec![0.0; n + 1] }))
    }
}

/// Axial nodal forces, N, `N + 1`: one number is the force at the end node (the others zero),
/// an array one force per node; errors name `field`.
pub(crate) fn axial_forces(field: &str, p_x: &PerItem, n: usize) -> Result<Vec<f64>, CaseError> {
    match p_x {
        PerItem::Uniform(end) => {
            let mut p_x = vec![0.0; n + 1];
            p_x[n] = *end;
            check_finite(field, &p_x)?;
            Ok(p_x)
        }
        each => each.expand(field, n + 1, "one number for the end node, or one per node, N + 1"),
    }
}

pub(crate) fn positive(field: &str, v: f64, unit: &str) -> Result<f64, CaseError> {
    if v.is_finite() && v > 0.0 {
        Ok(v)
    } else {
        Err(CaseError::invalid(field, format!("must be a finite number > 0 {unit}, got {v}")))
    }
}

pub(crate) fn non_negative(field: &str, values: &[f64], unit: &str) -> Result<(), CaseError> {
    check_finite(field, values)?;
    match values.iter().position(|v| *v < 0.0) {
        Some(i) => Err(CaseError::invalid(format!("{field}[{i}]"), format!("must be ≥ 0 {unit}, got {}", values[i]))),
        None => Ok(()),
    }
}

/// The continuation options of a case (field `solver`), checked by their own rules.
pub fn check_options(o: &ContinuationOptions) -> Result<(), CaseError> {
    Ok(o.validate().map_err(|e| e.under("solver"))?)
}

/// Largest chain accepted from a case file.
pub const MAX_LINKS: usize = 1_000_000;

impl ChainSpec {
    /// The chain, checked.
    pub fn validate(&self) -> Result<Chain, CaseError> {
        let n = self.links;
        if n == 0 || n > MAX_LINKS {
            return Err(CaseError::invalid("chain.links", format!("must be between 1 and {MAX_LINKS}, got {n}")));
        }
        let spans = match (&self.length_x, &self.spans) {
            (Some(lx), None) => vec![positive("chain.length_x", *lx, "m")? / n as f64; n],
            (None, Some(spans)) => {
                if spans.len() != n {
                    return Err(CaseError::invalid(
                        "chain.spans",
                        format!("expected {n} entries (one per link), got {}", spans.len()),
                    ));
                }
                for (i, a) in spans.iter().enumerate() {
                    positive(&format!("chain.spans[{i}]"), *a, "m")?;
                }
                spans.clone()
            }
            _ => {
                return Err(CaseError::invalid("chain", "give exactly one of `length_x` (m) and `spans` (m per link)"))
            }
        };
        let masses = self.masses.expand("chain.masses", n, "one per link")?;
        non_negative("chain.masses", &masses, "kg")?;
        if !(self.gravity.is_finite() && self.gravity >= 0.0) {
            return Err(CaseError::invalid(
                "chain.gravity",
                format!("must be a finite number ≥ 0 m/s², got {}", self.gravity),
            ));
        }
        Ok(Chain { spans, masses, gravity: self.gravity })
    }
}

impl GivenDesign {
    /// The design, checked against the chain: lengths, ranges, `Φ(θ0) = 0`, and a stable unloaded
    /// chain (the springs leave no free mechanism).
    pub fn validate(&self, chain: &Chain) -> Result<Design, CaseError> {
        let n = chain.n_links();
        if self.theta0.len() != n {
            return Err(CaseError::invalid(
                "design.theta0",
                format!("expected {n} entries (one per link), got {}", self.theta0.len()),
            ));
        }
        check_finite("design.theta0", &self.theta0)?;
        if let Some(i) = self.theta0.iter().position(|t| t.abs() >= FRAC_PI_2) {
            return Err(CaseError::invalid(
                format!("design.theta0[{i}]"),
                format!("must satisfy |θ0| < π/2 rad (the link length is a/cos θ0), got {}", self.theta0[i]),
            ));
        }
        let stiffness = self.stiffness.expand("design.stiffness", n + 1, "one per spring, N + 1")?;
        non_negative("design.stiffness", &stiffness, "N·m/rad")?;
        let phi = end_constraint(&chain.spans, &self.theta0, &self.theta0);
        let tol = 1e-9 * chain.length_x();
        if phi.abs() > tol {
            return Err(CaseError::invalid(
                "design.theta0",
                format!(
                    "the unloaded end must lie on the X axis: Σ a_i tan θ0_i = {phi:.3e} m, allowed |Φ| ≤ {tol:.1e} m"
                ),
            ));
        }
        let design = Design { theta0: self.theta0.clone(), stiffness };
        let (_, jac) = spine_model::jacobian::residual_and_state_jacobian(
            &chain.spans,
            &design,
            &LinkLoads::zero(n),
            &State::unloaded(&design),
        );
        let cert = spine_solve::stability::certify(&jac);
        if !cert.stable {
            return Err(CaseError::invalid(
                "design.stiffness",
                format!(
                    "the unloaded chain is not stable: the springs leave a free mechanism (smallest projected stiffness {:.3e} N·m/rad); give more nonzero springs",
                    cert.min_eigenvalue.unwrap_or(0.0)
                ),
            ));
        }
        Ok(design)
    }
}

/// An end displacement `δ = X_{N+1} − L_x` the chain can reach: the links keep within ±π/2 of
/// the X axis (the paper's assumption, and every bound of eq. (33)), so the end stays on the far
/// side of the base, `X_{N+1} > 0`, that is `δ > −L_x`. The error names `field` and the reach.
pub(crate) fn check_reach(field: &str, delta: f64, length_x: f64) -> Result<(), CaseError> {
    if delta > -length_x {
        return Ok(());
    }
    Err(CaseError::invalid(
        field,
        format!(
            "{delta} m is beyond the chain's reach: the end cannot pass the base (X_N+1 > 0 with every link within ±90° of the X axis), so δ > −L_x = {} m",
            -length_x
        ),
    ))
}

/// Bytes one design run of an `links`-link chain keeps until its census is settled (the design,
/// both equilibria, the multipliers of every row and bound, the certificate's numbers: about 25
/// numbers per link, with the run's bookkeeping).
pub fn run_bytes(links: usize) -> f64 {
    200.0 * links as f64 + 4096.0
}

/// `runs` kept design runs of an `links`-link chain within the memory budget
/// ([`spine_stop::memory`]); the error names `field` (the count to lower) and `chain.links`.
pub fn check_runs_memory(field: &str, runs: usize, links: usize) -> Result<(), CaseError> {
    spine_stop::memory::fits(runs as f64 * run_bytes(links)).map_err(|why| {
        CaseError::invalid(field, format!("{runs} runs of a {links}-link chain (chain.links) {why}; give fewer"))
    })
}
