//! Module-scope resources that a `#[shader_fn]` reads by name.
//!
//! A uniform block, texture or sampler is declared once, as a Rust `static`:
//!
//! ```
//! use nimbus_dsl::Binding;
//! use nimbus_dsl::cpu::{Sampler, Texture2d};
//! use nimbus_dsl::ir::SamplerDesc;
//!
//! pub static ALBEDO: Binding<Texture2d> = Binding::texture("albedo", 0, 1, "Base colour.");
//! pub static LINEAR: Binding<Sampler> =
//!     Binding::sampler("linear", 0, 2, SamplerDesc::LINEAR_REPEAT, "Bilinear, repeat.");
//! ```
//!
//! A function body then says `ALBEDO.get().sample_level(&LINEAR.get(), uv, 0.0)`, and nothing
//! passes the texture around. The two twins read it differently:
//!
//! - **Shader twin.** The macro sees a name that is neither a parameter nor a local, so it is an
//!   item; the item's type (a `Binding`) makes it a global of the module being recorded,
//!   declared there on first use. A module therefore declares exactly the bindings its code
//!   reads, which is what a specialised variant should bind.
//! - **CPU twin.** `get()` returns the value bound on this thread with [`CpuBindings`], the CPU's
//!   bind group. Thread-local bindings keep the CPU twin the function as written (no context
//!   parameter the shader would not have), and a guard restores the previous bindings when it
//!   is dropped, so nested or parallel uses do not see each other's values.

use std::any::Any;
use std::cell::RefCell;
use std::marker::PhantomData;
use std::sync::Arc;

use crate::constant::{ConstProbe, NamedConst};
use crate::ir::{ExprKind, Global, GlobalKind, SamplerDesc, Stmt};
use crate::record;
use crate::value::{ShaderType, Value};

/// Which kind of binding a [`Binding`] is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Kind {
    Uniform,
    Texture,
    Sampler(SamplerDesc),
}

/// A resource at `@group(g) @binding(b)`, holding a `T` (a `#[derive(ShaderStruct)]` uniform
/// block, a [`crate::cpu::Texture2d`], [`crate::cpu::Texture3d`] or [`crate::cpu::Sampler`]).
pub struct Binding<T> {
    name: &'static str,
    group: u32,
    binding: u32,
    kind: Kind,
    doc: &'static str,
    _t: PhantomData<fn() -> T>,
}

impl<T> Clone for Binding<T> {
    fn clone(&self) -> Self {
        *self
    }
}
impl<T> Copy for Binding<T> {}

impl<T> std::fmt::Debug for Binding<T> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "{} @group({}) @binding({})",
            self.name, self.group, self.binding
        )
    }
}

impl<T> Binding<T> {
    const fn new(
        name: &'static str,
        group: u32,
        binding: u32,
        kind: Kind,
        doc: &'static str,
    ) -> Self {
        Binding {
            name,
            group,
            binding,
            kind,
            doc,
            _t: PhantomData,
        }
    }

    /// A uniform buffer holding one `T`.
    pub const fn uniform(name: &'static str, group: u32, binding: u32, doc: &'static str) -> Self {
        Self::new(name, group, binding, Kind::Uniform, doc)
    }

    /// A filterable float texture.
    pub const fn texture(name: &'static str, group: u32, binding: u32, doc: &'static str) -> Self {
        Self::new(name, group, binding, Kind::Texture, doc)
    }

    /// The WGSL name.
    pub const fn name(&self) -> &'static str {
        self.name
    }

    /// `(group, binding)`.
    pub const fn slot(&self) -> (u32, u32) {
        (self.group, self.binding)
    }

    /// The doc comment printed above the declaration.
    pub const fn doc(&self) -> &'static str {
        self.doc
    }
}

impl Binding<crate::cpu::Sampler> {
    /// A sampler, created by every consumer with `desc`.
    pub const fn sampler(
        name: &'static str,
        group: u32,
        binding: u32,
        desc: SamplerDesc,
        doc: &'static str,
    ) -> Self {
        Self::new(name, group, binding, Kind::Sampler(desc), doc)
    }
}

impl<T: ShaderType> Binding<T> {
    fn global(&self, kind: GlobalKind) -> Global {
        Global {
            name: record::sanitize(self.name),
            ty: <T::Dsl as Value>::TYPE,
            kind,
            doc: self.doc.to_string(),
            sampler: match self.kind {
                Kind::Sampler(desc) => Some(desc),
                _ => None,
            },
        }
    }

    fn bound_kind(&self) -> GlobalKind {
        match self.kind {
            Kind::Uniform => GlobalKind::Uniform {
                group: self.group,
                binding: self.binding,
            },
            Kind::Texture | Kind::Sampler(_) => GlobalKind::Handle {
                group: self.group,
                binding: self.binding,
            },
        }
    }

    /// Shader twin of [`Self::get`]: a read of the global, declared in the module being
    /// recorded on first use (or the private variable [`Self::feed`] made of it).
    pub fn read(&self) -> T::Dsl {
        let private = self.global(GlobalKind::Private);
        let id = match record::find_global(&private) {
            Some(id) => id,
            None => match record::add_global(self.global(self.bound_kind())) {
                Ok(id) => id,
                Err(reason) => {
                    record::push_error(format!("binding `{}`: {reason}", self.name));
                    crate::ir::GlobalId(0)
                }
            },
        };
        T::Dsl::from_id(record::push_expr(
            ExprKind::Global(id),
            <T::Dsl as Value>::TYPE,
        ))
    }

    /// For harnesses that run a function once per input record (CPU/GPU parity): declares this
    /// binding as a `var<private>` of the module being recorded and assigns it `value`, so the
    /// code under test reads a per-invocation value where a pipeline would bind one buffer.
    /// Call it before anything reads the binding.
    #[track_caller]
    pub fn feed(&self, value: T::Dsl) {
        let caller = std::panic::Location::caller();
        let id = match record::add_global(self.global(GlobalKind::Private)) {
            Ok(id) => id,
            Err(reason) => {
                record::push_error(format!(
                    "binding `{}` fed per invocation: {reason} (feed it before it is read)",
                    self.name
                ));
                return;
            }
        };
        let target = record::push_expr(ExprKind::Global(id), <T::Dsl as Value>::TYPE);
        record::push_stmt(Stmt::Store {
            target,
            value: value.id(),
            loc: crate::ir::SourceLoc::new(caller.file(), caller.line(), caller.column()),
        });
    }
}

impl<T: Send + Sync + 'static> Binding<T> {
    /// CPU twin: the value bound to this slot on this thread (see [`CpuBindings`]).
    ///
    /// # Panics
    /// When nothing, or a value of another type, is bound there: the caller of the CPU twin
    /// forgot to bind its resources, a mistake in Rust code, not in data.
    pub fn get(&self) -> Arc<T> {
        BOUND.with(|b| {
            let b = b.borrow();
            let found = b
                .iter()
                .rev()
                .find(|(slot, _)| *slot == self.slot())
                .map(|(_, v)| v.clone());
            match found {
                Some(v) => v.downcast::<T>().unwrap_or_else(|_| {
                    panic!(
                        "{self:?} is bound on this thread to a value of another type than {}",
                        std::any::type_name::<T>()
                    )
                }),
                None => panic!(
                    "{self:?} was read by a CPU twin with nothing bound: bind it with nimbus_dsl::CpuBindings"
                ),
            }
        })
    }
}

/// The macro's constant probe, for an item that is a binding: the shader twin reads the global.
impl<T: ShaderType> NamedConst for &&ConstProbe<Binding<T>> {
    type Out = ShaderBinding<T>;
    fn shader_value(&self) -> ShaderBinding<T> {
        ShaderBinding(self.1)
    }
}

/// What a binding's name means inside a shader twin: `get()` reads the global.
pub struct ShaderBinding<T>(Binding<T>);

impl<T: ShaderType> ShaderBinding<T> {
    /// The global's value (recorded as a read of it).
    pub fn get(&self) -> T::Dsl {
        self.0.read()
    }
}

type Slot = (u32, u32);

thread_local! {
    static BOUND: RefCell<Vec<(Slot, Arc<dyn Any + Send + Sync>)>> = const { RefCell::new(Vec::new()) };
}

/// The CPU's bind group: the values [`Binding::get`] returns on this thread while the guard from
/// [`CpuBindings::bind`] lives.
///
/// ```
/// # use nimbus_dsl::{Binding, CpuBindings};
/// # use nimbus_dsl::cpu::Sampler;
/// # use nimbus_dsl::ir::SamplerDesc;
/// static SMP: Binding<Sampler> = Binding::sampler("smp", 0, 0, SamplerDesc::LINEAR_REPEAT, "");
/// let _bound = CpuBindings::new().set(&SMP, Sampler::default()).bind();
/// assert_eq!(*SMP.get(), Sampler::default());
/// ```
#[derive(Default)]
#[must_use = "nothing is bound until `bind()` is called and its guard kept"]
pub struct CpuBindings {
    values: Vec<(Slot, Arc<dyn Any + Send + Sync>)>,
}

impl CpuBindings {
    pub fn new() -> Self {
        Self::default()
    }

    /// Binds `value` to `binding`'s slot (an `Arc` is shared, not copied).
    pub fn set<T: Send + Sync + 'static>(
        mut self,
        binding: &Binding<T>,
        value: impl Into<Arc<T>>,
    ) -> Self {
        let value: Arc<T> = value.into();
        self.values.push((binding.slot(), value));
        self
    }

    /// Makes the values visible to [`Binding::get`] on this thread until the guard is dropped.
    pub fn bind(self) -> BoundGuard {
        let count = self.values.len();
        BOUND.with(|b| b.borrow_mut().extend(self.values));
        BoundGuard {
            count,
            _not_send: PhantomData,
        }
    }
}

/// Unbinds what [`CpuBindings::bind`] bound, when dropped.
#[must_use = "the values are unbound when the guard is dropped"]
pub struct BoundGuard {
    count: usize,
    _not_send: PhantomData<*const ()>,
}

impl Drop for BoundGuard {
    fn drop(&mut self) {
        BOUND.with(|b| {
            let mut b = b.borrow_mut();
            let keep = b.len().saturating_sub(self.count);
            b.truncate(keep);
        });
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::cpu::Sampler;

    static A: Binding<Sampler> = Binding::sampler("a", 0, 3, SamplerDesc::LINEAR_REPEAT, "");

    #[test]
    fn guards_nest_and_restore() {
        let outer = Sampler::default();
        let inner = Sampler {
            filter: crate::cpu::Filter::Nearest,
            ..Sampler::default()
        };
        let _g = CpuBindings::new().set(&A, outer).bind();
        {
            let _h = CpuBindings::new().set(&A, inner).bind();
            assert_eq!(*A.get(), inner);
        }
        assert_eq!(*A.get(), outer);
    }

    #[test]
    #[should_panic(expected = "nothing bound")]
    fn reading_an_unbound_slot_says_so() {
        let _ = A.get();
    }
}
