//! Progress on stderr: a bar redrawn in place on a terminal; in a batch log
//! or a pipe, where a bar draws nothing useful, a plain line now and then.

use std::io::IsTerminal;
use std::sync::Mutex;
use std::time::{Duration, Instant};

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use rgc::progress::Progress;

/// How often a log line is written when stderr is not a terminal: often
/// enough to see a job is alive, rarely enough to keep a Slurm log short.
const LOG_EVERY: Duration = Duration::from_secs(10);

/// The progress a subcommand shows on stderr.
pub enum Reporter {
    /// `--quiet`, or output a script reads (`--json`).
    Quiet,
    /// stderr is a terminal.
    Bar(Mutex<ProgressBar>),
    /// stderr is a file or a pipe.
    Log(Mutex<Stage>),
}

impl Reporter {
    /// A bar on a terminal, log lines elsewhere, nothing when `quiet`.
    pub fn new(quiet: bool) -> Reporter {
        if quiet {
            Reporter::Quiet
        } else if std::io::stderr().is_terminal() {
            Reporter::Bar(Mutex::new(ProgressBar::hidden()))
        } else {
            Reporter::Log(Mutex::new(Stage::new("", 0, Instant::now())))
        }
    }
}

impl Progress for Reporter {
    fn start(&self, label: &str, total: u64) {
        match self {
            Reporter::Quiet => {}
            Reporter::Bar(bar) => {
                let pb = ProgressBar::with_draw_target(Some(total), ProgressDrawTarget::stderr());
                pb.set_style(
                    ProgressStyle::with_template(
                        "{msg} [{elapsed_precise}] {wide_bar} {pos}/{len} {percent}% (about {eta} left)",
                    )
                    .expect("a valid template"),
                );
                pb.set_message(label.to_string());
                *lock(bar) = pb;
            }
            Reporter::Log(stage) => *lock(stage) = Stage::new(label, total, Instant::now()),
        }
    }

    fn advance(&self, units: u64) {
        match self {
            Reporter::Quiet => {}
            Reporter::Bar(bar) => lock(bar).inc(units),
            Reporter::Log(stage) => {
                if let Some(line) = lock(stage).advance(units, Instant::now()) {
                    eprintln!("{line}");
                }
            }
        }
    }

    fn finish(&self) {
        match self {
            Reporter::Quiet => {}
            Reporter::Bar(bar) => lock(bar).finish_and_clear(),
            Reporter::Log(stage) => eprintln!("{}", lock(stage).done(Instant::now())),
        }
    }

    fn note(&self, line: &str) {
        match self {
            Reporter::Quiet => {}
            Reporter::Bar(bar) => lock(bar).suspend(|| eprintln!("{line}")),
            Reporter::Log(_) => eprintln!("rgc: {line}"),
        }
    }
}

/// A poisoned lock only means another thread panicked while counting; the
/// count is still good enough to show.
fn lock<T>(m: &Mutex<T>) -> std::sync::MutexGuard<'_, T> {
    m.lock().unwrap_or_else(|e| e.into_inner())
}

/// One stage as the log sees it.
pub struct Stage {
    label: String,
    total: u64,
    done: u64,
    started: Instant,
    logged: Instant,
}

impl Stage {
    fn new(label: &str, total: u64, now: Instant) -> Stage {
        Stage {
            label: label.to_string(),
            total,
            done: 0,
            started: now,
            logged: now,
        }
    }

    /// Counts `units`; returns a line to log if [`LOG_EVERY`] has passed
    /// since the stage started or since the last line.
    fn advance(&mut self, units: u64, now: Instant) -> Option<String> {
        self.done += units;
        if now.duration_since(self.logged) < LOG_EVERY {
            return None;
        }
        self.logged = now;
        Some(format!("{}, {} elapsed", self.counts(), self.elapsed(now)))
    }

    /// The closing line of the stage.
    fn done(&self, now: Instant) -> String {
        format!("{}, done in {}", self.counts(), self.elapsed(now))
    }

    fn counts(&self) -> String {
        let percent = if self.total == 0 {
            100.0
        } else {
            100.0 * self.done as f64 / self.total as f64
        };
        format!(
            "rgc: {}: {}/{} ({percent:.0}%)",
            self.label, self.done, self.total
        )
    }

    fn elapsed(&self, now: Instant) -> String {
        let s = now.duration_since(self.started).as_secs();
        format!("{:02}:{:02}:{:02}", s / 3600, s / 60 % 60, s % 60)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_log_line_at_most_every_interval_with_counts_percent_and_time() {
        let t0 = Instant::now();
        let mut s = Stage::new("rods n=8", 200, t0);
        assert_eq!(s.advance(10, t0 + Duration::from_secs(3)), None);
        assert_eq!(
            s.advance(40, t0 + Duration::from_secs(10)).as_deref(),
            Some("rgc: rods n=8: 50/200 (25%), 00:00:10 elapsed")
        );
        assert_eq!(s.advance(50, t0 + Duration::from_secs(19)), None);
        assert_eq!(
            s.advance(50, t0 + Duration::from_secs(3725)).as_deref(),
            Some("rgc: rods n=8: 150/200 (75%), 01:02:05 elapsed")
        );
        s.advance(50, t0 + Duration::from_secs(3726));
        assert_eq!(
            s.done(t0 + Duration::from_secs(3727)),
            "rgc: rods n=8: 200/200 (100%), done in 01:02:07"
        );
    }
}
