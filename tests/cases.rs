//! Property tests over whole cases: random valid cases never panic and, when converged, have a
//! small residual; arbitrary text never panics the parser; every paper case file validates.

use proptest::prelude::*;
use spine_case::Case;
use spine_solve::solve_static;

/// A valid equilibrium case: a random antisymmetric shape (so `Σ tan θ0 = 0` holds exactly with equal
/// spans), random stiffness, masses and loads.
fn valid_case() -> impl Strategy<Value = String> {
    (2usize..24)
        .prop_flat_map(|n| {
            (
                Just(n),
                prop::collection::vec(-1.2f64..1.2, n / 2),
                prop::collection::vec(1e1f64..1e4, n + 1),
                0.0f64..0.5,
                -50.0f64..50.0,
                -2000.0f64..500.0,
                0.2f64..3.0,
            )
        })
        .prop_map(|(n, half, k, mass, p_y, p_x, lx)| {
            let mut theta0 = vec![0.0; n];
            for (i, t) in half.iter().enumerate() {
                theta0[i] = *t;
                theta0[n - 1 - i] = -t;
            }
            serde_json::json!({
                "kind": "equilibrium",
                "chain": { "links": n, "length_x": lx, "masses": mass },
                "design": { "theta0": theta0, "stiffness": k },
                "loads": { "p_y": p_y, "p_x": p_x }
            })
            .to_string()
        })
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 200, rng_seed: proptest::test_runner::RngSeed::Fixed(200), ..ProptestConfig::default() })]

    #[test]
    fn random_valid_cases_solve_without_panic(text in valid_case()) {
        let Case::Equilibrium(c) = Case::from_json(&text).unwrap() else { unreachable!() };
        let valid = c.validate().unwrap();
        let sol = solve_static(&valid.problem, &valid.options);
        for eq in std::iter::once(&sol.passive).chain(sol.loaded.as_ref()) {
            prop_assert!(eq.residual_norm.is_finite());
            if eq.load_factor == 1.0 {
                prop_assert!(eq.residual_norm <= eq.tolerance_used.max(1e-10), "{} > {}", eq.residual_norm, eq.tolerance_used);
                prop_assert!(eq.constraint_violation <= 1e-10);
            }
            if eq.status.is_stable() {
                prop_assert!(eq.stability.stable);
            }
        }
    }

    #[test]
    fn arbitrary_text_never_panics_the_parser(text in ".{0,400}") {
        if let Ok(Case::Equilibrium(c)) = Case::from_json(&text) {
            let _ = c.validate();
        }
    }

    #[test]
    fn mangled_valid_cases_never_panic(text in valid_case(), cut in 0usize..2000, byte in 0u8..128) {
        let mut bytes = text.into_bytes();
        if !bytes.is_empty() {
            let i = cut % bytes.len();
            bytes[i] = byte;
        }
        let text = String::from_utf8_lossy(&bytes);
        if let Ok(case) = Case::from_json(&text) {
            let _ = case.check();
        }
    }
}

#[test]
fn every_paper_case_validates() {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../paper-cases");
    let mut count = 0;
    for entry in std::fs::read_dir(&dir).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().is_some_and(|e| e == "json") {
            let text = std::fs::read_to_string(&path).unwrap();
            let ok = Case::from_json(&text).unwrap_or_else(|e| panic!("{}: {e}", path.display())).check();
            ok.unwrap_or_else(|e| panic!("{}: {e}", path.display()));
            count += 1;
        }
    }
    assert!(count >= 2);
}

/// Stable fuzzing (issue 19; cargo-fuzz needs nightly): every paper case, of every kind, mutated
/// 500 times by the seeded generator [`spine_case::fuzz::Mutator`] (extreme values of every JSON
/// type, keys removed, unknown keys added) and fed to `spine_case::fuzz::check_bytes`, the fuzz
/// target's own body. None may panic. `FUZZ_CASES` raises the count (`just fuzz-long`).
#[test]
fn mutated_paper_cases_never_panic_the_validator() {
    let per_case: usize = std::env::var("FUZZ_CASES").ok().and_then(|v| v.parse().ok()).unwrap_or(500);
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../paper-cases");
    let mut mutator = spine_case::fuzz::Mutator::new(1);
    let (mut tried, mut valid) = (0, 0);
    let mut files: Vec<_> = std::fs::read_dir(&dir).unwrap().map(|e| e.unwrap().path()).collect();
    files.sort();
    for path in files.iter().filter(|p| p.extension().is_some_and(|e| e == "json")) {
        let original: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap();
        for _ in 0..per_case {
            let text = mutator.mutate(&original).to_string();
            match std::panic::catch_unwind(|| spine_case::fuzz::check_bytes(text.as_bytes())) {
                Ok(ok) => valid += usize::from(ok),
                Err(_) => panic!("{}: the validator panicked on\n{text}", path.display()),
            }
            tried += 1;
        }
    }
    assert!(tried >= 300, "{tried} mutated cases");
    eprintln!("{tried} mutated cases, {valid} still valid");
}

/// The registry of case kinds (`spine_case::KINDS`) is the only list of kinds: every kind it holds
/// has its section in `docs/case-format.md` (a heading naming it) and at least one paper case that
/// runs it (as the file's kind or as a figure's run), so a kind added to the registry without its
/// documentation or a case fails here.
#[test]
fn every_registered_kind_has_its_docs_section_and_a_paper_case() {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let docs = std::fs::read_to_string(root.join("docs/case-format.md")).unwrap();
    let headings: Vec<&str> = docs.lines().filter(|l| l.starts_with('#')).collect();
    let mut run_kinds = std::collections::BTreeSet::new();
    for entry in std::fs::read_dir(root.join("paper-cases")).unwrap() {
        let path = entry.unwrap().path();
        let text = std::fs::read_to_string(&path).unwrap();
        let case = Case::from_json(&text).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        run_kinds.insert(case.kind());
        if let Case::Figure(f) = &case {
            run_kinds.extend(f.validate().unwrap().iter().map(|r| r.case.kind()));
        }
    }
    for kind in spine_case::KINDS {
        let quoted = format!("\"kind\": \"{kind}\"");
        let named = format!("`{kind}`");
        assert!(
            headings.iter().any(|h| h.contains(&quoted) || h.contains(&named)),
            "docs/case-format.md has no section for kind {kind:?}"
        );
        assert!(run_kinds.contains(kind), "no paper case runs kind {kind:?}");
    }
}

/// `docs/case.schema.json` is the schema generated from the Rust types (regenerate it with
/// `SPINE_UPDATE_SCHEMA=1 cargo test -p spine-integration-tests --test cases`), and every paper case
/// is valid against it, while files the parser refuses for their shape are invalid against it too.
#[test]
fn the_shipped_schema_is_generated_and_every_paper_case_is_valid_against_it() {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let path = root.join("docs/case.schema.json");
    let generated = spine_case::json_schema();
    let text = serde_json::to_string_pretty(&generated).unwrap() + "\n";
    if std::env::var_os("SPINE_UPDATE_SCHEMA").is_some() {
        std::fs::write(&path, &text).unwrap();
    }
    let shipped = std::fs::read_to_string(&path).unwrap_or_default();
    assert!(shipped == text, "docs/case.schema.json is stale: regenerate it with SPINE_UPDATE_SCHEMA=1");
    let validator = jsonschema::draft202012::new(&generated).expect("the schema is a valid draft 2020-12 schema");
    let mut checked = 0;
    for entry in std::fs::read_dir(root.join("paper-cases")).unwrap() {
        let p = entry.unwrap().path();
        let case: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(&p).unwrap()).unwrap();
        let errors: Vec<String> =
            validator.iter_errors(&case).map(|e| format!("{} at {}", e, e.instance_path())).collect();
        assert!(errors.is_empty(), "{}: {errors:?}", p.display());
        checked += 1;
    }
    assert!(checked >= 20, "only {checked} paper cases");
    for bad in [
        serde_json::json!({ "kind": "equilibrium", "chain": { "links": 2, "length_x": 1.0, "lenght": 1 },
            "design": { "theta0": [0.1, -0.1], "stiffness": 100 }, "loads": { "p_y": -1, "p_x": -1 } }),
        serde_json::json!({ "kind": "simulate_all" }),
        serde_json::json!({ "kind": "design", "delta_d": "-0.02" }),
    ] {
        assert!(!validator.is_valid(&bad), "the schema accepts {bad}");
        assert!(Case::from_json(&bad.to_string()).is_err(), "the parser accepts {bad}");
    }
}

/// Parse → serialise → parse gives the same case, for every paper case (every kind) and for random
/// valid cases; the serialised text validates the same.
#[test]
fn every_paper_case_round_trips_through_its_json() {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    for entry in std::fs::read_dir(root.join("paper-cases")).unwrap() {
        let p = entry.unwrap().path();
        let case = Case::from_json(&std::fs::read_to_string(&p).unwrap()).unwrap();
        let again = Case::from_json(&case.to_json().to_string())
            .unwrap_or_else(|e| panic!("{}: its own JSON is refused: {e}", p.display()));
        assert_eq!(again, case, "{}", p.display());
        assert_eq!(again.to_json(), case.to_json(), "{}", p.display());
        assert!(again.check().is_ok(), "{}", p.display());
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 100, rng_seed: proptest::test_runner::RngSeed::Fixed(100), ..ProptestConfig::default() })]
    #[test]
    fn random_valid_cases_round_trip_through_their_json(text in valid_case()) {
        let case = Case::from_json(&text).unwrap();
        let again = Case::from_json(&case.to_json().to_string()).unwrap();
        prop_assert_eq!(&again, &case);
    }
}
