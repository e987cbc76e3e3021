//! Statements of the shader twin: `let`, `let mut`, assignment, `if`, bounded `for`, `break`,
//! `continue` and `return`. `#[shader_fn]` rewrites the Rust statements into calls to these.
//!
//! Each dispatches on its operand: for a DSL value it records a statement; for a plain Rust value
//! (a generation-time `#[spec]` parameter or a literal) it just evaluates, so an `if` on a Rust
//! `bool` is decided while the shader is generated and only the taken branch is recorded.

use std::marker::PhantomData;

use crate::ir::{ExprId, ExprKind, Literal, LocalId, SourceLoc, Stmt, Type, leaves_loop};
use crate::record::{
    begin_block, end_block, known_value, new_local, push_error, push_expr, push_stmt, temp_name,
};
use crate::value::{Bool, I32, IntoValueOf, U32, Value};

/// A value an `if` arm can produce: `()`, a DSL value, or a Rust literal of a shader scalar
/// type (which becomes a DSL value when the condition is recorded).
pub trait BranchValue: Sized {
    /// The DSL type both arms are converted to when the condition is a DSL [`Bool`].
    type Merged: BranchValue<Merged = Self::Merged>;
    /// Converts to the merged type (recording a literal for Rust values).
    fn into_merged(self) -> Self::Merged;
    /// The recorded expression and its type, or `None` for `()`.
    fn expr(&self) -> Option<(ExprId, Type)>;
    /// Rebuilds the value from the merged local.
    fn from_expr(id: ExprId) -> Self;
    /// A placeholder for code after a `return` (never executed; dropped by the printer).
    fn placeholder() -> Self;
}

impl BranchValue for () {
    type Merged = ();
    fn into_merged(self) {}
    fn expr(&self) -> Option<(ExprId, Type)> {
        None
    }
    fn from_expr(_: ExprId) -> Self {}
    fn placeholder() -> Self {}
}

impl<T: Value> BranchValue for T {
    type Merged = T;
    fn into_merged(self) -> T {
        self
    }
    fn expr(&self) -> Option<(ExprId, Type)> {
        Some((self.id(), T::TYPE))
    }
    fn from_expr(id: ExprId) -> Self {
        T::from_id(id)
    }
    fn placeholder() -> Self {
        // The zero value `T()` is valid for every constructible type.
        T::from_id(push_expr(ExprKind::Construct(T::TYPE, Vec::new()), T::TYPE))
    }
}

macro_rules! branch_rust {
    ($($rust:ty => $dsl:ty),*) => {$(
        impl BranchValue for $rust {
            type Merged = $dsl;
            fn into_merged(self) -> $dsl {
                <$dsl>::lit(self)
            }
            fn expr(&self) -> Option<(ExprId, Type)> {
                Some((<$dsl>::lit(*self).id(), <$dsl as Value>::TYPE))
            }
            fn from_expr(_: ExprId) -> Self {
                Self::default()
            }
            fn placeholder() -> Self {
                Self::default()
            }
        }

        impl Condition<$rust, $dsl> for bool {
            type Out = $dsl;
            fn branch(self, _loc: SourceLoc, then: impl FnOnce() -> $rust, otherwise: impl FnOnce() -> $dsl) -> $dsl {
                if self { <$dsl>::lit(then()) } else { otherwise() }
            }
        }

        impl Condition<$dsl, $rust> for bool {
            type Out = $dsl;
            fn branch(self, _loc: SourceLoc, then: impl FnOnce() -> $dsl, otherwise: impl FnOnce() -> $rust) -> $dsl {
                if self { then() } else { <$dsl>::lit(otherwise()) }
            }
        }
    )*};
}
branch_rust!(f32 => crate::value::F32, i32 => I32, u32 => U32, bool => Bool);

/// The condition of an `if` with arms of types `A` and `B`: a Rust `bool` (decided now, only
/// the taken arm is recorded) or a DSL [`Bool`] (both arms recorded, values merged).
pub trait Condition<A, B> {
    type Out;
    fn branch(
        self,
        loc: SourceLoc,
        then: impl FnOnce() -> A,
        otherwise: impl FnOnce() -> B,
    ) -> Self::Out;
}

impl<A> Condition<A, A> for bool {
    type Out = A;
    fn branch(self, _loc: SourceLoc, then: impl FnOnce() -> A, otherwise: impl FnOnce() -> A) -> A {
        if self { then() } else { otherwise() }
    }
}

impl<A: BranchValue, B: BranchValue<Merged = A::Merged>> Condition<A, B> for Bool {
    type Out = A::Merged;
    fn branch(
        self,
        loc: SourceLoc,
        then: impl FnOnce() -> A,
        otherwise: impl FnOnce() -> B,
    ) -> A::Merged {
        begin_block();
        let a = then().into_merged();
        let mut then_block = end_block();
        begin_block();
        let b = otherwise().into_merged();
        let mut else_block = end_block();
        let merged = match (a.expr(), b.expr()) {
            (Some((ea, ty)), Some((eb, _))) => {
                let local = new_local(&temp_name("branch"), ty, true);
                then_block.push(Stmt::Assign {
                    local,
                    value: ea,
                    loc,
                });
                else_block.push(Stmt::Assign {
                    local,
                    value: eb,
                    loc,
                });
                push_stmt(Stmt::Var {
                    local,
                    init: None,
                    loc,
                });
                Some((local, ty))
            }
            _ => None,
        };
        push_stmt(Stmt::If {
            cond: self.id(),
            then: then_block,
            otherwise: else_block,
            loc,
        });
        match merged {
            Some((local, ty)) => A::Merged::from_expr(push_expr(ExprKind::Local(local), ty)),
            None => A::Merged::placeholder(),
        }
    }
}

/// `if cond { then } else { otherwise }`.
pub fn branch<A, B, C: Condition<A, B>>(
    loc: SourceLoc,
    cond: C,
    then: impl FnOnce() -> A,
    otherwise: impl FnOnce() -> B,
) -> C::Out {
    cond.branch(loc, then, otherwise)
}

/// A condition that is either fixed at generation time or read at run time: what a choice of a
/// specialised shader becomes in an uber-shader. `Fixed` records only the taken arm (like a Rust
/// `bool`); `Dynamic` records a run-time `if` with both arms.
#[derive(Clone, Copy, Debug)]
pub enum Switch {
    Fixed(bool),
    Dynamic(Bool),
}

impl<A: BranchValue, B: BranchValue<Merged = A::Merged>> Condition<A, B> for Switch {
    type Out = A::Merged;
    fn branch(
        self,
        loc: SourceLoc,
        then: impl FnOnce() -> A,
        otherwise: impl FnOnce() -> B,
    ) -> A::Merged {
        match self {
            Switch::Fixed(true) => then().into_merged(),
            Switch::Fixed(false) => otherwise().into_merged(),
            Switch::Dynamic(c) => c.branch(loc, then, otherwise),
        }
    }
}

/// A value `let` can name: DSL values are recorded as `let`, Rust values pass through.
pub trait Bind: Sized {
    fn bind(self, name: &str, loc: SourceLoc) -> Self;
}

impl<T: Value> Bind for T {
    fn bind(self, name: &str, loc: SourceLoc) -> Self {
        // A texture, sampler or a scalar/vector in a uniform is named, not copied; a struct
        // (`let s = LIGHTS.get().key_light;`) is copied once: one load that the code after it
        // reads from, as a hand-written shader would (drivers without load hoisting re-read
        // uniform memory at every use otherwise).
        if !matches!(T::TYPE, Type::Struct(_) | Type::Array(..))
            && crate::record::is_resource_place(self.id())
        {
            return self;
        }
        let local = new_local(name, T::TYPE, false);
        push_stmt(Stmt::Let {
            local,
            value: self.id(),
            loc,
        });
        T::from_id(push_expr(ExprKind::Local(local), T::TYPE))
    }
}

macro_rules! bind_rust {
    ($($t:ty),*) => {$(
        impl Bind for $t {
            fn bind(self, _name: &str, _loc: SourceLoc) -> Self {
                self
            }
        }
    )*};
}
bind_rust!(f32, i32, u32, bool, usize, u8);

/// `let name = value;`
pub fn bind<T: Bind>(name: &str, loc: SourceLoc, value: T) -> T {
    value.bind(name, loc)
}

/// A `var`: a mutable local of the shader twin (`let mut` in the Rust source).
#[derive(Debug)]
pub struct Var<T: Value> {
    local: LocalId,
    _ty: PhantomData<T>,
}

impl<T: Value> Clone for Var<T> {
    fn clone(&self) -> Self {
        *self
    }
}
impl<T: Value> Copy for Var<T> {}

impl<T: Value> Var<T> {
    /// Reads the current value.
    pub fn get(self) -> T {
        T::from_id(push_expr(ExprKind::Local(self.local), T::TYPE))
    }

    /// Assigns a new value.
    pub fn set(self, loc: SourceLoc, value: impl Into<T>) {
        let value = value.into().id();
        push_stmt(Stmt::Assign {
            local: self.local,
            value,
            loc,
        });
    }
}

/// `let mut name = init;` with the type taken from `init`.
pub fn var<V: IntoValueOf>(name: &str, loc: SourceLoc, init: V) -> Var<V::Value> {
    var_typed(name, loc, init.into_value_id())
}

/// `let mut name: T = init;`
pub fn var_typed<T: Value>(name: &str, loc: SourceLoc, init: impl Into<T>) -> Var<T> {
    let init = init.into().id();
    let local = new_local(name, T::TYPE, true);
    push_stmt(Stmt::Var {
        local,
        init: Some(init),
        loc,
    });
    Var {
        local,
        _ty: PhantomData,
    }
}

/// The bounds of `for i in start..end`: an integer pair, Rust or DSL, of one kind.
pub trait LoopRange {
    type Counter: Value;
    fn bounds(self) -> (ExprId, ExprId);
}

macro_rules! loop_range {
    ($counter:ident: $(($a:ty, $b:ty)),*) => {$(
        impl LoopRange for ($a, $b) {
            type Counter = $counter;
            fn bounds(self) -> (ExprId, ExprId) {
                (self.0.into_value_id().id(), self.1.into_value_id().id())
            }
        }
    )*};
}
loop_range!(U32: (U32, U32), (u32, U32), (U32, u32), (u32, u32));
loop_range!(I32: (I32, I32), (i32, I32), (I32, i32), (i32, i32));

/// `for name in start..end { body }`, always a bounded loop.
pub fn for_range<R: LoopRange>(
    name: &str,
    loc: SourceLoc,
    range: R,
    body: impl FnOnce(R::Counter),
) {
    let (start, end) = range.bounds();
    record_loop(name, loc, start, end, body);
}

/// Records `for name in start..end { body }` with the counter a local.
fn record_loop<C: Value>(
    name: &str,
    loc: SourceLoc,
    start: ExprId,
    end: ExprId,
    body: impl FnOnce(C),
) {
    let counter = new_local(name, C::TYPE, true);
    crate::record::mark_counter(counter);
    begin_block();
    body(C::from_id(push_expr(ExprKind::Local(counter), C::TYPE)));
    let body = end_block();
    push_stmt(Stmt::For {
        counter,
        start,
        end,
        body,
        loc,
    });
}

/// The marker of a loop the shader should hold unrolled: `for i in unroll(0u32..4u32) { .. }`.
/// On the CPU it is the range itself. In the shader twin the body is recorded once per value of
/// the counter, each copy reading it as a literal, so the generated code has no loop:
/// SwiftShader, the CPU rasteriser Chromium draws the packages with here, ran the resolve's
/// 3 × 3 neighbourhood as a loop about 8 ms slower in a 640 × 360 frame than as nine copies.
/// Only for a few iterations with bounds known when the shader is generated.
pub fn unroll<T>(range: std::ops::Range<T>) -> std::ops::Range<T> {
    range
}

/// The marker of a loop unrolled where the shader's generation fixes its count, and left a loop
/// where a uniform gives it: `for k in unroll_known(0u32..key_count(key, OCTAVES)) { .. }`. A
/// specialised shader knows the key's counts and gets the copies [`unroll`] makes (a small
/// loop indexing a vector by its counter ran as a loop in SwiftShader about 7 % of `low`'s
/// frame slower: the octaves' sum); the uber-shader reads them from its key uniform and keeps
/// the loop. On the CPU it is the range itself.
pub fn unroll_known<T>(range: std::ops::Range<T>) -> std::ops::Range<T> {
    range
}

/// The most copies [`unroll`] makes of one loop's body.
pub const UNROLL_LIMIT: i64 = 16;

/// `for name in unroll(start..end) { body }`: the body recorded once per counter value (see
/// [`unroll`]). Bounds not known then, more than [`UNROLL_LIMIT`] iterations, or a
/// `break`/`continue` in the body are recording errors (the module builder reports them, with
/// where the loop is); the loop is then recorded as an ordinary one.
pub fn unrolled_range<R: LoopRange>(
    name: &str,
    loc: SourceLoc,
    range: R,
    body: impl FnMut(R::Counter),
) {
    unroll_or_loop(name, loc, range, true, body);
}

/// `for name in unroll_known(start..end) { body }`: unrolled as [`unrolled_range`] when the
/// bounds are known when the shader is generated, an ordinary loop when they are not (see
/// [`unroll_known`]).
pub fn unrolled_range_if_known<R: LoopRange>(
    name: &str,
    loc: SourceLoc,
    range: R,
    body: impl FnMut(R::Counter),
) {
    unroll_or_loop(name, loc, range, false, body);
}

/// The body recorded once per counter value; with bounds unknown at generation, an error when
/// `required`, else the loop itself.
fn unroll_or_loop<R: LoopRange>(
    name: &str,
    loc: SourceLoc,
    range: R,
    required: bool,
    mut body: impl FnMut(R::Counter),
) {
    let (start, end) = range.bounds();
    let literal = |id: ExprId| match known_value(id) {
        Some(Literal::I32(v)) => Some((i64::from(v), Literal::I32(0))),
        Some(Literal::U32(v)) => Some((i64::from(v), Literal::U32(0))),
        _ => None,
    };
    let (Some((first, kind)), Some((last, _))) = (literal(start), literal(end)) else {
        if !required {
            return record_loop(name, loc, start, end, body);
        }
        push_error(format!(
            "{loc}: `for {name} in unroll(start..end)` needs bounds known when the shader is \
             generated (literals, constants or #[spec] values)"
        ));
        return record_loop(name, loc, start, end, body);
    };
    if last - first > UNROLL_LIMIT {
        push_error(format!(
            "{loc}: `unroll` of {} iterations of `{name}`: at most {UNROLL_LIMIT} (leave a \
             longer loop a loop)",
            last - first
        ));
        return record_loop(name, loc, start, end, body);
    }
    for i in first..last {
        let value = match kind {
            Literal::U32(_) => Literal::U32(i as u32),
            _ => Literal::I32(i as i32),
        };
        begin_block();
        body(R::Counter::from_id(push_expr(
            ExprKind::Literal(value),
            R::Counter::TYPE,
        )));
        let copy = end_block();
        if leaves_loop(&copy) {
            push_error(format!(
                "{loc}: `break` or `continue` in the unrolled loop over `{name}`: an unrolled \
                 body cannot leave early"
            ));
        }
        for stmt in copy {
            push_stmt(stmt);
        }
    }
}

/// `break;`
pub fn brk(loc: SourceLoc) {
    push_stmt(Stmt::Break { loc });
}

/// `continue;`
pub fn cont(loc: SourceLoc) {
    push_stmt(Stmt::Continue { loc });
}

/// `return value;`
pub fn ret<T: BranchValue>(loc: SourceLoc, value: T) {
    push_stmt(Stmt::Return {
        value: value.expr().map(|(id, _)| id),
        loc,
    });
}

/// The value of an expression that follows a `return` in the same Rust expression (never
/// executed; the printer drops statements after a `return`).
pub fn unreachable<T: BranchValue>() -> T {
    T::placeholder()
}

/// The tail expression of a function body, converted to the function's result type `R`.
/// `()` means the body ends without a value (every path returned explicitly).
pub trait FnTail<R> {
    fn tail(self) -> Option<ExprId>;
}

impl<R: Value> FnTail<R> for () {
    fn tail(self) -> Option<ExprId> {
        None
    }
}

impl<T: Value> FnTail<T> for T {
    fn tail(self) -> Option<ExprId> {
        Some(self.id())
    }
}

macro_rules! fn_tail_rust {
    ($($dsl:ty | $rust:ty),*) => {$(
        impl FnTail<$dsl> for $rust {
            fn tail(self) -> Option<ExprId> {
                Some(<$dsl>::from(self).id())
            }
        }
    )*};
}
use crate::value::{F32, Vec2, Vec3, Vec4};
fn_tail_rust!(
    F32 | f32,
    I32 | i32,
    U32 | u32,
    Bool | bool,
    Vec2 | glam::Vec2,
    Vec3 | glam::Vec3,
    Vec4 | glam::Vec4
);

/// Converts a function body's tail to its result expression.
pub fn tail<R, T: FnTail<R>>(value: T) -> Option<ExprId> {
    value.tail()
}
