//! Writing Nimbus's outputs so that nothing is lost: every file is written to a unique
//! temporary file in its destination folder, flushed to disk and renamed over the old one, so
//! a reader (or a crash) sees the complete old file or the complete new one; a folder of
//! outputs is replaced the same way, the old one moved aside only once the new one is
//! complete. A file or folder Nimbus did not write is never replaced unless the user says
//! `--force`: each file carries a signature Nimbus recognises ([`Signature`]), each folder a
//! record of every file Nimbus wrote into it ([`OWNERSHIP_FILE`]). Leftovers of an interrupted run are recognised by name and cleaned up.
//!
//! Destinations are checked ([`check_file`], [`check_folder`]) before any work starts, so a
//! bad `-o` fails in a second, not after a long render. A link, FIFO or device as a
//! destination is refused there too.

mod destination;
mod error;
mod exr_image;
mod file;
mod folder;
mod leftovers;
mod ownership;
mod signature;

pub use error::OutputError;
pub use exr_image::{ExrChannel, signed_exr};
pub use file::{check_file, write_exr, write_file, write_png};
pub use folder::{check_folder, replace_folder};
pub use ownership::OWNERSHIP_FILE;
pub use signature::{Signature, TEXT_MARKER, signed_png};

/// Whether an existing output Nimbus did not write may be replaced (`--force`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Overwrite {
    /// Only what Nimbus wrote (the default).
    #[default]
    OwnOnly,
    /// Anything: the user passed `--force`.
    Force,
}

impl Overwrite {
    /// `Force` when `force` (the flag's value).
    pub fn forced(force: bool) -> Self {
        if force {
            Overwrite::Force
        } else {
            Overwrite::OwnOnly
        }
    }
}
