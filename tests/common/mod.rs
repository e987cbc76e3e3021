//! Helpers shared by the integration tests.
#![allow(dead_code, reason = "each test binary uses a different subset")]

use std::sync::OnceLock;

use nimbus_dsl::ir::{ExprId, Type};
use nimbus_runtime::Gpu;
use nimbus_runtime::render::TextureSizes;
use nimbus_testkit::parity::{KernelFn, run_on_gpu};

/// Tiny noise textures, for tests of what the renderer creates and draws rather than of the
/// clouds' look: made in milliseconds.
pub const SMALL_TEXTURES: TextureSizes = TextureSizes {
    weather: 32,
    shape: 16,
    detail: 8,
    turbulence: 16,
};

/// The GPU for parity tests, or `None` with the reason printed. With `NIMBUS_REQUIRE_GPU=1`
/// (set by .ci/run, which installs lavapipe) a missing adapter is a failure, not a skip.
pub fn gpu() -> Option<&'static Gpu> {
    static GPU: OnceLock<Result<Gpu, String>> = OnceLock::new();
    match GPU.get_or_init(|| Gpu::new().map_err(|e| e.to_string())) {
        Ok(g) => Some(g),
        Err(e) => {
            if std::env::var("NIMBUS_REQUIRE_GPU").is_ok_and(|v| v == "1") {
                panic!("NIMBUS_REQUIRE_GPU=1 but no GPU adapter is available: {e}");
            }
            eprintln!("SKIPPED: no GPU adapter ({e})");
            None
        }
    }
}

/// Deterministic pseudo-random numbers (xorshift64*), so failures reproduce.
pub struct Rng(u64);

impl Rng {
    pub fn new(seed: u64) -> Self {
        Rng(seed.max(1))
    }

    pub fn next_u64(&mut self) -> u64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        self.0.wrapping_mul(0x2545_f491_4f6c_dd1d)
    }

    /// Uniform in [lo, hi].
    pub fn range(&mut self, lo: f32, hi: f32) -> f32 {
        let t = (self.next_u64() >> 40) as f32 / (1u64 << 24) as f32;
        lo + (hi - lo) * t
    }
}

/// `n` evenly spaced values from `lo` to `hi`, both included.
pub fn linspace(lo: f32, hi: f32, n: usize) -> Vec<f32> {
    (0..n)
        .map(|i| lo + (hi - lo) * i as f32 / (n - 1) as f32)
        .collect()
}

/// Runs `cmd --version`; `false` when the tool is not installed.
pub fn tool_available(tool: &str) -> bool {
    std::process::Command::new(tool)
        .arg("--version")
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::null())
        .status()
        .is_ok()
}

/// Whether Python can import `slangpy`, whose wheel ships the Slang compiler.
pub fn slang_available() -> bool {
    std::process::Command::new("python3")
        .args(["-c", "import slangpy"])
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::null())
        .status()
        .is_ok_and(|s| s.success())
}

pub const MIN_INPUTS: usize = 10_000;

/// A relative-plus-absolute tolerance: |gpu − cpu| ≤ abs + rel·|cpu|.
#[derive(Clone, Copy)]
pub struct Tolerance {
    pub abs: f32,
    pub rel: f32,
}

/// Runs `f` on both sides and compares every output component.
pub fn compare(
    name: &str,
    params: Vec<Type>,
    result: Type,
    call: &dyn Fn(&[ExprId]) -> ExprId,
    inputs: &[Vec<u32>],
    cpu: impl Fn(&[u32]) -> Vec<u32>,
    tol: Tolerance,
) {
    compare_with(
        name,
        params,
        result,
        call,
        &[],
        inputs,
        MIN_INPUTS,
        |w: &[u32]| vec![cpu(w)],
        tol,
    );
}

/// [`compare`] with textures and samplers bound for the function, and a minimum input count.
/// `cpu` gives, for an input, the outputs the GPU may return: the CPU twin's, and where the
/// function makes a decision on a threshold that the two sides' rounding can tip, the CPU
/// twin's on the other side of it (each compared whole, within `tol`; the first is reported).
#[allow(clippy::too_many_arguments, reason = "test helper mirroring compare")]
pub fn compare_with(
    name: &str,
    params: Vec<Type>,
    result: Type,
    call: &dyn Fn(&[ExprId]) -> ExprId,
    resources: &[(u32, nimbus_runtime::GpuResource)],
    inputs: &[Vec<u32>],
    min_inputs: usize,
    cpu: impl Fn(&[u32]) -> Vec<Vec<u32>>,
    tol: Tolerance,
) {
    assert!(
        inputs.len() >= min_inputs,
        "{name}: only {} inputs",
        inputs.len()
    );
    let Some(gpu) = gpu() else { return };
    let f = KernelFn {
        name,
        params,
        result,
        call,
        resources,
    };
    let flat: Vec<u32> = inputs.iter().flatten().copied().collect();
    let gpu_out = run_on_gpu(gpu, &f, &flat).expect("GPU run");
    let width = gpu_out.len() / inputs.len();
    let is_float = result.scalar() == Some(nimbus_dsl::ir::Scalar::F32);
    let (mut worst, mut worst_ratio, mut worst_at) = (0.0f64, 0.0f64, 0usize);
    for (i, input) in inputs.iter().enumerate() {
        let outputs = cpu(input);
        let got = &gpu_out[i * width..(i + 1) * width];
        // The CPU twin's own output unless the GPU's is off it and within the tolerance of an
        // alternative.
        let expected = if !is_float || within(got, &outputs[0], tol) {
            &outputs[0]
        } else {
            outputs
                .iter()
                .skip(1)
                .find(|alt| within(got, alt, tol))
                .unwrap_or(&outputs[0])
        };
        assert_eq!(expected.len(), width, "{name}: output width");
        for (k, want) in expected.iter().enumerate() {
            let got = gpu_out[i * width + k];
            if !is_float {
                assert_eq!(got, *want, "{name}: input #{i} {input:?} component {k}");
                continue;
            }
            let (g, c) = (f32::from_bits(got), f32::from_bits(*want));
            assert!(
                g.is_finite() == c.is_finite(),
                "{name}: input #{i} {input:?}: cpu {c} gpu {g}"
            );
            if !c.is_finite() {
                continue;
            }
            let diff = f64::from((g - c).abs());
            let allowed = f64::from(tol.abs) + f64::from(tol.rel) * f64::from(c.abs());
            let ratio = diff / allowed;
            if ratio > worst_ratio {
                (worst, worst_ratio, worst_at) = (diff, ratio, i);
            }
            assert!(
                diff <= allowed,
                "{name}: input #{i} {:?} component {k}: cpu {c} gpu {g} (|diff| {diff:e} > {allowed:e})",
                input.iter().map(|w| f32::from_bits(*w)).collect::<Vec<_>>()
            );
        }
    }
    println!(
        "parity {name}: {} inputs on {}; largest |gpu - cpu| = {worst:e} ({:.1}% of tolerance abs {:e} + rel {:e}, at input #{worst_at})",
        inputs.len(),
        gpu.info(),
        worst_ratio * 100.0,
        tol.abs,
        tol.rel
    );
}

/// Whether every component of `got` lies within `tol` of `want` as the assertion measures it
/// (floats; a non-finite value only where both are).
fn within(got: &[u32], want: &[u32], tol: Tolerance) -> bool {
    got.len() == want.len()
        && got.iter().zip(want).all(|(g, c)| {
            let (g, c) = (f32::from_bits(*g), f32::from_bits(*c));
            if !g.is_finite() || !c.is_finite() {
                return g.is_finite() == c.is_finite();
            }
            f64::from((g - c).abs()) <= f64::from(tol.abs) + f64::from(tol.rel) * f64::from(c.abs())
        })
}

/// SPIR-V as reviewable text: rspirv's disassembly, one instruction per line.
pub fn spirv_text(words: &[u32]) -> String {
    match rspirv::dr::load_words(words) {
        Ok(module) => format!(
            "; SPIR-V, {} words\n{}\n",
            words.len(),
            rspirv::binary::Disassemble::disassemble(&module)
        ),
        Err(e) => format!("; SPIR-V that rspirv cannot parse: {e}\n"),
    }
}

/// Runs the node script at `script` and parses what it prints as JSON; a failure shows node's
/// error beside `module`, the printed module the script imports.
pub fn run_node_json(script: &std::path::Path, module: &str) -> serde_json::Value {
    let out = std::process::Command::new("node")
        .arg(script)
        .output()
        .expect("node");
    assert!(
        out.status.success(),
        "node failed:\n{}\n--- module ---\n{module}",
        String::from_utf8_lossy(&out.stderr)
    );
    serde_json::from_slice(&out.stdout).expect("the script prints JSON")
}

/// Every number in a JSON value, depth first: arrays in order, objects by field name (serde_json
/// sorts them: a lookup's `u` before its `v`).
pub fn json_floats(v: &serde_json::Value) -> Vec<f64> {
    match v {
        serde_json::Value::Array(a) => a.iter().flat_map(json_floats).collect(),
        serde_json::Value::Number(n) => vec![n.as_f64().unwrap_or(f64::NAN)],
        serde_json::Value::Object(o) => o.values().flat_map(json_floats).collect(),
        _ => Vec::new(),
    }
}
