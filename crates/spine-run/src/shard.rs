//! A multi-start split over machines: `spine design CASE --shard K/N` solves the K-th share of the
//! starts and writes a partial result ([`Shard`], `shard.json`); `spine merge DIR…` checks that
//! the shards belong together and are complete, and gives the `result.json` the single run gives
//! (byte for byte with `--deterministic`).
//!
//! Start `i` (0: the case's own, 1…`starts`: the seeded ones) belongs to shard `i mod N + 1`, so
//! shares differ by one start at most. A shard holds Ipopt's unchecked runs ([`SolverRun`]); the
//! merge checks them against the case, which the shard carries verbatim with the overrides it ran
//! with, so a merge needs nothing but the shards.
//!
//! A census to a stated confidence (`--confidence P`) is sharded one batch at a time
//! (`--batch B --shard K/N`: the share of batch `B`'s starts, [`Batches`]); the merge of the
//! shards of batches `1..=B` settles them batch by batch and checks the rule after each, as the
//! single run does, so a census that reached its target gives the single run's bytes, and one
//! that did not says which batch comes next ([`Merged::next_batch`]).

use crate::confidence::{Batches, ConfidenceCensus};
use crate::design::{census, confidence_result, solve_all};
use crate::error::{design_case, MergeError, RunError, ShardContents};
use crate::overrides::DesignOverrides;
use crate::progress::Progress;
use crate::registry::KindResult;
use crate::result::CaseResult;
use crate::workers::{Task, Workers};
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

/// Why a command-line `--shard` is not a shard.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum ParseShardError {
    #[error("K/N expected, got {0:?}")]
    Form(String),
    /// One side is not a whole number (the side, and why).
    #[error("K/N: {part:?}: {reason}")]
    Number { part: String, reason: String },
    #[error("K/N with 1 ≤ K ≤ N ≤ {max}, got {given}")]
    Range { given: String, max: usize },
}

impl std::str::FromStr for ShardSpec {
    type Err = ParseShardError;
    /// `K/N` with `1 ≤ K ≤ N ≤ 10⁵`.
    fn from_str(text: &str) -> Result<Self, ParseShardError> {
        let (k, n) = text.split_once('/').ok_or_else(|| ParseShardError::Form(text.to_string()))?;
        let parse = |v: &str| {
            v.trim()
                .parse::<usize>()
                .map_err(|e| ParseShardError::Number { part: v.to_string(), reason: e.to_string() })
        };
        let (index, count) = (parse(k)?, parse(n)?);
        if !(1..=spine_case::MAX_STARTS).contains(&count) || !(1..=count).contains(&index) {
            return Err(ParseShardError::Range { given: text.to_string(), max: spine_case::MAX_STARTS });
        }
        Ok(Self { index, count })
    }
}

impl ShardSpec {
    /// The starts of this shard among `0..=starts`.
    pub fn starts(&self, starts: usize) -> Vec<usize> {
        self.share(0..=starts)
    }

    /// This shard's share of `starts`: start `i` belongs to shard `i mod N + 1` (the one rule of
    /// sharding, for a multi-start and for each batch of a census).
    pub fn share(&self, starts: impl IntoIterator<Item = usize>) -> Vec<usize> {
        starts.into_iter().filter(|i| i % self.count == self.index - 1).collect()
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
    /// With a census to a stated confidence: the batch whose starts the share is taken from.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub batch: Option<usize>,
}

/// The design case a shard runs, parsed from its case text.
fn shard_case(text: &str) -> Result<spine_case::DesignCase, RunError> {
    design_case(&spine_case::Case::from_json(text)?, "a sharded multi-start").cloned()
}

/// Runs shard `spec` of the design case `text` (with `overrides`): its share of the starts,
/// unchecked (in `workers` processes when given). A census to a stated confidence is sharded one
/// `batch` at a time (required then, refused otherwise).
pub fn run_shard(
    text: &str,
    overrides: &DesignOverrides,
    spec: ShardSpec,
    batch: Option<usize>,
    workers: Option<&Workers>,
    progress: &mut dyn FnMut(Progress<'_>),
) -> Result<Shard, RunError> {
    let ShardPlan { valid, share, used } = plan_shard(text, overrides, spec, batch)?;
    let last = share.last().copied().unwrap_or(0);
    let seeded = feasible_starts(&valid.problem, last, valid.multistart.seed);
    let tasks: Vec<Task> =
        share.iter().map(|&i| if i == 0 { Task::start(&valid.start) } else { Task::seeded(&seeded[i - 1]) }).collect();
    let runs = solve_all(&valid, &tasks, workers, progress)?;
    let complete = runs.len() == share.len();
    Ok(Shard {
        format: SHARD_FORMAT.into(),
        case: text.to_string(),
        overrides: used,
        shard: spec,
        runs: share.into_iter().zip(runs).collect(),
        complete,
        batch,
    })
}

/// Everything [`run_shard`] checks before its first solve, and nothing more (`spine design
/// --shard K/N --check`, what scripts/slurm/census.sh asks before it submits a job): the case is
/// a valid design case, the overrides fit it, the batch fits the census. `Ok`: the starts of the
/// share.
pub fn check_shard(
    text: &str,
    overrides: &DesignOverrides,
    spec: ShardSpec,
    batch: Option<usize>,
) -> Result<usize, RunError> {
    Ok(plan_shard(text, overrides, spec, batch)?.share.len())
}

/// What a design run of the case `text` with `overrides` checks before its first solve: a valid
/// design case, overrides that fit it (`spine design --check`).
pub fn check_design(text: &str, overrides: &DesignOverrides) -> Result<(), RunError> {
    let mut valid = shard_case(text)?.validate()?;
    Ok(overrides.apply(&mut valid)?)
}

/// A shard's problem, its share of the starts and the overrides it records.
struct ShardPlan {
    valid: spine_case::ValidDesign,
    share: Vec<usize>,
    used: DesignOverrides,
}

fn plan_shard(
    text: &str,
    overrides: &DesignOverrides,
    spec: ShardSpec,
    batch: Option<usize>,
) -> Result<ShardPlan, RunError> {
    let case = shard_case(text)?;
    let mut valid = case.validate()?;
    overrides.apply(&mut valid)?;
    let share = match (valid.multistart.confidence, batch) {
        (None, None) => spec.starts(valid.multistart.starts),
        (None, Some(_)) => {
            return Err(option_error("--batch", "only with --confidence (a census to a stated confidence)"))
        }
        (Some(_), b) => {
            let batches = Batches::new(&valid);
            let count = batches.count();
            let allowed = format!("a batch 1 ≤ B ≤ {count} (batches of 100 seeded starts up to the cap, --starts)");
            let b = b.ok_or_else(|| {
                option_error(
                    "--batch",
                    &format!("a census to a stated confidence is sharded one batch at a time: give {allowed}"),
                )
            })?;
            if !(1..=count).contains(&b) {
                return Err(option_error("--batch", &format!("{b}: expected {allowed}")));
            }
            spec.share(batches.starts(b))
        }
    };
    let used =
        DesignOverrides { starts: Some(valid.multistart.starts), seed: Some(valid.multistart.seed), ..*overrides };
    Ok(ShardPlan { valid, share, used })
}

fn option_error(field: &str, reason: &str) -> RunError {
    RunError::Option(spine_check::FieldError::new(field, reason.to_string()))
}

/// The merge of a multi-start's shards.
#[derive(Debug)]
pub struct Merged {
    pub result: CaseResult,
    /// A census to a stated confidence that has not reached its target, nor its cap: the batch
    /// to run next.
    pub next_batch: Option<usize>,
    /// Batches given beyond the one where the census reached its target (left out, as the
    /// single run would not have run them).
    pub unused_batches: Vec<usize>,
}

/// Merges the shards of one multi-start into the result of the single run. Refused (with the
/// reason) unless every shard has the same case, overrides and shard count, each of `1..=N`
/// appears once, and each is complete; for a census to a stated confidence, the same for each
/// batch `1..=B` (the shard count may differ between batches).
pub fn merge(mut shards: Vec<Shard>) -> Result<Merged, RunError> {
    let first = shards.first().ok_or(MergeError::Empty)?.clone();
    for s in &shards {
        if s.format != SHARD_FORMAT {
            return Err(MergeError::Format { found: s.format.clone(), expected: SHARD_FORMAT }.into());
        }
        let ShardSpec { index, count } = s.shard;
        if !(1..=spine_case::MAX_STARTS).contains(&count) || !(1..=count).contains(&index) {
            return Err(MergeError::ShardNumber { index, count, max: spine_case::MAX_STARTS }.into());
        }
        if let Some(starts) = s.overrides.starts.filter(|&n| n > spine_case::MAX_STARTS) {
            return Err(MergeError::TooManyStarts { starts, max: spine_case::MAX_STARTS }.into());
        }
        if s.case != first.case {
            return Err(MergeError::OtherCase { shard: s.name(), first: first.name() }.into());
        }
        let same_count = s.batch.is_some() || s.shard.count == first.shard.count;
        if s.overrides != first.overrides || !same_count || s.batch.is_some() != first.batch.is_some() {
            return Err(MergeError::OtherSettings {
                shard: s.name(),
                settings: s.overrides,
                batch: s.batch,
                first: first.name(),
                first_settings: first.overrides,
                first_batch: first.batch,
            }
            .into());
        }
    }
    let case = shard_case(&first.case)?;
    let mut valid = case.validate().map_err(MergeError::Case)?;
    first.overrides.apply(&mut valid)?;
    shards.sort_by_key(|s| (s.batch, s.shard.index));
    let Some(target) = valid.multistart.confidence else {
        if first.batch.is_some() {
            return Err(MergeError::NotACensus { shard: first.name() }.into());
        }
        let runs = complete_runs(&valid, shards)?;
        let mut result = census(&case, &valid, runs)?;
        crate::sensitivity::attach(&case, &valid, &first.overrides, &mut result)?;
        return Ok(Merged { result: KindResult::Design(result).into(), next_batch: None, unused_batches: Vec::new() });
    };
    // A census to a stated confidence, batch by batch.
    let batches = Batches::new(&valid);
    let mut by_batch: Vec<(usize, Vec<Shard>)> = Vec::new();
    for s in shards {
        let b = s.batch.unwrap_or(0);
        if !(1..=batches.count()).contains(&b) {
            return Err(MergeError::BatchNumber { shard: s.name(), batch: b, count: batches.count() }.into());
        }
        match by_batch.last_mut() {
            Some((last, group)) if *last == b => group.push(s),
            _ => by_batch.push((b, vec![s])),
        }
    }
    let given: Vec<usize> = by_batch.iter().map(|(b, _)| *b).collect();
    let missing: Vec<usize> =
        (1..=*given.last().unwrap_or(&0)).filter(|b| given.binary_search(b).is_err()).take(10).collect();
    if !missing.is_empty() {
        return Err(MergeError::MissingBatches { last: *given.last().unwrap_or(&0), missing }.into());
    }
    let mut groups = by_batch.into_iter();
    let (_, first_batch) = groups.next().ok_or(MergeError::Empty)?;
    let mut runs = complete_runs(&valid, first_batch)?.into_iter();
    let own = runs.next().ok_or(MergeError::NoStartZero)?;
    let mut census = ConfidenceCensus::new(&valid, target, own)?;
    let mut done = census.add_batch(runs.collect())?;
    let mut unused_batches = Vec::new();
    for (b, group) in groups {
        if done {
            unused_batches.push(b);
            continue;
        }
        done = census.add_batch(complete_runs(&valid, group)?)?;
    }
    let next_batch = (!done).then(|| census.batches() + 1);
    let (results, confidence) = census.finish();
    let mut result = confidence_result(&case, &valid, results, confidence);
    crate::sensitivity::attach(&case, &valid, &first.overrides, &mut result)?;
    Ok(Merged { result: KindResult::Design(result).into(), next_batch, unused_batches })
}

impl Shard {
    /// `shard.json`'s text as a shard; a field of the wrong form is named by its path in the
    /// workspace's words ([`spine_case::from_json_text`]).
    pub fn from_text(text: &str) -> Result<Self, spine_case::CaseError> {
        spine_case::from_json_text(text)
    }

    /// `K/N`, or `K/N of batch B`.
    fn name(&self) -> String {
        match self.batch {
            Some(b) => format!("{}/{} of batch {b}", self.shard.index, self.shard.count),
            None => format!("{}/{}", self.shard.index, self.shard.count),
        }
    }

    /// The starts this shard must hold.
    fn expected(&self, valid: &spine_case::ValidDesign) -> Vec<usize> {
        match self.batch {
            Some(b) => self.shard.share(Batches::new(valid).starts(b)),
            None => self.shard.starts(valid.multistart.starts),
        }
    }
}

/// The runs of one set of shards (one multi-start, or one batch of a census), each of `1..=N`
/// once and complete, checked against the problem, in start order.
fn complete_runs(valid: &spine_case::ValidDesign, shards: Vec<Shard>) -> Result<Vec<SolverRun>, RunError> {
    let first = shards.first().ok_or(MergeError::Empty)?;
    let count = first.shard.count;
    if let Some(other) = shards.iter().find(|s| s.shard.count != count) {
        return Err(MergeError::ShardCounts { shard: first.name(), other: other.name() }.into());
    }
    let indices: Vec<usize> = shards.iter().map(|s| s.shard.index).collect();
    let twice: Vec<usize> = indices.windows(2).filter(|w| w[0] == w[1]).map(|w| w[0]).collect();
    if !twice.is_empty() || indices.len() != count {
        let mut distinct = indices.clone();
        distinct.dedup();
        // Every index is in 1..=count (checked above), at most 10⁵ of them.
        let missing: Vec<usize> = (1..=count).filter(|k| distinct.binary_search(k).is_err()).take(10).collect();
        let missing_count = count - distinct.len();
        return Err(MergeError::MissingShards { count, batch: first.batch, missing, missing_count, twice }.into());
    }
    let mut runs = Vec::new();
    for s in shards {
        let expected = s.expected(valid);
        let got: Vec<usize> = s.runs.iter().map(|(i, _)| *i).collect();
        if !s.complete || got != expected {
            return Err(
                MergeError::IncompleteShard(ShardContents::compare(s.name(), s.complete, &got, &expected)).into()
            );
        }
        for (start, run) in &s.runs {
            run.fits(&valid.problem).map_err(|reason| MergeError::OtherProblem {
                shard: s.name(),
                start: *start,
                reason,
            })?;
        }
        runs.extend(s.runs);
    }
    runs.sort_by_key(|(i, _)| *i);
    Ok(runs.into_iter().map(|(_, run)| run).collect())
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
