// TypeScript declarations of nimbus-webgpu.js (NimbusWebGPU: a Nimbus package drawn with the
// WebGPU API alone). Written against the WebGPU types (@webgpu/types).

/// <reference types="@webgpu/types" />
import { NimbusHost, View } from './nimbus-host.js';

/** The engine's depth for a frame: a texture (read through a depth-only view), or a view of it. */
export type EngineDepth = GPUTexture | { texture: GPUTexture; view: GPUTextureView };

export declare class NimbusWebGPU extends NimbusHost {
  /**
   * Loads the package at `base` onto `device`; `options.pair` picks a genus × preset pair,
   * `options.format` the format of the texture `render` draws into. Every pipeline is compiled
   * asynchronously (createRenderPipelineAsync): an application switching pairs keeps drawing
   * the current one until the promise resolves. `options.compile: 'blocking'` compiles with
   * createRenderPipeline instead.
   */
  static load(
    base: URL | string,
    device: GPUDevice,
    options?: { pair?: string; format?: GPUTextureFormat; compile?: 'async' | 'blocking' },
  ): Promise<NimbusWebGPU>;
  readonly device: GPUDevice;
  /**
   * Where the clouds are seen from; a pair that reads the engine's depth also needs its
   * `projection`, `forward` and `far` (and `reversed` for a reversed-Z buffer).
   */
  setCamera(view: View): void;
  /** Draws one frame into `view`, over what it holds when the pair reads `options.depth`. */
  render(view: GPUTextureView, options?: { depth?: EngineDepth }): void;
  /** The clouds' shadow on the engine's objects (red: the sun's light through the clouds). */
  renderSceneShadow(options: { depth: EngineDepth }): GPUTexture;
  dispose(): void;
}
