//! Deterministic mutations of a text input, for the smoke runs of the fuzz targets' bodies in
//! the default tests (the fuzzers themselves mutate under libFuzzer on nightly): the same seed
//! and number give the same input on every machine, so a failure reproduces.

/// xorshift64*: small, fast and deterministic; the mutations need nothing better.
struct Rng(u64);

impl Rng {
    fn new(seed: u64) -> Self {
        Rng(seed.max(1))
    }

    fn next_u64(&mut self) -> u64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        self.0.wrapping_mul(0x2545_f491_4f6c_dd1d)
    }
}

/// Tokens of Nimbus's TOML files and edge values, spliced into inputs by [`mutate`].
pub const TOKENS: &[&str] = &[
    "nan",
    "inf",
    "-inf",
    "1e38",
    "-1e38",
    "0.0",
    "-0.0",
    "1e-45",
    "[[layers]]",
    "= ",
    "\"",
    "{",
    "}",
    "[",
    "]",
    ",",
    "\n",
    "coverage = ",
    "height = ",
    "density_profile = { a = 1e30, b = 80.0, c = 0.0, d = 0.0 }",
    "phase = { model = \"approximate-mie\", droplet_diameter_um = 50.0 }",
    "quality = \"reference\"",
    "features = { octaves = 12 }",
    "fov_deg = 170.0",
    "sun_elevation_deg = -90.0",
    "camera_altitude = 100000.0",
    "weather_offset = [1e6, -1e6]",
];

/// `seed`'s `n`-th mutation (deterministic): bytes flipped, [`TOKENS`] spliced in, lines
/// dropped or repeated, numbers replaced by edge values.
pub fn mutate(seed: &str, n: u64) -> Vec<u8> {
    let mut rng = Rng::new(n.wrapping_mul(0x9e37_79b9_7f4a_7c15) ^ seed.len() as u64);
    let mut bytes = seed.as_bytes().to_vec();
    let edits = 1 + rng.next_u64() % 4;
    for _ in 0..edits {
        let at = (rng.next_u64() as usize) % bytes.len().max(1);
        match rng.next_u64() % 5 {
            0 => {
                if let Some(b) = bytes.get_mut(at) {
                    *b ^= 1 << (rng.next_u64() % 8);
                }
            }
            1 => {
                let t = TOKENS[(rng.next_u64() as usize) % TOKENS.len()];
                bytes.splice(at..at, t.bytes());
            }
            2 => {
                // Drop a line.
                let text = String::from_utf8_lossy(&bytes).into_owned();
                let mut lines: Vec<&str> = text.lines().collect();
                if !lines.is_empty() {
                    let i = (rng.next_u64() as usize) % lines.len();
                    lines.remove(i);
                }
                bytes = lines.join("\n").into_bytes();
            }
            3 => {
                // Repeat a line (duplicate keys, extra layers).
                let text = String::from_utf8_lossy(&bytes).into_owned();
                let mut lines: Vec<String> = text.lines().map(str::to_string).collect();
                if !lines.is_empty() {
                    let i = (rng.next_u64() as usize) % lines.len();
                    let l = lines[i].clone();
                    lines.insert(i, l);
                }
                bytes = lines.join("\n").into_bytes();
            }
            _ => {
                // Replace a number by an edge value.
                let text = String::from_utf8_lossy(&bytes).into_owned();
                let numbers: Vec<(usize, usize)> = text
                    .match_indices(|c: char| c.is_ascii_digit())
                    .map(|(i, _)| {
                        let end = text[i..]
                            .find(|c: char| !(c.is_ascii_digit() || c == '.' || c == 'e'))
                            .map_or(text.len(), |e| i + e);
                        (i, end)
                    })
                    .collect();
                if !numbers.is_empty() {
                    let (i, end) = numbers[(rng.next_u64() as usize) % numbers.len()];
                    let t = ["0.0", "1e38", "nan", "-1.0", "1e-30", "1e9", "0"]
                        [(rng.next_u64() as usize) % 7];
                    bytes = format!("{}{t}{}", &text[..i], &text[end..]).into_bytes();
                }
            }
        }
    }
    bytes
}
