//! What the process used, peak memory and CPU time, which benchmarks and
//! studies report beside their wall times (on a shared machine the wall
//! time of a piece of work says little about its cost), and what memory it
//! may still use, which work too large for the machine is refused against.

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

/// How much memory a piece of work may use, and where that figure comes from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MemoryBudget {
    /// A limit asked for (`--memory-limit`).
    Limit(u64),
    /// What this process has available now ([`available_memory`]).
    Available(u64),
}

impl MemoryBudget {
    /// The limit asked for, or else what is available (none where that
    /// cannot be read).
    pub fn of(limit: Option<u64>) -> Option<Self> {
        match limit {
            Some(bytes) => Some(MemoryBudget::Limit(bytes)),
            None => available_memory().map(MemoryBudget::Available),
        }
    }

    pub fn bytes(self) -> u64 {
        match self {
            MemoryBudget::Limit(b) | MemoryBudget::Available(b) => b,
        }
    }

    /// The budget in words, for a message.
    pub fn describe(self) -> String {
        match self {
            MemoryBudget::Limit(b) => format!("the limit of {} (--memory-limit)", size(b)),
            MemoryBudget::Available(b) => format!("the {} this process has available", size(b)),
        }
    }
}

/// Bytes in binary units, three significant digits: `512 B`, `1.50 MiB`, `4.17 GiB`.
pub fn size(bytes: u64) -> String {
    let units = ["B", "KiB", "MiB", "GiB", "TiB", "PiB"];
    let mut value = bytes as f64;
    let mut unit = 0;
    while value >= 1024.0 && unit + 1 < units.len() {
        value /= 1024.0;
        unit += 1;
    }
    match unit {
        0 => format!("{bytes} B"),
        _ if value < 10.0 => format!("{value:.2} {}", units[unit]),
        _ if value < 100.0 => format!("{value:.1} {}", units[unit]),
        _ => format!("{value:.0} {}", units[unit]),
    }
}

/// Address space each worker thread may reserve beyond what it uses: glibc
/// gives a thread its own malloc arena, 64 MiB of address space, which an
/// address-space limit (`ulimit -v`) counts in full.
const ARENA: u64 = 64 << 20;

/// The memory this process can still take (Linux), bytes: the smallest of
/// what the machine has available (`MemAvailable`), what its cgroup's limit
/// leaves, and what its address-space limit (`ulimit -v`) leaves after the
/// address space it holds and an arena per worker thread. `None` where none
/// of them can be read.
pub fn available_memory() -> Option<u64> {
    let meminfo = std::fs::read_to_string("/proc/meminfo")
        .ok()
        .and_then(|info| {
            let line = info.lines().find(|l| l.starts_with("MemAvailable:"))?;
            let kib: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
            Some(kib * 1024)
        });
    [meminfo, cgroup_room(), address_room()]
        .into_iter()
        .flatten()
        .min()
}

/// A number of bytes from a file holding one (`max` or a huge value: no limit).
fn bytes_in(path: &str) -> Option<u64> {
    let v: u64 = std::fs::read_to_string(path).ok()?.trim().parse().ok()?;
    (v < 1 << 60).then_some(v)
}

/// What the cgroup's memory limit leaves (cgroup v2, else v1).
fn cgroup_room() -> Option<u64> {
    let pairs = [
        ("/sys/fs/cgroup/memory.max", "/sys/fs/cgroup/memory.current"),
        (
            "/sys/fs/cgroup/memory/memory.limit_in_bytes",
            "/sys/fs/cgroup/memory/memory.usage_in_bytes",
        ),
    ];
    pairs
        .iter()
        .find_map(|(max, now)| Some(bytes_in(max)?.saturating_sub(bytes_in(now).unwrap_or(0))))
}

/// What the address-space limit leaves: the soft limit of `/proc/self/limits`
/// less the address space held (`VmSize`) and an arena per worker thread.
fn address_room() -> Option<u64> {
    let limits = std::fs::read_to_string("/proc/self/limits").ok()?;
    let line = limits
        .lines()
        .find(|l| l.starts_with("Max address space"))?;
    let limit: u64 = line
        .trim_start_matches("Max address space")
        .split_whitespace()
        .next()?
        .parse()
        .ok()?;
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let held: u64 = status
        .lines()
        .find(|l| l.starts_with("VmSize:"))
        .and_then(|l| l.split_whitespace().nth(1)?.parse::<u64>().ok())
        .map_or(0, |kib| kib * 1024);
    let threads = rayon::current_num_threads() as u64;
    Some(limit.saturating_sub(held + threads * ARENA))
}
