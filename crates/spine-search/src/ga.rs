//! Real-coded genetic algorithm: binary tournaments by Deb's rules, SBX crossover, polynomial
//! mutation (both bounded), elitism.

use crate::{Bounds, Evaluation, Progress, SearchResult, SearchStatus};
use serde::{Deserialize, Serialize};
use spine_check::{require, FieldError};
use spine_rng::SplitMix64;

/// GA settings (defaults after Deb 2000).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields, default)]
pub struct GaSettings {
    /// Population size (≥ 4, even).
    pub population: usize,
    /// Number of generations after the first.
    pub generations: usize,
    /// Probability that a pair is recombined.
    pub crossover_probability: f64,
    /// SBX distribution index (larger: children closer to the parents).
    pub crossover_eta: f64,
    /// Per-gene mutation probability (`None`: `1/n`).
    pub mutation_probability: Option<f64>,
    /// Polynomial mutation distribution index.
    pub mutation_eta: f64,
    /// Best individuals copied unchanged into the next generation.
    pub elites: usize,
    /// Stop when the best point has not improved for this many generations.
    pub stall_generations: usize,
    /// Evaluation budget.
    pub max_evaluations: usize,
    pub seed: u64,
}

impl Default for GaSettings {
    fn default() -> Self {
        Self {
            population: 40,
            generations: 60,
            crossover_probability: 0.9,
            crossover_eta: 15.0,
            mutation_probability: None,
            mutation_eta: 20.0,
            elites: 2,
            stall_generations: 20,
            max_evaluations: usize::MAX,
            seed: 1,
        }
    }
}

impl GaSettings {
    /// Checks every setting (the GA runs only with valid settings; nothing is rounded).
    pub fn validate(&self) -> Result<(), FieldError> {
        let p = self.population;
        require(p >= 4 && p & 1 == 0 && p <= MAX_POPULATION, "population", || {
            format!("must be even, at least 4 and at most {MAX_POPULATION}, got {p}")
        })?;
        let g = self.generations;
        require(g <= MAX_GENERATIONS, "generations", || format!("must be at most {MAX_GENERATIONS}, got {g}"))?;
        let unit = |v: f64| (0.0..=1.0).contains(&v);
        require(unit(self.crossover_probability), "crossover_probability", || {
            format!("must be in [0, 1], got {}", self.crossover_probability)
        })?;
        let m = self.mutation_probability;
        require(m.is_none_or(unit), "mutation_probability", || {
            format!("must be in [0, 1], got {}", m.map_or("none".into(), spine_check::short))
        })?;
        for (field, eta) in [("crossover_eta", self.crossover_eta), ("mutation_eta", self.mutation_eta)] {
            require(eta.is_finite() && eta > 0.0, field, || format!("must be a finite number > 0, got {eta}"))?;
        }
        require(self.elites < p, "elites", || format!("must be below the population ({p}), got {}", self.elites))
    }
}

/// Largest GA population accepted (each member is one fitness evaluation per generation).
pub const MAX_POPULATION: usize = 10_000;
/// Most GA generations accepted.
pub const MAX_GENERATIONS: usize = 100_000;

/// `f` at every point, on rayon's pool (in order: the same values as one by one). Each pool thread
/// works under this thread's time limit; a limit that passed is then seen here too.
fn evaluate_all(f: &(dyn Fn(&[f64]) -> Evaluation + Sync), points: &[Vec<f64>]) -> Vec<Evaluation> {
    use rayon::prelude::*;
    let deadline = spine_stop::deadline();
    let values = points.par_iter().map(|x| spine_stop::with_deadline(deadline, || f(x)).0).collect();
    let _ = spine_stop::check();
    values
}

/// Minimises `f` over `bounds`. `start`, when given, is one member of the first population (the
/// rest are uniform in the bounds). The members of a generation are evaluated in parallel
/// (rayon's pool; `RAYON_NUM_THREADS` sets its size), which changes nothing but the wall time: `f`
/// must be a pure function of its point.
pub fn genetic_algorithm(
    f: &(dyn Fn(&[f64]) -> Evaluation + Sync),
    bounds: &Bounds,
    start: Option<&[f64]>,
    settings: &GaSettings,
    progress: &mut dyn FnMut(Progress),
) -> Result<SearchResult, FieldError> {
    settings.validate()?;
    let n = bounds.dim();
    let pop_size = settings.population;
    let mut rng = SplitMix64::new(settings.seed);
    let p_mut = settings.mutation_probability.unwrap_or(1.0 / n.max(1) as f64);
    let mut evaluations = 0;

    let mut population: Vec<Vec<f64>> = (0..pop_size)
        .map(|k| match (k, start) {
            (0, Some(s)) => (0..n).map(|i| bounds.clamp(i, s[i])).collect(),
            _ => (0..n).map(|i| rng.uniform(bounds.lower[i], bounds.upper[i])).collect(),
        })
        .collect();
    let mut values = evaluate_all(f, &population);
    evaluations += values.len();
    let best_of =
        |values: &[Evaluation]| (0..values.len()).fold(0, |b, k| if values[k].better_than(&values[b]) { k } else { b });
    let mut best = best_of(&values);
    let (mut best_x, mut best_value) = (population[best].clone(), values[best]);
    let mut history = vec![Progress { iteration: 0, evaluations, best: best_value }];
    progress(history[0]);
    let mut stall = 0;
    let mut status = SearchStatus::GenerationLimit;
    let mut generation = 0;

    while generation < settings.generations {
        if let Some(reason) = spine_stop::check() {
            status = reason.into();
            break;
        }
        if evaluations + pop_size > settings.max_evaluations {
            status = SearchStatus::EvaluationLimit;
            break;
        }
        if stall >= settings.stall_generations {
            status = SearchStatus::Stalled;
            break;
        }
        generation += 1;
        let (mut next, mut next_values) = elites(&population, &values, settings.elites.min(pop_size));
        let children = offspring(&population, &values, pop_size - next.len(), bounds, settings, p_mut, &mut rng);
        next_values.extend(evaluate_all(f, &children));
        evaluations += children.len();
        next.extend(children);
        population = next;
        values = next_values;
        best = best_of(&values);
        if values[best].better_than(&best_value) {
            best_value = values[best];
            best_x = population[best].clone();
            stall = 0;
        } else {
            stall += 1;
        }
        let p = Progress { iteration: generation, evaluations, best: best_value };
        history.push(p);
        progress(p);
    }
    if generation >= settings.generations && stall >= settings.stall_generations {
        status = SearchStatus::Stalled;
    }
    Ok(SearchResult { status, x: best_x, best: best_value, evaluations, iterations: generation, history })
}

/// The `count` best members with their values, best first (ties by position).
fn elites(population: &[Vec<f64>], values: &[Evaluation], count: usize) -> (Vec<Vec<f64>>, Vec<Evaluation>) {
    let mut order: Vec<usize> = (0..population.len()).collect();
    order.sort_by(|&a, &b| {
        if values[a].better_than(&values[b]) {
            std::cmp::Ordering::Less
        } else if values[b].better_than(&values[a]) {
            std::cmp::Ordering::Greater
        } else {
            a.cmp(&b)
        }
    });
    order.iter().take(count).map(|&k| (population[k].clone(), values[k])).unzip()
}

/// `count` children: parents by binary tournaments, recombined by SBX with probability
/// `crossover_probability` (each gene with probability 1/2), then mutated gene by gene with
/// probability `p_mut`.
fn offspring(
    population: &[Vec<f64>],
    values: &[Evaluation],
    count: usize,
    bounds: &Bounds,
    settings: &GaSettings,
    p_mut: f64,
    rng: &mut SplitMix64,
) -> Vec<Vec<f64>> {
    let (n, pop_size) = (bounds.dim(), population.len());
    let tournament = |rng: &mut SplitMix64| {
        let (a, b) = (rng.below(pop_size), rng.below(pop_size));
        if values[b].better_than(&values[a]) {
            b
        } else {
            a
        }
    };
    let mut children = Vec::new();
    while children.len() < count {
        let (pa, pb) = (tournament(rng), tournament(rng));
        let (mut c1, mut c2) = (population[pa].clone(), population[pb].clone());
        if rng.next_f64() < settings.crossover_probability {
            for i in 0..n {
                if rng.next_f64() < 0.5 {
                    (c1[i], c2[i]) = sbx(c1[i], c2[i], bounds.lower[i], bounds.upper[i], settings.crossover_eta, rng);
                }
            }
        }
        for c in [&mut c1, &mut c2] {
            for i in 0..n {
                if rng.next_f64() < p_mut {
                    c[i] = polynomial_mutation(c[i], bounds.lower[i], bounds.upper[i], settings.mutation_eta, rng);
                }
            }
        }
        children.push(c1);
        if children.len() < count {
            children.push(c2);
        }
    }
    children
}

/// Simulated binary crossover of one gene within `[lo, hi]` (Deb & Agrawal 1995, bounded form).
fn sbx(x1: f64, x2: f64, lo: f64, hi: f64, eta: f64, rng: &mut SplitMix64) -> (f64, f64) {
    if (x1 - x2).abs() < 1e-14 * (hi - lo) {
        return (x1, x2);
    }
    let (y1, y2) = if x1 < x2 { (x1, x2) } else { (x2, x1) };
    let u = rng.next_f64();
    let child = |beta: f64| {
        let alpha = 2.0 - beta.powf(-(eta + 1.0));

        if u <= 1.0 / alpha {
            (u * alpha).powf(1.0 / (eta + 1.0))
        } else {
            (1.0 / (2.0 - u * alpha)).powf(1.0 / (eta + 1.0))
        }
    };
    let bq1 = child(1.0 + 2.0 * (y1 - lo) / (y2 - y1));
    let bq2 = child(1.0 + 2.0 * (hi - y2) / (y2 - y1));
    let c1 = (0.5 * ((y1 + y2) - bq1 * (y2 - y1))).clamp(lo, hi);
    let c2 = (0.5 * ((y1 + y2) + bq2 * (y2 - y1))).clamp(lo, hi);
    if rng.next_f64() < 0.5 {
        (c2, c1)
    } else {
        (c1, c2)
    }
}

/// Polynomial mutation of one gene within `[lo, hi]` (Deb & Goyal 1996).
fn polynomial_mutation(x: f64, lo: f64, hi: f64, eta: f64, rng: &mut SplitMix64) -> f64 {
    let (d1, d2) = ((x - lo) / (hi - lo), (hi - x) / (hi - lo));
    let u = rng.next_f64();
    let power = 1.0 / (eta + 1.0);
    let dq = if u < 0.5 {
        (2.0 * u + (1.0 - 2.0 * u) * (1.0 - d1).powf(eta + 1.0)).powf(power) - 1.0
    } else {
        1.0 - (2.0 * (1.0 - u) + 2.0 * (u - 0.5) * (1.0 - d2).powf(eta + 1.0)).powf(power)
    };
    (x + dq * (hi - lo)).clamp(lo, hi)
}
