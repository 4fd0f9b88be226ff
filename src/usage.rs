//! What the process used, peak memory and CPU time, which benchmarks and
//! studies report beside their wall times (on a shared machine the wall
//! time of a piece of work says little about its cost).

/// Peak resident set size of this process (Linux `VmHWM`), MiB; 0 where unknown.
pub fn peak_rss_mib() -> f64 {
    std::fs::read_to_string("/proc/self/status")
        .ok()
        .and_then(|s| {
            s.lines()
                .find(|l| l.starts_with("VmHWM:"))
                .and_then(|l| l.split_whitespace().nth(1)?.parse::<f64>().ok())
        })
        .map_or(0.0, |kib| kib / 1024.0)
}

/// Lowers the peak resident set size to the current one (Linux 4.0 and
/// later, `clear_refs` mode 5), so that the next peak belongs to what runs
/// next and not to an earlier, larger system. False where it cannot.
pub fn reset_peak_rss() -> bool {
    std::fs::write("/proc/self/clear_refs", "5").is_ok()
}

/// CPU time of the calling thread, user plus system, from Linux
/// `/proc/thread-self/stat`; `None` where unknown.
pub fn thread_cpu_seconds() -> Option<f64> {
    cpu_seconds("/proc/thread-self/stat")
}

/// CPU time of the whole process, user plus system, all threads, from
/// `/proc/self/stat`; `None` where unknown.
pub fn process_cpu_seconds() -> Option<f64> {
    cpu_seconds("/proc/self/stat")
}

/// User plus system time of a Linux `stat` file, in the kernel's fixed 100
/// ticks per second.
fn cpu_seconds(path: &str) -> Option<f64> {
    let stat = std::fs::read_to_string(path).ok()?;
    // The fields after the command name, which may hold spaces, start at
    // the third (state); user and system time are the 14th and 15th.
    let fields: Vec<&str> = stat.rsplit_once(')')?.1.split_whitespace().collect();
    let ticks = |i: usize| fields.get(i)?.parse::<f64>().ok();
    Some((ticks(11)? + ticks(12)?) / 100.0)
}
