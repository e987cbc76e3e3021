//! Tests that need a tool this machine may lack (node, Chromium): each says what is missing and
//! passes, except where CI asks for the tool (`NIMBUS_REQUIRE_BROWSER=1`), where it fails, so
//! that a skipped test can never pass in CI.

/// `true` when `missing` names nothing (the test runs); otherwise prints why `test` is skipped
/// and returns `false`, or panics under `NIMBUS_REQUIRE_BROWSER=1`.
pub fn browser_tools_present(test: &str, missing: Option<String>) -> bool {
    let Some(why) = missing else { return true };
    let required = std::env::var("NIMBUS_REQUIRE_BROWSER").is_ok_and(|v| v == "1");
    println!("skipping {test}: {why}");
    assert!(!required, "NIMBUS_REQUIRE_BROWSER=1 but {why}");
    false
}

/// `None` when `node` runs, else why not.
pub fn node_missing() -> Option<String> {
    match std::process::Command::new("node").arg("--version").output() {
        Ok(o) if o.status.success() => None,
        _ => Some("node is not installed".into()),
    }
}
