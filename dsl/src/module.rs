//! Building a module: globals (uniforms, textures, storage buffers, overrides) and entry points.
//! Functions are not declared here: calling a `#[shader_fn]`'s shader twin from an entry point
//! records it (and everything it calls) into the module on first use.

use std::marker::PhantomData;

use thiserror::Error;

use crate::ir::{
    EntryPoint, ExprKind, Global, GlobalId, GlobalKind, Io, Literal, Module, Param, SamplerDesc,
    SourceLoc, Stage, Type,
};
use crate::record::{self, FunctionHeader, push_expr};
use crate::value::StorageElement;
use crate::value::{F32, ShaderType, StorageArray, U32, UVec3, Value, Vec4};

/// Why a module could not be recorded.
#[derive(Debug, Error, PartialEq)]
pub enum DslError {
    #[error("module `{module}`: {reason}")]
    InvalidModule { module: String, reason: String },
    #[error(
        "module `{module}`: another module is already being recorded on this thread (modules cannot nest)"
    )]
    Nested { module: String },
    #[error("module `{module}`: recording panicked: {reason}")]
    Panicked { module: String, reason: String },
    #[error(
        "module `{module}`: `{function}` was specialised twice with different generation-time values ({first}; then {second}) under one name; give its SpecValue a suffix that tells them apart"
    )]
    SpecialisationClash {
        module: String,
        function: String,
        first: String,
        second: String,
    },
}

/// A handle to a module global; `get()` reads it inside a function body.
#[derive(Debug)]
pub struct GlobalRef<T> {
    id: GlobalId,
    ty: Type,
    _t: PhantomData<T>,
}

impl<T> Clone for GlobalRef<T> {
    fn clone(&self) -> Self {
        *self
    }
}
impl<T> Copy for GlobalRef<T> {}

impl<T: Value> GlobalRef<T> {
    /// Reads the global (a uniform struct, texture, sampler or override).
    pub fn get(self) -> T {
        T::from_id(push_expr(ExprKind::Global(self.id), self.ty))
    }
}

impl<T: crate::value::StorageElement> GlobalRef<StorageArray<T>> {
    /// The storage buffer as an array.
    pub fn array(self) -> StorageArray<T> {
        StorageArray::from_id(push_expr(ExprKind::Global(self.id), self.ty))
    }
}

/// Records a module. Create one with [`ModuleBuilder::build`].
pub struct ModuleBuilder {
    name: String,
    errors: Vec<String>,
}

/// Ends the recording on every exit path, so a panic inside user code cannot leave the
/// thread-local recorder half-built for the next module.
struct RecordingGuard;

impl Drop for RecordingGuard {
    fn drop(&mut self) {
        let _ = record::end_module();
    }
}

impl ModuleBuilder {
    /// Records a module named `name` by running `body`.
    pub fn build(
        name: &str,
        doc: &str,
        loc: SourceLoc,
        body: impl FnOnce(&mut ModuleBuilder),
    ) -> Result<Module, DslError> {
        let module = Module {
            name: name.to_string(),
            doc: doc.lines().map(str::to_string).collect(),
            globals: Vec::new(),
            structs: Vec::new(),
            functions: Vec::new(),
            entry_points: Vec::new(),
            loc,
        };
        if !record::begin_module(module) {
            return Err(DslError::Nested {
                module: name.to_string(),
            });
        }
        let guard = RecordingGuard;
        let mut builder = ModuleBuilder {
            name: name.to_string(),
            errors: Vec::new(),
        };
        let outcome = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
            body(&mut builder);
        }));
        let clashes = record::take_clashes();
        let recorded_errors = record::take_errors();
        let module = record::end_module();
        std::mem::forget(guard);
        if let Err(payload) = outcome {
            let reason = payload
                .downcast_ref::<&str>()
                .map(|s| s.to_string())
                .or_else(|| payload.downcast_ref::<String>().cloned())
                .unwrap_or_else(|| "unknown panic".to_string());
            return Err(DslError::Panicked {
                module: name.to_string(),
                reason,
            });
        }
        if let Some(c) = clashes.into_iter().next() {
            return Err(DslError::SpecialisationClash {
                module: name.to_string(),
                function: c.function,
                first: c.first,
                second: c.second,
            });
        }
        if let Some(reason) = builder.errors.into_iter().chain(recorded_errors).next() {
            return Err(DslError::InvalidModule {
                module: name.to_string(),
                reason,
            });
        }
        module.ok_or_else(|| DslError::InvalidModule {
            module: name.to_string(),
            reason: "recorder vanished".to_string(),
        })
    }

    fn global<T>(&mut self, name: &str, ty: Type, kind: GlobalKind, doc: &str) -> GlobalRef<T> {
        let sampler = (ty == Type::Sampler).then_some(SamplerDesc::LINEAR_REPEAT);
        self.global_with(name, ty, kind, doc, sampler)
    }

    fn global_with<T>(
        &mut self,
        name: &str,
        ty: Type,
        kind: GlobalKind,
        doc: &str,
        sampler: Option<SamplerDesc>,
    ) -> GlobalRef<T> {
        let global = Global {
            name: record::sanitize(name),
            ty,
            kind,
            doc: doc.to_string(),
            sampler,
        };
        let id = match record::add_global(global) {
            Ok(id) => id,
            Err(reason) => {
                self.errors.push(reason);
                GlobalId(0)
            }
        };
        GlobalRef {
            id,
            ty,
            _t: PhantomData,
        }
    }

    /// A uniform buffer holding one `T` (a `#[derive(ShaderStruct)]` struct).
    pub fn uniform<T: ShaderType>(
        &mut self,
        name: &str,
        group: u32,
        binding: u32,
        doc: &str,
    ) -> GlobalRef<T::Dsl> {
        self.global(
            name,
            <T::Dsl as Value>::TYPE,
            GlobalKind::Uniform { group, binding },
            doc,
        )
    }

    /// A texture or sampler binding (`T` is a CPU texture or sampler type).
    pub fn handle<T: ShaderType>(
        &mut self,
        name: &str,
        group: u32,
        binding: u32,
        doc: &str,
    ) -> GlobalRef<T::Dsl> {
        self.global(
            name,
            <T::Dsl as Value>::TYPE,
            GlobalKind::Handle { group, binding },
            doc,
        )
    }

    /// A sampler binding with its address and filter modes (a sampler declared through
    /// [`Self::handle`] is linear and repeating).
    pub fn sampler(
        &mut self,
        name: &str,
        group: u32,
        binding: u32,
        desc: SamplerDesc,
        doc: &str,
    ) -> GlobalRef<crate::value::Sampler> {
        self.global_with(
            name,
            Type::Sampler,
            GlobalKind::Handle { group, binding },
            doc,
            Some(desc),
        )
    }

    /// A runtime-sized storage array of scalars.
    pub fn storage<T: StorageElement>(
        &mut self,
        name: &str,
        group: u32,
        binding: u32,
        read_write: bool,
        doc: &str,
    ) -> GlobalRef<StorageArray<T>> {
        let scalar = T::TYPE.scalar().unwrap_or(crate::ir::Scalar::F32);
        self.global(
            name,
            Type::RuntimeArray(scalar),
            GlobalKind::Storage {
                group,
                binding,
                read_write,
            },
            doc,
        )
    }

    /// A pipeline-overridable `f32` knob: an `override` in WGSL for wgpu, baked into a constant
    /// for every other target.
    pub fn override_f32(&mut self, name: &str, default: f32, doc: &str) -> GlobalRef<F32> {
        if !default.is_finite() {
            self.errors.push(format!(
                "override `{name}` has a non-finite default {default}"
            ));
        }
        self.global(
            name,
            Type::F32,
            GlobalKind::Override {
                default: Literal::f32(default),
            },
            doc,
        )
    }

    #[expect(
        clippy::too_many_arguments,
        reason = "private helper; each public entry point fixes most of them"
    )]
    fn entry(
        &mut self,
        stage: Stage,
        name: &str,
        doc: &str,
        loc: SourceLoc,
        input: (&str, Type, Io),
        output: Option<(Type, Io)>,
        workgroup_size: [u32; 3],
        body: impl FnOnce(crate::ir::ExprId) -> Option<crate::ir::ExprId>,
    ) {
        let fn_name = record::sanitize(name);
        if fn_name != name {
            self.errors.push(format!(
                "entry point name `{name}` is not a valid WGSL identifier (try `{fn_name}`)"
            ));
        }
        let header = FunctionHeader {
            name: fn_name.clone(),
            rust_name: name.to_string(),
            doc: doc.lines().map(str::to_string).collect(),
            specialised: Vec::new(),
            params: vec![Param {
                name: input.0.to_string(),
                ty: input.1,
            }],
            result: output.map(|o| o.0),
            loc,
        };
        record::ensure_function(header, |args| body(args[0]));
        record::add_entry_point(EntryPoint {
            stage,
            function: fn_name,
            inputs: vec![input.2],
            output: output.map(|o| o.1),
            workgroup_size,
        });
        let _ = &self.name;
    }

    /// A fragment entry point: input the window position, output colour attachment 0.
    pub fn fragment(
        &mut self,
        name: &str,
        doc: &str,
        loc: SourceLoc,
        body: impl FnOnce(Vec4) -> Vec4,
    ) {
        self.entry(
            Stage::Fragment,
            name,
            doc,
            loc,
            ("frag_coord", Vec4::TYPE, Io::Position),
            Some((Vec4::TYPE, Io::Location(0))),
            [0; 3],
            |arg| Some(body(Vec4::from_id(arg)).id()),
        );
    }

    /// A vertex entry point: input the vertex index, output the clip-space position.
    pub fn vertex(
        &mut self,
        name: &str,
        doc: &str,
        loc: SourceLoc,
        body: impl FnOnce(U32) -> Vec4,
    ) {
        self.entry(
            Stage::Vertex,
            name,
            doc,
            loc,
            ("vertex_index", U32::TYPE, Io::VertexIndex),
            Some((Vec4::TYPE, Io::Position)),
            [0; 3],
            |arg| Some(body(U32::from_id(arg)).id()),
        );
    }

    /// A compute entry point: input the invocation's index in the dispatch.
    pub fn compute(
        &mut self,
        name: &str,
        doc: &str,
        loc: SourceLoc,
        workgroup_size: [u32; 3],
        body: impl FnOnce(UVec3),
    ) {
        self.entry(
            Stage::Compute,
            name,
            doc,
            loc,
            ("global_id", UVec3::TYPE, Io::GlobalInvocationId),
            None,
            workgroup_size,
            |arg| {
                body(UVec3::from_id(arg));
                None
            },
        );
    }
}
