// TypeScript declarations of nimbus-clouds.js (NimbusClouds: a Nimbus package drawn with
// three.js alone). Written against three's own types (@types/three).

import type {
  Camera,
  DepthTexture,
  Material,
  Texture,
  WebGLRenderTarget,
  WebGLRenderer,
} from 'three';
import { NimbusHost } from './nimbus-host.js';

/** Where a frame's engine depth comes from (pairs built with --enable scene-depth). */
export interface SceneOptions {
  /** The render target the scene was drawn into, with a depthTexture: drawn first. */
  scene?: WebGLRenderTarget;
  /** The depth alone: the clouds are blended over what the target holds. */
  depth?: DepthTexture;
}

export declare class NimbusClouds extends NimbusHost {
  /** Loads the package at `base` (its folder's URL); `options.pair` picks a genus × preset pair. */
  static load(base: URL | string, options?: { pair?: string }): Promise<NimbusClouds>;
  /**
   * The engine's own camera: its world position (y is the altitude), rotation and projection
   * (a PerspectiveCamera, or an OrthographicCamera for pairs built with --enable orthographic).
   */
  setCamera(camera: Camera): void;
  /** Draws one frame into `target`, or the canvas when it is null. */
  render(renderer: WebGLRenderer, target?: WebGLRenderTarget | null, options?: SceneOptions): void;
  /**
   * The clouds' shadow on the engine's objects for this frame (pairs with a scene_shadow pass):
   * after the engine's depth, before its lit scene. Returns the texture it drew.
   */
  renderSceneShadow(renderer: WebGLRenderer, options: SceneOptions): Texture;
  /**
   * Makes a lit material (MeshStandardMaterial, MeshPhysicalMaterial, MeshLambertMaterial,
   * MeshPhongMaterial) scale its direct light by the clouds' shadow; returns it.
   */
  shadowMaterial<M extends Material>(material: M): M;
  dispose(): void;
}
