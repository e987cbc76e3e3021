//! The CPU-driver tuning: uniform blocks read through one private copy per invocation. The
//! result validates on every target, fills the copy only in entry points that read it, keeps
//! the binding's slot, and leaves no function reading the buffer directly.

use nimbus_clouds::CloudKey;
use nimbus_clouds::model::clouds::{cloud_module, resolve_module};
use nimbus_codegen::{Target, copy_uniforms_per_invocation, generate};

#[test]
fn uniform_blocks_are_copied_once_per_invocation() {
    for (name, mut module) in [
        ("uber", cloud_module(&CloudKey::uber()).expect("records")),
        ("resolve", resolve_module().expect("records")),
    ] {
        let block = if name == "uber" { "clouds" } else { "resolve" };
        copy_uniforms_per_invocation(&mut module);
        let g = generate(module, name, &Target::ALL).unwrap_or_else(|e| panic!("{name}: {e}"));
        let w = &g.wgsl;
        assert!(
            w.contains(&format!("@binding(0) var<uniform> {block}_buffer:")),
            "{name}: {w}"
        );
        assert!(w.contains(&format!("var<private> {block}:")), "{name}");
        // Filled once, at the top of the fragment entry point; the vertex stage reads nothing.
        assert_eq!(
            w.matches(&format!("{block} = {block}_buffer;")).count(),
            1,
            "{name}: {w}"
        );
        let code: String = w
            .lines()
            .filter(|l| !l.trim_start().starts_with("//"))
            .collect::<Vec<_>>()
            .join("\n");
        let reads = code.matches(&format!("{block}_buffer")).count();
        assert_eq!(
            reads, 2,
            "{name}: only the declaration and the copy name the buffer"
        );
        assert!(g.bindings.iter().any(|b| (b.group, b.binding) == (0, 0)));
    }
}
