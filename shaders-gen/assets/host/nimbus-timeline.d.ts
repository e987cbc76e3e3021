// TypeScript declarations of nimbus-timeline.js (NimbusTimeline: a scene's wind and weather
// states as the cloud block's uniforms at a time).

/** The cloud block's members a moment of the timeline sets. */
export interface TimelineUniforms {
  /** How far the air near the ground has travelled (m, x east, z south). */
  wind_drift: [number, number];
  /** How much farther per metre of altitude. */
  wind_shear_drift: [number, number];
  /** The coverage (0..1). */
  coverage: number;
}

export declare class NimbusTimeline {
  /** A still timeline whose coverage is `coverage` (0..1) until a weather state changes it. */
  constructor(coverage: number);
  /** m/s and where it blows from (degrees clockwise from north), near the ground and at 10 km. */
  setWind(speed: number, directionDeg: number, topSpeed?: number, topDirectionDeg?: number): void;
  /** By `at` seconds the coverage has become `coverage`, ramping over `over` seconds or from the state before. */
  setWeather(coverage: number, options?: { at?: number; over?: number; now?: number }): void;
  /** Forgets every weather state. */
  clearWeather(): void;
  /** The coverage `seconds` after the start. */
  coverageAt(seconds: number): number;
  /** The drift `seconds` after the start. */
  driftAt(seconds: number): Pick<TimelineUniforms, 'wind_drift' | 'wind_shear_drift'>;
  /** The uniforms `seconds` after the start. */
  at(seconds: number): TimelineUniforms;
}
