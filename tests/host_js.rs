//! The host's share of the lighting, written once: `sun_light` fills exactly the members
//! `CloudUniforms::for_genus` computes (bit for bit, on the CPU), and its JavaScript twin
//! (`print_js`, run by node) gives the same values, so a three.js host moving the sun lights the
//! clouds as Nimbus does.

mod common;

use std::path::Path;

use glam::Vec3;
use nimbus_clouds::model::march::CloudUniforms;
use nimbus_clouds::model::sun::{SunLight, host_module, sun_direction, sun_light};
use nimbus_clouds::{CloudLibrary, Quality};
use nimbus_codegen::print_js;
use nimbus_dsl::ir::Type;
use nimbus_dsl::layout::{UniformBytes, member_layout};
use serde_json::{Map, Value, json};

fn library() -> CloudLibrary {
    CloudLibrary::load(&Path::new(env!("CARGO_MANIFEST_DIR")).join("examples")).expect("data")
}

/// Sun directions from elevation and azimuth, as scenes give them.
fn sun(elevation: f32, azimuth: f32) -> Vec3 {
    sun_direction(elevation, azimuth)
}

fn cases() -> Vec<(String, CloudUniforms)> {
    let lib = library();
    let mut out = Vec::new();
    for genus in ["cumulus", "stratocumulus", "takram-default"] {
        let g = lib.genus(genus).expect("genus");
        for (q, el, az, alt) in [
            (Quality::Low, 35.0, 150.0, 2.0),
            (Quality::High, 8.0, 230.0, 500.0),
            (Quality::Ultra, 60.0, 10.0, 2500.0),
            (Quality::Medium, -3.0, 90.0, 2.0),
        ] {
            let u = CloudUniforms::for_genus(g, q, sun(el, az), alt);
            out.push((
                format!("{genus}.{} sun {el}° {az}° at {alt} m", q.name()),
                u,
            ));
        }
    }
    out
}

#[test]
fn sun_light_is_what_the_uniform_block_is_filled_with() {
    for (name, u) in cases() {
        let l = sun_light(u, u.light.sun_direction);
        assert_eq!(l.sun_irradiance, u.light.sun_irradiance, "{name}");
        assert_eq!(l.sky_irradiance, u.light.sky_irradiance, "{name}");
        assert_eq!(l.shadow_lookup, u.shadow.lookup, "{name}");
        assert_eq!(l.shadow_inverse_matrix, u.shadow.inverse_matrix, "{name}");
    }
}

/// A uniform value as the JavaScript twin takes it: nested objects by field name, arrays for
/// vectors and fixed arrays, matrices as arrays of columns.
fn js_value(u: &CloudUniforms) -> Value {
    let mut root = Value::Object(Map::new());
    for m in member_layout(
        CloudUniforms::shader_type(),
        &u.to_uniform_bytes().expect("sized by its layout"),
    ) {
        let leaf = match m.ty {
            Type::Scalar(_) => json!(m.value[0]),
            Type::Vector(..) => json!(m.value),
            Type::Matrix(n) => json!(m.value.chunks(n as usize).collect::<Vec<_>>()),
            other => panic!(
                "unexpected member type {}",
                nimbus_codegen::wgsl_type(other)
            ),
        };
        // `groups[1].min_height` → root.groups[1].min_height
        let parts: Vec<&str> = m.path.split('.').collect();
        insert(&mut root, &parts, leaf);
    }
    root
}

fn insert(node: &mut Value, parts: &[&str], leaf: Value) {
    let Some((part, rest)) = parts.split_first() else {
        *node = leaf;
        return;
    };
    if !node.is_object() {
        *node = Value::Object(Map::new());
    }
    let Some(map) = node.as_object_mut() else {
        return;
    };
    match part.split_once('[') {
        Some((key, index)) => {
            let ix: usize = index.trim_end_matches(']').parse().expect("index");
            let arr = map.entry(key).or_insert_with(|| json!([]));
            if let Some(arr) = arr.as_array_mut() {
                while arr.len() <= ix {
                    arr.push(Value::Null);
                }
                insert(&mut arr[ix], rest, leaf);
            }
        }
        None => insert(map.entry(*part).or_insert(Value::Null), rest, leaf),
    }
}

/// Elevations and azimuths the direction twins are compared at (degrees).
const ANGLES: [(f32, f32); 4] = [(35.0, 150.0), (8.0, 230.0), (-3.0, 90.0), (89.0, 0.0)];

#[test]
fn the_javascript_twin_of_sun_light_matches_the_cpu_twin() {
    if !nimbus_testkit::skip::browser_tools_present(
        "the JavaScript twin test",
        nimbus_testkit::skip::node_missing(),
    ) {
        return;
    }
    let module = host_module().expect("records");
    let js = print_js(&module, &["sun_direction", "sun_light"]).expect("prints");
    let dir = tempfile::tempdir().expect("tempdir");
    std::fs::write(dir.path().join("sun.mjs"), &js).expect("write module");
    let cases = cases();
    let inputs: Vec<Value> = cases
        .iter()
        .map(|(_, u)| json!({ "u": js_value(u), "sun": u.light.sun_direction.to_array() }))
        .collect();
    std::fs::write(
        dir.path().join("inputs.json"),
        serde_json::to_string(&inputs).expect("json"),
    )
    .expect("write inputs");
    std::fs::write(
        dir.path().join("run.mjs"),
        "import { readFileSync } from 'node:fs';\n\
         import { sun_direction, sun_light } from './sun.mjs';\n\
         const inputs = JSON.parse(readFileSync(new URL('./inputs.json', import.meta.url)));\n\
         const lights = inputs.map((c) => sun_light(c.u, c.sun));\n\
         const directions = ANGLES.map(([el, az]) => sun_direction(el, az));\n\
         console.log(JSON.stringify({ lights, directions }));\n"
            .replace("ANGLES", &serde_json::to_string(&ANGLES).expect("json")),
    )
    .expect("write runner");
    let output = common::run_node_json(&dir.path().join("run.mjs"), &js);
    let results = output["lights"].as_array().cloned().unwrap_or_default();
    for ((el, az), got) in ANGLES
        .iter()
        .zip(output["directions"].as_array().expect("directions"))
    {
        let want = sun_direction(*el, *az);
        for (j, c) in common::json_floats(got).iter().zip(want.to_array()) {
            assert!(
                (j - f64::from(c)).abs() < 1e-6,
                "sun_direction({el}, {az}): {j} vs {c}"
            );
        }
    }
    let mut worst = 0.0f64;
    for ((name, u), got) in cases.iter().zip(&results) {
        let want: SunLight = sun_light(*u, u.light.sun_direction);
        for (field, cpu) in [
            ("sun_irradiance", want.sun_irradiance.to_array().to_vec()),
            ("sky_irradiance", want.sky_irradiance.to_array().to_vec()),
            (
                "shadow_lookup",
                [want.shadow_lookup.u, want.shadow_lookup.v]
                    .iter()
                    .flat_map(|m| m.to_cols_array())
                    .collect(),
            ),
            (
                "shadow_inverse_matrix",
                want.shadow_inverse_matrix.to_cols_array().to_vec(),
            ),
        ] {
            let js_values = common::json_floats(&got[field]);
            assert_eq!(js_values.len(), cpu.len(), "{name}: {field}");
            for (j, c) in js_values.iter().zip(&cpu) {
                let c = f64::from(*c);
                let d = (j - c).abs() / (1e-6 + c.abs());
                worst = worst.max(d);
                assert!(d < 1e-4, "{name}: {field}: JavaScript {j} against CPU {c}");
            }
        }
    }
    println!(
        "{} cases, largest relative difference JavaScript (f64) vs CPU twin (f32): {worst:.2e}",
        cases.len()
    );
}
