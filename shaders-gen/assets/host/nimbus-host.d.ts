// TypeScript declarations of nimbus-host.js (NimbusHost: what any JavaScript host of a Nimbus
// package keeps and writes into its uniform blocks, with no graphics API).

import { NimbusTimeline } from './nimbus-timeline.js';

/** A member of a uniform block, as the package's uniforms/*.json list it. */
export interface BlockMember {
  member: string;
  offset: number;
  type: string;
  value: number[];
}

/** A uniform block file of the package (uniforms/<pair>.json, resolve.json, display.json). */
export interface BlockFile {
  size: number;
  bytes_hex: string;
  members: BlockMember[];
}

/** A uniform block: its bytes, with float and uint views, and member offsets by path. */
export declare class Block {
  constructor(json: BlockFile);
  readonly bytes: Uint8Array;
  readonly floats: Float32Array;
  readonly uints: Uint32Array;
  /** Writes each field of a generated host function's result into the member of that name. */
  assign(values: Record<string, number | number[] | number[][]>): void;
  /** The block as the JavaScript twins of shader functions take it. */
  toObject(): Record<string, unknown>;
  word(path: string): number;
  setFloats(path: string, values: ArrayLike<number>): void;
  setUint(path: string, value: number): void;
  float(path: string): number;
  vector(path: string, n: number): number[];
}

/** The inverse of a 4×4 matrix given column by column (16 numbers). */
export declare function invert(m: ArrayLike<number>): number[];

/** A genus × preset pair of the package description (nimbus-package.json). */
export interface PackagePair {
  pair: string;
  genus: string;
  quality: string;
  uniforms: string;
  camera: 'perspective' | 'orthographic';
  scene_depth: boolean;
  passes: unknown[];
}

/** The blocks a pair writes. */
export interface Blocks {
  pair: Block;
  resolve: Block;
  display: Block;
  /** Only for pairs built with --enable scene-depth. */
  scene?: Block;
}

/**
 * The bytes of an RGBA8 texture file as half floats (binary16 bits), each byte through the
 * package's `texel_halves` table.
 */
export declare function widenTexels(bytes: Uint8Array, texelHalves: ArrayLike<number>): Uint16Array;

/** Fetches the package description at `base` for `engine`, its pair and its blocks. */
export declare function loadPackage(
  base: URL | string,
  engine: string,
  options?: { pair?: string },
): Promise<{
  pkg: { engine: string; pairs: PackagePair[] } & Record<string, unknown>;
  pair: PackagePair;
  blocks: Blocks;
  url(path: string): string;
  get(path: string, as?: 'text' | 'json' | 'bytes' | 'blob'): Promise<unknown>;
}>;

/** The camera as NimbusHost.setView takes it (y up, metres; x east, −z north). */
export interface View {
  /** Projection × view without translation, 16 numbers column by column. */
  viewProjection: ArrayLike<number>;
  /** The camera's place in the world: y is its altitude above the ground. */
  position: [number, number, number];
  /** With scene depth: the projection (16 numbers) and forward direction. */
  projection?: ArrayLike<number>;
  forward?: [number, number, number];
  far?: number;
  reversed?: boolean;
}

/** A copy of the pair block's bytes, with a float view of them. */
export interface BlockCopy {
  bytes: Uint8Array;
  floats: Float32Array;
}

/** What the shadow or air pass draws in a frame (`NimbusHost.shadowTiles`, `airBands`). */
export interface BandPlan {
  rects: [number, number, number, number][];
  back: boolean;
  copy: [number, number, number, number] | null;
}

export declare class NimbusHost {
  constructor(pkg: unknown, pair: PackagePair, blocks: Blocks);
  readonly pair: PackagePair;
  readonly blocks: Blocks;
  /** Whether the pair reads the engine's depth (built with --enable scene-depth). */
  readonly readsDepth: boolean;
  readonly timeline: NimbusTimeline;
  readonly width: number;
  readonly height: number;
  /** The cloud pass's target size. */
  readonly lowWidth: number;
  readonly lowHeight: number;
  /** Seed of the per-frame jitter sequence. */
  seed: number;
  /** Shade one pixel in sixteen per frame (restarts the history). */
  upscale: boolean;
  /** Average still frames (restarts the history). */
  accumulate: boolean;
  readonly temporal: boolean;
  /** Every tile of the shadow atlas is out of date: redraw from the next frame. */
  shadowDirty: boolean;
  /**
   * Redraw the out-of-date cascade tiles in turn, each in bands of rows over several frames
   * (drawn into a back atlas, copied into the one the clouds read when done), once the atlas
   * has been drawn whole (default), and the air table in bands likewise; false redraws the
   * whole atlas when a tile is out of date, and the whole table.
   */
  cascadeRotation: boolean;
  /**
   * Redraw the air table (the sky and the air in front of the clouds) from the next frame:
   * whole, or in bands with `cascadeRotation` once it has been drawn.
   */
  airDirty: boolean;
  /** Linear radiance is scaled by this before the tone curve. */
  exposure: number;
  /** The sun's direction (unit, x east, y up, z south). */
  readonly sunDirection: number[];
  setSize(width: number, height: number): void;
  setView(view: View): void;
  /** Degrees: elevation above the horizon, azimuth clockwise from north. */
  setSun(elevation: number, azimuth: number): void;
  relight(): void;
  /**
   * What the shadow pass draws this frame, with the block's `shadow.lookup` written for the
   * tiles as they will be read: call before the blocks are uploaded. The pass draws each of
   * `rects` (`[x, y, width, height]` in atlas texels) alone, from `passBlocks.shadow`, into
   * the back atlas when `back`; then `copy`, when not null, is copied from the back atlas into
   * the atlas the clouds read.
   */
  shadowTiles(): BandPlan;
  /**
   * What the air pass draws this frame, as `shadowTiles` for the shadow pass: the whole table,
   * or with `cascadeRotation` (once drawn whole) a band of it into the back table, the table
   * copied in with the last band; drawn from `passBlocks.air`.
   */
  airBands(): BandPlan;
  /**
   * `shadowTiles` for a pass drawn before the frame's `render` (the scene's shadow): the
   * frame's band is drawn then, and `render`'s own call draws none.
   */
  shadowTilesAhead(): BandPlan;
  /**
   * The block bytes the shadow and air passes draw from (bind them as their cloud block): the
   * pair block as it was when the tile or table in progress began.
   */
  readonly passBlocks: { shadow: BlockCopy; air: BlockCopy };
  /**
   * Whether the bake (a pair of a baked path: slices, impostor, blob2d) must be redrawn this frame: a member
   * of the block outside the package's `cloud_bake.ignores` changed since it was drawn.
   * Marks it drawn.
   */
  bakeOutOfDate(): boolean;
  setWind(speed: number, directionDeg: number, topSpeed?: number, topDirectionDeg?: number): void;
  setWeather(coverage: number, options?: { at?: number; over?: number }): void;
  clearWeather(): void;
  /** Seconds since the timeline's start. */
  setTime(seconds: number): void;
  drift(): number[];
  setDepthEncoding(encoding: {
    logarithmic?: boolean;
    depthScale: number;
    depthOffset: number;
    width: number;
    height: number;
    flipY: boolean;
  }): void;
  beginFrame(): number;
  resolveFrame(index: number): void;
  endFrame(): void;
}
