// Milliseconds per frame as both pages measure them: each frame drawn and then waited for with a
// one-pixel readPixels (gl.finish() returns early in Chromium); the median after warm-up.
export function timeFrames(gl, draw, warmup, count) {
  const pixel = new Uint8Array(4);
  const times = [];
  for (let i = 0; i < warmup + count; i++) {
    const t0 = performance.now();
    draw();
    gl.readPixels(0, 0, 1, 1, gl.RGBA, gl.UNSIGNED_BYTE, pixel);
    if (i >= warmup) times.push(performance.now() - t0);
  }
  times.sort((a, b) => a - b);
  return { ms: times[Math.floor(times.length / 2)], times };
}
