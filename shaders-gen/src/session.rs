//! The process's environment, settled before anything else runs.
//!
//! Mesa's Vulkan `device_select` layer asks the Wayland compositor which GPU drives the
//! display whenever an instance enables `VK_KHR_wayland_surface` (wgpu always does). Without a
//! desktop session (no `XDG_RUNTIME_DIR`: a server, a container, CI) there is no compositor to
//! ask, and libwayland prints "error: XDG_RUNTIME_DIR is invalid or not set" twice on every
//! run. The layer has nothing to choose between there, so it is switched off by the variable
//! it documents for that (`NODEVICE_SELECT`), unless the user set it either way.

/// Switches off Mesa's display-probing layer where there is no desktop session. Call first in
/// `main`, before any thread exists.
pub(crate) fn quiet_display_probes() {
    let no_session = std::env::var_os("XDG_RUNTIME_DIR").is_none_or(|d| d.is_empty());
    if no_session && std::env::var_os("NODEVICE_SELECT").is_none() {
        // SAFETY: called at the start of `main`, before any other thread is spawned, so no
        // thread can read the environment while it is written.
        #[allow(unsafe_code)]
        unsafe {
            std::env::set_var("NODEVICE_SELECT", "1");
        }
    }
}
