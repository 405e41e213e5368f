//! The worker processes of a run's multi-starts: `--jobs N`, this program started again as
//! `spine worker`.

/// Worker processes (`--jobs`, default one per core) solving `case` with `design` overrides:
/// `spine worker CASE --overrides JSON`, this program started again; `None` for one job.
pub(crate) fn workers(
    jobs: Option<usize>,
    case: &std::path::Path,
    design: &spine_run::DesignOverrides,
) -> Result<Option<spine_run::workers::Workers>, crate::Failure> {
    let jobs = jobs.unwrap_or_else(|| std::thread::available_parallelism().map_or(1, |n| n.get()));
    if jobs <= 1 {
        return Ok(None);
    }
    let program = std::env::current_exe()
        .map_err(|e| crate::Failure::Other(format!("--jobs: cannot find this program to start workers: {e}")))?;
    let design = serde_json::to_string(design).expect("overrides serialise");
    let args = vec!["worker".to_string(), case.display().to_string(), "--overrides".into(), design];
    let command = spine_run::workers::WorkerCommand { program, args };
    Ok(Some(spine_run::workers::Workers { jobs, command }))
}
