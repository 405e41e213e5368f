//! A multi-start split over machines: `spine design CASE --shard K/N` solves the K-th share of the
//! starts and writes a partial result ([`Shard`], `shard.json`); `spine merge DIR…` checks that
//! the shards belong together and are complete, and gives the `result.json` the single run gives
//! (byte for byte with `--deterministic`).
//!
//! Start `i` (0: the case's own, 1…`starts`: the seeded ones) belongs to shard `i mod N + 1`, so
//! shares differ by one start at most. A shard holds Ipopt's unchecked runs ([`SolverRun`]); the
//! merge checks them against the case, which the shard carries verbatim with the overrides it ran
//! with, so a merge needs nothing but the shards.

use crate::design::{census, solve_all, DesignOverrides};
use crate::error::{MergeError, RunError};
use crate::progress::Progress;
use crate::result::{CaseResult, KindResult};
use crate::workers::Workers;
use serde::{Deserialize, Serialize};
use spine_design::multistart::feasible_starts;
use spine_design::SolverRun;

/// Largest `shard.json` read, bytes (a 10⁵-start shard of a 10-link case is about 200 MB).
pub const MAX_SHARD_BYTES: usize = 512 << 20;

/// The format tag of `shard.json`.
pub const SHARD_FORMAT: &str = "spine-shard-1";

/// Which share of the starts a run solves: shard `index` of `count` (1-based, `K/N` on the
/// command line).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct ShardSpec {
    pub index: usize,
    pub count: usize,
}

impl std::str::FromStr for ShardSpec {
    type Err = String;
    /// `K/N` with `1 ≤ K ≤ N ≤ 10⁵`.
    fn from_str(text: &str) -> Result<Self, String> {
        let (k, n) = text.split_once('/').ok_or_else(|| format!("K/N expected, got {text:?}"))?;
        let parse = |v: &str| v.trim().parse::<usize>().map_err(|e| format!("K/N: {v:?}: {e}"));
        let (index, count) = (parse(k)?, parse(n)?);
        if !(1..=spine_case::MAX_STARTS).contains(&count) || !(1..=count).contains(&index) {
            return Err(format!("K/N with 1 ≤ K ≤ N ≤ {}, got {text}", spine_case::MAX_STARTS));
        }
        Ok(Self { index, count })
    }
}

impl ShardSpec {
    /// The starts of this shard among `0..=starts`.
    pub fn starts(&self, starts: usize) -> Vec<usize> {
        (0..=starts).filter(|i| i % self.count == self.index - 1).collect()
    }
}

/// `shard.json`: the runs of one shard, with what a merge needs to check and finish them.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Shard {
    pub format: String,
    /// The case file's text, verbatim.
    pub case: String,
    /// The overrides the shard ran with (`starts` and `seed` as used).
    pub overrides: DesignOverrides,
    pub shard: ShardSpec,
    /// `(start, run)` in start order; fewer than the share when a time limit stopped the shard.
    pub runs: Vec<(usize, SolverRun)>,
    /// Every start of the share was solved.
    pub complete: bool,
}

fn design_case(text: &str) -> Result<spine_case::DesignCase, RunError> {
    match spine_case::Case::from_json(text)? {
        spine_case::Case::Design(c) => Ok(c),
        other => Err(RunError::Option(spine_check::FieldError::new(
            "--shard",
            format!("a multi-start shards \"design\" cases, not \"{}\"", other.kind()),
        ))),
    }
}

/// Runs shard `spec` of the design case `text` (with `overrides`): its share of the starts,
/// unchecked (in `workers` processes when given).
pub fn run_shard(
    text: &str,
    overrides: &DesignOverrides,
    spec: ShardSpec,
    workers: Option<&Workers>,
    progress: &mut dyn FnMut(Progress<'_>),
) -> Result<Shard, RunError> {
    let case = design_case(text)?;
    let mut valid = case.validate()?;
    overrides.apply(&mut valid);
    if valid.multistart.confidence.is_some() {
        return Err(RunError::Case(spine_case::CaseError::invalid(
            "multistart.confidence",
            "a census to a stated confidence runs in one process (with --jobs), not in shards: its batches depend on the census so far",
        )));
    }
    let used =
        DesignOverrides { starts: Some(valid.multistart.starts), seed: Some(valid.multistart.seed), ..*overrides };
    let seeded = feasible_starts(&valid.problem, valid.multistart.starts, valid.multistart.seed);
    let share = spec.starts(valid.multistart.starts);
    let designs: Vec<_> =
        share.iter().map(|&i| if i == 0 { valid.start.clone() } else { seeded[i - 1].clone() }).collect();
    let runs = solve_all(&valid, &designs, workers, progress)?;
    let complete = runs.len() == share.len();
    Ok(Shard {
        format: SHARD_FORMAT.into(),
        case: text.to_string(),
        overrides: used,
        shard: spec,
        runs: share.into_iter().zip(runs).collect(),
        complete,
    })
}

/// Merges the shards of one multi-start into the result of the single run. Refused (with the
/// reason) unless every shard has the same case, overrides and shard count, each of `1..=N`
/// appears once, and each is complete.
pub fn merge(mut shards: Vec<Shard>) -> Result<CaseResult, RunError> {
    let first = shards.first().ok_or(MergeError::Empty)?.clone();
    for s in &shards {
        if s.format != SHARD_FORMAT {
            let format = spine_check::shown(&s.format);
            return Err(MergeError::Mismatch(format!("shard format \"{format}\", expected \"{SHARD_FORMAT}\"")).into());
        }
        let ShardSpec { index, count } = s.shard;
        if !(1..=spine_case::MAX_STARTS).contains(&count) || !(1..=count).contains(&index) {
            return Err(MergeError::Mismatch(format!(
                "shard.index {index} of shard.count {count}: 1 ≤ index ≤ count ≤ {} expected",
                spine_case::MAX_STARTS
            ))
            .into());
        }
        if let Some(starts) = s.overrides.starts.filter(|&n| n > spine_case::MAX_STARTS) {
            return Err(MergeError::Mismatch(format!(
                "overrides.starts {starts}: at most {} expected",
                spine_case::MAX_STARTS
            ))
            .into());
        }
        if s.case != first.case {
            return Err(MergeError::Mismatch(format!(
                "shard {}/{} ran another case file than shard {}/{}",
                s.shard.index, s.shard.count, first.shard.index, first.shard.count
            ))
            .into());
        }
        if s.overrides != first.overrides || s.shard.count != first.shard.count {
            let settings = |o: &DesignOverrides| serde_json::to_string(o).unwrap_or_default();
            return Err(MergeError::Mismatch(format!(
                "shard {}/{} ran with other settings ({}) than shard {}/{} ({})",
                s.shard.index,
                s.shard.count,
                settings(&s.overrides),
                first.shard.index,
                first.shard.count,
                settings(&first.overrides)
            ))
            .into());
        }
    }
    let count = first.shard.count;
    shards.sort_by_key(|s| s.shard.index);
    let indices: Vec<usize> = shards.iter().map(|s| s.shard.index).collect();
    let twice: Vec<usize> = indices.windows(2).filter(|w| w[0] == w[1]).map(|w| w[0]).collect();
    if !twice.is_empty() || indices.len() != count {
        let mut distinct = indices.clone();
        distinct.dedup();
        // Every index is in 1..=count (checked above), at most 10⁵ of them.
        let missing: Vec<usize> = (1..=count).filter(|k| distinct.binary_search(k).is_err()).take(10).collect();
        let missing_count = count - distinct.len();
        let mut parts = Vec::new();
        if missing_count > 0 {
            parts.push(format!("missing {} ({} of them)", crate::text::numbers(&missing), missing_count));
        }
        if !twice.is_empty() {
            parts.push(format!("given more than once {}", crate::text::numbers(&twice)));
        }
        return Err(MergeError::Incomplete(format!("{count} shards expected; {}", parts.join("; "))).into());
    }
    let case = design_case(&first.case).map_err(|e| MergeError::Case(e.to_string()))?;
    let mut valid = case.validate().map_err(|e| MergeError::Case(e.to_string()))?;
    first.overrides.apply(&mut valid);
    let mut runs = Vec::with_capacity(valid.multistart.starts + 1);
    for s in shards {
        let expected = s.shard.starts(valid.multistart.starts);
        let got: Vec<usize> = s.runs.iter().map(|(i, _)| *i).collect();
        if !s.complete || got != expected {
            return Err(MergeError::Incomplete(format!(
                "shard {}/{} is incomplete: {} of its {} starts solved (stopped early?)",
                s.shard.index,
                count,
                got.len(),
                expected.len()
            ))
            .into());
        }
        for (start, run) in &s.runs {
            run.fits(&valid.problem)
                .map_err(|e| MergeError::Mismatch(format!("shard {}/{count}, start {start}: {e}", s.shard.index)))?;
        }
        runs.extend(s.runs);
    }
    runs.sort_by_key(|(i, _)| *i);
    let mut result = census(&case, &valid, runs.into_iter().map(|(_, run)| run).collect())?;
    crate::sensitivity::attach(&case, &valid, &first.overrides, &mut result)?;
    Ok(KindResult::Design(result).into())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shares_cover_every_start_once_and_differ_by_one_at_most() {
        for (starts, count) in [(0, 1), (12, 3), (7, 4), (3, 5)] {
            let mut all: Vec<usize> = Vec::new();
            let sizes: Vec<usize> = (1..=count)
                .map(|index| {
                    let share = ShardSpec { index, count }.starts(starts);
                    all.extend(&share);
                    share.len()
                })
                .collect();
            all.sort_unstable();
            assert_eq!(all, (0..=starts).collect::<Vec<_>>());
            assert!(sizes.iter().max().unwrap() - sizes.iter().min().unwrap() <= 1, "{sizes:?}");
        }
        assert_eq!("2/3".parse::<ShardSpec>(), Ok(ShardSpec { index: 2, count: 3 }));
        for bad in ["0/3", "4/3", "3", "a/b", "1/0"] {
            assert!(bad.parse::<ShardSpec>().is_err(), "{bad}");
        }
    }
}
