//! Leftovers of interrupted runs. Temporary files and folders are named after the process that
//! made them (`.nimbus-<pid>-…`, `.<name>.nimbus-new-<pid>`, `.<name>.nimbus-old-<pid>`), so a
//! later run can tell a dead run's leftovers from a live run's work in progress.

/// Whether process `pid` is running: `/proc/<pid>` where there is a `/proc` (Linux), else
/// `kill -0 <pid>` on other Unixes (no such process means dead; one we may not signal is
/// alive). Where neither can tell, it is assumed to be, so nothing another run may still use is
/// touched.
pub(crate) fn alive(pid: u32) -> bool {
    let proc = std::path::Path::new("/proc");
    if proc.join("self").exists() {
        return proc.join(pid.to_string()).exists();
    }
    if cfg!(unix) {
        return match std::process::Command::new("kill")
            .args(["-0", &pid.to_string()])
            .stdout(std::process::Stdio::null())
            .output()
        {
            Ok(o) if o.status.success() => true,
            Ok(o) => !String::from_utf8_lossy(&o.stderr)
                .to_lowercase()
                .contains("no such process"),
            Err(_) => true,
        };
    }
    true
}

/// The process id of a temporary file `<prefix><pid>-<random><suffix>`.
pub(crate) fn pid_of_file(name: &str, prefix: &str) -> Option<u32> {
    let rest = name.strip_prefix(prefix)?;
    rest.split('-').next()?.parse().ok()
}

/// The process id of a folder named `<prefix><pid>` exactly: the pid is the whole remainder,
/// so `.a.nimbus-old-7.nimbus-new-99` (a leftover of a folder named `a.nimbus-old-7`) is not
/// taken for a leftover of `a`.
pub(crate) fn pid_of_folder(name: &str, prefix: &str) -> Option<u32> {
    name.strip_prefix(prefix)?.parse().ok()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_folder_leftover_is_named_by_its_whole_remainder() {
        assert_eq!(pid_of_folder(".a.nimbus-old-7", ".a.nimbus-old-"), Some(7));
        // The half-written new folder of a destination named `a.nimbus-old-7`.
        assert_eq!(
            pid_of_folder(".a.nimbus-old-7.nimbus-new-99", ".a.nimbus-old-"),
            None
        );
        assert_eq!(
            pid_of_file(".nimbus-42-Xyz12.partial", ".nimbus-"),
            Some(42)
        );
    }

    #[test]
    fn this_process_is_alive_and_an_impossible_one_is_not() {
        assert!(alive(std::process::id()));
        if cfg!(unix) {
            assert!(!alive(u32::MAX - 1));
        }
    }
}
