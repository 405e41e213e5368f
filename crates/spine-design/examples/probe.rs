use spine_design::fixtures::*;
use spine_design::*;

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let n: usize = args.get(1).map_or(5, |s| s.parse().unwrap());
    let delta: f64 = args.get(2).map_or(-0.02, |s| s.parse().unwrap());
    let ck: f64 = args.get(3).map_or(1.0, |s| s.parse().unwrap());
    let scaled = args.get(4).is_some_and(|s| s == "scaled");
    let problem = if scaled {
        scaled_family(n)
    } else if n == 5 {
        paper_problem(5, -10.0, -400.0, delta, ck)
    } else {
        paper_problem(n, -5.0, -400.0, delta, ck)
    };
    let s = n as f64 / 10.0;
    let start = if n == 5 && !scaled {
        paper_five_link_start()
    } else {
        arch_start(n, 0.3, 1e3 * if scaled { s * s } else { 1.0 })
    };
    for f in [Formulation::Full, Formulation::Reduced] {
        if f == Formulation::Reduced && n > 200 {
            continue;
        }
        let r = solve_design(&problem, &start, f, &SolverSettings::default(), &mut |_| true).unwrap();
        println!(
            "{:?}: status {} it {} J {:.10} t {:.3}s eval {:.3}s viol {:?} warnings {:?}",
            f,
            r.solver.status,
            r.solver.iterations,
            r.objective,
            r.solver.ipopt_seconds,
            r.solver.evaluation_seconds,
            r.violations.as_ref().map(|v| v.max),
            r.warnings
        );
        if n <= 10 {
            println!(
                "  theta0 {:?}\n  K {:?}",
                r.design.theta0.iter().map(|x| (x * 1e4).round() / 1e4).collect::<Vec<_>>(),
                r.design.stiffness.iter().map(|x| x.round()).collect::<Vec<_>>()
            );
        }
    }
}
