//! Eq. (33) multi-start solves in worker processes (`--jobs N`).
//!
//! Debian's Ipopt 3.11.9 with MUMPS aborts when two solves run in one process (and the abort exits
//! 0), so independent solves run in separate processes, never threads. A worker is this program
//! started again ([`WorkerCommand`], `spine worker CASE …`): it checks the same case with the same
//! overrides, then reads start designs from its standard input, one JSON line each, and answers
//! each with one JSON line: the unchecked [`SolverRun`] or an error ([`serve`]). The parent hands
//! out starts as workers become free, checks every run itself ([`SolverRun::check`]) and keeps
//! them in start order, so the census is the one the sequential run gives, byte for byte.
//!
//! A time limit or an interrupt stops handing out starts; solves still in flight are abandoned
//! (their workers are killed), so the census holds the starts completed.

use crate::error::{RunError, WorkerError};
use serde::{Deserialize, Serialize};
use spine_design::solver_run::SolverRun;
use spine_model::Design;
use std::io::{BufRead, BufReader, Write};
use std::path::PathBuf;
use std::process::{Child, ChildStdin, ChildStdout, Command, Stdio};
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::mpsc;
use std::time::Duration;

/// How to start a worker process: a program and its arguments (the CLI: its own executable with
/// `worker CASE` and the design overrides).
#[derive(Clone, Debug, PartialEq)]
pub struct WorkerCommand {
    pub program: PathBuf,
    pub args: Vec<String>,
}

/// Worker processes for the independent solves of a multi-start.
#[derive(Clone, Debug, PartialEq)]
pub struct Workers {
    /// How many solves run at once (processes), ≥ 1; 1 runs every solve in this process.
    pub jobs: usize,
    pub command: WorkerCommand,
}

impl Workers {
    /// The same workers for the run `name` of a figure case: each worker checks that run
    /// (`spine worker FIGURE … --run NAME`).
    pub fn for_run(&self, name: &str) -> Self {
        let mut command = self.command.clone();
        command.args.extend(["--run".to_string(), name.to_string()]);
        Self { jobs: self.jobs, command }
    }
}

/// Most worker processes allowed.
pub const MAX_JOBS: usize = 256;

/// One solve handed to a worker: a start design, and for a study point the C_K of eq. (34) and
/// Ipopt's scaling that replace the case's.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Task {
    pub start: Design,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub stiffness_scale: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub scaling: Option<spine_design::ScalingMethod>,
    /// Solve like the paper's fmincon: the reduced space with
    /// [`spine_design::SolverSettings::fmincon_like`].
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub fmincon_like: bool,
    /// A seeded start of a multi-start: solved with the census's barrier strategy
    /// (`multistart.barrier_strategy`) instead of the case's.
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub seeded: bool,
}

impl Task {
    /// A start of the case as it is.
    pub fn start(start: &Design) -> Self {
        Self { start: start.clone(), stiffness_scale: None, scaling: None, fmincon_like: false, seeded: false }
    }

    /// A seeded start of the case's multi-start.
    pub fn seeded(start: &Design) -> Self {
        Self { seeded: true, ..Self::start(start) }
    }

    /// The case this task solves: `valid` with the task's C_K, scaling and solver.
    pub fn case(&self, valid: &spine_case::ValidDesign) -> spine_case::ValidDesign {
        let mut v = valid.clone();
        if let Some(c) = self.stiffness_scale {
            v.problem.stiffness_scale = c;
        }
        if let Some(s) = self.scaling {
            v.settings.scaling = s;
        }
        if self.seeded {
            v.settings.barrier_strategy = v.multistart.barrier_strategy;
        }
        if self.fmincon_like {
            v = v.with_preset(spine_design::SolverPreset::FminconLike);
        }
        v
    }
}

/// One answer of a worker.
#[derive(Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
enum Answer {
    Run(Box<SolverRun>),
    Error(String),
}

/// The worker's side: eq. (33) of `valid` for every [`Task`] read from `input` (one JSON line
/// each), one answer line each on `output`, until `input` ends.
pub fn serve(valid: &spine_case::ValidDesign, input: impl BufRead, mut output: impl Write) -> std::io::Result<()> {
    for line in input.lines() {
        let line = line?;
        let answer = match serde_json::from_str::<Task>(&line) {
            Ok(task) => {
                let v = task.case(valid);
                match v.solver().run(&v.problem, &task.start, &mut |_| true) {
                    Ok(run) => Answer::Run(Box::new(run)),
                    Err(e) => Answer::Error(format!("solver: {e}")),
                }
            }
            Err(e) => Answer::Error(format!("worker: not a task: {e}")),
        };
        // Invariant: an answer is structs, enums and maps with string keys; serde_json writes any such
        // value (a non-finite float is written as null).
        let mut text = serde_json::to_string(&answer).expect("answers serialise");
        text.push('\n');
        output.write_all(text.as_bytes())?;
        output.flush()?;
    }
    Ok(())
}

/// The pipes of a running worker.
struct Pipes {
    input: ChildStdin,
    output: BufReader<ChildStdout>,
}

/// Starts a worker; its process and its pipes.
fn start_worker(command: &WorkerCommand) -> Result<(Child, Pipes), RunError> {
    let mut child = Command::new(&command.program)
        .args(&command.args)
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::inherit())
        .spawn()
        .map_err(|source| WorkerError::Start { program: command.program.clone(), source })?;
    match (child.stdin.take(), child.stdout.take()) {
        (Some(input), Some(output)) => Ok((child, Pipes { input, output: BufReader::new(output) })),
        _ => {
            let _ = child.kill();
            let _ = child.wait();
            Err(WorkerError::NoPipes.into())
        }
    }
}

impl Pipes {
    /// Solves `task` in the worker.
    fn solve(&mut self, task: &Task) -> Result<SolverRun, RunError> {
        // Invariant: as for the answers, a task holds no map with non-string keys.
        let mut line = serde_json::to_string(task).expect("tasks serialise");
        line.push('\n');
        let lost = WorkerError::Lost;
        self.input.write_all(line.as_bytes()).map_err(lost)?;
        self.input.flush().map_err(lost)?;
        let mut answer = String::new();
        if self.output.read_line(&mut answer).map_err(lost)? == 0 {
            return Err(WorkerError::Ended.into());
        }
        match serde_json::from_str(&answer) {
            Ok(Answer::Run(run)) => Ok(*run),
            Ok(Answer::Error(message)) => Err(WorkerError::Failed(message).into()),
            Err(e) => Err(WorkerError::NotARun(e).into()),
        }
    }
}

/// What a worker thread reports to the thread that drives the run.
type Event = (usize, Result<SolverRun, RunError>);

/// Eq. (33) for every task of `starts` in `workers.jobs` worker processes. Returns the runs in
/// task order up to the first task not completed (a stop: the time limit or an interrupt, seen
/// through [`spine_stop::check`] on this thread, which ends every worker at once); `done(k)` is
/// called as runs complete, `k` of them so far.
pub fn solve_starts(
    workers: &Workers,
    starts: &[Task],
    done: &mut dyn FnMut(usize),
) -> Result<Vec<SolverRun>, RunError> {
    let jobs = workers.jobs.clamp(1, MAX_JOBS).min(starts.len().max(1));
    let mut children = Vec::with_capacity(jobs);
    let mut pipes = Vec::with_capacity(jobs);
    // Only this thread touches the processes; the worker threads hold their pipes.
    let end = |children: &mut Vec<Child>| {
        for c in children.iter_mut() {
            let _ = c.kill();
            let _ = c.wait();
        }
    };
    for _ in 0..jobs {
        match start_worker(&workers.command) {
            Ok((child, p)) => {
                children.push(child);
                pipes.push(p);
            }
            Err(e) => {
                end(&mut children);
                return Err(e);
            }
        }
    }
    let next = AtomicUsize::new(0);
    let stop = AtomicBool::new(false);
    let mut slots: Vec<Option<SolverRun>> = vec![None; starts.len()];
    let mut failure = None;
    let (send, receive) = mpsc::channel::<Event>();
    std::thread::scope(|scope| {
        for mut p in pipes {
            let (send, next, stop) = (send.clone(), &next, &stop);
            scope.spawn(move || {
                while !stop.load(Ordering::SeqCst) {
                    let k = next.fetch_add(1, Ordering::SeqCst);
                    let Some(start) = starts.get(k) else { break };
                    let run = p.solve(start);
                    let failed = run.is_err();
                    if send.send((k, run)).is_err() || failed {
                        break;
                    }
                }
                // Dropping the pipes closes the worker's input: it ends.
            });
        }
        drop(send);
        let mut completed = 0;
        loop {
            match receive.recv_timeout(Duration::from_millis(20)) {
                Ok((k, Ok(run))) => {
                    slots[k] = Some(run);
                    completed += 1;
                    done(completed);
                }
                Ok((_, Err(e))) => {
                    failure.get_or_insert(e);
                    stop.store(true, Ordering::SeqCst);
                }
                Err(mpsc::RecvTimeoutError::Timeout) => {}
                Err(mpsc::RecvTimeoutError::Disconnected) => break,
            }
            if spine_stop::check().is_some() && !stop.swap(true, Ordering::SeqCst) {
                // Abandon the solves in flight: their threads see the pipes close.
                for c in children.iter_mut() {
                    let _ = c.kill();
                }
            }
        }
    });
    end(&mut children);
    if spine_stop::interrupt_requested() {
        return Err(RunError::Interrupted);
    }
    if let Some(e) = failure.filter(|_| spine_stop::check().is_none()) {
        return Err(e);
    }
    Ok(slots.into_iter().map_while(|s| s).collect())
}
