//! The two forms of every distinct shader agree: the naga module codegen lowers from the DSL's
//! IR (what every backend and the wgpu runtime consume) and the WGSL codegen prints from the
//! same IR (what people review and WebGPU hosts load), parsed back by naga's WGSL front end.
//! The printed text must validate, and both must declare the same interface: entry points and
//! their IO, functions, globals with their bindings, and every type laid out to the same byte
//! offsets. That the bodies compute the same is shown by pictures (`tests/render.rs` draws a
//! frame from each form) and by the GPU twin tests, which run the lowered module.

use std::path::Path;

use nimbus_clouds::CloudLibrary;
use nimbus_clouds::catalog::{catalog, cloud_catalog};
use nimbus_codegen::{Target, generate_variant, validate};
use nimbus_dsl::ShaderVariant;

/// A type spelled out with its layout, comparable across two modules' arenas.
fn layout(m: &naga::Module, ty: naga::Handle<naga::Type>) -> String {
    let t = &m.types[ty];
    match &t.inner {
        naga::TypeInner::Struct { members, span } => {
            let fields: Vec<String> = members
                .iter()
                .map(|f| {
                    format!(
                        "{}@{}:{}",
                        f.name.as_deref().unwrap_or("?"),
                        f.offset,
                        layout(m, f.ty)
                    )
                })
                .collect();
            format!(
                "struct {}[{span}]{{{}}}",
                t.name.as_deref().unwrap_or("?"),
                fields.join(",")
            )
        }
        naga::TypeInner::Array { base, size, stride } => {
            format!("array<{}, {size:?}, stride {stride}>", layout(m, *base))
        }
        other => format!("{other:?}"),
    }
}

/// Everything outside the function bodies, as lines.
fn interface(m: &naga::Module) -> Vec<String> {
    let mut out = Vec::new();
    for (_, g) in m.global_variables.iter() {
        out.push(format!(
            "global {:?} {:?} {:?}: {}",
            g.name,
            g.space,
            g.binding,
            layout(m, g.ty)
        ));
    }
    for (_, c) in m.constants.iter() {
        out.push(format!(
            "const {:?}: {} = {:?}",
            c.name,
            layout(m, c.ty),
            m.global_expressions[c.init]
        ));
    }
    for (_, o) in m.overrides.iter() {
        out.push(format!(
            "override {:?}: {} = {:?}",
            o.name,
            layout(m, o.ty),
            o.init.map(|i| &m.global_expressions[i])
        ));
    }
    let signature = |f: &naga::Function| {
        let args: Vec<String> = f
            .arguments
            .iter()
            .map(|a| format!("{:?} {:?}: {}", a.name, a.binding, layout(m, a.ty)))
            .collect();
        let result = f
            .result
            .as_ref()
            .map(|r| format!("{:?} {}", r.binding, layout(m, r.ty)));
        format!("fn {:?}({}) -> {result:?}", f.name, args.join(", "))
    };
    for (_, f) in m.functions.iter() {
        out.push(signature(f));
    }
    for e in &m.entry_points {
        out.push(format!(
            "entry {} {:?} {:?} {}",
            e.name,
            e.stage,
            e.workgroup_size,
            signature(&e.function)
        ));
    }
    out
}

#[test]
fn the_printed_wgsl_and_the_lowered_module_declare_the_same_shader() {
    let lib = CloudLibrary::load(&Path::new(env!("CARGO_MANIFEST_DIR")).join("examples"))
        .expect("the example library loads");
    let mut all = catalog();
    all.extend(cloud_catalog(&lib));
    let mut lines = 0;
    for source in &all {
        let g = generate_variant(source, &[Target::Wgsl])
            .unwrap_or_else(|e| panic!("{}: {e}", source.id()));
        let (parsed, _) = validate(&g.wgsl, &g.spans, &g.module_name, &g.variant)
            .unwrap_or_else(|e| panic!("{}: the printed WGSL: {e}", g.id()));
        let (a, b) = (interface(&parsed), interface(&g.naga));
        for (x, y) in a.iter().zip(&b) {
            assert_eq!(
                x,
                y,
                "{}: printed (left) and lowered (right) differ",
                g.id()
            );
        }
        assert_eq!(a.len(), b.len(), "{}: declaration counts differ", g.id());
        lines += a.len();
    }
    println!(
        "{} shaders: printed and lowered agree on {lines} declarations",
        all.len()
    );
    assert!(all.len() >= 12 && lines > 100, "{} shaders", all.len());
}
