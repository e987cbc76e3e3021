//! One variant through the whole chain: specialise, print WGSL, validate with naga, translate to
//! every requested target.

use std::collections::BTreeMap;

use nimbus_dsl::ir::{ExprKind, Module, Stage, Stmt};

use crate::backend::{self, Contents};
use crate::bindings::{BindingInfo, describe};
use crate::error::CodegenError;
use crate::manifest::BindingManifest;
use crate::names::rename_for_wgsl;
use crate::share::share_repeated_subexpressions;
use crate::specialise::{specialise, walk_block};
use crate::target::Target;
use crate::validate::{Validated, lower_and_validate};
use crate::wgsl::{SpanTable, print_module};

/// One emitted file.
#[derive(Clone, Debug, PartialEq)]
pub struct OutputFile {
    pub file_name: String,
    pub target: Target,
    /// `None` for the WGSL and HLSL files, which hold every entry point.
    pub entry_point: Option<(String, Stage)>,
    pub contents: Contents,
    pub manifest: Option<BindingManifest>,
}

/// Facts about a variant, for the manifest a reviewer scans.
#[derive(Clone, Debug, PartialEq)]
pub struct VariantStats {
    /// FNV-1a 64 of the WGSL text (stable across platforms and runs).
    pub hash: u64,
    pub wgsl_lines: usize,
    pub wgsl_bytes: usize,
    pub functions: usize,
    pub bindings: usize,
    pub texture_samples: usize,
    pub loops: usize,
    /// Total bytes per target (all entry points).
    pub target_bytes: BTreeMap<Target, usize>,
}

impl VariantStats {
    /// One manifest line: `module/variant hash=... wgsl=NL/NB fns=.. ...`.
    pub fn manifest_line(&self, key: &str) -> String {
        let mut line = format!(
            "{key:<24} hash={:016x} wgsl={}L/{}B fns={} bindings={} samples={} loops={}",
            self.hash,
            self.wgsl_lines,
            self.wgsl_bytes,
            self.functions,
            self.bindings,
            self.texture_samples,
            self.loops
        );
        for (t, b) in &self.target_bytes {
            if *t != Target::Wgsl {
                line.push_str(&format!(" {}={b}B", t.name()));
            }
        }
        line
    }
}

/// A generated variant.
#[derive(Debug)]
pub struct Generated {
    pub module_name: String,
    pub variant: String,
    /// The specialised IR.
    pub ir: Module,
    pub wgsl: String,
    pub spans: SpanTable,
    /// The validated naga module lowered from the IR, overrides unresolved: what the wgpu
    /// runtime compiles (the WGSL above is its readable print).
    pub naga: naga::Module,
    /// Every binding the specialised module keeps, as data.
    pub bindings: Vec<BindingInfo>,
    pub files: Vec<OutputFile>,
    pub stats: VariantStats,
}

impl Generated {
    /// `module-variant`: the shader's identity (file names, snapshots, manifest rows).
    pub fn id(&self) -> String {
        shader_id(&self.module_name, &self.variant)
    }

    /// The binding at `(group, binding)`, if the module kept it.
    pub fn binding(&self, group: u32, binding: u32) -> Option<&BindingInfo> {
        self.bindings
            .iter()
            .find(|b| b.group == group && b.binding == binding)
    }

    pub fn file(&self, target: Target, entry: &str) -> Option<&OutputFile> {
        self.files
            .iter()
            .find(|f| f.target == target && f.entry_point.as_ref().is_some_and(|(e, _)| e == entry))
    }
}

pub(crate) fn fnv1a(bytes: &[u8]) -> u64 {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for b in bytes {
        h ^= u64::from(*b);
        h = h.wrapping_mul(0x0000_0100_0000_01b3);
    }
    h
}

fn stage_ext(stage: Stage) -> &'static str {
    match stage {
        Stage::Vertex => "vert",
        Stage::Fragment => "frag",
        Stage::Compute => "comp",
    }
}

/// `module-variant`.
pub fn shader_id(module: &str, variant: &str) -> String {
    format!("{module}-{variant}")
}

/// The file name of one entry point's output.
pub fn file_name(module: &str, variant: &str, target: Target, entry: &str, stage: Stage) -> String {
    let id = shader_id(module, variant);
    let base = format!("{id}.{entry}");
    match target {
        Target::Wgsl => format!("{id}.wgsl"),
        Target::Hlsl => format!("{id}.hlsl"),
        Target::GlslEs300 => format!("{base}.es300.{}", stage_ext(stage)),
        Target::Glsl450 => format!("{base}.450.{}", stage_ext(stage)),
        Target::Msl | Target::SpirV => format!("{base}.{}", target.extension()),
    }
}

fn count(module: &Module) -> (usize, usize) {
    let (mut samples, mut loops) = (0, 0);
    for f in &module.functions {
        walk_block(f, &f.body, &mut |id| {
            if matches!(
                f.expr(id).kind,
                ExprKind::Sample { .. } | ExprKind::Load { .. }
            ) {
                samples += 1;
            }
        });
        fn count_loops(b: &[Stmt]) -> usize {
            b.iter()
                .map(|s| match s {
                    Stmt::For { body, .. } => 1 + count_loops(body),
                    Stmt::If {
                        then, otherwise, ..
                    } => count_loops(then) + count_loops(otherwise),
                    _ => 0,
                })
                .sum()
        }
        loops += count_loops(&f.body);
    }
    (samples, loops)
}

/// Prints a recorded module and lowers it to a validated naga module (no backends).
pub fn print_and_validate(
    mut module: Module,
    variant: &str,
) -> Result<(Module, String, SpanTable, Validated), CodegenError> {
    specialise(&mut module);
    share_repeated_subexpressions(&mut module);
    rename_for_wgsl(&mut module);
    let (wgsl, spans) = print_module(&module, variant)?;
    let validated = lower_and_validate(&module, &wgsl, &spans, variant)?;
    Ok((module, wgsl, spans, validated))
}

/// Generates `targets` for a recorded module.
pub fn generate(
    module: Module,
    variant: &str,
    targets: &[Target],
) -> Result<Generated, CodegenError> {
    let (module, wgsl, spans, validated) = print_and_validate(module, variant)?;
    let mut files = Vec::new();
    let mut target_bytes = BTreeMap::new();
    // Overrides are baked once per entry point and shared by every backend.
    let constants = backend::default_constants(&module);
    let mut baked = Vec::new();
    if targets
        .iter()
        .any(|t| !matches!(t, Target::Wgsl | Target::Hlsl))
    {
        for ep in &module.entry_points {
            let b = backend::bake(&module, &ep.function).map_err(|message| CodegenError::Bake {
                module: module.name.clone(),
                variant: variant.to_string(),
                entry_point: ep.function.clone(),
                message,
            })?;
            baked.push(b);
        }
    }
    for &target in targets {
        if target == Target::Wgsl {
            files.push(OutputFile {
                file_name: file_name(&module.name, variant, target, "", Stage::Vertex),
                target,
                entry_point: None,
                contents: Contents::Text(wgsl.clone()),
                manifest: None,
            });
            target_bytes.insert(target, wgsl.len());
            continue;
        }
        if target == Target::Hlsl {
            let (text, manifest) = crate::hlsl::print_module(&module, variant)?;
            target_bytes.insert(target, text.len());
            files.push(OutputFile {
                file_name: file_name(&module.name, variant, target, "", Stage::Vertex),
                target,
                entry_point: None,
                contents: Contents::Text(text),
                manifest: Some(manifest),
            });
            continue;
        }
        for (ep, b) in module.entry_points.iter().zip(&baked) {
            // WebGL2 has no compute shaders; such entry points are skipped for GLSL ES only.
            if target == Target::GlslEs300 && ep.stage == Stage::Compute {
                continue;
            }
            let (contents, manifest) = backend::translate(
                b,
                &constants,
                &module,
                variant,
                target,
                ep.stage,
                &ep.function,
            )
            .map_err(|message| CodegenError::Backend {
                module: module.name.clone(),
                variant: variant.to_string(),
                target,
                entry_point: ep.function.clone(),
                message,
            })?;
            *target_bytes.entry(target).or_insert(0) += contents.len_bytes();
            files.push(OutputFile {
                file_name: file_name(&module.name, variant, target, &ep.function, ep.stage),
                target,
                entry_point: Some((ep.function.clone(), ep.stage)),
                contents,
                manifest,
            });
        }
    }
    let bindings = describe(&module, &validated);
    let (texture_samples, loops) = count(&module);
    let stats = VariantStats {
        hash: fnv1a(wgsl.as_bytes()),
        wgsl_lines: wgsl.lines().count(),
        wgsl_bytes: wgsl.len(),
        functions: module.functions.len(),
        bindings: module
            .globals
            .iter()
            .filter(|g| g.binding().is_some())
            .count(),
        texture_samples,
        loops,
        target_bytes,
    };
    Ok(Generated {
        module_name: module.name.clone(),
        variant: variant.to_string(),
        ir: module,
        wgsl,
        spans,
        naga: validated.module,
        bindings,
        files,
        stats,
    })
}
