//! One variant through the whole chain: specialise, print WGSL, validate with naga, translate to
//! every requested target.

use std::collections::BTreeMap;
use std::sync::OnceLock;

use nimbus_dsl::ir::{ExprKind, Module, Stage, Stmt};

use crate::backend::{self, Contents};
use crate::bindings::{BindingInfo, describe};
use crate::error::CodegenError;
use crate::manifest::BindingManifest;
use crate::names::rename_for_wgsl;
use crate::share::{share_on_every_core, share_repeated_subexpressions};
use crate::specialise::{specialise, specialise_on_every_core, walk_block};
use crate::target::Target;
use crate::validate::{Validated, explain_refusal, lower_and_validate, lower_checked};
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

/// The passes over the recorded IR every target shares: constants folded and dead code gone,
/// repeated sub-expressions bound once, names made legal everywhere. `every_core`: the
/// per-function work on rayon's pool (for a key generated for several targets; a key for WGSL
/// alone stays on its thread, where a hand-off costs more than it saves).
fn prepare(mut module: Module, every_core: bool) -> Module {
    if every_core {
        specialise_on_every_core(&mut module);
        share_on_every_core(&mut module);
    } else {
        specialise(&mut module);
        share_repeated_subexpressions(&mut module);
    }
    rename_for_wgsl(&mut module);
    module
}

/// Prints a prepared module as WGSL and lowers it to a validated naga module.
fn print_then_validate(
    module: &Module,
    variant: &str,
) -> Result<(String, SpanTable, Validated), CodegenError> {
    let (wgsl, spans) = print_module(module, variant)?;
    let validated = lower_and_validate(module, &wgsl, &spans, variant)?;
    Ok((wgsl, spans, validated))
}

/// Prints a recorded module and lowers it to a validated naga module (no backends).
pub fn print_and_validate(
    module: Module,
    variant: &str,
) -> Result<(Module, String, SpanTable, Validated), CodegenError> {
    let module = prepare(module, false);
    let (wgsl, spans, validated) = print_then_validate(&module, variant)?;
    Ok((module, wgsl, spans, validated))
}

/// Whether `target` gets a file for an entry point of `stage`: WebGL2 has no compute shaders,
/// so GLSL ES skips them; every other target takes every entry point.
fn translates(target: Target, stage: Stage) -> bool {
    !(target == Target::GlslEs300 && stage == Stage::Compute)
}

/// One entry point translated to one of naga's targets: the file and its manifest.
type Translated = Result<(Contents, Option<BindingManifest>), CodegenError>;

/// Generates `targets` for a recorded module.
///
/// After the shared passes (per function on every core), the work is independent per target
/// and entry point and runs in one rayon scope: the WGSL print, the lowering and validation,
/// the HLSL print and each entry point's override baking side by side, each entry point's
/// translations starting as soon as its baking is done. A key for WGSL alone stays on its
/// thread. Errors are reported in the order a serial run meets them: the WGSL's, the
/// baking's by entry point, then by target and entry point.
pub fn generate(
    module: Module,
    variant: &str,
    targets: &[Target],
) -> Result<Generated, CodegenError> {
    let translated_targets: Vec<Target> = targets
        .iter()
        .copied()
        .filter(|t| !matches!(t, Target::Wgsl | Target::Hlsl))
        .collect();
    let every_core = !translated_targets.is_empty() || targets.contains(&Target::Hlsl);
    let module = prepare(module, every_core);
    let constants = backend::default_constants(&module);
    // Every (target, entry point) pair, in the order the files are listed.
    let jobs: Vec<(Target, usize)> = translated_targets
        .iter()
        .flat_map(|&target| {
            module
                .entry_points
                .iter()
                .enumerate()
                .filter(move |(_, ep)| translates(target, ep.stage))
                .map(move |(i, _)| (target, i))
        })
        .collect();
    let bake_entry = |ep: &nimbus_dsl::ir::EntryPoint| {
        backend::bake(&module, &ep.function).map_err(|message| CodegenError::Bake {
            module: module.name.clone(),
            variant: variant.to_string(),
            entry_point: ep.function.clone(),
            message,
        })
    };
    let translate = |baked: &backend::Baked, target: Target, i: usize| {
        let ep = &module.entry_points[i];
        backend::translate(
            baked,
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
        })
    };
    // Filled by the tasks below; read in a serial run's order afterwards.
    let baked: Vec<OnceLock<Result<backend::Baked, CodegenError>>> = module
        .entry_points
        .iter()
        .map(|_| OnceLock::new())
        .collect();
    let translated: Vec<OnceLock<Translated>> = jobs.iter().map(|_| OnceLock::new()).collect();
    let (wgsl, spans, validated, hlsl) = if !every_core {
        // WGSL alone: nothing to run beside it, and a hand-off to the pool costs more than it
        // saves.
        let (wgsl, spans, validated) = print_then_validate(&module, variant)?;
        (wgsl, spans, validated, None)
    } else {
        let mut printed = None;
        let mut checked = None;
        let mut hlsl = None;
        rayon::scope(|s| {
            s.spawn(|_| printed = Some(print_module(&module, variant)));
            s.spawn(|_| checked = Some(lower_checked(&module)));
            if targets.contains(&Target::Hlsl) {
                s.spawn(|_| hlsl = Some(crate::hlsl::print_module(&module, variant)));
            }
            // Overrides are baked once per entry point and shared by every backend; an entry
            // point's translations start as soon as its baking is done.
            for (i, ep) in module.entry_points.iter().enumerate() {
                if !jobs.iter().any(|&(_, e)| e == i) {
                    continue;
                }
                let (baked, translated, jobs) = (&baked, &translated, &jobs);
                let (bake_entry, translate) = (&bake_entry, &translate);
                s.spawn(move |s| {
                    if let Ok(b) = baked[i].get_or_init(|| bake_entry(ep)) {
                        for (j, &(target, e)) in jobs.iter().enumerate() {
                            if e == i {
                                s.spawn(move |_| {
                                    translated[j].get_or_init(|| translate(b, target, i));
                                });
                            }
                        }
                    }
                });
            }
        });
        let (wgsl, spans) = printed.expect("the print ran in the scope")?;
        let validated = checked
            .expect("the lowering ran in the scope")
            .map_err(|refused| explain_refusal(&module, &wgsl, &spans, variant, refused))?;
        (wgsl, spans, validated, hlsl)
    };
    for b in baked {
        if let Some(Err(e)) = b.into_inner() {
            return Err(e);
        }
    }
    let translated: Vec<Translated> = translated
        .into_iter()
        .map(|t| t.into_inner().expect("every job's entry point was baked"))
        .collect();
    let mut translated = jobs.into_iter().zip(translated);
    let mut hlsl = hlsl;
    let mut files = Vec::new();
    let mut target_bytes = BTreeMap::new();
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
            // The print from the scope; a list that names HLSL twice prints it again.
            let (text, manifest) = match hlsl.take() {
                Some(printed) => printed?,
                None => crate::hlsl::print_module(&module, variant)?,
            };
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
        // This target's entry points, in order (a target listed twice has its jobs twice).
        let count = module
            .entry_points
            .iter()
            .filter(|ep| translates(target, ep.stage))
            .count();
        for ((job_target, i), result) in translated.by_ref().take(count) {
            debug_assert_eq!(job_target, target);
            let ep = &module.entry_points[i];
            let (contents, manifest) = result?;
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
