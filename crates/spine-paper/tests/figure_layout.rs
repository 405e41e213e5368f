//! Every paper figure drawn as `just paper` draws it (each census cut to a few seeded starts, so
//! the data differ a little but the recipes and panels are the same) and checked from its own
//! layout: no legend over a point, line or bar; every text inside the canvas and clear of the
//! others; no character the font cannot draw (`spine_plot::Figure::check`).

use serde_json::Value;
use spine_run::{run_case, run_study, FileContent, KindResult, Overrides};

/// The case `paper-cases/NAME.json`, its census (if any) run only to P = 0.5.
fn light_case(name: &str) -> spine_case::Case {
    let path = format!("{}/../../paper-cases/{name}.json", env!("CARGO_MANIFEST_DIR"));
    let mut json: Value = serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap();
    for pointer in ["/base/multistart", "/multistart"] {
        if let Some(m) = json.pointer_mut(pointer) {
            *m = serde_json::json!({ "confidence": 0.5, "seed": 1 });
        }
    }
    spine_case::Case::from_json(&json.to_string()).unwrap()
}

fn figures(result: &KindResult) -> Vec<(String, spine_plot::Figure)> {
    result
        .files()
        .into_iter()
        .filter_map(|f| match f.content {
            FileContent::Figure(fig) => Some((f.name, fig)),
            _ => None,
        })
        .collect()
}

fn check(name: &str) {
    let case = light_case(name);
    let result = if name == "study-ck" {
        run_study(&case, &Overrides::default(), &spine_run::study::half_decades(), &mut spine_run::quiet)
    } else {
        run_case(&case, &Overrides::default(), &spine_paper::PaperFigures, &mut spine_run::quiet)
    }
    .unwrap_or_else(|e| panic!("{name}: {e}"));
    assert_eq!(result.to_json()["kind"], result.result.kind(), "{name}: the tag without serialising");
    let drawn = figures(&result.result);
    assert!(!drawn.is_empty(), "{name} draws a figure");
    let mut report = Vec::new();
    for (stem, figure) in &drawn {
        let problems = figure.check().unwrap();
        report.extend(problems.iter().map(|p| format!("{name}/{stem}: {p}")));
        // Every panel that has a legend keeps it clear of the data by construction.
        for panel in figure.layout().panels {
            if let Some(legend) = panel.legend {
                assert!(
                    panel.cell.holds(&legend.rect, 0.0),
                    "{name}/{stem}: legend inside its panel: {:?} in {:?}",
                    legend.rect,
                    panel.cell
                );
            }
        }
    }
    assert!(report.is_empty(), "{}", report.join("\n"));
}

macro_rules! figure_tests {
    ($($test:ident => $name:literal),* $(,)?) => {
        $(#[test] fn $test() { check($name); })*
    };
}

figure_tests! {
    twolink_figure_is_clean => "twolink",
    fig3_is_clean => "fig3",
    fig4_is_clean => "fig4",
    fig5_is_clean => "fig5",
    fig6_is_clean => "fig6",
    fig7_is_clean => "fig7",
    fig8_is_clean => "fig8",
    fig9_is_clean => "fig9",
    fig10_is_clean => "fig10",
    fig11_is_clean => "fig11",
    fig12_is_clean => "fig12",
    ck_study_figure_is_clean => "study-ck",
}
