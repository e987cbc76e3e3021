// What both pages publish for their drivers on `window.nimbus`: the frame as a PNG data URL, the
// adapter, any WebGL error, and whether the run failed; `run` is the page's whole work.
export function publish(run) {
  const result = { done: false, error: null, png: null, messages: [] };
  window.nimbus = result;
  run(result)
    .then(({ gl, canvas }) => {
      const error = gl.getError();
      if (error !== gl.NO_ERROR) result.messages.push(`WebGL error 0x${error.toString(16)}`);
      const info = gl.getExtension('WEBGL_debug_renderer_info');
      result.renderer = gl.getParameter(info ? info.UNMASKED_RENDERER_WEBGL : gl.RENDERER);
      result.png = canvas.toDataURL('image/png');
    })
    .catch((e) => { result.error = String(e && e.stack ? e.stack : e); })
    .finally(() => { result.done = true; });
}
