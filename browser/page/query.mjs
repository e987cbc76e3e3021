// What the test pages are driven by: the query string, the numbers they all read from it, and
// Nimbus's camera convention applied to a three.js camera.
export const q = new URLSearchParams(location.search);
export const number = (name, fallback) => (q.has(name) ? Number(q.get(name)) : fallback);
export const width = number('width', 160);
export const height = number('height', 90);
const degrees = Math.PI / 180;

/**
 * Places `camera` as Nimbus's scenes do: `altitude` metres up, pitched up from the horizon and
 * yawed clockwise from -z (north) by the query's degrees (`pitch` defaulting to `pitch`).
 */
export function placeCamera(camera, pitch) {
  camera.rotation.order = 'YXZ';
  camera.rotation.set(number('pitch', pitch) * degrees, -number('yaw', 0) * degrees, 0);
  camera.position.set(0, number('altitude', 2), 0);
}
