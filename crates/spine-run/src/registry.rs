//! The registry of the workspace's kinds: `spine_case::case_kinds!` expanded by
//! [`define_results!`](crate::define_results) into the one result enum [`KindResult`] and the one
//! dispatch ([`run_kind`], [`in_figure`], [`moves`]). Above every runner; nothing below imports it.

use spine_case::Case;

spine_case::case_kinds!(crate::define_results);

#[cfg(test)]
mod tests {
    //! The add-a-kind recipe, followed by a kind of this test's own: a case type, its runner and
    //! its line in a registry (here a list of two kinds handed to the same macros that make the
    //! workspace's), then parsed, run and written as any kind is.

    use crate::{KindOutput, RunContext, RunError, RunKind};
    use serde::{Deserialize, Serialize};

    /// 1. The case type: `"kind": "tally"` counts the links of a chain and the springs they need.
    #[derive(Clone, Debug, PartialEq, Serialize, Deserialize, spine_case::__private::schemars::JsonSchema)]
    #[schemars(crate = "spine_case::__private::schemars")]
    #[serde(deny_unknown_fields)]
    pub struct TallyCase {
        #[serde(default)]
        pub title: String,
        pub chain: spine_case::ChainSpec,
    }

    impl TallyCase {
        pub fn validate(&self) -> Result<spine_model::Chain, spine_case::CaseError> {
            self.chain.validate()
        }
    }

    /// 2. Its result and its runner.
    #[derive(Clone, Debug, Serialize)]
    pub struct TallyResult {
        pub links: usize,
        pub springs: usize,
    }

    impl std::fmt::Display for TallyResult {
        fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
            writeln!(f, "{} links, {} springs", self.links, self.springs)
        }
    }

    impl KindOutput for TallyResult {
        fn is_clean(&self) -> bool {
            self.springs == self.links + 1
        }
    }

    /// A figure may hold it: inside a figure the run is its own result, which a recipe asks for
    /// by type.
    impl crate::InFigure for TallyResult {
        const KIND: &'static str = "tally";
    }

    impl RunKind for TallyCase {
        type Output = TallyResult;
        const IN_FIGURE: bool = true;
        fn run(&self, _: &mut RunContext<'_>) -> Result<TallyResult, RunError> {
            let chain = self.validate()?;
            Ok(TallyResult { links: chain.n_links(), springs: chain.n_links() + 1 })
        }
        fn in_figure(
            &self,
            _: Option<&crate::workers::Workers>,
            _: &mut dyn FnMut(crate::Progress<'_>),
        ) -> Option<Result<crate::RunOutput, RunError>> {
            let overrides = crate::Overrides::default();
            let mut cx = RunContext {
                overrides: &overrides,
                recipes: &crate::NoRecipes,
                progress: &mut crate::quiet,
                figure_run: &crate::in_figure,
            };
            Some(self.run(&mut cx).map(crate::RunOutput::new))
        }
    }

    /// 3. The registry line (this test's registry: the equilibrium kind and the new one).
    // The commands' variants and a few methods are not used by this test.
    #[allow(dead_code)]
    mod registry {
        use super::TallyCase;
        macro_rules! test_kinds {
            ($($then:tt)+) => {
                $($then)+! {
                    Equilibrium(spine_case::EquilibriumCase) = "equilibrium",
                    /// `"kind": "tally"`.
                    Tally(TallyCase) = "tally",
                }
            };
        }
        test_kinds!(spine_case::define_cases);
        test_kinds!(crate::define_results);
    }

    #[test]
    fn a_kind_added_by_the_recipe_parses_runs_and_writes_its_result() {
        use registry::{json_schema, run_kind, Case, KindResult, KINDS};
        assert_eq!(KINDS, ["equilibrium", "tally"]);
        let case = Case::from_json(r#"{ "kind": "tally", "chain": { "links": 4, "length_x": 1.0 } }"#).unwrap();
        assert_eq!(case.kind(), "tally");
        case.check().unwrap();
        let overrides = crate::Overrides::default();
        let mut cx = RunContext {
            overrides: &overrides,
            recipes: &crate::NoRecipes,
            progress: &mut crate::quiet,
            figure_run: &crate::in_figure,
        };
        let result = run_kind(&case, &mut cx).unwrap();
        assert!(matches!(result, KindResult::Tally(TallyResult { links: 4, springs: 5 })));
        assert!(result.is_clean());
        assert_eq!(result.kind(), "tally");
        let json = crate::with_timings(&result);
        assert_eq!(json["kind"], "tally");
        assert_eq!(json["springs"], 5);
        assert_eq!(result.to_string(), "4 links, 5 springs\n");
        // Errors name the field, as for every kind; the schema has the new kind's alternative.
        let bad = Case::from_json(r#"{ "kind": "tally", "chain": { "links": 0, "length_x": 1.0 } }"#).unwrap();
        assert!(bad.check().unwrap_err().to_string().starts_with("chain.links"));
        let unknown = Case::from_json(r#"{ "kind": "tallies" }"#).unwrap_err().to_string();
        assert!(unknown.contains("one of equilibrium, tally"), "{unknown}");
        assert_eq!(json_schema()["oneOf"][1]["properties"]["kind"]["const"], "tally");
        // A figure may hold it: the run is the kind's own value, found by its type and written
        // with the kind's tag; the error for a kind a figure cannot hold names the new one.
        let held = registry::in_figure(&case, None, &mut crate::quiet).unwrap();
        assert_eq!(held.kind(), "tally");
        assert_eq!(held.get::<TallyResult>().map(|t| (t.links, t.springs)), Some((4, 5)));
        assert!(held.get::<crate::StaticDesign>().is_none());
        let written = serde_json::to_value(&held).unwrap();
        assert_eq!(written, serde_json::json!({ "kind": "tally", "links": 4, "springs": 5 }));
        assert_eq!(registry::figure_kinds(), "a \"tally\"");
        let equilibrium = Case::from_json(
            r#"{ "kind": "equilibrium", "chain": { "links": 2, "length_x": 1.0 }, "design": { "theta0": [0.1, -0.1], "stiffness": [1, 1, 1] }, "loads": { "p_y": -1.0 } }"#,
        )
        .unwrap();
        let refused = registry::in_figure(&equilibrium, None, &mut crate::quiet).unwrap_err().to_string();
        assert_eq!(refused, "kind: a figure's run needs a \"tally\" case, the file is \"equilibrium\"");
        assert!(!registry::moves(&case));
    }

    /// The workspace's registry names the kinds a figure may hold, from their runners.
    #[test]
    fn a_figure_holds_the_kinds_whose_runners_say_so() {
        assert_eq!(
            crate::registry::figure_kinds(),
            "a \"twolink\", \"design\", \"simulate\", \"damping\" or \"periodic\""
        );
    }
}
