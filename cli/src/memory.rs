//! What the planner's `--memory-limit` is checked against: the larger of the
//! heap bytes the global allocator holds and the process's resident set. The
//! allocator's own overhead (pages it keeps, fragmentation) is about a tenth
//! of the heap on the large searches, and a limit is a bound on what the
//! machine gives the process, so the resident set counts too.

/// Bytes in use by the process, as the memory limit counts them.
pub fn in_use() -> usize {
    hipop_analyzer::alloc::in_use().max(resident().unwrap_or(0))
}

/// The resident set, from `/proc/self/status` (`VmRSS`, in KiB); `None`
/// where there is no such file.
fn resident() -> Option<usize> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with("VmRSS:"))?;
    let kib: usize = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kib.saturating_mul(1024))
}

#[cfg(test)]
mod tests {
    /// On Linux the resident set is read, and is at least the heap this
    /// test holds once it is touched.
    #[test]
    #[cfg(target_os = "linux")]
    fn the_resident_set_is_read() {
        let held = vec![1u8; 8 << 20];
        let rss = super::resident().expect("/proc/self/status has VmRSS");
        assert!(rss >= held.len(), "{rss} < {}", held.len());
        drop(held);
    }
}
