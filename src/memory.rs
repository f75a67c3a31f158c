//! The process's own memory, for the viewer's `memory` script action, its stats panel and the
//! soak tests.

/// Resident set size of this process in bytes (`VmRSS` in Linux's `/proc/self/status`); `None`
/// where that file does not exist or cannot be read.
pub fn resident_bytes() -> Option<u64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with("VmRSS:"))?;
    let kb: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kb * 1024)
}
