//! What a long run reports while it works (a front end draws it; the library prints nothing).

/// One report of a run in progress.
#[derive(Clone, Debug, PartialEq)]
pub enum Progress<'a> {
    /// `done` of `total` steps of the stage `stage` (solves of a multi-start or a study,
    /// generations of the GA, targets of eq. (35), …).
    Step { stage: &'a str, done: usize, total: usize },
    /// A stage finished; `message` is one line for the user.
    Done { message: String },
}

/// A progress sink that drops everything.
pub fn quiet(_: Progress<'_>) {}
