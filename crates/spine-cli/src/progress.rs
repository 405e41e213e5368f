//! Progress of a long run on the terminal (stderr): one bar per stage, finished lines printed.

use indicatif::{ProgressBar, ProgressStyle};
use spine_run::Progress;

/// Draws [`Progress`] reports as bars.
#[derive(Default)]
pub struct Bars {
    bar: Option<(String, ProgressBar)>,
}

impl Bars {
    pub fn report(&mut self, p: Progress<'_>) {
        match p {
            Progress::Step { stage, done, total } => {
                if self.bar.as_ref().is_none_or(|(s, _)| s != stage) {
                    self.clear();
                    let bar = ProgressBar::new(total as u64);
                    let style =
                        ProgressStyle::with_template("  {msg} {bar:40} {pos}/{len} [{elapsed_precise}, ETA {eta}]");
                    bar.set_style(style.expect("a valid template"));
                    bar.set_message(stage.to_string());
                    self.bar = Some((stage.to_string(), bar));
                }
                if let Some((_, bar)) = &self.bar {
                    bar.set_length(total as u64);
                    bar.set_position(done as u64);
                }
            }
            Progress::Done { message } => {
                self.clear();
                crate::output::say(&format!("{message}\n"));
            }
        }
    }

    pub fn clear(&mut self) {
        if let Some((_, bar)) = self.bar.take() {
            bar.finish_and_clear();
        }
    }
}
