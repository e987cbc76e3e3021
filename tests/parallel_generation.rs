//! A key's targets are generated on every core (`nimbus_codegen::generate` splits the work after
//! the shared passes). The files must not depend on it: one thread and many give the same files,
//! byte for byte, in the order the targets were asked for (a target asked twice gives its files
//! twice), with the same manifests.

use std::path::Path;

use nimbus_clouds::CloudLibrary;
use nimbus_clouds::catalog::{catalog, cloud_catalog};
use nimbus_codegen::{Generated, Target, generate_variant};
use nimbus_dsl::ShaderVariant;

/// Everything a consumer reads of one file: name, target, entry point, bytes and manifest.
type FileFacts = (String, Target, Option<String>, Vec<u8>, String);

fn files(g: &Generated) -> Vec<FileFacts> {
    g.files
        .iter()
        .map(|f| {
            (
                f.file_name.clone(),
                f.target,
                f.entry_point.as_ref().map(|(e, _)| e.clone()),
                f.contents.to_bytes(),
                format!("{:?}", f.manifest),
            )
        })
        .collect()
}

fn pool(threads: usize) -> rayon::ThreadPool {
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .expect("thread pool")
}

#[test]
fn one_thread_and_many_give_the_same_files_in_the_asked_order() {
    let lib = CloudLibrary::load(&Path::new(env!("CARGO_MANIFEST_DIR")).join("examples"))
        .expect("example genera");
    // Every kind of pass (previews, resolve, display, sun light, scene shadow) and the cloud and
    // shadow shaders of the genera: compute and fragment entry points, every binding kind.
    let mut entries = catalog();
    entries.extend(cloud_catalog(&lib).into_iter().step_by(7));
    assert!(entries.len() > 10, "{} shaders", entries.len());
    let (one, many) = (pool(1), pool(4));
    // Backwards, one target twice, WGSL among the translated ones.
    let shuffled = [
        Target::SpirV,
        Target::Hlsl,
        Target::GlslEs300,
        Target::Wgsl,
        Target::Msl,
        Target::SpirV,
        Target::Glsl450,
    ];
    for entry in &entries {
        let serial = one
            .install(|| generate_variant(entry, &Target::ALL))
            .unwrap_or_else(|e| panic!("{}: {e}", entry.id()));
        let parallel = many
            .install(|| generate_variant(entry, &Target::ALL))
            .unwrap_or_else(|e| panic!("{}: {e}", entry.id()));
        assert_eq!(files(&serial), files(&parallel), "{}", entry.id());
        assert_eq!(serial.wgsl, parallel.wgsl, "{}", entry.id());
        assert_eq!(serial.bindings, parallel.bindings, "{}", entry.id());

        let asked = many
            .install(|| generate_variant(entry, &shuffled))
            .unwrap_or_else(|e| panic!("{}: {e}", entry.id()));
        let all = files(&serial);
        let expected: Vec<_> = shuffled
            .iter()
            .flat_map(|t| all.iter().filter(move |f| f.1 == *t).cloned())
            .collect();
        assert_eq!(files(&asked), expected, "{}", entry.id());
    }
}
