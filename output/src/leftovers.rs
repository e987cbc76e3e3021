//! Leftovers of interrupted runs. Temporary files and folders are named after the process that
//! made them (`.nimbus-<pid>-…`, `.<name>.nimbus-new-<pid>`, `.<name>.nimbus-old-<pid>`), so a
//! later run can tell a dead run's leftovers from a live run's work in progress.

/// Whether process `pid` is running. Where that cannot be told (no `/proc`), it is assumed to
/// be, so nothing another run may still use is touched.
pub(crate) fn alive(pid: u32) -> bool {
    let proc = std::path::Path::new("/proc");
    !proc.is_dir() || proc.join(pid.to_string()).exists()
}

/// The process id in a leftover's name: what follows `prefix`, up to `-` or the end.
pub(crate) fn pid_after(name: &str, prefix: &str) -> Option<u32> {
    let rest = name.strip_prefix(prefix)?;
    let digits = rest.split(['-', '.']).next()?;
    digits.parse().ok()
}
