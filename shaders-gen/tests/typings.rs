//! The JavaScript hosts' typings: the `.d.ts` printed beside each host module (`nimbus-frame.js`,
//! `nimbus-sun.js`, `nimbus-wind.js`: what the JavaScript twins take and return), those of the
//! shared host state (`nimbus-host.js`, `nimbus-timeline.js`) and of the engine hosts
//! (`NimbusClouds` against three's own types, `NimbusWebGPU` against the WebGPU types).
//! TypeScript's own checker (`tsc --strict`, from browser/node_modules) accepts a host written
//! against them, and refuses the same host with a call missing an argument, results misread and
//! arguments of the wrong kind (the control).
//!
//! Needs node and `browser/node_modules` (`npm ci` in browser/).

mod common;

use std::process::Command;

use common::{browser_dir, emit_package, text};
use nimbus_testkit::skip::{browser_tools_present, node_missing};

/// A host of the three modules, in TypeScript; `broken` adds two mistakes.
fn host(broken: bool) -> String {
    let mut ts = String::from(
        "import { cloud_frame, resolve_frame, drift_at } from './pkg/nimbus-frame.js';\n\
         import { sun_direction, sun_light } from './pkg/nimbus-sun.js';\n\
         import { TOP_ALTITUDE, wind_velocity, wind_velocity_at } from './pkg/nimbus-wind.js';\n\
         const frame = cloud_frame(3, 7, 1);\n\
         const jitter: number = frame.jitter;\n\
         const offset: [number, number] = frame.pixel_offset;\n\
         const resolve = resolve_frame(4, 1, 0, [1, 2, 3, 4], [1, 2, 3, 4], 1500, [640, 360]);\n\
         const shift: [number, number, number] = resolve.cloud_shift;\n\
         const at: [number, number, number] = drift_at([0, 0, 0.1, 0.2], 2000);\n\
         const sun: [number, number, number] = sun_direction(30, 150);\n\
         declare const block: Parameters<typeof sun_light>[0];\n\
         const light = sun_light(block, sun);\n\
         const cascades: [number, number, number, number][] = [...light.shadow_lookup.u];\n\
         const wind: [number, number] = wind_velocity_at(wind_velocity(6, 270), wind_velocity(20, 280), TOP_ALTITUDE);\n\
         import { NimbusHost, loadPackage } from './pkg/nimbus-host.js';\n\
         import { NimbusTimeline } from './pkg/nimbus-timeline.js';\n\
         export async function drive(): Promise<number> {\n\
           const { pkg, pair, blocks } = await loadPackage(new URL('https://example.invalid/'), 'webgpu');\n\
           const host = new NimbusHost(pkg, pair, blocks);\n\
           host.upscale = true;\n\
           host.setSize(640, 360);\n\
           host.setView({ viewProjection: new Float32Array(16), position: [0, 2, 0] });\n\
           host.setSun(30, 150);\n\
           host.setWind(6, 260);\n\
           host.setWeather(0.4, { at: 600 });\n\
           host.setTime(300);\n\
           const index: number = host.beginFrame();\n\
           host.resolveFrame(index);\n\
           host.endFrame();\n\
           const coverage: number = new NimbusTimeline(0.3).at(60).coverage;\n\
           return index + coverage + host.lowWidth + blocks.pair.float('media.coverage');\n\
         }\n\
         export const used = [jitter, offset, shift, at, cascades, wind, block.march.max_height];\n\
         import * as THREE from 'three';\n\
         import { NimbusClouds } from './pkg3/nimbus-clouds.js';\n\
         export async function three(renderer: THREE.WebGLRenderer, camera: THREE.PerspectiveCamera): Promise<number> {\n\
           const clouds = await NimbusClouds.load(new URL('https://example.invalid/'));\n\
           const target = new THREE.WebGLRenderTarget(4, 4, { depthTexture: new THREE.DepthTexture(4, 4) });\n\
           clouds.setSize(4, 4);\n\
           clouds.setCamera(camera);\n\
           const shadow: THREE.Texture = clouds.renderSceneShadow(renderer, { scene: target });\n\
           const ground = clouds.shadowMaterial(new THREE.MeshStandardMaterial());\n\
           clouds.render(renderer, null, { scene: target });\n\
           return ground.roughness + shadow.id + (clouds.readsDepth ? 1 : 0);\n\
         }\n\
         import { NimbusWebGPU } from './pkg/nimbus-webgpu.js';\n\
         export async function webgpu(device: GPUDevice, view: GPUTextureView, depth: GPUTexture): Promise<GPUTexture> {\n\
           const clouds = await NimbusWebGPU.load('https://example.invalid/', device, { format: 'rgba8unorm' });\n\
           clouds.setSize(4, 4);\n\
           clouds.setCamera({ viewProjection: new Float32Array(16), position: [0, 2, 0], projection: new Float32Array(16), forward: [0, 0, -1], far: 1e6 });\n\
           clouds.render(view, { depth });\n\
           return clouds.renderSceneShadow({ depth });\n\
         }\n",
    );
    if broken {
        ts.push_str(
            "export const missing = cloud_frame(3, 7);\n\
             export const misread: string = resolve.variance_gamma;\n\
             export const wrong: string = new NimbusTimeline(0.3).coverageAt(1);\n\
             export const notATarget = (r: THREE.WebGLRenderer, c: NimbusClouds) => c.render(r, 'canvas');\n\
             export const notANumber = (c: NimbusClouds): string => c.shadowMaterial(new THREE.MeshStandardMaterial()).roughness;\n\
             export const notADepth = (c: NimbusWebGPU, v: GPUTextureView) => c.render(v, { depth: 3 });\n",
        );
    }
    ts
}

#[test]
fn the_host_modules_typings_check_a_typescript_host() {
    let tsc = browser_dir().join("node_modules/typescript/bin/tsc");
    if !browser_tools_present(
        "the typings test",
        node_missing().or_else(|| {
            (!tsc.is_file())
                .then(|| "browser/node_modules is missing: run `npm ci` in browser/".into())
        }),
    ) {
        return;
    }
    // Inside browser/, so that `three` and the WebGPU types resolve from its node_modules as
    // they would in a user's project.
    let dir = tempfile::Builder::new()
        .prefix(".typings-")
        .tempdir_in(browser_dir())
        .expect("temp dir");
    let package = dir.path().join("pkg");
    emit_package("webgpu", "cumulus", "low", &["scene-depth"], &package);
    emit_package(
        "three",
        "cumulus",
        "medium",
        &["scene-depth"],
        &dir.path().join("pkg3"),
    );
    for module in ["nimbus-frame", "nimbus-sun", "nimbus-wind"] {
        assert!(
            package.join(format!("{module}.d.ts")).is_file(),
            "{module}.d.ts missing"
        );
    }
    let check = |name: &str, broken: bool| -> (bool, String) {
        let file = dir.path().join(name);
        std::fs::write(&file, host(broken)).expect("writes the host");
        let out = Command::new("node")
            .arg(&tsc)
            .args([
                "--noEmit",
                "--strict",
                "--target",
                "es2022",
                "--module",
                "es2022",
                "--moduleResolution",
                "bundler",
            ])
            .arg(&file)
            .current_dir(dir.path())
            .output()
            .expect("runs tsc");
        (
            out.status.success(),
            format!("{}{}", text(&out.stdout), text(&out.stderr)),
        )
    };
    let (ok, log) = check("host.ts", false);
    assert!(ok, "tsc refused a correct host:\n{log}");
    let (ok, log) = check("broken.ts", true);
    println!("the control, as tsc reports it:\n{log}");
    assert!(
        !ok,
        "tsc accepted a host with a missing argument, misread fields and wrong arguments"
    );
    assert!(
        log.contains("broken.ts") && log.matches("error TS").count() >= 6,
        "{log}"
    );
}
