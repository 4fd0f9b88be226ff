//! What the process used, peak memory and CPU time, which benchmarks and
//! studies report beside their wall times (on a shared machine the wall
//! time of a piece of work says little about its cost); what it holds now
//! and may still take; and the guard that refuses a step of work before it
//! would take the process past its limit, instead of an allocation failing
//! (an abort) or a scheduler killing the job.

use std::sync::OnceLock;

use serde::{Deserialize, Serialize};

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

/// What the machine has available (`MemAvailable`) and its cgroup's limit
/// leaves, the smaller.
fn machine_room() -> Option<u64> {
    let meminfo = std::fs::read_to_string("/proc/meminfo")
        .ok()
        .and_then(|info| {
            let line = info.lines().find(|l| l.starts_with("MemAvailable:"))?;
            let kib: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
            Some(kib * 1024)
        });
    [meminfo, cgroup_room()].into_iter().flatten().min()
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

/// The soft address-space limit (`ulimit -v`) of `/proc/self/limits`,
/// `None` where there is none.
fn address_limit() -> Option<u64> {
    let limits = std::fs::read_to_string("/proc/self/limits").ok()?;
    let line = limits
        .lines()
        .find(|l| l.starts_with("Max address space"))?;
    line.trim_start_matches("Max address space")
        .split_whitespace()
        .next()?
        .parse()
        .ok()
}

/// The address space the worker threads' malloc arenas may take.
fn arenas() -> u64 {
    rayon::current_num_threads() as u64 * ARENA
}

/// What the process holds now, bytes (Linux `/proc/self/statm`, a read of
/// a few microseconds).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Held {
    /// Resident set size: what a memory limit (a cgroup, Slurm's `--mem`) counts.
    pub resident: u64,
    /// Address space (`VmSize`): what `ulimit -v` counts.
    pub address: u64,
}

/// What the process holds now; `None` where it cannot be read.
pub fn held() -> Option<Held> {
    let statm = std::fs::read_to_string("/proc/self/statm").ok()?;
    let mut pages = statm.split_whitespace().map(|v| v.parse::<u64>().ok());
    let (address, resident) = (pages.next()??, pages.next()??);
    let page = page_size();
    Some(Held {
        resident: resident * page,
        address: address * page,
    })
}

/// The page size, from the auxiliary vector's `AT_PAGESZ` (4096 where it
/// cannot be read).
fn page_size() -> u64 {
    static PAGE: OnceLock<u64> = OnceLock::new();
    *PAGE.get_or_init(|| {
        const AT_PAGESZ: usize = 6;
        let word = std::mem::size_of::<usize>();
        let auxv = std::fs::read("/proc/self/auxv").unwrap_or_default();
        auxv.chunks_exact(2 * word)
            .find_map(|pair| {
                let value = |at: usize| -> Option<usize> {
                    Some(usize::from_ne_bytes(pair[at..at + word].try_into().ok()?))
                };
                (value(0)? == AT_PAGESZ).then(|| value(word)).flatten()
            })
            .map_or(4096, |p| p as u64)
    })
}

/// Address space that faer's matrix products (`private-gemm-x86`) reserve
/// on a thread's first large product and keep: twice the last-level cache,
/// mostly never touched, so it costs no resident memory but counts in full
/// against `ulimit -v`. 0 off x86-64 or where the cache size is unknown.
pub fn product_scratch() -> u64 {
    static SCRATCH: OnceLock<u64> = OnceLock::new();
    *SCRATCH.get_or_init(|| {
        if !cfg!(target_arch = "x86_64") {
            return 0;
        }
        let dir = "/sys/devices/system/cpu/cpu0/cache";
        let read = |index: &str, file: &str| {
            std::fs::read_to_string(format!("{dir}/{index}/{file}")).unwrap_or_default()
        };
        (0..8)
            .map(|i| format!("index{i}"))
            .filter(|i| read(i, "level").trim() == "3")
            .find_map(|i| {
                let text = read(&i, "size");
                let kib: u64 = text.trim().strip_suffix('K')?.parse().ok()?;
                Some(2 * kib * 1024)
            })
            .unwrap_or(0)
    })
}

/// What a refused step would have taken the process past.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Bound {
    /// The limit asked for (`--memory-limit`), on the resident size.
    Limit,
    /// What the machine, or the process's cgroup, lets it hold now.
    Available,
    /// The address-space limit (`ulimit -v`), on the address space.
    AddressSpace,
}

/// A step of work refused before it ran: what it needed, what the process
/// held, and the bound between them.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct Refusal {
    /// Bytes the step would add (address space, for [`Bound::AddressSpace`]).
    pub need: u64,
    /// Bytes the process held (address space, for [`Bound::AddressSpace`]).
    pub held: u64,
    pub limit: u64,
    pub bound: Bound,
}

impl Refusal {
    /// One line: `<what> needs about X, the process holds Y, over the limit
    /// of Z (--memory-limit)`.
    pub fn describe(&self, what: &str) -> String {
        let over = match self.bound {
            Bound::Limit => format!("the limit of {} (--memory-limit)", size(self.limit)),
            Bound::Available => format!(
                "the {} it may hold now (free memory, its cgroup's limit)",
                size(self.limit)
            ),
            Bound::AddressSpace => format!(
                "its address-space limit of {} (ulimit -v)",
                size(self.limit)
            ),
        };
        let space = match self.bound {
            Bound::AddressSpace => " of address space",
            _ => "",
        };
        format!(
            "{what} needs about {}{space}, the process holds {}, over {over}",
            size(self.need),
            size(self.held)
        )
    }
}

/// Refuses a step that would add `need` bytes (and reserve `scratch` more
/// of address space that it does not touch) if the process would pass
/// `limit` (on its resident size), what the machine or its cgroup has
/// available, or its address-space limit; reads them all now. Returns the
/// resident size it read (`None` where it cannot be read: nothing is
/// checked then).
pub fn reserve(need: u64, scratch: u64, limit: Option<u64>) -> Result<Option<u64>, Refusal> {
    let Some(now) = held() else {
        return Ok(None);
    };
    if let Some(limit) = limit
        && now.resident + need > limit
    {
        return Err(Refusal {
            need,
            held: now.resident,
            limit,
            bound: Bound::Limit,
        });
    }
    if let Some(limit) = address_limit() {
        let need = need + scratch + arenas();
        if now.address + need > limit {
            return Err(Refusal {
                need,
                held: now.address,
                limit,
                bound: Bound::AddressSpace,
            });
        }
    }
    if let Some(room) = machine_room()
        && need > room
    {
        return Err(Refusal {
            need,
            held: now.resident,
            limit: now.resident + room,
            bound: Bound::Available,
        });
    }
    Ok(Some(now.resident))
}

/// Growth a [`Guard`] admits on its estimates alone between two readings
/// of the process's size: a reading costs tens of microseconds, so a run
/// of small steps (most fronts of an elimination) is read now and then.
const UNREAD: u64 = 8 << 20;

/// [`reserve`] over the many steps of one piece of work, cheap for small
/// ones: a step is admitted without a reading while the last reading plus
/// the estimates admitted since stay within the limit and below
/// 8 MiB; otherwise the process's size is read again.
#[derive(Clone, Debug)]
pub struct Guard {
    limit: Option<u64>,
    /// Resident bytes at the last reading.
    read: Option<u64>,
    /// Bytes admitted since.
    since: u64,
    readings: usize,
}

impl Guard {
    /// A guard of `limit` (on the resident size; the machine and the
    /// address-space limit are always checked).
    pub fn new(limit: Option<u64>) -> Guard {
        Guard {
            limit,
            read: None,
            since: 0,
            readings: 0,
        }
    }

    /// Admits a step that adds about `need` bytes and reserves `scratch`
    /// bytes of address space it does not touch, or refuses it.
    pub fn admit(&mut self, need: u64, scratch: u64) -> Result<(), Refusal> {
        let since = self.since + need;
        if scratch == 0
            && since < UNREAD
            && let Some(read) = self.read
            && self.limit.is_none_or(|l| read + since <= l)
        {
            self.since = since;
            return Ok(());
        }
        self.read = reserve(need, scratch, self.limit)?;
        self.since = need;
        self.readings += 1;
        Ok(())
    }

    /// How often it read the process's size.
    pub fn readings(&self) -> usize {
        self.readings
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_guard_reads_the_process_size_for_large_or_accumulated_steps() {
        let Some(now) = held() else {
            return;
        };
        assert!(now.resident > 0 && now.address >= now.resident, "{now:?}");
        let mut guard = Guard::new(None);
        guard.admit(1 << 20, 0).unwrap();
        assert_eq!(guard.readings(), 1, "the first step reads");
        for _ in 0..6 {
            guard.admit(1 << 20, 0).unwrap();
        }
        assert_eq!(guard.readings(), 1, "7 MiB of small steps pass unread");
        guard.admit(1 << 20, 0).unwrap();
        assert_eq!(guard.readings(), 2, "8 MiB since the last reading");
        guard.admit(UNREAD, 0).unwrap();
        assert_eq!(guard.readings(), 3, "one large step reads");
        guard.admit(0, 1).unwrap();
        assert_eq!(guard.readings(), 4, "address space to reserve reads");
    }

    #[test]
    fn a_step_over_the_limit_is_refused_with_what_is_held() {
        let Some(now) = held() else {
            return;
        };
        // Room for 64 MiB more: a 1 GiB step is refused naming the limit.
        let limit = now.resident + (64 << 20);
        let refusal = reserve(1 << 30, 0, Some(limit)).unwrap_err();
        assert_eq!((refusal.bound, refusal.limit), (Bound::Limit, limit));
        assert_eq!(refusal.need, 1 << 30);
        assert!(refusal.held >= now.resident / 2, "{refusal:?}");
        let text = refusal.describe("the step");
        assert!(
            text.starts_with("the step needs about 1.00 GiB, the process holds ")
                && text.ends_with(&format!(
                    ", over the limit of {} (--memory-limit)",
                    size(limit)
                )),
            "{text}"
        );
        // Estimates are not held memory: steps that allocate nothing pass,
        // the process's size read again every 8 MiB of them.
        let mut guard = Guard::new(Some(limit));
        for _ in 0..100 {
            guard.admit(1 << 20, 0).unwrap();
        }
        assert_eq!(guard.readings(), 15, "steps 1, 8, 15, ..., 99");
    }

    #[test]
    fn reading_the_process_size_is_cheap() {
        // What a guard pays per reading: statm alone, and everything
        // `reserve` reads (statm, limits, meminfo, the cgroup's files).
        let time = |f: &dyn Fn()| {
            let start = std::time::Instant::now();
            for _ in 0..2000 {
                f();
            }
            start.elapsed().as_secs_f64() / 2000.0
        };
        let statm = time(&|| {
            std::hint::black_box(held());
        });
        let whole = time(&|| {
            let _ = std::hint::black_box(reserve(0, 0, None));
        });
        eprintln!(
            "one reading: statm {:.1} us, reserve {:.1} us",
            statm * 1e6,
            whole * 1e6
        );
        assert!(statm < 1e-3 && whole < 2e-3, "{statm} {whole}");
    }
}
