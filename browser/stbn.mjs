// A stand-in for @takram/three-geospatial's spatiotemporal blue noise texture (stbn.bin: 128×128×64
// bytes, one channel, read by its STBNLoader). The npm packages do not ship that file (their
// DEFAULT_STBN_URL points at GitHub's LFS media host), so this makes one offline: a 128×128 blue
// noise mask by void-and-cluster (Ulichney 1993, toroidal Gaussian energy, sigma 1.5), and its 64
// slices animated by the golden ratio (slice z holds fract(rank + z·0.618…)), the usual cheap
// approximation of NVIDIA's STBN: each slice is blue in space, each texel low-discrepancy in time.
// Deterministic (fixed seed), about a second in Node.
export const STBN_WIDTH = 128;
export const STBN_HEIGHT = 128;
export const STBN_DEPTH = 64;

function mulberry32(seed) {
  let a = seed >>> 0;
  return () => {
    a = (a + 0x6d2b79f5) >>> 0;
    let t = a;
    t = Math.imul(t ^ (t >>> 15), t | 1);
    t ^= t + Math.imul(t ^ (t >>> 7), t | 61);
    return ((t ^ (t >>> 14)) >>> 0) / 4294967296;
  };
}

// Ranks 0..W·H-1 of a W×H blue noise mask (void-and-cluster).
export function blueNoiseRanks(width = STBN_WIDTH, height = STBN_HEIGHT, seed = 1, sigma = 1.5) {
  const n = width * height;
  const radius = Math.ceil(sigma * 4);
  const kernel = [];
  for (let dy = -radius; dy <= radius; dy++) {
    for (let dx = -radius; dx <= radius; dx++) {
      kernel.push(dx, dy, Math.exp(-(dx * dx + dy * dy) / (2 * sigma * sigma)));
    }
  }
  const energy = new Float64Array(n);
  const on = new Uint8Array(n);
  const splat = (i, sign) => {
    const x = i % width;
    const y = (i / width) | 0;
    for (let k = 0; k < kernel.length; k += 3) {
      const xx = (x + kernel[k] + width) % width;
      const yy = (y + kernel[k + 1] + height) % height;
      energy[yy * width + xx] += sign * kernel[k + 2];
    }
    on[i] = sign > 0 ? 1 : 0;
  };
  const tightestCluster = () => {
    let best = -1;
    let value = -Infinity;
    for (let i = 0; i < n; i++) if (on[i] && energy[i] > value) { value = energy[i]; best = i; }
    return best;
  };
  const largestVoid = () => {
    let best = -1;
    let value = Infinity;
    for (let i = 0; i < n; i++) if (!on[i] && energy[i] < value) { value = energy[i]; best = i; }
    return best;
  };

  // Initial binary pattern: a tenth of the texels at random, relaxed until stable.
  const random = mulberry32(seed);
  const initial = Math.floor(n / 10);
  for (let placed = 0; placed < initial;) {
    const i = Math.floor(random() * n);
    if (!on[i]) { splat(i, 1); placed++; }
  }
  for (let guard = 0; guard < n; guard++) {
    const cluster = tightestCluster();
    splat(cluster, -1);
    const hole = largestVoid();
    if (hole === cluster) { splat(cluster, 1); break; }
    splat(hole, 1);
  }
  const prototype = on.slice();
  const prototypeEnergy = energy.slice();
  const ranks = new Uint32Array(n);
  // Phase 1: remove the tightest clusters of the prototype, ranking down.
  for (let rank = initial - 1; rank >= 0; rank--) {
    const cluster = tightestCluster();
    splat(cluster, -1);
    ranks[cluster] = rank;
  }
  // Phases 2 and 3: fill the largest voids of the prototype, ranking up.
  on.set(prototype);
  energy.set(prototypeEnergy);
  for (let rank = initial; rank < n; rank++) {
    const hole = largestVoid();
    splat(hole, 1);
    ranks[hole] = rank;
  }
  return ranks;
}

// The bytes of stbn.bin: slice after slice, row after row.
export function makeSTBN() {
  const ranks = blueNoiseRanks();
  const n = STBN_WIDTH * STBN_HEIGHT;
  const golden = (Math.sqrt(5) - 1) / 2;
  const data = new Uint8Array(n * STBN_DEPTH);
  for (let z = 0; z < STBN_DEPTH; z++) {
    for (let i = 0; i < n; i++) {
      const v = ((ranks[i] + 0.5) / n + z * golden) % 1;
      data[z * n + i] = Math.min(255, Math.floor(v * 256));
    }
  }
  return data;
}
