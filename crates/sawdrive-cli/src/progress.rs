//! The command line's progress display: a spinner on stderr (a terminal only) showing the stage
//! the library reports through its [`RunControl`]. The library itself draws nothing.

use std::io::IsTerminal;
use std::time::Duration;

use indicatif::{ProgressBar, ProgressStyle};
use sawdrive::pipeline::RunControl;

/// Tick of the spinner. Unit: ms. Default 120 (smooth without costing a core).
const TICK_MS: u64 = 120;

/// A spinner and the run control that feeds it. Dropped (or [`Spinner::finish`]ed), it clears
/// its line.
#[derive(Debug)]
pub struct Spinner {
    bar: ProgressBar,
    control: RunControl,
}

impl Spinner {
    /// A spinner shown when `enabled` and stderr is a terminal; else hidden (its control
    /// reports to nobody).
    pub fn new(enabled: bool) -> Self {
        if !enabled || !std::io::stderr().is_terminal() {
            return Self {
                bar: ProgressBar::hidden(),
                control: RunControl::none(),
            };
        }
        let bar = ProgressBar::new_spinner();
        if let Ok(style) = ProgressStyle::with_template("{spinner} [{elapsed}] {msg}") {
            bar.set_style(style);
        }
        bar.enable_steady_tick(Duration::from_millis(TICK_MS));
        let shown = bar.clone();
        let control = RunControl::none().with_progress(move |p| shown.set_message(p.to_string()));
        Self { bar, control }
    }

    /// The run control to hand the library (never stops; Ctrl-C ends the process).
    pub fn control(&self) -> &RunControl {
        &self.control
    }

    /// Clear the spinner's line.
    pub fn finish(&self) {
        self.bar.finish_and_clear();
    }
}

impl Drop for Spinner {
    fn drop(&mut self) {
        self.finish();
    }
}
