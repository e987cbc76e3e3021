//! naga as the single gate: the module lowered from the IR is validated with every check on.
//! When naga refuses it, the printed WGSL is parsed and validated instead, and naga's errors are
//! mapped back through the span table to the Rust source (the lowered module carries no spans).

use naga::valid::{Capabilities, ModuleInfo, ValidationFlags, Validator};

use crate::error::{CodegenError, Origin};
use crate::lower::{LowerError, Lowered, Lowering, lower};
use crate::wgsl::SpanTable;

/// A validated naga module.
pub struct Validated {
    pub module: naga::Module,
    pub info: ModuleInfo,
    /// `globals[i]`: the naga global variable of the IR's global `i`, if it became one.
    pub globals: Vec<Option<naga::Handle<naga::GlobalVariable>>>,
}

/// Lowers a specialised, renamed module to naga and validates it. `wgsl` and `spans` (the same
/// module printed) are read only when naga refuses, to say which Rust line is at fault.
pub fn lower_and_validate(
    ir: &nimbus_dsl::ir::Module,
    wgsl: &str,
    spans: &SpanTable,
    variant: &str,
) -> Result<Validated, CodegenError> {
    lower_checked(ir).map_err(|refused| explain_refusal(ir, wgsl, spans, variant, refused))
}

/// Why naga refused a lowered module (before the printed text has located it).
pub(crate) enum Refusal {
    /// The lowering itself failed with an error that already says where.
    Located(CodegenError),
    /// naga's message; the printed WGSL is to say which Rust line is at fault.
    Unlocated(String),
}

/// [`lower_and_validate`] without the printed text: what runs beside the print.
pub(crate) fn lower_checked(ir: &nimbus_dsl::ir::Module) -> Result<Validated, Refusal> {
    match lower(ir, Lowering::Whole) {
        Ok(Lowered { module, globals }) => {
            let mut validator = Validator::new(ValidationFlags::all(), Capabilities::default());
            match validator.validate(&module) {
                Ok(info) => Ok(Validated {
                    module,
                    info,
                    globals,
                }),
                Err(e) => Err(Refusal::Unlocated(chain(e.as_inner()))),
            }
        }
        Err(LowerError::Codegen(e)) => Err(Refusal::Located(e)),
        Err(LowerError::Unsupported(what)) => {
            Err(Refusal::Unlocated(format!("cannot lower {what}")))
        }
    }
}

/// The error for a refused module: located through the printed text where naga's validation of
/// that text finds the fault, else the lowering's own message.
pub(crate) fn explain_refusal(
    ir: &nimbus_dsl::ir::Module,
    wgsl: &str,
    spans: &SpanTable,
    variant: &str,
    refused: Refusal,
) -> CodegenError {
    let message = match refused {
        Refusal::Located(e) => return e,
        Refusal::Unlocated(message) => message,
    };
    // The text path locates the fault; if it finds none, the lowering is at fault.
    if let Err(located) = validate(wgsl, spans, &ir.name, variant) {
        return located;
    }
    CodegenError::Lowering {
        module: ir.name.clone(),
        variant: variant.to_string(),
        message,
    }
}

/// The origin of the most specific span among `offsets` (a statement beats a whole function).
fn best_origin(
    wgsl: &str,
    spans: &SpanTable,
    offsets: impl Iterator<Item = usize>,
) -> Option<Origin> {
    offsets
        .filter_map(|o| spans.lookup(o).map(|e| (e.range.len(), o)))
        .min_by_key(|(len, _)| *len)
        .and_then(|(_, o)| origin_at(wgsl, spans, o))
}

fn origin_at(wgsl: &str, spans: &SpanTable, offset: usize) -> Option<Origin> {
    let entry = spans.lookup(offset)?;
    let line_start = wgsl[..offset.min(wgsl.len())]
        .rfind('\n')
        .map_or(0, |i| i + 1);
    let line_end = wgsl[line_start..]
        .find('\n')
        .map_or(wgsl.len(), |i| line_start + i);
    Some(Origin {
        function: entry.rust_name.to_string(),
        loc: entry.loc,
        wgsl_line: wgsl[line_start..line_end].to_string(),
    })
}

fn chain(e: &dyn std::error::Error) -> String {
    let mut msg = e.to_string();
    let mut source = e.source();
    while let Some(s) = source {
        let text = s.to_string();
        if !msg.contains(&text) {
            msg.push_str(": ");
            msg.push_str(&text);
        }
        source = s.source();
    }
    msg
}

/// Parses and validates printed WGSL; errors name the module, variant and Rust origin. The
/// check of the text people and WebGPU hosts read (generation itself validates the lowered
/// module).
pub fn validate(
    wgsl: &str,
    spans: &SpanTable,
    module_name: &str,
    variant: &str,
) -> Result<(naga::Module, ModuleInfo), CodegenError> {
    let module = naga::front::wgsl::parse_str(wgsl).map_err(|e| {
        let origin = best_origin(
            wgsl,
            spans,
            e.labels()
                .filter_map(|(span, _)| span.to_range())
                .map(|r| r.start),
        );
        let mut message = e.message().to_string();
        for (_, label) in e.labels() {
            if !label.is_empty() && !message.contains(label) {
                message.push_str(&format!(" ({label})"));
            }
        }
        CodegenError::Parse {
            module: module_name.to_string(),
            variant: variant.to_string(),
            origin: origin.map(Box::new),
            message,
        }
    })?;
    let mut validator = Validator::new(ValidationFlags::all(), Capabilities::default());
    let info = validator.validate(&module).map_err(|e| {
        let mut origin = best_origin(
            wgsl,
            spans,
            e.spans()
                .filter_map(|(span, _)| span.to_range())
                .map(|r| r.start),
        );
        if origin.is_none() {
            // Some errors (e.g. a stage using a forbidden operation) carry no span; they still
            // name the function or entry point, which the span table knows.
            let name = match e.as_inner() {
                naga::valid::ValidationError::Function { name, .. }
                | naga::valid::ValidationError::EntryPoint { name, .. } => Some(name.clone()),
                _ => None,
            };
            origin = name.and_then(|n| {
                spans.function(&n).map(|entry| Origin {
                    function: entry.rust_name.to_string(),
                    loc: entry.loc,
                    wgsl_line: format!("fn {n}(..)"),
                })
            });
        }
        CodegenError::Validation {
            module: module_name.to_string(),
            variant: variant.to_string(),
            origin: origin.map(Box::new),
            message: chain(e.as_inner()),
        }
    })?;
    Ok((module, info))
}
