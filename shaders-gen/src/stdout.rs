//! What the commands print for people, written so that a closed reader ends the printing and
//! nothing else: `nimbus list | head -1` must not panic (Rust ignores SIGPIPE, so `println!`
//! panics on a closed pipe), and a `render` whose log is piped into something that stops
//! reading still writes its picture. Other write errors (a full disk under a redirect) are
//! reported once on stderr and the command goes on: the log is never the command's product.

use std::io::Write;
use std::sync::atomic::{AtomicBool, Ordering};

/// Set once stdout cannot be written; later lines are dropped.
static CLOSED: AtomicBool = AtomicBool::new(false);

/// Writes `args` to stdout (with `newline`), unless stdout stopped taking lines.
pub(crate) fn write(args: std::fmt::Arguments<'_>, newline: bool) {
    if CLOSED.load(Ordering::Relaxed) {
        return;
    }
    let mut out = std::io::stdout().lock();
    let written = if newline {
        writeln!(out, "{args}")
    } else {
        write!(out, "{args}")
    };
    if let Err(e) = written.and_then(|()| out.flush()) {
        CLOSED.store(true, Ordering::Relaxed);
        if e.kind() != std::io::ErrorKind::BrokenPipe {
            let _ = writeln!(
                std::io::stderr(),
                "warning: cannot write to stdout ({e}); the rest of the log is dropped"
            );
        }
    }
}

/// Writes `args` and a newline to stderr; a closed stderr drops it (nothing else can be told).
pub(crate) fn write_err(args: std::fmt::Arguments<'_>) {
    let _ = writeln!(std::io::stderr().lock(), "{args}");
}

/// `println!` for the command's log (see the module).
macro_rules! say {
    () => { $crate::stdout::write(format_args!(""), true) };
    ($($arg:tt)*) => { $crate::stdout::write(format_args!($($arg)*), true) };
}

/// `print!` for the command's log.
macro_rules! say_part {
    ($($arg:tt)*) => { $crate::stdout::write(format_args!($($arg)*), false) };
}

/// `eprintln!` for warnings and failures that must not panic on a closed stderr.
macro_rules! say_err {
    ($($arg:tt)*) => { $crate::stdout::write_err(format_args!($($arg)*)) };
}
